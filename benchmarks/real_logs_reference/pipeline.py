"""Robust identification of a rotating joint's dynamic parameters from one or more logs.

Model (q counter-clockwise from horizontal-right, g = 9.81):

    tau = I*qdd + h*g*cos(q) + B*qd + Fc*sign(qd) + bias

Pipeline for one log (`identify` = `prepare` + `fit_prepared`):
  1. resample_uniform   cubic spline onto a uniform grid if the sampling interval jitters > 1 %
  2. choose_cutoff      fc = 3 x the 95 % power frequency of the motion (cos q, sin q), capped by an
                        errors-in-variables bound from the angle's noise floor
  3. derivatives        Savitzky-Golay smoothing of q (its -3 dB point at 3 fc) then central differences;
     build_filtered     the same S-G smoother and a zero-phase Butterworth (order 4, robust odd padding)
                        applied alike to tau and every COLUMN (qdd, g cos q, qd, sign(qd)), then
                        decimation to 20 samples per cutoff Hz
  4. standstill_mask    |qd| < 10 % of its RMS (>= 3 velocity resolutions); rests dilated by the support
  5. robust step        FAST-LTS (50 % coverage) -> Tukey-bisquare MM -> MAD scale -> hysteresis flags
                        (core above the Bonferroni level for n_eff independent residuals, extent
                        |z| > 2) -> least squares on the rest
  6. ols_hac            Newey-West standard errors on the gapped time grid, n_eff, corr(qdd, g cos q),
                        h/I with its delta-method SE
  7. pooled_fit         runs stacked with weights 1/sigma_run^2, one torque offset per run

Self-contained: numpy + scipy (pandas only to read CSV quickly).
"""
import numpy as np
from scipy import signal, interpolate
from scipy.stats import norm

G = 9.81
PARAMS = ("I", "h", "B", "Fc", "bias")


# ----------------------------------------------------------------------------------------------
# 1. input and uniform grid
# ----------------------------------------------------------------------------------------------
def load_log(path, position_offset=-np.pi / 2):
    """CSV with columns time,position,velocity,torque -> dict(t, q, qd_log, tau).
    q = position + position_offset (DFKI pendulum logs: position 0 = hanging down, so q = position - pi/2)."""
    import pandas as pd
    d = pd.read_csv(path)
    return dict(t=d["time"].to_numpy(float), q=d["position"].to_numpy(float) + position_offset,
                qd_log=d["velocity"].to_numpy(float) if "velocity" in d else None,
                tau=d["torque"].to_numpy(float))


def resample_uniform(t, cols, rel_jitter=0.01):
    """If the sampling interval deviates from its median by more than rel_jitter anywhere, put every
    column on a uniform grid with the median step (cubic spline).  Returns (t_u, cols_u, fs, info)."""
    dt = np.diff(t)
    dt_med = float(np.median(dt))
    jitter = float(np.max(np.abs(dt - dt_med)) / dt_med)
    if jitter <= rel_jitter:
        return t - t[0], cols, 1.0 / dt_med, dict(resampled=False, jitter=jitter)
    tt = t - t[0]
    tu = np.arange(0.0, tt[-1] + 1e-12, dt_med)
    out = {k: (None if v is None else interpolate.CubicSpline(tt, v)(tu)) for k, v in cols.items()}
    return tu, out, 1.0 / dt_med, dict(resampled=True, jitter=jitter)


def quant_step(x):
    """Resolution of a quantised signal: the smallest clearly non-zero step between samples."""
    d = np.abs(np.diff(x))
    d = d[d > 1e-9 * max(1.0, float(np.max(np.abs(x))))]
    return float(np.percentile(d, 1)) if d.size else 0.0


# ----------------------------------------------------------------------------------------------
# 2. low-pass, padding, support
# ----------------------------------------------------------------------------------------------
def _pad_odd_robust(x, npad, nfit):
    """Odd extension about a locally fitted edge value (straight line through the first / last nfit
    samples) instead of about the single edge sample: a torque column full of spikes (or a raw
    acceleration) would otherwise throw one sample's noise, mirrored over the whole pad, into the
    zero-phase filter's output at the ends.  Linear in x, so it is applied alike to every column."""
    n = x.shape[-1]
    npad = min(npad, n - 1)
    nfit = int(min(max(nfit, 3), n))
    k = np.arange(nfit, dtype=float)
    A = np.vstack([np.ones(nfit), k - k.mean()]).T
    Pm = np.linalg.pinv(A)                              # 2 x nfit
    cl = x[..., :nfit] @ Pm.T
    cr = x[..., n - nfit:] @ Pm.T
    x0 = cl[..., 0] - cl[..., 1] * k.mean()             # fitted value at the first sample
    xn = cr[..., 0] + cr[..., 1] * k.mean()             # fitted value at the last sample
    left = 2 * x0[..., None] - x[..., npad:0:-1]
    right = 2 * xn[..., None] - x[..., n - 2:n - 2 - npad:-1]
    return np.concatenate([left, x, right], axis=-1), npad


def lowpass(x, fc, fs, order=4):
    """Zero-phase Butterworth (second-order sections, forward-backward).  The record is extended at
    both ends by 3 filter time constants (3 fs/fc samples, robust odd extension) and the extension is
    cut off afterwards, so the ends of a short log stay usable (an FIR of the same selectivity would
    have to discard its full length at each end)."""
    sos = signal.butter(order, fc, fs=fs, output="sos")
    x = np.asarray(x, float)
    xp, npad = _pad_odd_robust(x, int(3 * fs / fc), int(0.5 * fs / fc))
    y = signal.sosfiltfilt(sos, xp, axis=-1, padtype=None)
    return y[..., npad:npad + x.shape[-1]]


def filter_support(fc, fs, order=4, frac=0.95):
    """Half-width (s) of the zero-phase filter's impulse response holding `frac` of its |area|: a
    disturbance at time t leaks into filtered samples within +-support (order 4: ~1.03/fc)."""
    n = int(20 * fs / fc) + 1
    x = np.zeros(2 * n + 1)
    x[n] = 1.0
    sos = signal.butter(order, fc, fs=fs, output="sos")
    h = np.abs(signal.sosfiltfilt(sos, x)[n:])
    c = np.cumsum(h) / np.sum(h)
    return float(np.searchsorted(c, frac) / fs)


# ----------------------------------------------------------------------------------------------
# 3. automatic cutoff
# ----------------------------------------------------------------------------------------------
def _periodogram(x, fs):
    """Hann-tapered periodogram of the whole record (best resolution for short logs)."""
    return signal.periodogram(signal.detrend(x), fs, window="hann", detrend=False)


def motion_bandwidth(q, fs, frac=0.95):
    """Frequency below which `frac` of the power of the motion lies.  The motion is measured by the
    unit vector (cos q, sin q): bounded, so a joint that turns over many times (q drifting by many
    turns) does not swamp the spectrum the way a ramp in q would; for small swings it is q itself."""
    f, P1 = _periodogram(np.cos(q), fs)
    _, P2 = _periodogram(np.sin(q), fs)
    c = np.cumsum(P1 + P2)
    return float(f[np.searchsorted(c / c[-1], frac)])


def eiv_cutoff_cap(q, fs, fc_guess, eps=0.01):
    """Errors-in-variables cap.  White noise of PSD N0 in q (quantisation, encoder noise; N0 = median
    periodogram of q over 0.25-0.45 fs) becomes noise in qdd of variance (2 pi)^4 N0 fc^5 / 5 after
    a low-pass at fc; noise in the qdd column biases I low by the ratio noise/signal variance.  The cap
    is the fc at which that ratio reaches eps (1 %)."""
    f, Pq = _periodogram(q, fs)
    band = (f > 0.25 * fs) & (f < 0.45 * fs)
    N0 = float(np.median(Pq[band]))
    win = min(savgol_window(fs, 3 * fc_guess), (len(q) // 2) * 2 - 1)
    qdd = np.gradient(np.gradient(signal.savgol_filter(q, win, 3), 1 / fs), 1 / fs)
    v = float(np.var(lowpass(qdd, fc_guess, fs)))
    if N0 <= 0:
        return np.inf
    return float((5 * eps * v / ((2 * np.pi) ** 4 * N0)) ** 0.2)


def choose_cutoff(q, fs, k=3.0, frac=0.95, eps=0.01):
    """fc = min(k x motion bandwidth, errors-in-variables cap), within [4/T, fs/10].
    Rationale: the rigid-body torque is a function of the motion; its columns live in the motion's band
    and its first harmonics (k = 3 keeps the 3rd harmonic of the dominant swing, enough for the cos q
    nonlinearity of large swings; the Coulomb column's sharp harmonics need not pass, because tau and
    the column are filtered alike).  Everything in tau far above the motion band cannot come from the
    rigid-body model (stick-slip spikes, current ripple, controller chatter) and everything in qdd
    there is noise that biases I low (errors in variables), so the cutoff follows the motion, not the
    sampling rate.  The 95 % (not 99 %) point ignores brief transients (hits, slips)."""
    fb = motion_bandwidth(q, fs, frac)
    T = len(q) / fs
    cap = eiv_cutoff_cap(q, fs, k * fb, eps)
    fc = min(k * fb, cap)
    lo, hi = 4.0 / T, fs / 10.0
    fc_clip = float(np.clip(fc, lo, hi))
    reason = ("%.0f%% of the (cos q, sin q) power lies below %.2f Hz -> %.1f x %.2f = %.2f Hz; "
              "noise cap %.1f Hz" % (100 * frac, fb, k, fb, k * fb, cap))
    if cap < k * fb:
        reason += " (cap binds)"
    if fc_clip != fc:
        reason += " (clipped to [%.2f, %.1f] Hz)" % (lo, hi)
    return fc_clip, reason, fb


# ----------------------------------------------------------------------------------------------
# 4. derivatives, columns, filtering, decimation
# ----------------------------------------------------------------------------------------------
def savgol_window(fs, f3db, polyorder=3):
    """Odd window whose Savitzky-Golay smoothing has its -3 dB point near f3db
    (Schafer 2011: f_3dB/fs ~ (p+1)/(3.2 M - 4.6), window 2M+1)."""
    M = int(np.ceil(((polyorder + 1) * fs / f3db + 4.6) / 3.2))
    return 2 * M + 1


def derivatives(q, fs, method="savgol", qd_log=None, fc=None):
    """Velocity and acceleration before the common low-pass, plus the pre-smoother that must then be
    applied alike to the other columns (None = none).
    'savgol' : cubic Savitzky-Golay smoothing of q with its -3 dB point at 3 fc (flat where the
               Butterworth passes), then central differences of the SMOOTHED angle.  (S-G derivative
               filters are not (i w)^k times the S-G smoother, so using them would filter qdd
               differently from tau.)  The smoother removes the huge sample-to-sample noise of a
               twice-differenced quantised angle (one count at 500 Hz ~ 700 rad/s^2), which otherwise
               corrupts the filter's padding at the ends of the record.
    'diff'   : central differences of the raw angle, no pre-smoothing.
    'logged' : the logged velocity column, qdd its central difference, no pre-smoothing."""
    dt = 1.0 / fs
    if method == "savgol":
        win = min(savgol_window(fs, 3.0 * fc), (len(q) // 2) * 2 - 1)
        qs = signal.savgol_filter(q, win, 3, mode="interp")
        qd = np.gradient(qs, dt)
        qdd = np.gradient(qd, dt)
        return qd, qdd, (lambda x: signal.savgol_filter(x, win, 3, mode="interp", axis=-1))
    if method == "diff":
        qd = np.gradient(q, dt)
    elif method == "logged":
        qd = np.asarray(qd_log, float)
    else:
        raise ValueError(method)
    return qd, np.gradient(qd, dt), None


def build_filtered(q, qd, qdd, tau, fs, fc, order=4, dec_per_fc=20.0, friction="sign", smooth=None,
                   sign_fc_mult=3.0):
    """Filter tau and every regressor column alike (pre-smoother if any, then the zero-phase
    Butterworth at fc), then keep every D-th sample, D = fs/(dec_per_fc fc) (the low-pass is the
    anti-alias filter).  The Coulomb column is sign(qd) of the velocity low-passed at 3 fc (enough to
    stop quantisation chatter, without shifting its zero crossings as a low-pass at fc would); that
    column is then filtered like every other one.  Returns X (n x 5: qdd, g cos q, qd, sign, 1), y,
    the kept indices, the decimated rate and the velocity low-passed at fc."""
    qd_f = lowpass(qd, fc, fs, order)
    qd_s = lowpass(qd, min(sign_fc_mult * fc, 0.4 * fs), fs, order)
    if friction == "sign":
        fr = np.sign(qd_s)
    elif friction == "atan100":                       # the published model's friction shape
        fr = np.arctan(100.0 * qd_s)
    else:
        raise ValueError(friction)
    gc = G * np.cos(q)
    if smooth is not None:                            # qd, qdd already carry it
        gc, fr, tau = smooth(np.vstack([gc, fr, tau]))
    filt = lowpass(np.vstack([qdd, gc, qd, fr, tau]), fc, fs, order)
    D = max(1, int(fs / (dec_per_fc * fc)))
    idx = np.arange(0, len(q), D)
    X = np.column_stack([filt[0, idx], filt[1, idx], filt[2, idx], filt[3, idx], np.ones(len(idx))])
    return X, filt[4, idx], idx, fs / D, qd_f[idx]


# ----------------------------------------------------------------------------------------------
# 5. interval helpers
# ----------------------------------------------------------------------------------------------
def mask_to_intervals(mask):
    """Boolean mask -> list of (i0, i1) inclusive index pairs of its True runs."""
    m = np.concatenate([[0], np.asarray(mask, np.int8), [0]])
    d = np.diff(m)
    return list(zip(np.where(d == 1)[0], np.where(d == -1)[0] - 1))


def dilate(mask, n):
    """Grow every True run by n samples on both sides."""
    if n <= 0:
        return mask.copy()
    return np.convolve(mask.astype(float), np.ones(2 * n + 1), mode="same") > 0.5


def close_gaps(mask, n):
    """Merge True runs separated by fewer than n False samples."""
    out = mask.copy()
    iv = mask_to_intervals(mask)
    for (a0, a1), (b0, b1) in zip(iv[:-1], iv[1:]):
        if b0 - a1 - 1 < n:
            out[a1:b0] = True
    return out


# ----------------------------------------------------------------------------------------------
# 6. least squares with autocorrelation-honest errors
# ----------------------------------------------------------------------------------------------
def ols(X, y, w=None):
    if w is None:
        return np.linalg.lstsq(X, y, rcond=None)[0]
    sw = np.sqrt(w)
    return np.linalg.lstsq(X * sw[:, None], y * sw, rcond=None)[0]


def acf_sum(r, keep, L):
    """Bartlett-weighted 1 + 2 sum_k (1 - k/(L+1)) rho_k of the residuals on the time grid; excluded
    samples are zeroed so that pairs straddling a gap do not count.  n_eff = n / acf_sum."""
    e = np.where(keep, r, 0.0)
    c0 = np.dot(e, e)
    s = 1.0
    for k in range(1, L + 1):
        s += 2 * (1 - k / (L + 1)) * np.dot(e[:-k], e[k:]) / c0
    return max(s, 1.0)


def hac_lag(n, support_n):
    """Newey-West lag: the larger of the usual 4 (n/100)^(2/9) and twice the filter support in
    samples (the low-pass alone correlates residuals over its impulse response)."""
    return int(min(n - 1, max(np.floor(4 * (n / 100.0) ** (2 / 9)), 2 * support_n)))


def hac_meat(X, e, keep, L):
    """Bartlett-weighted sum of score cross-products on the gapped time grid."""
    U = np.where(keep[:, None], X, 0.0) * np.where(keep, e, 0.0)[:, None]
    S = U.T @ U
    for k in range(1, L + 1):
        Gk = U[k:].T @ U[:-k]
        S += (1 - k / (L + 1)) * (Gk + Gk.T)
    return S


def ols_hac(X, y, keep, L):
    """OLS on the kept rows; Newey-West covariance; also the iid covariance and n_eff."""
    theta = ols(X[keep], y[keep])
    r = y - X @ theta
    n, p = int(keep.sum()), X.shape[1]
    A = np.linalg.inv(X[keep].T @ X[keep])
    cov = A @ hac_meat(X, r, keep, L) @ A * n / (n - p)
    s2 = float(np.sum(r[keep] ** 2) / (n - p))
    return theta, cov, np.sqrt(s2), n / acf_sum(r, keep, L), A * s2


# ----------------------------------------------------------------------------------------------
# 7. robust step
# ----------------------------------------------------------------------------------------------
def fast_lts(X, y, coverage=0.5, n_starts=200, rng=None, sub_max=1500, n_best=10, max_csteps=30):
    """FAST-LTS (Rousseeuw & Van Driessen 2006): random elemental (p-row) starts, two concentration
    steps each on a subsample of <= sub_max rows, the n_best iterated to convergence there, the best
    two then to convergence on all rows.  Minimises the sum of the h = coverage*n smallest squared
    residuals; breakdown 1 - coverage (50 % at the default)."""
    rng = np.random.default_rng(0) if rng is None else rng
    n, p = X.shape
    sub = np.arange(n) if n <= sub_max else np.sort(rng.choice(n, sub_max, replace=False))
    Xs, ys = X[sub], y[sub]

    def csteps(theta, Xa, ya, k):
        hh = max(p + 1, int(coverage * len(ya)))
        obj = np.inf
        for _ in range(k):
            r2 = (ya - Xa @ theta) ** 2
            sel = np.argpartition(r2, hh - 1)[:hh]
            new = float(np.sum(r2[sel]))
            if new >= obj * (1 - 1e-9):
                break
            obj = new
            try:
                theta = np.linalg.solve(Xa[sel].T @ Xa[sel], Xa[sel].T @ ya[sel])
            except np.linalg.LinAlgError:
                break
        r2 = (ya - Xa @ theta) ** 2
        return theta, float(np.sum(np.partition(r2, hh - 1)[:hh]))

    cands = []
    for _ in range(n_starts):
        el = rng.choice(len(sub), p, replace=False)
        try:
            th = np.linalg.solve(Xs[el], ys[el])
        except np.linalg.LinAlgError:
            continue
        cands.append(csteps(th, Xs, ys, 2)[::-1])
    cands.sort(key=lambda c: c[0])
    refined = sorted((csteps(th, Xs, ys, max_csteps)[::-1] for _, th in cands[:n_best]),
                     key=lambda c: c[0])
    if len(sub) == n:
        return refined[0][1]
    final = [csteps(th, X, y, max_csteps)[::-1] for _, th in refined[:2]]
    return min(final, key=lambda c: c[0])[1]


def bisquare_irls(X, y, theta, scale, c=4.685, n_iter=50):
    """Tukey-bisquare M-estimate with the scale fixed at the high-breakdown value, started from LTS
    (the MM estimator, Yohai 1987): keeps LTS's breakdown, restores ~95 % Gaussian efficiency, so
    the informative large-torque samples that a 50 % LTS trims come back."""
    for _ in range(n_iter):
        u = (y - X @ theta) / (c * scale)
        w = np.where(np.abs(u) < 1, (1 - u ** 2) ** 2, 0.0)
        new = ols(X, y, w)
        if np.allclose(new, theta, rtol=1e-8, atol=1e-12):
            return new
        theta = new
    return theta


def mad_sigma(r):
    return 1.4826 * float(np.median(np.abs(r - np.median(r))))


def flag_outside_torque(z, usable, n_eff, support_n, c_low=2.0, alpha=0.01, dilate_n=0):
    """Hysteresis flagging of intervals where an outside torque acts.
    Core: |r|/sigma above c_hi = Phi^-1(1 - alpha/(2 n_eff)), the Bonferroni level at which a clean
    log with n_eff INDEPENDENT Gaussian residuals raises a false alarm with probability alpha.  Using
    n_eff (from the residual autocorrelation) instead of the sample count makes it robust to the strong
    autocorrelation of low-passed residuals and independent of the decimation rate.
    Extent: the contiguous stretch around a core with |r|/sigma > c_low: the low-pass smear of the
    push is part of the residual, so it is followed as far as it stands out of the noise; beyond that
    the leak is below 2 sigma.  (Adding a full support on each side as well excluded ~45 % of the
    synthetic log.)  Optional extra dilation, then intervals closer than two supports are merged."""
    c_hi = float(norm.isf(alpha / (2 * max(n_eff, 1.0))))
    low = (z > c_low) & usable
    out = np.zeros_like(low)
    for i0, i1 in mask_to_intervals(low):
        if np.any(z[i0:i1 + 1] > c_hi):
            out[i0:i1 + 1] = True
    return close_gaps(dilate(out, dilate_n), 2 * support_n), c_hi


def standstill_mask(qd_f, v_thr, support_n, min_len_n, drop_dips=True):
    """Samples where the joint does not slide (|qd| < v_thr): there the friction torque is static
    (anything within +-Fs), not Fc sign(qd).  Short dips (a swing reversing, shorter than min_len_n
    samples) are dropped as they are; genuine rests (longer) are dilated by the filter support,
    because the filtered Coulomb column around them is contaminated that far.
    Returns (all standstill samples, the rests)."""
    low = np.abs(qd_f) < v_thr
    rest = np.zeros_like(low)
    for i0, i1 in mask_to_intervals(low):
        if i1 - i0 + 1 >= min_len_n:
            rest[i0:i1 + 1] = True
    rest = dilate(rest, support_n)
    return (low | rest) if drop_dips else rest, rest


# ----------------------------------------------------------------------------------------------
# 8. one run
# ----------------------------------------------------------------------------------------------
DEFAULTS = dict(
    cutoff=None,        # None = automatic (choose_cutoff), else Hz
    k_bw=3.0, bw_frac=0.95, eps_eiv=0.01,
    order=4,            # Butterworth order (applied forward and backward)
    deriv="savgol",     # 'savgol' | 'diff' | 'logged'
    dec_per_fc=20.0,    # decimated rate = 20 x fc
    friction="sign", sign_fc_mult=3.0, fit_coulomb=True, fit_bias=True,
    standstill=True, v_frac=0.1, drop_dips=True,
    robust=True, coverage=0.5, mm=True, alpha=0.01, c_low=2.0, dilate_frac=0.0, fs_ratio=1.5,
    n_starts=200, seed=0, edge_trim=False)


def prepare(log, **kw):
    """Steps 1-4: uniform grid, cutoff, columns, filtering, decimation, standstill mask."""
    o = dict(DEFAULTS)
    o.update(kw)
    t, cols, fs, rs = resample_uniform(log["t"], dict(q=log["q"], tau=log["tau"], qd_log=log.get("qd_log")))
    q, tau = cols["q"], cols["tau"]
    if o["cutoff"] is None:
        fc, reason, fb = choose_cutoff(q, fs, o["k_bw"], o["bw_frac"], o["eps_eiv"])
    else:
        fc, reason, fb = float(o["cutoff"]), "fixed", motion_bandwidth(q, fs, o["bw_frac"])
    qd, qdd, smooth = derivatives(q, fs, o["deriv"], cols.get("qd_log"), fc)
    X, y, idx, fsd, qd_f = build_filtered(q, qd, qdd, tau, fs, fc, o["order"], o["dec_per_fc"],
                                          o["friction"], smooth, o["sign_fc_mult"])
    n = len(y)
    sup = filter_support(fc, fs, o["order"])
    sup_n = int(np.ceil(sup * fsd))
    usable = np.ones(n, bool)
    if o["edge_trim"]:                     # variant only: drop half a cutoff period at each end
        e = int(np.ceil(0.5 / fc * fsd))
        usable[:e] = usable[n - e:] = False
    # standstill threshold: 10 % of the RMS filtered speed (the Coulomb model describes sliding; below
    # a tenth of the joint's typical speed it is in its stick/Stribeck region), never below three
    # velocity resolutions (one encoder count per half cutoff period)
    v_res = quant_step(q) * 2 * fc
    v_thr = max(o["v_frac"] * float(np.sqrt(np.mean(qd_f ** 2))), 3 * v_res)
    still = np.zeros(n, bool)
    rest = np.zeros(n, bool)
    if o["standstill"] and o["fit_coulomb"]:
        still, rest = standstill_mask(qd_f, v_thr, sup_n, max(2, sup_n), o["drop_dips"])
    cols_used = [0, 1, 2] + ([3] if o["fit_coulomb"] else []) + ([4] if o["fit_bias"] else [])
    return dict(o=o, X=X, y=y, t_dec=t[idx], fs=fs, fs_dec=fsd, fc=fc, fb=fb, reason=reason,
                support=sup, support_n=sup_n, usable=usable, still=still, rest=rest, v_thr=v_thr,
                cols_used=cols_used, resample=rs, T=float(t[-1]))


def robust_exclusions(P):
    """Step 5: intervals where an outside torque acts (boolean mask on the decimated grid)."""
    o, cu = P["o"], P["cols_used"]
    Xu, y = P["X"][:, cu], P["y"]
    base = P["usable"] & ~P["still"]
    L = hac_lag(int(base.sum()), P["support_n"])
    rng = np.random.default_rng(o["seed"])
    th0 = fast_lts(Xu[base], y[base], o["coverage"], o["n_starts"], rng=rng)
    s0 = mad_sigma((y - Xu @ th0)[base])
    th = bisquare_irls(Xu[base], y[base], th0, s0) if o["mm"] else th0
    r = y - Xu @ th
    sigma = mad_sigma(r[base])                  # 50 % breakdown scale over all sliding samples
    z = np.abs(r) / sigma
    if 3 in cu:
        # at rest the friction is static, anything within +-Fs: count only torque beyond that
        # (dead zone, Fs = 1.5 |Fc|, a typical upper breakaway/Coulomb ratio)
        jc = cu.index(3)
        dz = np.maximum(np.abs(r + th[jc] * Xu[:, jc]) - o["fs_ratio"] * abs(th[jc]), 0.0)
        z = np.where(P["rest"], dz / sigma, z)
    z = np.where(P["usable"], z, 0.0)
    inl = base & (z < 2.5)
    neff = inl.sum() / acf_sum(r, inl, L)
    pushes, c_hi = flag_outside_torque(z, P["usable"], neff, P["support_n"], o["c_low"], o["alpha"],
                                       int(np.ceil(o["dilate_frac"] * P["support_n"])))
    return pushes, dict(theta_mm=th, sigma_mm=sigma, z=z, c_hi=c_hi, n_eff_flag=neff)


def fit_prepared(P, pushes=None):
    """Step 6: least squares on the kept samples with HAC errors."""
    cu = P["cols_used"]
    Xu, y = P["X"][:, cu], P["y"]
    n = len(y)
    pushes = np.zeros(n, bool) if pushes is None else pushes
    keep = P["usable"] & ~P["still"] & ~pushes
    if keep.sum() < 4 * len(cu):
        raise RuntimeError("too few samples left (%d) after exclusions" % keep.sum())
    L = hac_lag(int(keep.sum()), P["support_n"])
    theta, cov, s, neff, cov_iid = ols_hac(Xu, y, keep, L)
    full = np.zeros(5)
    full[cu] = theta
    C = np.zeros((5, 5))
    C[np.ix_(cu, cu)] = cov
    Ci = np.zeros((5, 5))
    Ci[np.ix_(cu, cu)] = cov_iid
    I_, h_ = full[0], full[1]
    gr = np.array([-h_ / I_ ** 2, 1 / I_])
    td = P["t_dec"]
    ivs = [(float(td[a]), float(td[b])) for a, b in mask_to_intervals(pushes)]
    edge = P["support"]
    return dict(theta=full, se=np.sqrt(np.diag(C)), se_iid=np.sqrt(np.diag(Ci)), cov=C, sigma=s,
                n=int(keep.sum()), n_dec=n, n_eff=neff, hac_lag=L, keep=keep, pushes=pushes,
                corr_qdd_gcos=float(np.corrcoef(P["X"][keep, 0], P["X"][keep, 1])[0, 1]),
                ratio=h_ / I_, ratio_se=float(np.sqrt(gr @ C[:2, :2] @ gr)),
                resid=y - P["X"] @ full, push_intervals=ivs,
                interval_kind=["edge transient" if (a < td[0] + edge or b > td[-1] - edge) else "outside torque"
                               for a, b in ivs],
                frac_push=float(pushes.sum() / n), frac_still=float(P["still"].sum() / n),
                frac_excluded=float(1 - keep.sum() / n))


def identify(log, **kw):
    """The whole pipeline on one log (dict with t, q, tau[, qd_log]).  Returns one dict."""
    P = prepare(log, **kw)
    extra = dict(c_hi=np.nan, z=np.zeros(len(P["y"])))
    pushes = None
    if P["o"]["robust"]:
        pushes, extra = robust_exclusions(P)
    R = fit_prepared(P, pushes)
    out = dict(P)
    out.update(extra)
    out.update(R)
    return out


# ----------------------------------------------------------------------------------------------
# 9. several runs, prediction
# ----------------------------------------------------------------------------------------------
def pooled_fit(results):
    """Stack prepared runs (each with its own cutoff and exclusions) with weights 1/sigma_run^2.
    I, h, B, Fc are common; each run keeps its own torque offset (a current-sensor offset is not a
    property of the joint).  Covariance: sandwich with per-run HAC score sums (runs independent).
    Returns theta (I, h, B, Fc, bias_1..bias_R), se, cov."""
    R = len(results)
    Xs, ys, ws, meta = [], [], [], []
    for j, r in enumerate(results):
        Bc = np.zeros((len(r["y"]), R))
        Bc[:, j] = 1.0
        Xs.append(np.hstack([r["X"][:, :4], Bc]))
        ys.append(r["y"])
        ws.append(np.full(len(r["y"]), 1.0 / r["sigma"] ** 2))
    k = np.concatenate([r["keep"] for r in results])
    X, y, w = np.vstack(Xs), np.concatenate(ys), np.concatenate(ws)
    theta = ols(X[k], y[k], w[k])
    A = np.linalg.inv((X[k] * w[k, None]).T @ X[k])
    S = np.zeros((X.shape[1], X.shape[1]))
    off = 0
    for j, r in enumerate(results):
        m = len(r["y"])
        Xj = X[off:off + m]
        e = (y[off:off + m] - Xj @ theta) / r["sigma"] ** 2
        S += hac_meat(Xj, e, r["keep"], r["hac_lag"])
        off += m
    cov = A @ S @ A
    return theta, np.sqrt(np.diag(cov)), cov


def predict_filtered(log, theta, fc=3.0, friction="sign"):
    """Measured torque and the model's torque, both through the same zero-phase low-pass at fc
    (tau_hat = X theta with the columns filtered like tau).  Returns t, tau_f, tau_hat."""
    P = prepare(log, cutoff=fc, friction=friction, robust=False)
    return P["t_dec"], P["y"], P["X"] @ np.asarray(theta, float)
