"""Logs of motor current and voltage (--effort), motors (--motor), and the gains a controller takes (--gains
wpilib), checked against models written here: closed forms from the motor's constants, never jointid's output."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from support.cli_support import fit_json, refused, run

G = 9.81
PHYSICAL = {"I": 0.8, "h": 0.4, "B": 0.15}
GAINS = {"kS": 0.2, "kG": 0.9, "kV": 1.8, "kA": 0.12}
OFFSET = -0.05

# WPILib's NEO (allwpilib DCMotor.getNEO): 12 V, stall 2.6 N m at 105 A, free 1.8 A at 5676 rpm; R and Kv as its
# constructor derives them.
NEO_R = 12 / 105
NEO_KT = 2.6 / 105
NEO_KV = (5676 * 2 * math.pi / 60) / (12 - NEO_R * 1.8)


def motion(t):
    """q, qd, qdd of two sines with an offset, exact derivatives: moving both ways, rarely at rest."""
    q = 0.3 + 0.9 * np.sin(1.1 * t) + 0.3 * np.sin(2.9 * t + 0.4)
    qd = 0.9 * 1.1 * np.cos(1.1 * t) + 0.3 * 2.9 * np.cos(2.9 * t + 0.4)
    qdd = -0.9 * 1.1**2 * np.sin(1.1 * t) - 0.3 * 2.9**2 * np.sin(2.9 * t + 0.4)
    return q, qd, qdd


def write(path, t, q, qd, qdd, effort, name="tau"):
    np.savetxt(path, np.column_stack([t, q, qd, qdd, effort]), delimiter=",", header=f"t,q,qd,qdd,{name}",
               comments="", fmt="%.17g")
    return str(path)


@pytest.fixture
def times():
    return np.linspace(0.0, 12.0, 1201)


def test_a_current_log_gives_the_torque_logs_parameters(tmp_path, capsys, times):
    q, qd, qdd = motion(times)
    tau = PHYSICAL["I"] * qdd + PHYSICAL["h"] * G * np.cos(q) + PHYSICAL["B"] * qd
    current = tau / (6 * 0.091)  # gear 6, kt 0.091 N m/A, efficiency 1
    torque_log = write(tmp_path / "torque.csv", times, q, qd, qdd, tau)
    current_log = write(tmp_path / "current.csv", times, q, qd, qdd, current)
    by_torque = fit_json(capsys, "--csv", torque_log, "--model", "plain")["estimate"]
    by_current = fit_json(capsys, "--csv", current_log, "--model", "plain", "--effort", "current", "--gear", "6",
                          "--kt", "0.091")
    for name, value in PHYSICAL.items():
        assert by_current["estimate"][name] == pytest.approx(by_torque[name], rel=1e-9)
        assert by_current["estimate"][name] == pytest.approx(value, rel=1e-6)
    assert by_current["logs"]["training"]["effort"] == "current"
    assert by_current["logs"]["training"]["effort_scale"] == pytest.approx(6 * 0.091)
    assert any("--effort current" in note for note in by_current["notes"])


def test_efficiency_scales_the_current(tmp_path, capsys, times):
    q, qd, qdd = motion(times)
    tau = PHYSICAL["I"] * qdd + PHYSICAL["h"] * G * np.cos(q) + PHYSICAL["B"] * qd
    log = write(tmp_path / "current.csv", times, q, qd, qdd, tau / (6 * 0.091 * 0.8))
    fitted = fit_json(capsys, "--csv", log, "--model", "plain", "--effort", "current", "--gear", "6", "--kt",
                      "0.091", "--efficiency", "0.8")["estimate"]
    assert fitted["I"] == pytest.approx(PHYSICAL["I"], rel=1e-6)


def voltage_log(path, t):
    """A log of the WPILib arm feedforward's voltage for the motion, written from the gains above."""
    q, qd, qdd = motion(t)
    volts = (GAINS["kS"] * np.sign(qd) + GAINS["kG"] * np.cos(q + OFFSET) + GAINS["kV"] * qd
             + GAINS["kA"] * qdd)
    return write(path, t, q, qd, qdd, volts, "effort")


def test_gains_wpilib_reproduces_the_gains_of_a_noiseless_voltage_log(tmp_path, capsys, times):
    document = fit_json(capsys, "--csv", voltage_log(tmp_path / "arm.csv", times), "--effort", "voltage",
                        "--gains", "wpilib", "--no-robust")
    assert document["effort"] == {"name": "voltage", "unit": "V"}
    assert document["units"]["kV"] == "V s/rad" and document["units"]["kA"] == "V s²/rad"
    gains = document["gains"]["gains"]
    for name, value in GAINS.items():
        assert gains[name]["value"] == pytest.approx(value, rel=1e-6)
        # SysId's direction (acceleration on voltage) agrees on exact data.
        assert gains[name]["sysid_direction"] == pytest.approx(value, rel=1e-6)
        assert gains[name]["verdict"] == "well determined"
    assert gains["q0"]["value"] == pytest.approx(OFFSET, abs=1e-7)
    # Per rotation, as WPILib defines them: V/(rot/s) = 2 pi V/(rad/s).
    assert gains["kV"]["per_rotation"] == pytest.approx(2 * math.pi * GAINS["kV"], rel=1e-6)
    assert gains["kA"]["per_rotation"] == pytest.approx(2 * math.pi * GAINS["kA"], rel=1e-6)
    assert gains["kS"]["per_rotation"] == pytest.approx(GAINS["kS"], rel=1e-6)
    java = document["gains"]["constructors"]["java"]
    assert java.startswith("new ArmFeedforward(0.2, 0.9, 1.8, 0.12")
    assert document["gains"]["constructors"]["python"].startswith("wpimath.controller.ArmFeedforward(0.2, 0.9,")


def test_gains_text_flags_a_static_gain_the_motion_cannot_show(tmp_path, capsys):
    """An arm without static friction, logged with voltage noise: kS is within its error of 0, not determined, and
    the text says not to trust it; every unit shown before the notes is a volt's."""
    t = np.linspace(0.0, 12.0, 1201)
    q, qd, qdd = motion(t)
    volts = GAINS["kG"] * np.cos(q + OFFSET) + GAINS["kV"] * qd + GAINS["kA"] * qdd
    volts += np.random.default_rng(3).normal(0.0, 0.05, len(t))
    log = write(tmp_path / "arm.csv", t, q, qd, qdd, volts, "effort")
    status, out, err = run(capsys, "fit", "--csv", log, "--effort", "voltage", "--gains", "wpilib")
    assert status == 0, err
    assert "Training RMSE (V)" in out and "kV (V s/rad)" in out and "N m" not in out.split("Note:")[0]
    assert "new ArmFeedforward(" in out and "frc::ArmFeedforward{units::volt_t{" in out
    assert "Not well determined" in out and "kS (" in out.split("Not well determined")[1]


def test_a_motor_gives_the_physical_parameters_behind_voltage_gains(tmp_path, capsys, times):
    """2 NEOs at 50:1: V = tau / c + (G/Kv) qd with c = G n kt / R, so I = c kA, h = c kG / g, B = c (kV - G/Kv)."""
    q, qd, qdd = motion(times)
    fc = 0.3
    tau = PHYSICAL["I"] * qdd + PHYSICAL["h"] * G * np.cos(q) + PHYSICAL["B"] * qd + fc * np.sign(qd)
    c = 50 * 2 * NEO_KT / NEO_R
    volts = tau / c + 50 / NEO_KV * qd
    log = write(tmp_path / "arm.csv", times, q, qd, qdd, volts, "effort")
    document = fit_json(capsys, "--csv", log, "--effort", "voltage", "--motor", "neo", "--motor-count", "2",
                        "--gear", "50", "--no-robust")
    motor = document["motor"]
    assert motor["torque_per_volt_n_m_per_v"] == pytest.approx(c, rel=1e-12)
    assert motor["back_emf_v_s_per_rad"] == pytest.approx(50 / NEO_KV, rel=1e-12)
    for name, value in {**PHYSICAL, "Fc": fc}.items():
        assert motor["parameters"][name]["value"] == pytest.approx(value, rel=1e-6)
    assert motor["reflected_inertia_kg_m2"] is None
    # The gains themselves are the closed form's.
    assert document["estimate"]["kA"] == pytest.approx(PHYSICAL["I"] / c, rel=1e-6)
    assert document["estimate"]["kV"] == pytest.approx(PHYSICAL["B"] / c + 50 / NEO_KV, rel=1e-6)
    # A rotor inertia given separates the rotors' reflected share from the load's.
    document = fit_json(capsys, "--csv", log, "--effort", "voltage", "--motor", "NEO", "--motor-count", "2",
                        "--gear", "50", "--motor-inertia", "1e-5", "--no-robust")
    reflected = 2 * 50**2 * 1e-5
    assert document["motor"]["reflected_inertia_kg_m2"] == pytest.approx(reflected)
    assert document["motor"]["load_inertia_kg_m2"] == pytest.approx(PHYSICAL["I"] - reflected, rel=1e-6)


def test_a_custom_motor_and_a_torque_log_convert_to_gains(tmp_path, capsys, times):
    q, qd, qdd = motion(times)
    tau = PHYSICAL["I"] * qdd + PHYSICAL["h"] * G * np.cos(q) + PHYSICAL["B"] * qd
    log = write(tmp_path / "torque.csv", times, q, qd, qdd, tau)
    r, kt, kv, gear = 0.05, 0.02, 40.0, 100.0
    c = gear * kt / r
    document = fit_json(capsys, "--csv", log, "--model", "plain", "--motor-r", str(r), "--motor-kt", str(kt),
                        "--motor-kv", str(kv), "--gear", str(gear), "--gains", "wpilib")
    gains = document["gains"]["gains"]
    assert gains["kA"]["value"] == pytest.approx(PHYSICAL["I"] / c, rel=1e-6)
    assert gains["kG"]["value"] == pytest.approx(PHYSICAL["h"] * G / c, rel=1e-6)
    assert gains["kV"]["value"] == pytest.approx(PHYSICAL["B"] / c + gear / kv, rel=1e-6)
    assert document["gains"]["not_in_model"] == ["kS"]
    assert document["gains"]["converted_through"]["torque_per_volt_n_m_per_v"] == pytest.approx(c)


def test_simulate_writes_a_voltage_log_that_fits_back(tmp_path, capsys):
    out = str(tmp_path / "arm.csv")
    status, _, err = run(capsys, "simulate", "--rate", "100", "--duration", "10", "--effort", "voltage", "--motor",
                         "Kraken X60", "--gear", "80", "--true-coulomb", "0.3", "--out", out)
    assert status == 0, err
    document = fit_json(capsys, "--csv", out, "--effort", "voltage", "--motor", "kraken-x60", "--gear", "80")
    for name, value in {**PHYSICAL, "Fc": 0.3}.items():
        assert document["motor"]["parameters"][name]["value"] == pytest.approx(value, rel=1e-4)


@pytest.mark.parametrize("argv, words", [
    (("--effort", "current"), "--effort current needs --kt"),
    (("--effort", "voltage", "--motor", "NEO 600"), "unknown motor 'NEO 600'; known (WPILib's DCMotor): CIM"),
    (("--gains", "wpilib"), "--gains wpilib needs volts"),
    (("--effort", "current", "--kt", "0.1", "--effort-scale", "2"), "--effort-scale: not with --effort current"),
    (("--kt", "0.1"), "--kt: only with --effort current"),
    (("--gear", "5"), "--gear: only with --effort current or a motor"),
    (("--motor-r", "0.1"), "needs --motor-kt, --motor-kv as well"),
    (("--motor", "NEO", "--motor-kv", "50"), "not both"),
    (("--motor-count", "2"), "--motor-count: only with a motor"),
])
def test_bad_effort_options_are_refused_in_one_line(tmp_path, capsys, times, argv, words):
    q, qd, qdd = motion(times)
    log = write(tmp_path / "log.csv", times, q, qd, qdd, qd + np.cos(q) + 0.1 * qdd)
    assert words in refused(capsys, "fit", "--csv", log, *argv)


def test_effort_options_without_a_log_are_refused(capsys):
    assert "only for fitting a log" in refused(capsys, "fit", "--effort", "voltage")


def test_a_held_out_log_in_other_units_is_refused(tmp_path):
    """The command line reads both logs with one --effort; the library can mix them, and is refused."""
    from jointid.logs.effort import EffortReading
    from jointid.logs.request import HELDOUT, TRAINING, LoadRequest, load_joint_log
    from jointid.logs.table import LogError
    from jointid.studies.log_fit import fit_logs

    t = np.linspace(0.0, 12.0, 1201)
    q, qd, qdd = motion(t)
    log = write(tmp_path / "log.csv", t, q, qd, qdd, qd + np.cos(q) + 0.1 * qdd)
    volts = load_joint_log(LoadRequest(log, TRAINING, effort=EffortReading("voltage")))
    torque = load_joint_log(LoadRequest(log, HELDOUT))
    with pytest.raises(LogError, match="holds torque"):
        fit_logs(volts, torque)


def test_the_library_fits_voltage_arrays_as_the_command_line_does(times):
    import jointid
    from jointid.studies.gains import arm_gains

    q, qd, qdd = motion(times)
    volts = (GAINS["kS"] * np.sign(qd) + GAINS["kG"] * np.cos(q + OFFSET) + GAINS["kV"] * qd
             + GAINS["kA"] * qdd)
    fit = jointid.fit_log({"t": times, "q": q, "qd": qd, "qdd": qdd, "tau": volts}, effort="voltage", robust=False)
    assert fit.result.model.names == ("kA", "kG", "kV", "kS", "q0")  # SysId's arm by default
    gains = arm_gains(fit)
    for name, value in GAINS.items():
        assert gains[name].value == pytest.approx(value, rel=1e-6)
        assert gains[name].per_rotation == pytest.approx(value * (2 * math.pi if name in ("kV", "kA") else 1.0))
    with pytest.raises(ValueError, match="torque constant"):
        jointid.fit_log({"t": times, "q": q, "tau": volts}, effort="current")


def test_several_voltage_runs_pool_into_one_set_of_gains(tmp_path, capsys):
    """Two runs of other motions (as SysId's quasistatic and dynamic tests are): the pooled fit reports kG and q0
    (not their cosine and sine columns), and its gains are the arm's."""
    logs = []
    for k, (start, end) in enumerate(((0.0, 12.0), (3.0, 9.0))):
        t = np.linspace(start, end, 1201)
        logs += ["--csv", voltage_log(tmp_path / f"run{k}.csv", t)]
    document = fit_json(capsys, *logs, "--effort", "voltage", "--gains", "wpilib", "--no-robust")
    assert set(document["pooled"]["estimate"]) == {"kA", "kG", "kV", "kS", "q0"}
    assert document["pooled"]["estimate"]["q0"] == pytest.approx(OFFSET, abs=1e-7)
    for name, value in GAINS.items():
        assert document["gains"]["gains"][name]["value"] == pytest.approx(value, rel=1e-6)
        assert document["gains"]["gains"][name]["sysid_direction"] == pytest.approx(value, rel=1e-6)
    status, out, err = run(capsys, "fit", *logs, "--effort", "voltage", "--gains", "wpilib")
    assert status == 0, err
    assert "pooled fit of 2 voltage runs" in out and "filtered voltage predicted" in out


def test_several_torque_runs_with_an_angle_offset_report_h_and_q0(tmp_path, capsys, times):
    """The pooled fit of an angle-offset model used to look its columns (h_c, h_s) up among the reported names."""
    logs = []
    for k, shift in enumerate((0.0, 2.0)):
        q, qd, qdd = motion(times + shift)
        tau = PHYSICAL["I"] * qdd + PHYSICAL["h"] * G * np.cos(q + OFFSET) + PHYSICAL["B"] * qd
        logs += ["--csv", write(tmp_path / f"run{k}.csv", times, q, qd, qdd, tau)]
    pooled = fit_json(capsys, *logs, "--model", "angle-offset", "--no-robust")["pooled"]
    assert pooled["estimate"]["h"] == pytest.approx(PHYSICAL["h"], rel=1e-6)
    assert pooled["estimate"]["q0"] == pytest.approx(OFFSET, abs=1e-7)


def test_compare_fits_the_ladder_of_a_voltage_log_in_volts(tmp_path, capsys, times):
    status, out, err = run(capsys, "compare", "--csv", voltage_log(tmp_path / "arm.csv", times), "--effort",
                           "voltage", "--no-robust")
    assert status == 0, err
    assert re.search(r"coulomb\+angle-offset \S* *kA, kG, kV, kS, q0", out) and "voltage and regressor low-passed" in out
    assert "I, h, B" not in out


def test_export_of_a_voltage_log_writes_the_physical_joint_behind_the_gains(tmp_path, capsys, times):
    """2 NEOs at 50:1 as above: the MJCF holds B and Fc of the closed form, a link whose I and h are the physical
    ones, and the rotors' reflected inertia as the joint's armature; without a motor the export is refused."""
    import xml.etree.ElementTree as ET

    q, qd, qdd = motion(times)
    fc = 0.3
    tau = PHYSICAL["I"] * qdd + PHYSICAL["h"] * G * np.cos(q) + PHYSICAL["B"] * qd + fc * np.sign(qd)
    c = 50 * 2 * NEO_KT / NEO_R
    log = write(tmp_path / "arm.csv", times, q, qd, qdd, tau / c + 50 / NEO_KV * qd, "effort")
    drive = ("--effort", "voltage", "--motor", "NEO", "--motor-count", "2", "--gear", "50", "--no-robust")
    assert "gives gains in volts" in refused(capsys, "export", "--csv", log, *drive[:2], "--mass", "2",
                                             "--mujoco", str(tmp_path / "no.xml"))
    assert not (tmp_path / "no.xml").exists()
    mjcf = tmp_path / "arm.xml"
    status, _, err = run(capsys, "export", "--csv", log, *drive, "--motor-inertia", "1e-5", "--mass", "2",
                           "--mujoco", str(mjcf))
    assert status == 0, err
    joint = ET.parse(mjcf).find(".//joint")
    inertial = ET.parse(mjcf).find(".//inertial")
    armature = 2 * 50**2 * 1e-5
    assert float(joint.get("damping")) == pytest.approx(PHYSICAL["B"], rel=1e-5)
    assert float(joint.get("frictionloss")) == pytest.approx(fc, rel=1e-5)
    assert float(joint.get("armature")) == pytest.approx(armature, rel=1e-9)
    mass, com = float(inertial.get("mass")), float(inertial.get("pos").split()[0])
    assert mass * com == pytest.approx(PHYSICAL["h"], rel=1e-5)  # h = m r
    about_axis = float(inertial.get("diaginertia").split()[1]) + mass * com**2 + armature
    assert about_axis == pytest.approx(PHYSICAL["I"], rel=1e-5)


def test_a_report_of_a_voltage_log_draws_volts_and_holds_the_gains(tmp_path, capsys, times):
    """The page's axes follow the effort (volts), and it holds the gains and the constructor `fit` prints."""
    log = voltage_log(tmp_path / "arm.csv", times)
    page = tmp_path / "arm.html"
    status, _, err = run(capsys, "report", "--csv", log, "--effort", "voltage", "--gains", "wpilib", "--no-robust",
                         "--out", str(page))
    assert status == 0, err
    html = page.read_text()
    assert "Voltage (V)" in html and "Training residuals (V)" in html and "Torque (N m)" not in html
    assert "Training and held-out voltages" in html and "held-out torques" not in html
    assert "new ArmFeedforward(0.2, 0.9, 1.8, 0.12" in html


def test_a_gear_that_makes_the_damping_negative_is_named(tmp_path, capsys, times):
    """2 NEOs at 50:1 fitted as if at 100:1: the back-EMF G/Kv the text assumes exceeds the fitted kV, so B comes
    out negative (c (kV - G/Kv) with the closed form's kV = B/c + 50/Kv < 100/Kv), and the text says to check the
    gear rather than calling a negative damping well determined without a word."""
    q, qd, qdd = motion(times)
    tau = PHYSICAL["I"] * qdd + PHYSICAL["h"] * G * np.cos(q) + PHYSICAL["B"] * qd
    c = 50 * 2 * NEO_KT / NEO_R
    assert PHYSICAL["B"] / c + 50 / NEO_KV < 100 / NEO_KV  # the premise, from the closed form
    log = write(tmp_path / "arm.csv", times, q, qd, qdd, tau / c + 50 / NEO_KV * qd, "effort")
    status, out, err = run(capsys, "fit", "--csv", log, "--effort", "voltage", "--motor", "NEO", "--motor-count", "2",
                           "--gear", "100", "--no-robust")
    assert status == 0, err
    assert "B is negative by more than two standard errors" in out and "--gear, 100:1 here" in out
    status, out, err = run(capsys, "fit", "--csv", log, "--effort", "voltage", "--motor", "NEO", "--motor-count", "2",
                           "--gear", "50", "--no-robust")
    assert status == 0 and "B is negative" not in out
