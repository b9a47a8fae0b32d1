"""SysId routines of the mechanisms teams characterise, fitted as each one's WPILib feedforward, chosen from the log.

The logs come from tests/support/sysid_mechanisms.py: a flywheel, an elevator, an arm and a velocity-only roller
simulated from known gains (scipy's integrator), sampled at 50 Hz with jitter, quantised by their encoders and
written with robotpy-wpiutil's own writer under the names SysIdRoutineLog gives them. Every gain is checked against
the simulation's truth, and every mechanism is chosen without --mechanism.
"""

import dataclasses
import json
import math

import numpy as np
import pytest
from support.cli_support import refused, run
from support.sysid_mechanisms import ARM, ELEVATOR, FLYWHEEL, ROLLER, write_mechanism_log

from jointid.studies.gains import arm_gains
from jointid.studies.sysid import fit_wpilog

wpiutil = pytest.importorskip("wpiutil")

ROTATION = 2 * math.pi
"""A rotations log is fitted per radian: per rotation is 2 pi times kV and kA."""


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    """Each mechanism's routine written once, and an elevator on a drum logged in rotations."""
    folder = tmp_path_factory.mktemp("mechanisms")
    drum = dataclasses.replace(ELEVATOR, unit="rotations", resolution=1 / 2048, routine="Drum")
    ramped = dataclasses.replace(FLYWHEEL, ramp=0.25, routine="Ramped")
    pushed = dataclasses.replace(ramped, push=(0, 4.0, 1.0), routine="Pushed")
    return {name: write_mechanism_log(folder / f"{name}.wpilog", mechanism) for name, mechanism in
            (("flywheel", FLYWHEEL), ("elevator", ELEVATOR), ("arm", ARM), ("roller", ROLLER), ("drum", drum),
             ("ramped", ramped), ("pushed", pushed))}


@pytest.fixture(scope="module")
def flywheel(logs):
    """The flywheel's tests fitted as the log chooses."""
    return fit_wpilog(str(logs["flywheel"]))


def within(value: float, truth: float, share: float) -> bool:
    """True when value is within share of truth."""
    return abs(value - truth) <= share * abs(truth)


def test_a_flywheel_is_a_simple_motor_with_its_gains(flywheel):
    truth = FLYWHEEL.gains
    assert flywheel.mechanism.mechanism == "simple" and flywheel.mechanism.given_by is None
    gains = arm_gains(flywheel)
    assert gains.feedforward == "SimpleMotorFeedforward"
    # A shooter wheel never gets a gravity gain or an angle offset.
    assert set(flywheel.params) == {"kS", "kV", "kA"} and gains.names == ("kS", "kV", "kA")
    assert within(gains["kS"].value, truth["kS"], 0.20)
    assert within(gains["kV"].per_rotation, truth["kV"], 0.03)
    assert within(gains["kA"].per_rotation, truth["kA"], 0.20)
    # The constructor is in the log's own unit, per rotation, in SimpleMotorFeedforward's order.
    assert gains.constructor_unit == "rotation"
    assert gains.constructor_value("kV") == pytest.approx(flywheel.params["kV"] * ROTATION, rel=1e-12)


def test_the_choice_says_why(flywheel):
    note = flywheel.mechanism.note()
    assert note.startswith("Mechanism: simple motor (SimpleMotorFeedforward), chosen from the log")
    bic = dict(flywheel.mechanism.bic)
    assert "arm" not in bic and bic["elevator"] > bic["simple"]
    assert "not supported" in note and "revolutions" in note
    # The wheel turned as often as its speed says: the ramps reach about 8 V / kV rotations per second.
    assert flywheel.mechanism.revolutions > 50


def test_an_arm_is_still_an_arm(logs):
    fit = fit_wpilog(str(logs["arm"]))
    assert fit.mechanism.mechanism == "arm"
    gains = arm_gains(fit)
    truth = ARM.gains
    assert gains.feedforward == "ArmFeedforward" and gains.constructor_unit == "radian"
    assert within(gains["kG"].value, truth["kG"], 0.05)
    assert within(gains["kV"].per_rotation, truth["kV"], 0.03)
    assert abs(gains["q0"].value - truth["offset"]) < 0.01


def assert_elevator(fit, per_unit) -> None:
    """The fit is an elevator's with the simulated gains: kG within 5 %, kV 5 %, kA 25 % (per_unit: a Gain's value
    in the log's own unit)."""
    assert fit.mechanism.mechanism == "elevator"
    gains = arm_gains(fit)
    truth = ELEVATOR.gains
    assert gains.feedforward == "ElevatorFeedforward" and gains.names == ("kS", "kG", "kV", "kA")
    assert within(gains["kG"].value, truth["kG"], 0.05)
    assert within(per_unit(gains["kV"]), truth["kV"], 0.05)
    assert within(per_unit(gains["kA"]), truth["kA"], 0.25)


def test_an_elevator_on_a_drum_in_rotations_is_an_elevator(logs):
    # The same elevator's numbers, per rotation of its drum.
    assert_elevator(fit_wpilog(str(logs["drum"])), lambda gain: gain.per_rotation)


def test_an_elevator_in_metres_is_an_elevator_per_metre(logs):
    fit = fit_wpilog(str(logs["elevator"]))
    assert_elevator(fit, lambda gain: gain.value)
    gains = arm_gains(fit)
    assert gains.linear and gains.constructor_unit == "meter"


def test_a_velocity_only_roller_is_a_simple_motor(logs):
    fit = fit_wpilog(str(logs["roller"]))
    assert fit.mechanism.mechanism == "simple"
    gains = arm_gains(fit)
    assert gains.feedforward == "SimpleMotorFeedforward"
    assert within(gains["kV"].per_rotation, ROLLER.gains["kV"], 0.03)


def test_a_voltage_step_is_data(logs):
    # The dynamic step reaches 7 V through a 0.25 s open-loop ramp and the logged voltage carries the bus's ripple:
    # its start, where kA's information is, is kept, and kA agrees with the fit that keeps everything.
    robust = fit_wpilog(str(logs["ramped"]), mechanism="simple")
    for run in robust.runs:
        if run.name.startswith("dynamic"):
            assert run.exclusions.excluded == (), run.name
    assert within(robust.params["kA"] * ROTATION, FLYWHEEL.gains["kA"], 0.20)


def test_an_outside_torque_is_still_found(logs):
    # A hand against the wheel for 0.3 s from 4 s into the forward ramp (1 V's worth): that stretch is left out.
    fit = fit_wpilog(str(logs["pushed"]), mechanism="simple")
    ramp = fit.runs[0]
    start = float(ramp.exclusions.since[0])
    assert any(a - start <= 4.05 and b - start >= 4.25 for a, b in ramp.exclusions.excluded), \
        ramp.exclusions.excluded
    assert all(run.exclusions.excluded == () for run in fit.runs[2:])


def test_mechanism_flag_fits_that_mechanism(logs):
    fit = fit_wpilog(str(logs["flywheel"]), mechanism="elevator", sensitivity=False)
    assert fit.mechanism.mechanism == "elevator" and fit.mechanism.given_by == "--mechanism"
    # The flywheel has no constant load: the elevator's kG is zero within a few errors.
    assert abs(fit.params["kG"]) < 4 * fit.bse["kG"]
    with pytest.raises(ValueError, match="mechanism"):
        fit_wpilog(str(logs["flywheel"]), mechanism="wheel")


def test_an_arm_needs_an_angle():
    from jointid.studies.mechanism import MechanismError, check_mechanism

    class Table:
        """A table read in metres, as a Meter log is."""

        units = (("q", "meters"), ("qd", "meters"))

    class Source:
        """Its source."""

        table = Table()

    class Log:
        """A log of it."""

        path, source = "lift.wpilog", Source()

    with pytest.raises(MechanismError) as raised:
        check_mechanism("arm", [Log()])
    message = str(raised.value)
    assert "\n" not in message and "meters" in message and "--mechanism arm" in message
    check_mechanism("elevator", [Log()])  # an elevator needs no angle


def test_mechanism_arm_on_a_meter_log_is_one_line(capsys, logs):
    refused(capsys, "fit", "--wpilog", logs["elevator"], "--mechanism", "arm")


def test_the_command_line_names_the_class(capsys, logs):
    status, out, err = run(capsys, "fit", "--wpilog", logs["flywheel"], "--gains", "wpilib", "--json")
    assert status == 0, err
    document = json.loads(out)
    assert document["gains"]["feedforward"] == "SimpleMotorFeedforward"
    assert document["mechanism"]["mechanism"] == "simple"
    assert set(document["gains"]["gains"]) == {"kS", "kV", "kA"}
    java = document["gains"]["constructors"]["java"]
    values = document["gains"]["constructor_values"]
    assert java == "new SimpleMotorFeedforward({:.6g}, {:.6g}, {:.6g});".format(
        values["kS"], values["kV"], values["kA"])
    status, out, err = run(capsys, "fit", "--wpilog", logs["flywheel"], "--gains", "wpilib")
    gains = out[out.index("WPILib SimpleMotorFeedforward gains"):]
    assert status == 0 and "ArmFeedforward" not in gains and "kG" not in gains and "q0" not in gains
    assert "Mechanism: simple motor" in out


def test_a_test_that_cannot_determine_a_gain_shows_none(capsys, logs):
    status, out, err = run(capsys, "fit", "--wpilog", logs["arm"], "--json")
    document = json.loads(out)
    dynamic = next(run for run in document["runs"] if run["name"] == "dynamic-reverse")
    # A dynamic test's voltage is constant: it says nothing of any gain on its own.
    assert all(value is None for value in dynamic["own_estimate"].values())
    assert set(dynamic["not_determined"]) == set(dynamic["own_estimate"])
    status, out, err = run(capsys, "fit", "--wpilog", logs["arm"])
    row = next(line for line in out.splitlines() if line.startswith("dynamic-reverse"))
    assert "0.000000" not in row and row.count("—") == 5


def test_the_simulated_flywheel_velocity_lags_like_a_spark_max(logs):
    from support.sysid_mechanisms import routine_samples

    test = routine_samples(FLYWHEEL)[2]  # dynamic-forward
    # A SPARK MAX's velocity (32 ms x 8 deep) trails the true speed by about 0.14 s during the spin-up.
    early = np.flatnonzero(test.t < 0.3)
    assert np.all(test.velocity[early[5:]] < test.truth_velocity[early[5:]])
    lag = np.interp(test.velocity[early[-1]], test.truth_velocity[early], test.t[early])
    assert 0.08 < test.t[early[-1]] - lag < 0.2


def _swerve_tests():
    """The swerve log's front-left drive motor, each test's first run on its own (read in metres, then labelled
    radians so that no precondition rules out an arm: the fit is linear in q either way, so the data must)."""
    import dataclasses

    from support.real_logs import REAL_LOGS

    from jointid.logs.conventions import EntryMap
    from jointid.logs.effort import EffortReading, read_effort
    from jointid.logs.pipeline import joint_log_from_table
    from jointid.logs.wpilog import read_wpilog_table

    names = "q=position-drive-frontleft-SwerveSubsystem,tau=voltage-drive-frontleft-SwerveSubsystem," \
            "state=sysid-test-state-SwerveSubsystem"
    table = read_wpilog_table(REAL_LOGS / "wpilog" / "swerve_drive_sysid.wpilog", EntryMap.parse(names, "entry"))
    logs = []
    for part in table.run_tables():
        t = part.columns["t"]
        gaps = np.flatnonzero(np.diff(t) > 1.0)  # quasistatic-forward was run twice: the first run, as SysId does
        if len(gaps):
            part = part.sliced(slice(0, int(gaps[0]) + 1), "its first run")
        part = dataclasses.replace(part, units=(("q", "radians"), ("qd", "radians")))
        part = read_effort(part, EffortReading("voltage"), False)
        logs.append(joint_log_from_table(part, degrees=False, window=None, order=3, cutoff=None))
    return logs


def test_a_real_drives_voltage_steps_are_kept():
    from support.real_logs import needs_real_logs

    from jointid.estimation.exclusion import ExclusionRequest
    from jointid.model.terms import model_named
    from jointid.studies.sysid import fit_sysid_runs

    if needs_real_logs.args[0]:  # the real logs are not beside the checkout
        pytest.skip(needs_real_logs.kwargs["reason"])
    logs = _swerve_tests()
    robust = fit_sysid_runs(logs, model_named("simple"), sensitivity=False)
    everything = fit_sysid_runs(logs, model_named("simple"), sensitivity=False, exclusion=ExclusionRequest(False))
    for run in robust.runs[-2:]:  # the dynamic tests: their opening 0.3 s (the spin-up, where kA lives) is kept
        pushed, since = run.exclusions.pushes, run.exclusions.since
        assert not pushed[since - since[0] < 0.3].any(), run.name
    # kA with the robust step agrees with kA keeping every sample, within their errors (it was -0.0007 against
    # 0.0145 when the robust step dropped each spin-up).
    gap = abs(robust.params["kA"] - everything.params["kA"])
    assert gap < 2 * math.hypot(robust.bse["kA"], everything.bse["kA"])
    assert robust.params["kA"] > 3 * robust.noise_bse["kA"]  # its noise; the window's choice widens it further


def test_a_real_drive_is_a_simple_motor():
    from support.real_logs import needs_real_logs

    from jointid.estimation.exclusion import ExclusionRequest
    from jointid.studies.sysid import fit_sysid

    if needs_real_logs.args[0]:  # the real logs are not beside the checkout
        pytest.skip(needs_real_logs.kwargs["reason"])
    logs = _swerve_tests()
    # Read as if in radians, it could be an arm; its data choose a simple motor, with the robust step or without.
    for robust in (True, False):
        fit = fit_sysid(logs, sensitivity=False, exclusion=ExclusionRequest(robust))
        assert fit.mechanism.mechanism == "simple", fit.mechanism.note()


def test_mechanism_and_model_together_are_one_line(capsys, logs):
    line = refused(capsys, "fit", "--wpilog", logs["flywheel"], "--mechanism", "arm", "--model", "plain")
    assert "--mechanism arm" in line and "--model plain" in line


def test_a_csv_voltage_log_takes_a_mechanism(capsys, tmp_path):
    # A CSV voltage log is fitted as an arm unless --mechanism says otherwise.
    path = tmp_path / "wheel.csv"
    t = np.arange(0, 6, 0.01)
    volts = 6 * np.sin(1.3 * t) + 3 * np.sin(4.1 * t)
    # A wheel with kS 0.1 V, kV 0.5 V s/rad, kA 0.05 V s²/rad, integrated by a fine explicit step.
    speed, angle, q, rows = 0.0, 0.0, [], []
    fine = 0.0001
    for k, now in enumerate(t):
        q.append(angle)
        for _ in range(100):
            v = 6 * np.sin(1.3 * (now + _ * fine)) + 3 * np.sin(4.1 * (now + _ * fine))
            speed += fine * (v - 0.1 * np.sign(speed) - 0.5 * speed) / 0.05
            angle += fine * speed
    rows = "\n".join(f"{a:.6f},{b:.9f},{c:.6f}" for a, b, c in zip(t, q, volts))
    path.write_text("t,q,tau\n" + rows + "\n")
    status, out, err = run(capsys, "fit", "--csv", path, "--effort", "voltage", "--mechanism", "simple", "--gains",
                           "wpilib", "--json")
    assert status == 0, err
    gains = json.loads(out)["gains"]
    assert gains["feedforward"] == "SimpleMotorFeedforward" and set(gains["gains"]) == {"kS", "kV", "kA"}
    assert within(gains["gains"]["kV"]["value"], 0.5, 0.03)


def test_an_elevators_motion_is_in_metres_per_second(logs):
    """A length's speed is m/s in a test's readouts (text and report), a flywheel's rad/s: the unit follows the log."""
    from jointid.present.report import log_blocks
    from jointid.present.summary import log_fit_summary

    for name, speed in (("elevator", "m/s"), ("flywheel", "rad/s")):
        run_fit = fit_wpilog(str(logs[name])).runs[0]
        text = log_fit_summary(run_fit)
        assert f"Speed RMS ({speed}) " in text and f"Acceleration RMS ({speed}²) " in text, text
        labels = {row[0] for block in log_blocks(run_fit) for row in getattr(block, "rows", ())}
        assert {f"Speed RMS ({speed})", f"Acceleration RMS ({speed}²)"} <= labels
