"""The excitation designer: the Fourier-series motion that, within the joint's limits, reveals the parameters best.

The variables are a FourierMotion's coefficients x = [q_c, a_1..a_K, b_1..b_K].
q, qd and qdd are linear in x, so the kinematic limits |q| <= q_max,
|qd| <= qd_max, |qdd| <= qdd_max on a dense time grid over one period are
linear constraints; an optional actuator-torque limit |tau| <= tau_max of the
true joint is a nonlinear one. scipy.optimize's SLSQP (imported lazily)
optimises one criterion of the training regressor X at the experiment's
sample times (t_i = 8 i/(N-1)) from several random starts, deterministic for a
seed, and keeps the best. Criteria, with C = (X^T X)^-1 the covariance per unit
noise variance of the reported parameters and S = diag(reference values):

- ``d`` (D-optimal): maximise log det(S C S)^-1, the information matrix in
  relative units. The scaling is fixed (the true joint's parameter values, 1
  for a parameter whose true value is 0), so the optimum is the classical
  D-optimal one. Scaling by the design's own column norms instead would make
  log det measure only how orthogonal the columns are (Hadamard's inequality),
  the same mistake as ``cond``.
- ``a`` (A-optimal): minimise trace(S^-1 C S^-1), the sum of relative variances.
- ``cond``: minimise the condition number of the column-scaled regressor. It
  is here as the counter-example: a small, well-balanced motion has
  orthogonal columns (condition number near 1) and little information.

After the optimisation the limits are checked on a 4000-point grid; if a peak
between the dense grid's points overshoots, the harmonics are shrunk until
every limit holds there (the mean angle stays), so the design never breaks a
limit it reports as kept. `progress(done, total)` runs after each start and
`cancelled()` is polled inside the optimiser, so an app can run a design in a
worker thread and stop it promptly.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from ..estimation.solver import solve_least_squares
from ..estimation.uncertainty import parameter_uncertainty
from ..model.terms import COULOMB, NONNEGATIVE, G, JointModel, Term
from ..options import (
    CRITERIA,
    DEFAULT_CRITERION,
    DEFAULT_HARMONICS,
    DEFAULT_NOISE,
    DEFAULT_PERIOD,
    DEFAULT_SEED,
    DEFAULT_STARTS,
    HARMONIC_LIMITS,
    LIMIT_RANGES,
    PERIOD_LIMITS,
    RICH_ENVELOPE,
    STARTS_LIMITS,
)
from ..synthetic.fourier import FourierMotion, fourier_basis, from_coefficients
from ..synthetic.samples import training_data
from ..synthetic.settings import Settings

DESIGN_GRID = 400
"""Time points per period on which the optimiser enforces the limits."""
CHECK_GRID = 4000
"""Time points per period on which the finished design's limits are verified."""
ACTIVE_SHARE = 0.005
"""A limit whose peak is within this share of it counts as active."""


class DesignError(ValueError):
    """Limits or options no design can satisfy; the message is one line for a user."""


class DesignCancelled(Exception):
    """Raised inside `design_motion` when its `cancelled()` check returns True."""


@dataclass(frozen=True)
class Limits:
    """The joint's limits: angle (rad), speed (rad/s), acceleration (rad/s²) and, optionally, torque (N m)."""

    q_max: float = RICH_ENVELOPE["q_max"]
    qd_max: float = RICH_ENVELOPE["qd_max"]
    qdd_max: float = RICH_ENVELOPE["qdd_max"]
    tau_max: float | None = None

    def items(self) -> list[tuple[str, float]]:
        """(name, value) of each limit that is set, in the order q, qd, qdd, tau."""
        return [(name, getattr(self, name)) for name in LIMIT_RANGES if getattr(self, name) is not None]




@dataclass(frozen=True)
class DesignSpec:
    """What to design: limits, criterion, harmonics, period, and the experiment the motion is for."""

    limits: Limits = Limits()
    criterion: str = DEFAULT_CRITERION
    harmonics: int = DEFAULT_HARMONICS
    period: float = DEFAULT_PERIOD
    starts: int = DEFAULT_STARTS
    seed: int = DEFAULT_SEED
    """Seed of the random starts (not of the torque noise)."""
    experiment: Settings = field(default_factory=lambda: Settings(noise=DEFAULT_NOISE))
    """Samples, noise bound, fitted model and true joint the design is for (its motion and seed are unused)."""

    def __post_init__(self):
        check_spec(self)


def check_spec(spec: DesignSpec) -> None:
    """Raise DesignError (one line) for limits or options no design can satisfy."""
    for name, value in spec.limits.items():
        high, unit = LIMIT_RANGES[name]
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
                or not 0 < value <= high:
            raise DesignError(f"{name.replace('_', '-')} must be a number greater than 0 and at most {high:g} "
                              f"{unit}; got {value!r}")
    if spec.criterion not in CRITERIA:
        raise DesignError(f"unknown criterion {spec.criterion!r}: use one of {', '.join(CRITERIA)}")
    low, high = HARMONIC_LIMITS
    if not isinstance(spec.harmonics, int) or not low <= spec.harmonics <= high:
        raise DesignError(f"harmonics must be a whole number from {low} to {high}; got {spec.harmonics!r}")
    low, high = PERIOD_LIMITS
    if isinstance(spec.period, bool) or not isinstance(spec.period, (int, float)) or not low <= spec.period <= high:
        raise DesignError(f"period must be a number from {low:g} to {high:g} s; got {spec.period!r}")
    low, high = STARTS_LIMITS
    if not isinstance(spec.starts, int) or not low <= spec.starts <= high:
        raise DesignError(f"starts must be a whole number from {low} to {high}; got {spec.starts!r}")
    model, samples = spec.experiment.joint_model, spec.experiment.samples
    if samples < 64:  # too few distinct states and no motion can help, yet the optimiser would blame the limits
        from ..synthetic.motions import sample_times

        def phases(count: int) -> int:
            # A periodic motion repeats its states: samples a whole number of periods apart are one state.
            return len(np.unique(np.round(np.mod(sample_times(count) / spec.period, 1.0) * 1e9) % 1e9))

        if phases(samples) < model.size:
            enough = next(count for count in range(samples + 1, 4 * model.size + 8) if phases(count) >= model.size)
            raise DesignError(f"samples: the {model.name} model's {model.size} parameters need samples at "
                              f"{model.size} different phases of the motion; {samples} samples over 0..8 s give "
                              f"{phases(samples)} (use --samples {enough} or more)")
    tau_max = spec.limits.tau_max
    if tau_max is not None:
        # Over a period qd and qdd average to zero, so the torque averages h*g*mean(cos q): at least
        # h*g*cos(q_max) while |q| <= q_max < pi/2. A torque limit below that admits no motion at all.
        joint = spec.experiment.true_joint
        holding = joint.mass_moment * G * math.cos(min(spec.limits.q_max, math.pi / 2))
        if tau_max <= holding:
            raise DesignError(f"tau-max {tau_max:g} N m is inconsistent with q-max {spec.limits.q_max:g} rad: "
                              f"holding the joint anywhere within |q| <= q-max takes at least {holding:.3f} N m")


@dataclass(frozen=True, eq=False)
class LimitCheck:
    """One limit against the design's peak on the verification grid."""

    name: str
    """'q_max', 'qd_max', 'qdd_max' or 'tau_max'."""
    limit: float
    peak: float
    """max |quantity| over CHECK_GRID points of one period."""

    @property
    def margin(self) -> float:
        """limit - peak (>= 0 when the limit holds)."""
        return self.limit - self.peak

    @property
    def holds(self) -> bool:
        """True when the peak does not exceed the limit."""
        return self.peak <= self.limit

    @property
    def active(self) -> bool:
        """True when the peak reaches the limit (within ACTIVE_SHARE of it): the limit shapes the design."""
        return self.margin <= ACTIVE_SHARE * self.limit


@dataclass(frozen=True, eq=False)
class MotionPrecision:
    """How well one training motion determines the parameters at given samples, noise and model."""

    noise_bound_std_error: np.ndarray | None
    """(p,) Standard errors sqrt(b²/3 diag((X^T X)^-1)) of the reported parameters, or None when rank-deficient."""
    relative_std_pct: np.ndarray | None
    """(p,) Those as % of |noise-free estimate| (NaN for a parameter the true joint lacks), or None."""
    condition_number: float
    """Condition number of the column-scaled regressor (inf when rank-deficient)."""


def motion_precision(settings: Settings) -> MotionPrecision:
    """Expected standard errors and condition number of `settings`' motion, from its noise-free fit."""
    truth = training_data(replace(settings, noise=0.0))
    model = settings.joint_model
    solution = solve_least_squares(model.data_regressor(truth), truth.tau)
    uncertainty = parameter_uncertainty(solution, settings.noise, model)
    if uncertainty is None:
        return MotionPrecision(None, None, solution.condition_number)
    errors, magnitude = uncertainty.noise_bound_std_error, np.abs(uncertainty.estimate)
    # A parameter the joint does not have (Coulomb friction of 0) fits to rounding noise: no relative error.
    present = magnitude > ZERO_SHARE * max(1.0, float(np.max(magnitude)))
    with np.errstate(divide="ignore", invalid="ignore"):
        relative = np.where(present, 100.0 * errors / magnitude, np.nan)
    return MotionPrecision(errors, relative, solution.condition_number)


ZERO_SHARE = 1e-9
"""A noise-free estimate below this share of the largest one is a parameter the true joint does not have."""


@dataclass(frozen=True, eq=False)
class DesignResult:
    """A designed motion, its precision beside rich motion's, and its limits checked on CHECK_GRID points."""

    spec: DesignSpec
    motion: FourierMotion
    design: MotionPrecision
    rich: MotionPrecision
    """Rich motion at the same samples, noise and model."""
    checks: tuple[LimitCheck, ...]
    criterion_value: float
    """The criterion at the design (see `criterion_function`; smaller is better)."""
    converged: int
    """How many starts ended in a design that met the limits."""

    @property
    def model(self):
        """The fitted model the design is for."""
        return self.spec.experiment.joint_model

    @property
    def settings(self) -> Settings:
        """The experiment on the designed motion."""
        return replace(self.spec.experiment, motion=self.motion)

    @cached_property
    def worse_than_rich(self) -> tuple[str, ...]:
        """Parameters whose expected standard error is larger under the design than under rich motion."""
        if self.design.noise_bound_std_error is None or self.rich.noise_bound_std_error is None:
            return ()
        return tuple(name for name, mine, theirs in
                     zip(self.model.names, self.design.noise_bound_std_error, self.rich.noise_bound_std_error)
                     if mine > theirs)


@dataclass
class _Problem:
    """The numbers one design's objective and constraints need, computed once."""

    spec: DesignSpec

    def __post_init__(self):
        spec, settings = self.spec, self.spec.experiment
        self.model = settings.joint_model
        self.smooth_model = smoothed(self.model)
        self.joint = settings.true_joint
        from ..synthetic.motions import sample_times

        self.sample_basis = fourier_basis(sample_times(settings.samples), spec.period, spec.harmonics)
        grid = np.arange(DESIGN_GRID) * (spec.period / DESIGN_GRID)
        self.grid_basis = fourier_basis(grid, spec.period, spec.harmonics)
        truth = self.joint.values_for(self.model)
        self.reference = np.where(truth != 0, np.abs(truth), 1.0)
        columns = truth.copy()
        if self.model.angle_offset is not None:  # the columns behind h and q0 are h_c = h cos q0, h_s = -h sin q0
            offset = self.model.angle_offset
            h, q0 = truth[offset.cosine], truth[offset.sine]
            columns[offset.cosine], columns[offset.sine] = h * math.cos(q0), -h * math.sin(q0)
        self.jacobian = self.model.report_jacobian(columns)
        # log det(S^-1 J C J^T S^-1) = log det C + log det(J)^2 - log det(S)^2: the constant part, once
        jacobian_term = 0.0 if self.jacobian is None else 2 * math.log(abs(np.linalg.det(self.jacobian)))
        self.log_det_offset = jacobian_term - 2 * float(np.sum(np.log(self.reference)))

    def regressors(self, xs: np.ndarray) -> np.ndarray:
        """(m, N, p) Training regressors of m coefficient vectors xs (m, 2K+1), at the logged angle."""
        q, qd, qdd = (xs @ basis.T for basis in self.sample_basis)  # each (m, N)
        rows = self.smooth_model.regressor(self.joint.logged_angle(q), qd, qdd)  # one call for all m: (m*N, p)
        return rows.reshape(len(xs), -1, self.model.size)

    def criteria(self, xs: np.ndarray) -> np.ndarray:
        """(m,) The criterion at each of m coefficient vectors, smaller is better (PENALTY where X is singular)."""
        matrices = self.regressors(xs)
        with np.errstate(all="ignore"):
            if self.spec.criterion == "cond":
                norms = np.linalg.norm(matrices, axis=1, keepdims=True)
                singular = np.linalg.svd(matrices / norms, compute_uv=False)
                values = np.log(singular[:, 0] / singular[:, -1])
            else:
                information = np.einsum("mni,mnj->mij", matrices, matrices)
                sign, logdet = np.linalg.slogdet(information)
                if self.spec.criterion == "d":
                    values = np.where(sign > 0, self.log_det_offset - logdet, np.nan)
                else:
                    try:
                        covariance = np.linalg.inv(information)
                    except np.linalg.LinAlgError:
                        covariance = np.full_like(information, np.nan)
                    if self.jacobian is not None:
                        covariance = self.jacobian @ covariance @ self.jacobian.T
                    relative = np.einsum("mii->mi", covariance) / self.reference**2
                    values = np.where(sign > 0, np.log(relative.sum(axis=1)), np.nan)
        return np.where(np.isfinite(values), values, PENALTY)

    def criterion(self, x: np.ndarray) -> float:
        """The criterion at coefficients x (2K+1,)."""
        return float(self.criteria(x[None, :])[0])

    def criterion_gradient(self, x: np.ndarray) -> np.ndarray:
        """(2K+1,) Forward-difference gradient of the criterion, every step evaluated in one batch."""
        steps = FD_STEP * np.maximum(1.0, np.abs(x))
        points = np.vstack([x, x + np.diag(steps)])
        values = self.criteria(points)
        return (values[1:] - values[0]) / steps

    def grid_values(self, x: np.ndarray) -> dict[str, np.ndarray]:
        """Each limited quantity (q, qd, qdd and the actuator torque if limited) on the design grid."""
        q, qd, qdd = (basis @ x for basis in self.grid_basis)
        values = {"q_max": q, "qd_max": qd, "qdd_max": qdd}
        if self.spec.limits.tau_max is not None:
            values["tau_max"] = self.joint.actuator_torque(q, qd, qdd)
        return values

    def worst_violation(self, x: np.ndarray) -> float:
        """max over the design grid of |quantity| / limit - 1 (<= 0 when every limit holds)."""
        return max(float(np.max(np.abs(v))) / limit - 1 for (_, limit), v in
                   zip(self.spec.limits.items(), self.grid_values(x).values()))

    def peaks(self, x: np.ndarray, stride: int | None = None) -> dict[str, set[tuple[int, float]]]:
        """(grid index, sign) of each local maximum of |quantity| on the design grid and its neighbours, per limit;
        with `stride`, every stride-th point with both signs too."""
        found = {}
        for name, values in self.grid_values(x).items():
            magnitude = np.abs(values)
            local = np.flatnonzero((magnitude >= np.roll(magnitude, 1)) & (magnitude >= np.roll(magnitude, -1)))
            index = np.unique(np.concatenate([local - 1, local, local + 1]) % len(values))
            points = {(int(i), float(np.sign(values[i]) or 1.0)) for i in index}
            if stride is not None:
                points |= {(int(i), sign) for i in range(0, len(values), stride) for sign in (1.0, -1.0)}
            found[name] = points
        return found

    def constraints(self, working: dict[str, set[tuple[int, float]]]) -> list[dict]:
        """SLSQP's inequality constraints (each >= 0) at the working set's grid points and signs."""
        limits = dict(self.spec.limits.items())
        rows, bounds = [], []
        for i, name in enumerate(("q_max", "qd_max", "qdd_max")):
            points = sorted(working.get(name, ()))
            if points:
                index = np.array([i for i, _ in points], dtype=int)
                signs = np.array([sign for _, sign in points])
                rows.append(signs[:, None] * self.grid_basis[i][index])
                bounds.append(np.full(len(index), limits[name]))
        matrix, bound = np.vstack(rows), np.concatenate(bounds)
        constraints = [{"type": "ineq", "fun": lambda x: bound - matrix @ x, "jac": lambda x: -matrix}]
        torque_points = sorted(working.get("tau_max", ()))
        if torque_points:
            index = np.array([i for i, _ in torque_points], dtype=int)
            signs = np.array([sign for _, sign in torque_points])
            tau_max, basis = limits["tau_max"], self.grid_basis[:, index]
            joint = self.joint

            def torque_margin(x):
                q, qd, qdd = (b @ x for b in basis)
                return tau_max - signs * joint.actuator_torque(q, qd, qdd)

            def torque_jacobian(x):
                q = basis[0] @ x
                slope = (joint.inertia * basis[2] + joint.damping * basis[1]
                         - (joint.mass_moment * G * np.sin(q))[:, None] * basis[0])
                return -signs[:, None] * slope  # Coulomb's sign(qd) has derivative 0 almost everywhere

            constraints.append({"type": "ineq", "fun": torque_margin, "jac": torque_jacobian})
        return constraints

    def start(self, rng: np.random.Generator) -> np.ndarray:
        """A random feasible starting point: random harmonics scaled to 80 % of the kinematic limits."""
        k = self.spec.harmonics
        limits = self.spec.limits
        x = np.concatenate([[rng.uniform(-0.3, 0.3) * limits.q_max], rng.uniform(-1.0, 1.0, 2 * k)])
        oscillation = x.copy()
        oscillation[0] = 0.0
        peaks = [np.max(np.abs(basis @ oscillation)) for basis in self.grid_basis]
        room = [limits.q_max - abs(x[0]), limits.qd_max, limits.qdd_max]
        scale = 0.8 * min(r / p for r, p in zip(room, peaks) if p > 0)
        oscillation *= scale
        oscillation[0] = x[0]
        return oscillation


SMOOTH_SPEED = 0.02
"""qd (rad/s) over which the optimiser's Coulomb column tanh(qd/SMOOTH_SPEED) turns from -1 to 1."""
SMOOTH_COULOMB = Term("Fc", "Coulomb friction", "N m", NONNEGATIVE, "no velocity",
                      lambda q, qd, qdd: np.tanh(qd / SMOOTH_SPEED))
"""sign(qd) made smooth: with the step itself a sample crossing qd = 0 would make the criterion jump and its
finite-difference gradient meaningless. Only the optimiser uses it; every figure reported uses sign(qd)."""


def smoothed(model: JointModel) -> JointModel:
    """The model with its Coulomb column made smooth for the optimiser (itself when it has none)."""
    terms = tuple(SMOOTH_COULOMB if term is COULOMB else term for term in model.terms)
    return model if terms == model.terms else replace(model, terms=terms)


FD_STEP = 1.4901161193847656e-08
"""Relative forward-difference step of the criterion's gradient (sqrt of machine epsilon)."""
FEASIBLE = 1e-9
"""Largest relative overshoot of a limit on the design grid that counts as meeting it (rounding)."""
STRIDE = 20
"""Every STRIDE-th design grid point is in the optimiser's first working set, with the start's peaks."""
EXCHANGE_ROUNDS = 30
"""Most rounds of adding violated grid points to the optimiser's working set per start."""


PENALTY = 1e6
"""Criterion value of a rank-deficient regressor: worse than any design that determines the parameters."""


def check_limits(motion: FourierMotion, spec: DesignSpec) -> tuple[LimitCheck, ...]:
    """Each set limit against the motion's peak on CHECK_GRID points of one period."""
    grid = np.arange(CHECK_GRID) * (motion.period / CHECK_GRID)
    states = motion.states(grid)
    peaks = {"q_max": states.q, "qd_max": states.qd, "qdd_max": states.qdd}
    if spec.limits.tau_max is not None:
        peaks["tau_max"] = spec.experiment.true_joint.actuator_torque(states.q, states.qd, states.qdd)
    return tuple(LimitCheck(name, float(limit), float(np.max(np.abs(peaks[name])))) for name, limit in
                 spec.limits.items())


def shrink_to_limits(motion: FourierMotion, spec: DesignSpec) -> FourierMotion:
    """The motion with its harmonics scaled down until every limit holds on the check grid (itself if they do).

    Scaling the harmonics by s <= 1 scales qd and qdd by s and keeps q between
    q_c and its old values, so the kinematic limits hold after one step; the
    torque limit may need a few.
    """
    for _ in range(60):
        checks = check_limits(motion, spec)
        if all(check.holds for check in checks):
            return motion
        scale = min(1.0, *(check.limit / check.peak for check in checks if check.peak > 0)) * (1 - 1e-12)
        scale = min(scale, 1 - 1e-3) if scale >= 1 - 1e-12 else scale
        motion = replace(motion, a=tuple(v * scale for v in motion.a), b=tuple(v * scale for v in motion.b))
    raise DesignError("could not bring the design within the torque limit; raise --tau-max")


DESIGN_BUDGET_SECONDS = 30.0
"""Estimated seconds of work a `jointid design` runs without being told to do less (see `design_seconds`)."""
SECONDS_PER_UNIT = 3e-7
"""Seconds per unit of starts x parameters x harmonics² x (samples + FIXED_SAMPLES), measured here (2 cores):
each start's SLSQP takes iterations and gradient points that grow with the harmonics, each criterion a regressor
of samples x parameters. Per start: 3 harmonics, 240,000 samples, plain 1.98 s (est. 1.95); 3 harmonics, 24,000
samples, coulomb+bias 0.36 s (est. 0.36); 10 harmonics, 24 samples 0.22 s (est. 0.22; 1000 starts took 258 s);
20 harmonics, 24 samples 0.86 s (est. 0.87). Small designs are overestimated (6 harmonics: 0.03 s, est. 0.08).
At the budget's edge (est. 30 s): 8 starts x 3 harmonics x 460,562 samples ran 21 s, 137 starts x 10 harmonics 35 s."""
FIXED_SAMPLES = 2400
"""The optimiser's own work per start, outside the regressor, as the samples that would cost as much."""


def design_seconds(spec: DesignSpec) -> float:
    """Estimated seconds `design_motion(spec)` takes on this machine (SECONDS_PER_UNIT's figures)."""
    return _seconds(spec.starts, spec.harmonics, spec.experiment.samples, spec.experiment.joint_model.size)


def _seconds(starts: int, harmonics: int, samples: int, parameters: int) -> float:
    return SECONDS_PER_UNIT * starts * parameters * harmonics**2 * (samples + FIXED_SAMPLES)


def budget_overrun(spec: DesignSpec, budget: float | None = None) -> str | None:
    """None when the design's estimated time is within `budget` seconds (DESIGN_BUDGET_SECONDS by default);
    otherwise how much work it is and the budget, as a clause both faces end with their own advice."""
    budget = DESIGN_BUDGET_SECONDS if budget is None else budget
    seconds = design_seconds(spec)
    if seconds <= budget:
        return None
    parameters = spec.experiment.joint_model.size
    return (f"a design of {spec.starts:,} starts x {spec.harmonics} harmonics x {spec.experiment.samples:,} samples "
            f"for the {parameters}-parameter {spec.experiment.joint_model.name} model is about {_duration(seconds)} "
            f"of work here, over the {budget:g} s budget")


def over_budget(spec: DesignSpec, budget: float | None = None) -> str | None:
    """None when the design's estimated time is within `budget` seconds (DESIGN_BUDGET_SECONDS by default);
    otherwise one line saying how long, and which of --samples, --harmonics and --starts to lower to what."""
    budget = DESIGN_BUDGET_SECONDS if budget is None else budget
    overrun = budget_overrun(spec, budget)
    if overrun is None:
        return None
    starts, harmonics = spec.starts, spec.harmonics
    samples, parameters = spec.experiment.samples, spec.experiment.joint_model.size
    unit = SECONDS_PER_UNIT * parameters
    # The largest value of each flag that fits the budget with the others as given (absent when none does).
    fits = {
        "--samples": math.floor(budget / (unit * starts * harmonics**2)) - FIXED_SAMPLES,
        "--harmonics": math.floor(math.sqrt(budget / (unit * starts * (samples + FIXED_SAMPLES)))),
        "--starts": math.floor(budget / (unit * harmonics**2 * (samples + FIXED_SAMPLES))),
    }
    lowest = {"--samples": 64, "--harmonics": HARMONIC_LIMITS[0], "--starts": STARTS_LIMITS[0]}
    ways = [f"{flag} {value}" for flag, value in fits.items() if value >= lowest[flag]]
    if ways:
        how = f"{', '.join(ways[:-1])} or {ways[-1]}" if len(ways) > 1 else ways[0]
        advice = f"lower --samples, --harmonics or --starts ({how} would fit with the rest as given)"
    else:
        advice = "lower --samples, --harmonics and --starts together"
    return f"{overrun}; {advice}"


def _duration(seconds: float) -> str:
    """'45 s', '4 minutes', '3.2 hours'."""
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} minutes"
    return f"{seconds / 3600:.1f} hours"


def design_motion(
    spec: DesignSpec = DesignSpec(),
    *,
    progress: Callable[[int, int], None] | None = None,
    cancelled: Callable[[], bool] | None = None,
) -> DesignResult:
    """Design the motion that best meets `spec`'s criterion within its limits; DesignError if none does."""
    from scipy.optimize import minimize  # lazily: scipy.optimize costs about 0.3 s to import
    from threadpoolctl import threadpool_limits

    # SLSQP's BLAS calls are on matrices of a few hundred numbers: threads only cost (6-10x on this
    # busy 2-core machine; benchmarks/bench_design.py). The limit is the process's while the design runs.
    with threadpool_limits(limits=1, user_api="blas"):
        return _design(spec, minimize, progress, cancelled)


def _design(spec: DesignSpec, minimize, progress, cancelled) -> DesignResult:
    """design_motion's work, with scipy's minimize given."""
    problem = _Problem(spec)
    rng = np.random.default_rng(spec.seed)
    best, best_value, converged = None, math.inf, 0

    def objective(x):
        if cancelled is not None and cancelled():
            raise DesignCancelled("design cancelled")
        return problem.criterion(x)

    for start in range(spec.starts):
        if cancelled is not None and cancelled():
            raise DesignCancelled(f"design cancelled after {start} of {spec.starts} starts")
        x = problem.start(rng)
        # An exchange method: the optimiser sees only the grid points where |quantity| peaks, which are
        # few (a K-harmonic signal has at most 4K peaks of |.| a period); points that peak at its
        # solution join the working set and it runs again, until every point of the grid holds.
        working = problem.peaks(x, stride=STRIDE)
        for _ in range(EXCHANGE_ROUNDS):
            x = minimize(objective, x, jac=problem.criterion_gradient, method="SLSQP",
                         constraints=problem.constraints(working), options={"maxiter": 200, "ftol": 1e-9}).x
            if problem.worst_violation(x) <= FEASIBLE:
                break
            size = sum(map(len, working.values()))
            for name, points in problem.peaks(x).items():
                working[name] |= points
            if sum(map(len, working.values())) == size:  # the optimiser cannot meet points it already has
                break
        value = problem.criterion(x)
        if problem.worst_violation(x) <= FEASIBLE and value < PENALTY:
            converged += 1
            if value < best_value:
                best, best_value = x, value
        if progress is not None:
            progress(start + 1, spec.starts)
    if best is None:
        raise DesignError("no start found a motion within the limits that determines every parameter; "
                          "widen the limits or add harmonics")
    motion = shrink_to_limits(from_coefficients(best, spec.period, provenance(spec)), spec)
    value = problem.criterion(motion.coefficients)
    design = motion_precision(replace(spec.experiment, motion=motion))
    rich = motion_precision(replace(spec.experiment, motion="rich"))
    return DesignResult(spec=spec, motion=motion, design=design, rich=rich, checks=check_limits(motion, spec),
                        criterion_value=value, converged=converged)


def provenance(spec: DesignSpec) -> dict:
    """How a design was made, for its motion file's `made` record."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        jointid_version = version("jointid")
    except PackageNotFoundError:
        jointid_version = "unknown"
    settings = spec.experiment
    return {
        "by": "jointid design",
        "criterion": spec.criterion,
        "limits": {name: value for name, value in spec.limits.items()},
        "harmonics": spec.harmonics,
        "samples": settings.samples,
        "noise": settings.noise,
        "model": settings.model,
        "starts": spec.starts,
        "seed": spec.seed,
        "jointid": jointid_version,
    }
