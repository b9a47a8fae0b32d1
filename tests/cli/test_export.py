"""`jointid export`: MJCF and URDF read back with ElementTree give the fit's damping and friction and the link the
test derives itself from I, h and the mass; impossible links and existing files are refused in one line; MuJoCo
loads the MJCF, and its joint swings with the period the identified model has (solved here with scipy)."""

from __future__ import annotations

import contextlib
import errno
import io
import json
import math
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from support.cli_support import refused, run

from jointid.cli import main

G = 9.81


def floats(text: str) -> list[float]:
    return [float(part) for part in text.split()]


def coulomb_log(path, seed: int = 3):
    """8 s at 250 Hz of the lesson's rich motion on a joint with I 0.8, h 0.4, B 0.15, Coulomb 0.2 N m, written
    with its exact qd and qdd and a little torque noise (a numpy model, not jointid's)."""
    t = np.linspace(0.0, 8.0, 2001)
    q = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t)
    qd = 0.91 * np.cos(1.3 * t) + 0.675 * np.cos(2.7 * t)
    qdd = -1.183 * np.sin(1.3 * t) - 1.8225 * np.sin(2.7 * t)
    tau = 0.8 * qdd + 0.4 * G * np.cos(q) + 0.15 * qd + 0.2 * np.sign(qd)
    tau = tau + 0.01 * np.random.default_rng(seed).standard_normal(t.size)
    np.savetxt(path, np.column_stack([t, q, qd, qdd, tau]), delimiter=",", header="t,q,qd,qdd,tau", comments="",
               fmt="%.17g")
    return path


@pytest.fixture(scope="module")
def fitted_log(tmp_path_factory):
    """A Coulomb joint's log and `jointid fit --csv LOG --model coulomb --json` of it, written as fit.json."""
    folder = tmp_path_factory.mktemp("export")
    log = coulomb_log(folder / "coulomb.csv")
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["fit", "--csv", str(log), "--model", "coulomb", "--json"]) == 0
    (folder / "fit.json").write_text(out.getvalue())
    return log, folder / "fit.json", json.loads(out.getvalue())


def test_both_files_read_back_as_the_fits_damping_friction_and_the_link_derived_from_the_mass(
        capsys, tmp_path, fitted_log):
    log, _, document = fitted_log
    I, h, B, Fc = (document["estimate"][name] for name in ("I", "h", "B", "Fc"))
    mass = 1.5
    r, I_com = h / mass, I - h**2 / mass  # the test's own split of I and h
    xml, urdf = tmp_path / "arm.xml", tmp_path / "arm.urdf"
    status, out, err = run(capsys, "export", "--csv", log, "--model", "coulomb", "--mass", mass,
                           "--mujoco", xml, "--urdf", urdf)
    assert status == 0 and err == "", err
    assert f"Wrote {xml} (MuJoCo MJCF) and {urdf} (URDF)." in out

    mjcf = ET.parse(xml).getroot()
    joint = mjcf.find("worldbody/body/joint")
    assert joint.get("type") == "hinge" and floats(joint.get("axis")) == [0, -1, 0]
    assert float(joint.get("damping")) == B and float(joint.get("frictionloss")) == Fc
    assert float(joint.get("armature")) == 0
    inertial = mjcf.find("worldbody/body/inertial")
    assert float(inertial.get("mass")) == mass
    assert floats(inertial.get("pos")) == pytest.approx([r, 0, 0], rel=1e-14, abs=1e-15)
    assert floats(inertial.get("diaginertia")) == pytest.approx([I_com / 2, I_com, I_com / 2], rel=1e-12)
    assert floats(mjcf.find("option").get("gravity")) == [0, 0, -G]

    robot = ET.parse(urdf).getroot()
    dynamics = robot.find("joint/dynamics")
    assert float(dynamics.get("damping")) == B and float(dynamics.get("friction")) == Fc
    assert robot.find("joint").get("type") == "continuous" and floats(robot.find("joint/axis").get("xyz")) == [0, -1, 0]
    inertial = robot.find("link[@name='joint_link']/inertial")
    assert float(inertial.find("mass").get("value")) == mass
    assert floats(inertial.find("origin").get("xyz")) == pytest.approx([r, 0, 0], rel=1e-14, abs=1e-15)
    moments = {key: float(inertial.find("inertia").get(key)) for key in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}
    assert moments == pytest.approx({"ixx": I_com / 2, "iyy": I_com, "izz": I_com / 2, "ixy": 0, "ixz": 0, "iyz": 0},
                                    rel=1e-12)
    # About the axis the link has the identified inertia back (parallel axes): I_com + m r^2 = I.
    assert I_com + mass * r**2 == pytest.approx(I, rel=1e-12)


def test_a_fits_json_exports_the_same_files_as_fitting_here(capsys, tmp_path, fitted_log):
    log, fit_json, _ = fitted_log
    assert run(capsys, "export", "--csv", log, "--model", "coulomb", "--com-distance", 0.3,
               "--mujoco", tmp_path / "here.xml")[0] == 0
    assert run(capsys, "export", "--from-json", fit_json, "--com-distance", 0.3, "--mujoco", tmp_path / "json.xml")[0] == 0
    here, there = ((tmp_path / name).read_text().split("-->", 1) for name in ("here.xml", "json.xml"))
    assert here[1] == there[1]  # the comment says where the numbers came from; the model is the same
    inertial = ET.parse(tmp_path / "here.xml").getroot().find("worldbody/body/inertial")
    h = json.loads(fit_json.read_text())["estimate"]["h"]
    assert float(inertial.get("mass")) == pytest.approx(h / 0.3, rel=1e-14)


def test_json_gives_the_link_the_files_hold(capsys, tmp_path):
    status, out, _ = run(capsys, "export", "--com-distance", 0.25, "--length", 0.5, "--mujoco", tmp_path / "a.xml",
                         "--json")
    assert status == 0
    document = json.loads(out)
    link = document["link"]
    I, h = document["estimate"]["I"], document["estimate"]["h"]
    assert link["mass"] == pytest.approx(h / 0.25, rel=1e-15) and link["length"] == 0.5
    assert link["inertia_about_com"] == pytest.approx(I - 0.25 * h, rel=1e-14)
    inertial = ET.parse(tmp_path / "a.xml").getroot().find("worldbody/body/inertial")
    assert float(inertial.get("mass")) == link["mass"] and floats(inertial.get("pos")) == link["com_position"]
    assert document["files"] == {"mujoco": str(tmp_path / "a.xml")} and document["not_determined"] == []


def test_several_runs_export_their_pooled_fit(capsys, tmp_path, fitted_log):
    log, _, document = fitted_log
    other = coulomb_log(tmp_path / "second.csv", seed=4)
    status, _, err = run(capsys, "export", "--csv", log, "--csv", other, "--model", "coulomb", "--mass", 2,
                           "--urdf", tmp_path / "pooled.urdf")
    assert status == 0 and err == "", err
    robot = ET.parse(tmp_path / "pooled.urdf").getroot()
    comment = " ".join((tmp_path / "pooled.urdf").read_text().split("-->")[0].split())
    assert "Exported by jointid from the pooled fit of 2 runs (coulomb.csv, second.csv; model coulomb)." in comment
    # Two runs of one joint: the pooled damping is near the first run's alone and the truth, not either exactly.
    damping = float(robot.find("joint/dynamics").get("damping"))
    assert damping != document["estimate"]["B"] and damping == pytest.approx(0.15, rel=0.05)


def test_a_mass_too_small_for_i_and_h_is_refused_in_one_line_and_writes_nothing(capsys, tmp_path):
    # The lesson's joint (I 0.8, h 0.4) needs m > h^2/I = 0.2 kg: 0.19 kg would need a negative inertia.
    line = refused(capsys, "export", "--mass", 0.19, "--mujoco", tmp_path / "a.xml", "--urdf", tmp_path / "a.urdf")
    assert line.startswith("jointid: --mass 0.19 kg is too small") and "h²/I = 0.2 kg" in line
    assert list(tmp_path.iterdir()) == []
    line = refused(capsys, "export", "--com-distance", 2.5, "--urdf", tmp_path / "a.urdf")
    assert "within I/h = 2 m" in line
    line = refused(capsys, "export", "--mass", 1, "--length", 0.3, "--urdf", tmp_path / "a.urdf")
    assert "0.4 m from the axis, beyond --length 0.3 m" in line
    assert list(tmp_path.iterdir()) == []


def test_an_existing_file_is_refused_without_force_and_replaced_with_it(capsys, tmp_path):
    xml, urdf = tmp_path / "a.xml", tmp_path / "a.urdf"
    xml.write_text("mine")
    line = refused(capsys, "export", "--mass", 2, "--urdf", urdf, "--mujoco", xml)
    assert line == f"jointid: {xml}: already exists; not overwriting it (add --force to replace it)"
    assert xml.read_text() == "mine" and not urdf.exists()  # the pair is written together or not at all
    assert run(capsys, "export", "--mass", 2, "--urdf", urdf, "--mujoco", xml, "--force")[0] == 0
    assert ET.parse(xml).getroot().tag == "mujoco" and ET.parse(urdf).getroot().tag == "robot"


def test_export_never_replaces_anything_but_a_regular_file_even_with_force(capsys, tmp_path):
    folder, target = tmp_path / "folder.xml", tmp_path / "target.xml"
    folder.mkdir()
    target.write_text("theirs")
    (tmp_path / "link.xml").symlink_to(target)
    os.mkfifo(tmp_path / "pipe.xml")
    kinds = {folder: "a directory", tmp_path / "link.xml": "a symbolic link", tmp_path / "pipe.xml": "a named pipe (FIFO)"}
    for path, kind in kinds.items():
        line = refused(capsys, "export", "--mass", 2, "--mujoco", path, "--force")
        assert line == f"jointid: {path}: {kind}, not a regular file; not replacing it"
    assert target.read_text() == "theirs" and not any(name.startswith(".") for name in os.listdir(tmp_path))


def test_a_full_disk_leaves_neither_file(capsys, tmp_path, monkeypatch):
    real_fdopen = os.fdopen

    def fdopen(descriptor, *args, **kwargs):  # the URDF's temporary finds the disk full
        handle = real_fdopen(descriptor, *args, **kwargs)
        if os.readlink(f"/proc/self/fd/{descriptor}").endswith("-1.jointid-part"):  # the group's second: b.urdf
            handle.write = disk_full
        return handle

    def disk_full(_text):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "fdopen", fdopen)
    line = refused(capsys, "export", "--mass", 2, "--mujoco", tmp_path / "a.xml", "--urdf", tmp_path / "b.urdf")
    assert line.endswith("cannot write: No space left on device")
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("argv, expected", [
    (["--mass", "2"], "jointid: give --mujoco FILE.xml, --urdf FILE.urdf or both: the files to write"),
    (["--mass", "2", "--mujoco", "same", "--urdf", "./same"], "jointid: --mujoco and --urdf name the same file"),
    (["--mujoco", "a.xml"], "jointid export: one of the arguments --mass --com-distance is required"),
    (["--mass", "0", "--mujoco", "a.xml"], "jointid export: argument --mass: must be a finite number greater than 0"),
    (["--mass", "2", "--motion", "holds", "--mujoco", "a.xml"], "has no unique estimate (rank 1 of 3)"),
    (["--mass", "2", "--armature", "0.9", "--mujoco", "a.xml"], "--armature 0.9 kg m² must be 0 or more and less"),
    (["--mass", "2", "--name", "a b", "--mujoco", "a.xml"], "jointid export: argument --name: must start with"),
    (["--mass", "2", "--from-json", "fit.json", "--noise", "0.1", "--mujoco", "a.xml"],
     "jointid: --noise: --from-json takes the fit from its file"),
    (["--mass", "2", "--from-json", "missing.json", "--mujoco", "a.xml"], "jointid: missing.json: cannot open"),
])
def test_bad_input_is_one_line(capsys, tmp_path, monkeypatch, argv, expected):
    monkeypatch.chdir(tmp_path)
    assert expected in refused(capsys, "export", *argv)
    assert list(tmp_path.iterdir()) == []


def test_a_file_that_is_not_a_fits_json_is_one_line(capsys, tmp_path):
    for text, expected in (("{", "not JSON"), ("[1]", "not a fit's JSON object"),
                           ('{"model": "plain", "estimate": {"I": "x"}}', "estimate is not an object of numbers"),
                           ("[" * 200_000 + "]" * 200_000, "JSON nested too deeply"),  # was a RecursionError
                           ('{"a":' * 100_000 + "1" + "}" * 100_000, "JSON nested too deeply")):
        (tmp_path / "fit.json").write_text(text)
        assert expected in refused(capsys, "export", "--from-json", tmp_path / "fit.json", "--mass", 1,
                                   "--mujoco", tmp_path / "a.xml")


def test_a_parameter_the_fit_did_not_determine_is_exported_with_a_one_line_warning(capsys, tmp_path):
    # Slow motion hardly accelerates or moves: I and B are not determined (at the lesson's noise 0.2 its I is
    # -1.6, which no body has, so the noise here is smaller: I 0.68 ± 0.27).
    status, out, err = run(capsys, "export", "--motion", "slow", "--noise", "0.01", "--mass", 2,
                           "--mujoco", tmp_path / "a.xml")
    assert status == 0 and (tmp_path / "a.xml").exists() and "Wrote" in out
    assert err.count("\n") == 1 and err.startswith("jointid export: warning: I and B are not determined"), err


def test_the_logs_angle_convention_becomes_the_joints(capsys, tmp_path, fitted_log):
    _, fit_json, document = fitted_log
    logged = json.loads(fit_json.read_text())
    logged["conventions"] = {"training": {"zero": "down", "clockwise": True}, "heldout": None}
    (tmp_path / "down.json").write_text(json.dumps(logged))
    assert run(capsys, "export", "--from-json", tmp_path / "down.json", "--mass", 2, "--mujoco",
               tmp_path / "down.xml")[0] == 0
    body = ET.parse(tmp_path / "down.xml").getroot().find("worldbody/body")
    # Joint value 0 is the log's 0: hanging straight down; the log's angle grows clockwise: about +y.
    assert floats(body.find("joint").get("axis")) == [0, 1, 0]
    assert floats(body.find("inertial").get("pos")) == [0, 0, -document["estimate"]["h"] / 2]


@pytest.fixture
def mujoco():
    """MuJoCo's Python bindings: the test extra installs them; the export itself never imports them."""
    return pytest.importorskip("mujoco")


def swing(mujoco, model, start: float, seconds: float) -> tuple[np.ndarray, np.ndarray]:
    """(t, joint value) of MuJoCo's free swing from rest at `start` (RK4, 1 ms steps)."""
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    model.opt.timestep = 1e-3
    data = mujoco.MjData(model)
    data.qpos[0] = start
    steps = round(seconds / model.opt.timestep)
    values = np.empty(steps + 1)
    values[0] = start
    for k in range(steps):
        mujoco.mj_step(model, data)
        values[k + 1] = data.qpos[0]
    return np.arange(steps + 1) * model.opt.timestep, values


def upward_crossings(t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Times where x crosses 0 upward, interpolated linearly between samples."""
    k = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    return t[k] - x[k] * (t[k + 1] - t[k]) / (x[k + 1] - x[k])


def test_mujoco_swings_the_exported_joint_with_the_identified_models_period(capsys, tmp_path, mujoco):
    from scipy.integrate import solve_ivp

    xml = tmp_path / "lesson.xml"
    assert run(capsys, "export", "--mass", 2, "--armature", 0.05, "--mujoco", xml)[0] == 0
    model = mujoco.MjModel.from_xml_path(str(xml))
    I, h, B = 0.8, 0.4, 0.15  # the lesson's joint, which the noiseless rich fit recovers

    # At rest and horizontal MuJoCo's torque to hold the joint is h g, and with no torque it accelerates at -h g/I.
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    assert data.qfrc_bias[0] == pytest.approx(h * G, rel=1e-9)
    assert data.qacc[0] == pytest.approx(-h * G / I, rel=1e-9)

    # A small swing about hanging straight down (q = -pi/2), against the same model solved by scipy.
    start, seconds = -math.pi / 2 + 0.02, 12.0
    t, q = swing(mujoco, model, start, seconds)
    reference = solve_ivp(lambda _, y: [y[1], -(h * G * math.cos(y[0]) + B * y[1]) / I], (0, seconds), [start, 0.0],
                          method="DOP853", rtol=1e-11, atol=1e-12, dense_output=True)
    q_reference = reference.sol(t)[0]
    mujoco_period = np.diff(upward_crossings(t, q + math.pi / 2)).mean()
    model_period = np.diff(upward_crossings(t, q_reference + math.pi / 2)).mean()
    damped = 2 * math.pi / math.sqrt(h * G / I - (B / (2 * I)) ** 2)  # the linearised damped swing's period
    print(f"MuJoCo period {mujoco_period:.9f} s, identified model (scipy) {model_period:.9f} s, "
          f"linearised {damped:.9f} s; largest gap {np.max(np.abs(q - q_reference)):.2e} rad")
    assert mujoco_period == pytest.approx(model_period, rel=1e-8)
    assert model_period == pytest.approx(damped, rel=1e-4)  # 0.02 rad of swing lengthens it by about 2.5e-5
    assert np.max(np.abs(q - q_reference)) < 1e-8  # the whole decaying swing, not just its period (3.6e-12 here)


@pytest.mark.parametrize("zero, clockwise", [("right", False), ("down", False), ("up", True)])
def test_mujocos_gravity_torque_follows_the_logs_angle_convention(capsys, tmp_path, fitted_log, mujoco, zero,
                                                                 clockwise):
    _, fit_json, document = fitted_log
    logged = json.loads(fit_json.read_text())
    logged["conventions"] = {"training": {"zero": zero, "clockwise": clockwise}, "heldout": None}
    (tmp_path / "fit.json").write_text(json.dumps(logged))
    assert run(capsys, "export", "--from-json", tmp_path / "fit.json", "--mass", 2, "--mujoco", tmp_path / "a.xml")[0] == 0
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "a.xml"))
    data = mujoco.MjData(model)
    sign = -1 if clockwise else 1
    offset = {"right": 0.0, "down": -math.pi / 2, "up": math.pi / 2}[zero]
    h = document["estimate"]["h"]
    for angle in (0.0, 0.4, 2.0, -1.1):  # the log's angle: jointid's q = sign * angle + offset
        data.qpos[0] = angle
        mujoco.mj_forward(model, data)
        # Torque toward increasing logged angle that holds the joint: sign * h g cos q.
        assert data.qfrc_bias[0] == pytest.approx(sign * h * G * math.cos(sign * angle + offset), abs=1e-12)


def test_mujoco_reads_the_urdf_as_the_same_joint_with_the_armature_in_the_link(capsys, tmp_path, mujoco):
    assert run(capsys, "export", "--mass", 2, "--armature", 0.05, "--mujoco", tmp_path / "a.xml",
               "--urdf", tmp_path / "a.urdf")[0] == 0
    I, h, B = 0.8, 0.4, 0.15
    for path in (tmp_path / "a.xml", tmp_path / "a.urdf"):
        model = mujoco.MjModel.from_xml_path(str(path))
        data = mujoco.MjData(model)
        assert model.dof_damping[0] == pytest.approx(B, rel=1e-12)
        for q in (0.0, 0.7, -2.0):
            data.qpos[0], data.qvel[0] = q, 0.0
            mujoco.mj_forward(model, data)
            assert data.qfrc_bias[0] == pytest.approx(h * G * math.cos(q), abs=1e-12)
            assert data.qacc[0] == pytest.approx(-h * G * math.cos(q) / I, abs=1e-12)


@pytest.mark.parametrize("zero, clockwise", [("right", False), ("up", True)])
def test_check_reads_the_identified_inertia_and_gravity_torque_back_from_mujoco(capsys, tmp_path, fitted_log, mujoco,
                                                                                zero, clockwise):
    _, fit_json, document = fitted_log
    logged = json.loads(fit_json.read_text())
    logged["conventions"] = {"training": {"zero": zero, "clockwise": clockwise}, "heldout": None}
    (tmp_path / "fit.json").write_text(json.dumps(logged))
    status, out, _ = run(capsys, "export", "--from-json", tmp_path / "fit.json", "--mass", 2, "--armature", 0.1,
                         "--mujoco", tmp_path / "a.xml", "--check", "--json")
    assert status == 0
    check = json.loads(out)["mujoco_check"]
    assert check["agrees"] and check["version"] == mujoco.__version__
    assert check["joint_inertia"] == pytest.approx(document["estimate"]["I"], rel=1e-12)
    assert check["gravity_torque"] == pytest.approx(document["estimate"]["h"] * G, rel=1e-12)


def test_check_without_mujoco_is_one_line_naming_the_extra_and_writes_nothing(capsys, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "mujoco", None)  # `import mujoco` then raises ImportError
    line = refused(capsys, "export", "--mass", 2, "--mujoco", tmp_path / "a.xml", "--check")
    assert line == "jointid: --check loads the model in MuJoCo, which is optional: pip install 'jointid[mujoco]'"
    assert os.listdir(tmp_path) == []
    assert "add --mujoco FILE.xml" in refused(capsys, "export", "--mass", 2, "--urdf", tmp_path / "a.urdf", "--check")
