"""The lesson's numbers, reproduced to 6 decimals (the lesson is the specification)."""

import numpy as np
import pytest

from jointid.estimation.fit import fit_joint
from jointid.model.breakdown import torque_breakdown
from jointid.model.terms import TRUE_PARAMETERS
from jointid.present.readouts import readouts
from jointid.present.status import status_message
from jointid.present.text import format_number
from jointid.samples import JointData
from jointid.studies.experiment import run_experiment
from jointid.synthetic.samples import training_data
from jointid.synthetic.settings import Settings

# motion, noise -> (I, h, B, training RMSE, held-out RMSE), copied from the lesson's table.
LESSON_TABLE = {
    ("rich", 0.0): ("0.800000", "0.400000", "0.150000", "0.000000", "0.000000"),
    ("rich", 0.2): ("0.793312", "0.401350", "0.153888", "0.119280", "0.014150"),
    ("slow", 0.2): ("-1.607788", "0.400094", "0.109966", "0.118472", "2.261865"),
}


@pytest.mark.parametrize(("motion", "noise"), list(LESSON_TABLE))
def test_full_rank_cases_match_the_lesson_table(motion, noise):
    result = run_experiment(Settings(motion=motion, noise=noise))
    texts = {r.key: r.text for r in readouts(result)}
    expected = dict(zip(("I", "h", "B", "training_rmse", "heldout_rmse"), LESSON_TABLE[motion, noise]))
    assert texts["rank"] == "3 / 3"
    assert {key: texts[key] for key in expected} == expected


def test_holds_have_rank_one_and_no_unique_fit():
    result = run_experiment(Settings(motion="holds"))
    assert result.rank == 1
    assert result.estimate is None
    assert result.training_rmse is None and result.heldout_rmse is None
    texts = {r.key: r.text for r in readouts(result)}
    assert [texts[k] for k in ("I", "h", "B", "training_rmse", "heldout_rmse")] == ["unavailable"] * 5
    assert "no unique least-squares fit" in status_message(result)


@pytest.mark.parametrize(
    ("motion", "accel", "speed"),
    [("rich", "1.430761", "0.816288"), ("slow", "0.008781", None)],
)
def test_excitation_rms_matches_the_lesson(motion, accel, speed):
    result = run_experiment(Settings(motion=motion))
    assert format_number(result.accel_rms) == accel
    if speed is not None:
        assert format_number(result.speed_rms) == speed


def test_slow_noisy_fit_names_the_negative_inertia_unclipped():
    result = run_experiment(Settings(motion="slow", noise=0.2))
    assert result.sign_failures == ("I",)
    assert result.estimate[0] < 0
    assert "-1.607788" in status_message(result) and "I > 0" in status_message(result)
    assert next(r for r in readouts(result) if r.key == "I").sign_failure


def test_full_rank_message_warns_that_signs_do_not_prove_accuracy():
    result = run_experiment(Settings(motion="rich", noise=0.2))
    assert status_message(result).startswith("Rank 3 of 3: a unique least-squares fit.")
    assert "Held-out torque RMSE is 0.014150 N m." in status_message(result)
    assert "Positive parameter signs alone do not establish an accurate physical model." in status_message(result)


def test_three_hand_picked_instants_identify_the_joint_exactly():
    # Horizontal hold, vertical acceleration, vertical motion: the lesson's table.
    q = np.array([0.0, np.pi / 2, np.pi / 2])
    qd = np.array([0.0, 0.0, -3.0])
    qdd = np.array([0.0, 2.0, 0.0])
    tau = np.array([3.924, 1.600, -0.450])
    result = fit_joint(JointData(t=None, q=q, qd=qd, qdd=qdd, tau=tau))
    assert result.rank == 3
    np.testing.assert_allclose(result.estimate, [0.8, 0.4, 0.15], rtol=0, atol=1e-12)


def test_sixty_identical_holds_still_have_rank_one():
    hold = np.zeros(60)
    data = JointData(t=None, q=hold, qd=hold, qdd=hold, tau=np.full(60, 3.924))
    assert fit_joint(data).rank == 1


def test_holds_training_torque_is_the_holding_torque():
    data = training_data(Settings(motion="holds", samples=5))
    np.testing.assert_allclose(data.tau, 0.4 * 9.81)


def test_exercise_two_torque_and_damper_power():
    parts = torque_breakdown(np.radians(60), -2.0, 3.0, TRUE_PARAMETERS)
    assert format_number(parts.inertia) == "2.400000"
    assert format_number(parts.gravity) == "1.962000"
    assert format_number(parts.damping) == "-0.300000"
    assert format_number(parts.total) == "4.062000"
    assert format_number(parts.damper_power) == "0.600000"
