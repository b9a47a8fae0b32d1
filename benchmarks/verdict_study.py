"""Do the verdicts hold from run to run? Real runs judged against the others, synthetic joints against the truth
(not a timing).

1. The three shared pendulum runs (../shared/real-logs, --zero down): each run fitted alone as `jointid fit --csv`
   does, judged against the pooled fit of the other two; prints every parameter's value, 95 % interval, noise
   verdict, judged verdict and whether the interval holds the others' value, then the count of "well determined"
   values whose interval misses it (the goal: none), by the noise verdicts and by the judged ones.
2. The same three runs pooled: the pooled verdicts with the run-to-run scatter.
3. The candidate checks that might reveal ddp's h (5.7 % above the other two runs): its scatter over contiguous
   thirds and quarters, a block bootstrap over blocks of 4 and 8 Newey-West lags, and the model's terms as a choice
   (the bias dropped: coulomb alone, with its BIC against coulomb+bias on each run), each with what it gives on
   ddp's h and on the clean joints of part 4.
4. SEEDS synthetic Coulomb joints (the generator below: each seed its own motion, 12-bit angles, torque noise):
   how often the 95 % intervals hold the truth (goal 85-99 %), the standard errors against the estimates' own
   scatter over the seeds (about 1: not inflated), and how many "well determined" noise verdicts the other
   checks weakened on this clean data.

    PYTHONPATH=. .venv/bin/python benchmarks/verdict_study.py [SEEDS]
"""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path

import numpy as np

from jointid import fit_log
from jointid.logs.request import TRAINING, LoadRequest, load_joint_log
from jointid.logs.conventions import AngleConvention
from jointid.model.terms import model_named
from jointid.options import LOG_MODEL
from jointid.studies.runs import fit_runs

CHECKOUT = Path(__file__).resolve().parent.parent
LOGS = next((folder for folder in (CHECKOUT.parent / "shared" / "real-logs", CHECKOUT.parent.parent / "shared" /
             "real-logs") if folder.is_dir()), CHECKOUT.parent / "shared" / "real-logs")  # a worktree's is one up
RUNS = ("pd", "ddp", "energy_shaping")
WELL = "well determined"
G = 9.81
TRUTH = {"I": 0.8, "h": 0.4, "B": 0.15, "Fc": 0.2, "tau0": 0.0}


def coulomb_joint(seed: int) -> dict:
    """A joint with Coulomb friction 0.2 N m on a motion of two sines whose amplitudes and frequencies vary with
    the seed, 20 s at 500 Hz, 12-bit angles, torque noise 5 % of its RMS."""
    rng = np.random.default_rng(seed)
    t = np.arange(0, 20, 1 / 500)
    (a1, a2), (w1, w2) = rng.uniform([0.5, 0.15], [0.9, 0.35]), rng.uniform([1.0, 2.3], [1.6, 3.1])
    q = a1 * np.sin(w1 * t) + a2 * np.sin(w2 * t)
    qd = a1 * w1 * np.cos(w1 * t) + a2 * w2 * np.cos(w2 * t)
    qdd = -a1 * w1**2 * np.sin(w1 * t) - a2 * w2**2 * np.sin(w2 * t)
    tau = TRUTH["I"] * qdd + TRUTH["h"] * G * np.cos(q) + TRUTH["B"] * qd + TRUTH["Fc"] * np.sign(qd)
    tau = tau + 0.05 * np.sqrt(np.mean(tau**2)) * rng.standard_normal(len(t))
    step = 2 * np.pi / 4096
    return {"t": t, "q": np.round(q / step) * step, "tau": tau}


def real_runs() -> None:
    """Part 1 and 2: each shared run against the other two's pooled fit, then all three pooled."""
    fits = {run: fit_log(LOGS / f"pendulum_{run}.csv", zero="down") for run in RUNS}
    loaded = {run: load_joint_log(LoadRequest(str(LOGS / f"pendulum_{run}.csv"), TRAINING,
                                              angle=AngleConvention("down", False))) for run in RUNS}
    model = model_named(LOG_MODEL)
    misses = {"noise": 0, "judged": 0}
    for run in RUNS:
        others = fit_runs([loaded[other] for other in RUNS if other != run], model)
        result = fits[run].result
        interval = dict(zip(result.model.names, result.uncertainty.interval95))
        # The noise-only interval: the same Student t on the Newey-West error before the judgement widened it.
        half = (result.uncertainty.interval95[:, 1] - result.uncertainty.estimate) / result.uncertainty.residual_std_error
        noise_interval = {name: (value - h * error, value + h * error) for name, value, h, error in zip(
            result.model.names, result.uncertainty.estimate, half, result.uncertainty.noise_std_error)}
        print(f"{run} against the others pooled:")
        for name in others.shared:
            low, high = interval[name]
            reference = others.params[name]
            noise, judged = result.judgement.noise_verdicts, result.judgement.verdicts
            index = result.model.names.index(name)
            holds = low <= reference <= high
            noise_low, noise_high = noise_interval[name]
            misses["noise"] += (not noise_low <= reference <= noise_high) and noise[index] == WELL
            misses["judged"] += (not holds) and judged[index] == WELL
            print(f"  {name:5s} {result.params[name]:10.6f} [{low:.6f}, {high:.6f}] others {reference:10.6f} "
                  f"{'holds' if holds else 'MISSES'}; noise: {noise[index]}; judged: {judged[index]}"
                  + (f" ({result.judgement.reasons[index]})" if result.judgement.reasons[index] else ""))
    print(f"'well determined' values whose 95 % interval misses the others' pooled value: {misses['noise']} by the "
          f"noise verdicts and intervals, {misses['judged']} by the judged (widened) ones")
    pooled = fit_runs([loaded[run] for run in RUNS], model)
    print("three runs pooled: " + ", ".join(
        f"{name} {pooled.params[name]:.6f} ± {pooled.bse[name]:.6f} {pooled.verdicts[name]}"
        + (f" ({pooled.judgement.reason_of(name)})" if pooled.judgement.reason_of(name) else "")
        for name in pooled.shared))


def candidates(seeds: int) -> None:
    """Part 3: what each candidate check gives on ddp's h, and dropping the bias on the clean joints."""
    from jointid.estimation.solver import solve_least_squares
    from jointid.estimation.student_t import student_t_quantile
    from jointid.studies.refits import _fit_rows, beyond_noise, scatter_ratios

    logs = fit_log(LOGS / "pendulum_ddp.csv", zero="down")
    result = logs.result
    index = result.model.names.index("h")
    positions, lag = result.correlation
    X, tau = result.training_regressor, result.training.tau
    print(f"ddp's h {logs.params['h']:.6f}: noise error {logs.noise_bse['h']:.6f}, reported {logs.bse['h']:.6f}; "
          f"{len(tau)} fitted samples over {positions[-1] - positions[0]} grid steps, Newey-West lag {lag}")
    for pieces in (3, 4):
        edges = np.linspace(positions[0], positions[-1] + 1, pieces + 1)
        fits = [_fit_rows(X[inside], tau[inside], positions[inside] - positions[inside][0], lag, result.model)
                for inside in ((positions >= a) & (positions < b) for a, b in zip(edges[:-1], edges[1:]))]
        values, errors = np.array([f[0] for f in fits]), np.array([f[1] for f in fits])
        ratio, significant = scatter_ratios(values, errors)
        print(f"  {pieces} contiguous stretches: h {np.round(values[:, index], 4).tolist()} ± "
              f"{np.round(errors[:, index], 4).tolist()}, Birge ratio {ratio[index]:.2f} "
              f"({'significant' if significant[index] else 'not significant'} at 1 %; each stretch "
              f"{(edges[1] - edges[0]) / lag:.1f} lags long)")
    rng = np.random.default_rng(0)
    for multiple in (4, 8):
        length = multiple * lag
        blocks = [np.flatnonzero((positions >= start) & (positions < start + length))
                  for start in np.arange(positions[0], positions[-1] + 1, length)]
        solved = [solve_least_squares(X[rows], tau[rows]).estimate for rows in
                  (np.concatenate([blocks[k] for k in rng.integers(0, len(blocks), len(blocks))]) for _ in range(400))]
        draws = [result.model.report(estimate)[index] for estimate in solved if estimate is not None]
        print(f"  block bootstrap, blocks of {multiple} lags: {len(blocks)} blocks, standard deviation of h "
              f"{np.std(draws, ddof=1):.6f} ({len(draws)} of 400 resamples with a unique fit)")

    def without_bias(logs, data, **options):
        """(names, the bias-dropped model's move beyond noise per parameter) of a coulomb+bias fit."""
        other = fit_log(data, model="coulomb", **options)
        names = logs.result.model.names
        found = beyond_noise(names, logs.result.estimate, np.array([logs.noise_bse[n] for n in names]),
                             [[other.params.get(n, logs.params[n]) for n in names]], "the bias dropped",
                             [[other.noise_bse.get(n, logs.noise_bse[n]) for n in names]])
        return other, {spread.name: spread.error for spread in found}

    def bic(fitted) -> float:
        """BIC on a log fit's kept rows, counting the independent samples the low-pass leaves (as the ladder)."""
        count, low_pass = fitted.result.training.count, fitted.filter
        independent = count * min(1.0, 2 * low_pass.cutoff * low_pass.decimation / low_pass.rate) \
            if low_pass is not None and low_pass.active else count
        return independent * np.log(fitted.result.training_rmse ** 2) + fitted.result.model.size * np.log(independent)

    other, spreads = without_bias(logs, LOGS / "pendulum_ddp.csv", zero="down")
    for run in RUNS:
        both = logs if run == "ddp" else fit_log(LOGS / f"pendulum_{run}.csv", zero="down")
        alone = other if run == "ddp" else fit_log(LOGS / f"pendulum_{run}.csv", zero="down", model="coulomb")
        print(f"  {run}: coulomb alone against coulomb+bias, BIC {bic(alone) - bic(both):+.1f} (each on its own "
              f"fit's rows: {alone.result.training.count} and {both.result.training.count})")
    widened = float(np.hypot(logs.bse["h"], spreads.get("h", 0.0)))
    half = student_t_quantile(0.975, result.uncertainty.interval_degrees_of_freedom) * widened
    print(f"  the bias dropped (coulomb alone): h {other.params['h']:.6f}, beyond noise {spreads.get('h', 0.0):.6f}, "
          f"widened error {widened:.6f}, interval [{logs.params['h'] - half:.6f}, {logs.params['h'] + half:.6f}]")
    covered = {"now": 0, "with it": 0}
    count = total = 0
    for seed in range(1, seeds + 1):
        clean = fit_log(coulomb_joint(seed))
        _, spreads = without_bias(clean, coulomb_joint(seed))
        quantile = student_t_quantile(0.975, clean.result.uncertainty.interval_degrees_of_freedom)
        for name, value in clean.params.items():
            covered["now"] += abs(value - TRUTH[name]) <= quantile * clean.bse[name]
            covered["with it"] += abs(value - TRUTH[name]) <= quantile * np.hypot(clean.bse[name],
                                                                                  spreads.get(name, 0.0))
            total += 1
        count += len(spreads)
    print(f"  the bias dropped on {seeds} clean joints: coverage {covered['now']} -> {covered['with it']} of {total}, "
          f"{count} parameters widened")


def synthetic(seeds: int) -> None:
    """Part 4: coverage of the truth, the errors against the seeds' scatter, clean data's weakened verdicts."""
    covered = total = weakened = well = 0
    why = Counter()
    estimates, errors, widening = [], [], []
    for seed in range(1, seeds + 1):
        result = fit_log(coulomb_joint(seed)).result
        names = result.model.names
        for index, name in enumerate(names):
            low, high = result.uncertainty.interval95[index]
            covered += low <= TRUTH[name] <= high
            total += 1
            noise, judged = result.judgement.noise_verdicts[index], result.judgement.verdicts[index]
            well += noise == WELL
            weakened += noise == WELL and judged != WELL
            if noise == WELL and judged != WELL:
                for reason in result.judgement.reasons[index].split(", "):
                    kind = reason.split(" by ")[-1] if "standard errors by" in reason else reason.split(" scatter")[0]
                    why[kind] += 1
        estimates.append(result.estimate), errors.append(result.uncertainty.residual_std_error)
        widening.append(result.uncertainty.residual_std_error / result.uncertainty.noise_std_error)
    scatter = np.std(estimates, axis=0, ddof=1)
    inflation = np.mean(errors, axis=0) / scatter
    print(f"{seeds} synthetic Coulomb joints: 95 % intervals hold the truth {covered} of {total} times "
          f"({100 * covered / total:.0f} %); mean standard error / the estimates' scatter over the seeds: "
          + ", ".join(f"{name} {value:.2f}" for name, value in zip(names, inflation))
          + f"; errors widened (reported / noise): median {np.median(widening):.2f}, widened at all "
          + f"{int(np.sum(np.array(widening) > 1))} of {np.size(widening)}"
          + f"; 'well determined' noise verdicts weakened by the other checks: {weakened} of {well} ("
          + ", ".join(f"{reason}: {count}" for reason, count in why.items()) + ")")


if __name__ == "__main__":
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 20
    if LOGS.is_dir():
        real_runs()
        candidates(count)
    synthetic(count)
