"""ROS bags as robots write them: a position wrapped by the driver, counted far from zero, or zero pointing down.

Bags are written with rosbags' own writers (tests/support/bag_support.py) from the closed-form joint of
test_conventions; expected values are computed here with numpy.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

pytest.importorskip("rosbags")

from support.bag_support import bag_path, write_joint_bag  # noqa: E402
from support.conventions_support import TRUE, joint, logged, lstsq, wrap  # noqa: E402

from jointid.cli import main  # noqa: E402
from jointid.logs.conventions import AngleConvention  # noqa: E402
from jointid.logs.request import LoadRequest, load_joint_log  # noqa: E402

RATE, WINDOW = 250.0, 31
HALF = WINDOW // 2


def times(count=3000):
    return np.arange(count) / RATE


def load(path, **options):
    return load_joint_log(LoadRequest(str(path), joint="arm", window=WINDOW, **options))


@pytest.mark.parametrize("kind", ["sqlite3", "ros1"])
def test_wrapped_position_is_unwrapped(tmp_path, kind):
    t = times()
    q, qd, qdd, tau = joint(t, spin=2.0)
    a = wrap(q)
    path = write_joint_bag(bag_path(tmp_path, "wrapped", kind), kind, t, {"arm": (a, qd, tau)})
    log = load(path)
    jumps = int(np.count_nonzero(np.abs(np.diff(a)) > np.pi))
    np.testing.assert_allclose(log.data.q, q + (a[0] - q[0]), rtol=0, atol=1e-9)  # nothing trimmed
    middle = slice(HALF, -HALF)  # away from the smoothing's polynomial ends; central differences are O(h^2)
    np.testing.assert_allclose(log.data.qdd[middle], qdd[middle], rtol=0, atol=1e-2)
    assert f"{path}: position is wrapped to (-pi, pi]: unwrapped (numpy.unwrap) at {jumps} jumps of nearly a full " \
           "turn between samples." in log.notes
    status = main(["fit", "--bag", str(path), "--joint", "arm", "--window", str(WINDOW), "--cutoff", "0", "--json"])
    assert status == 0


def test_wrapped_bag_fits_the_joint(tmp_path, capsys):
    t = times()
    q, qd, qdd, tau = joint(t, spin=2.0)
    path = write_joint_bag(bag_path(tmp_path, "wrapped", "mcap"), "mcap", t, {"arm": (wrap(q, positive=True), qd, tau)})
    assert main(["fit", "--bag", str(path), "--joint", "arm", "--window", str(WINDOW), "--cutoff", "0", "--json",
                 "--model", "plain"]) == 0
    document = json.loads(capsys.readouterr().out)
    found = np.array([document["estimate"][name] for name in ("I", "h", "B")])
    np.testing.assert_allclose(found, lstsq(q, qd, qdd, tau), rtol=1e-4)
    np.testing.assert_allclose(found, TRUE, rtol=1e-4)
    conventions = document["conventions"]["training"]
    assert conventions["wrapped_range"] == "[0, 2 pi)" and conventions["unwrapped_jumps"] > 2
    assert conventions["columns"] == {"t": "header.stamp", "q": "position", "qd": "velocity", "tau": "effort"}


def test_far_off_position_loses_its_turns(tmp_path):
    t = times(600)
    q, qd, qdd, tau = joint(t)
    stored = q + 0.5 + 2 * np.pi * 1e14
    path = write_joint_bag(bag_path(tmp_path, "far", "sqlite3"), "sqlite3", t, {"arm": (stored, qd, tau)})
    log = load(path)
    expected = np.unwrap(np.arctan2(np.sin(stored), np.cos(stored)))
    np.testing.assert_allclose(log.data.q, expected, rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.cos(log.data.q), np.cos(stored), rtol=0, atol=1e-12)
    assert any(note.startswith(f"{path}: position is 100000000000000 whole turns from zero") for note in log.notes)


@pytest.mark.parametrize("zero, clockwise", [("down", False), ("right", True), ("left", True)])
def test_zero_and_direction_convert_a_bag(tmp_path, capsys, zero, clockwise):
    t = times()
    q, qd, qdd, tau = joint(t)
    a, ad, _, tau_a = logged(t, zero, clockwise)
    path = write_joint_bag(bag_path(tmp_path, "robot", "sqlite3"), "sqlite3", t, {"arm": (a, ad, tau_a)})
    log = load(path, angle=AngleConvention(zero, clockwise))
    middle = slice(HALF, -HALF)  # away from the smoothing's polynomial ends; central differences are O(h^2)
    np.testing.assert_allclose(log.data.q, q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(log.data.qd[middle], qd[middle], rtol=0, atol=1e-4)  # estimated: the log's qd alone
    np.testing.assert_allclose(log.data.qdd[middle], qdd[middle], rtol=0, atol=1e-2)
    np.testing.assert_allclose(log.data.tau, tau, rtol=0, atol=1e-12)
    turning = "clockwise" if clockwise else "counter-clockwise"
    assert any(note.startswith(f"{path}: angle 0 pointing {zero}, {turning}: q = ") for note in log.notes)
    argv = ["fit", "--bag", str(path), "--joint", "arm", "--window", str(WINDOW), "--cutoff", "0", "--json",
            "--zero", zero, *(["--clockwise"] if clockwise else [])]
    assert main(argv) == 0
    document = json.loads(capsys.readouterr().out)
    np.testing.assert_allclose([document["estimate"][name] for name in ("I", "h", "B")], TRUE, rtol=1e-4)
    assert document["conventions"]["training"]["zero"] == zero
