"""Loss factor from the Nyquist plot: circle fit, loss-factor plane and its diagonal ridge.

The paper's Section 3.2.2 (Figs. 12-13, Eq. 45), after Ewins, *Modal Testing*, Section 4.3.

Method, for each resonance
--------------------------
1. The FRF is brought to *displacement form* (receptance-like, where a mode of the structural
   damping model of Eq. (11) is the term ``A_r / (omega_r^2 (1 + i eta_r) - omega^2)``, an exact
   circle): receptance and dynamic stiffness (F/x) as they are, mobility divided by ``i omega``,
   accelerance by ``-omega^2``, apparent mass (F/a, the paper's TRFAM, Eq. 12) multiplied by
   ``-omega^2``. A 0 Hz (DC) line is left out: no resonance uses it, and its displacement form is
   undefined for every kind but displacement.
2. Points within ``omega_r^2 (1 +- bandwidths * eta)``, a window ``bandwidths`` half-power bandwidths
   ``B = eta f_r`` wide (``f_r +- (bandwidths / 2) B``; ``omega_r``, ``eta``: a one-mode fit started
   from the half-power estimate around the peak of ``|H|``, both sought within ``+-search`` of the
   request and no further than halfway to the neighbouring requests) are fitted by a circle in the
   *geometric* least-squares sense (sum of squared distances to the circle,
   ``scipy.optimize.least_squares``, started from the algebraic Kasa fit), the "nonlinear
   curve-fitting technique" of the paper.
3. The resonance is the point of fastest sweep of the angle ``phi`` (seen from the centre) per unit
   ``omega^2``: the law of a hysteretic mode,
   ``phi = phi_r + s 2 atan((omega_r^2 - omega^2) / (eta omega_r^2))`` (``s = +-1``, the sense of
   travel), whose sweep rate peaks exactly at ``omega_r``, fitted to the angles from the one-mode
   fit's ``omega_r`` and ``eta``; a fitted resonance with fewer than ``min_side`` points on one side
   is no resonance in the window.
4. Loss-factor plane: for every point ``b`` below and ``a`` above the resonance, with centre angles
   ``theta = |phi - phi_r|``,

       eta(b, a) = (omega_a^2 - omega_b^2) / (omega_r^2 (tan(theta_a / 2) + tan(theta_b / 2))).

   This is Ewins' formula; it is the paper's Eq. (45) with the angles of Eq. (45) seen from the
   circle's point opposite to the resonance (half the centre angles, inscribed-angle theorem).
   Rows and columns are ordered by increasing distance from the resonance; the *diagonal*
   ``eta(k, k)`` pairs points at matching distances below and above (where a small error in
   ``phi_r`` cancels to first order); the identified loss factor is its median.
5. Neighbouring modes: a constant contribution of other modes only shifts the circle (the
   circle's offset, the point opposite to the resonance, absorbs it), but their slope over the
   window distorts it. After all requested modes are fitted, the fitted modal terms of the *other*
   identified modes, ``A_k / (omega_k^2 (1 + i s eta_k) - omega^2)`` with
   ``A_k = 2 R_k exp(i phi_rk) i s eta_k omega_k^2``, are subtracted from the FRF and each mode is
   fitted again; this repeats until the loss factors change by less than 1e-7 (relative).
   Resonance peaks of ``|H|`` within ``+-search`` of a request but not requested are fitted and
   subtracted too (not returned: ``extra["unrequested_hz"]``); modes further away remain as the
   circle's offset.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy.ndimage import median_filter, uniform_filter1d
from scipy.optimize import least_squares
from scipy.signal import find_peaks

from ..errors import ModelError, ModelWarning, plain
from ..model.validators import Choice, array_1d, integer, number

FRF_KINDS = ("displacement", "velocity", "acceleration", "apparent_mass")
#: Warning bound on the circle's rms radial residual over its radius. With complex noise of a relative
#: level e on H, rms/R ~ e and the loss factor's random error (rms over seeds, ~40 points in the window)
#: is 0.43 rms/R (tests at e = 1-20 %: 0.4, 1.3, 2.1, 4.4, 10.6 %); 0.05 is a 2 % random error, and
#: 2.8 (rms/R) / sqrt(points) is reported as the estimate.
RMS_RATIO_WARN = 0.05
#: Warning bound on the expected leakage bias of a Hann-window (Welch) FRF estimate, 2 (df / B)^2 with B
#: the true half-power bandwidth eta f_r (Hz) and df the line spacing (simulated Welch estimates of one mode
#: give +6-11 % at 4-5.5 lines per bandwidth, +2-3 % at 8-11; the window's second moment alone gives
#: (4/3)(df / B)^2); B is solved from the fitted, widened bandwidth (:func:`_leakage_bias`).
LEAKAGE_BIAS_WARN = 0.01
#: The circle fit of a *viscously* damped mode (receptance ``1 / (omega_n^2 - omega^2 + 2 i zeta omega_n omega)``,
#: any kind: all go to displacement form) with the default window: rows (fitted eta, eta / (2 zeta) - 1,
#: f_r / f_n - 1), computed from that closed form at zeta = 0.05, 0.08, 0.1, 0.125, 0.15, 0.2, 0.25
#: (tests/identification/test_circlefit.py recomputes them). Both grow as about 1.5 zeta^2 and -zeta^2 up to
#: zeta = 0.1, faster above (2 zeta^2 and -1.1 zeta^2 at 0.2).
VISCOUS_BIAS = (
    (0.10038, 0.00380, -0.00251),
    (0.16159, 0.00992, -0.00648),
    (0.20316, 0.01582, -0.01019),
    (0.25639, 0.02555, -0.01611),
    (0.31156, 0.03852, -0.02357),
    (0.43208, 0.08020, -0.04424),
    (0.58544, 0.17087, -0.07804),
)
#: Default limit of neighbour-correction sweeps (``max_iter``). Well separated modes settle in about five
#: sweeps, so the limit costs nothing there; close modes converge slowly, swinging above and below their
#: values: two of eta 0.02, 0.75 half-power bandwidths apart (100 and 101.5 Hz), settle in 451 sweeps
#: (8 s on one core; after 50 their loss factors were 4.7 % off), 0.4 apart (100 and 100.8 Hz, opposite
#: signs) in 4586 (60 s; after 50, 21 % low): a larger max_iter for those.
MAX_ITER = 500
#: Default full width of each circle's window in half-power bandwidths (:func:`loss_factor_circle`'s
#: ``bandwidths``: +-B around the resonance).
BANDWIDTHS = 2.0
#: Default relative half-width around each resonance searched for its peak (:func:`loss_factor_circle`'s
#: ``search``).
SEARCH = 0.1
#: Warning bound on the fitted eta: above it, were the damping viscous, eta / 2 would be more than 1 %
#: above zeta (VISCOUS_BIAS: 0.99 % at eta = 0.1616).
VISCOUS_ETA_WARN = 0.16


def to_displacement_form(freqs_hz, H, kind="displacement"):
    """FRF in displacement form, where a mode of the structural model (Eq. 11) is an exact circle
    (Section 3.2.2; the module docstring, step 1).

    ``kind``: ``"displacement"`` (receptance m/N, or dynamic stiffness N/m: unchanged),
    ``"velocity"`` (mobility, divided by ``i omega``), ``"acceleration"`` (accelerance, divided by
    ``-omega^2``), ``"apparent_mass"`` (F/a in kg, e.g. the TRFAM of Eq. 12, times ``-omega^2``).
    Frequencies in Hz; ``omega = 2 pi f``.
    """
    Choice(*FRF_KINDS)("kind", kind)
    w = 2.0 * np.pi * np.asarray(freqs_hz, dtype=float)
    H = np.asarray(H, dtype=complex)
    if kind == "displacement":
        return H.copy()
    if np.any(w == 0.0):
        raise ModelError("freqs_hz", 0.0, f"0 Hz cannot be converted from kind {kind!r}; leave it out")
    if kind == "velocity":
        return H / (1j * w)
    if kind == "acceleration":
        return H / (-(w**2))
    return H * (-(w**2))


def fit_circle(z):
    """Geometric least-squares circle through complex points ``z`` (the Nyquist circle of Section 3.2.2, Fig. 12).

    Minimises ``sum (|z_i - c| - R)^2`` over centre ``c`` and radius ``R`` with
    ``scipy.optimize.least_squares`` (analytic Jacobian), started from the algebraic (Kasa) fit
    ``|z|^2 + D x + E y + F = 0``. Returns ``(centre: complex, radius: float, rms: float)`` with
    ``rms`` the root-mean-square radial residual (unit of ``z``).
    """
    z = np.asarray(z, dtype=complex)
    if z.size < 3:
        raise ModelError("points", z.size, "a circle needs at least 3 points")
    scale = float(np.max(np.abs(z - z.mean())))
    if scale == 0.0:
        raise ModelError("points", "all equal", "a circle needs distinct points")
    off = z.mean()
    u = (z - off) / scale
    x, y = u.real, u.imag
    M = np.column_stack([x, y, np.ones_like(x)])
    D, E, F = np.linalg.lstsq(M, -(x * x + y * y), rcond=None)[0]
    c0 = complex(-D / 2.0, -E / 2.0)
    R0 = float(np.sqrt(max(abs(c0) ** 2 - F, 1e-12)))

    def res(p):
        return np.hypot(x - p[0], y - p[1]) - p[2]

    def jac(p):
        d = np.hypot(x - p[0], y - p[1])
        d = np.where(d == 0.0, 1e-300, d)
        return np.column_stack([-(x - p[0]) / d, -(y - p[1]) / d, -np.ones_like(x)])

    sol = least_squares(res, [c0.real, c0.imag, R0], jac=jac, method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    cx, cy, R = sol.x
    rms = float(np.sqrt(np.mean(sol.fun**2))) * scale
    return complex(cx, cy) * scale + off, abs(float(R)) * scale, rms


def _structural_mode(w2, wr2, eta, sense=1.0, A=1.0):
    """One structurally damped mode's term of the receptance, A / (omega_r^2 (1 + i s eta) - omega^2)
    (Eq. 11): w2 = omega^2 and wr2 = omega_r^2 in rad^2/s^2, eta the loss factor, s = ``sense`` = +1
    or -1 (-1 for the conjugate convention of the data), A the modal constant (the FRF's unit times
    rad^2/s^2; 1 gives the unit mode)."""
    return A / (wr2 * (1.0 + 1j * sense * eta) - w2)


@dataclass(frozen=True)
class CircleFitResult:
    """Loss factor of one resonance identified from the Nyquist circle (Section 3.2.2, Fig. 13).

    Frequencies in Hz, angles in rad, ``centre``, ``radius``, ``offset`` in the unit of the
    displacement-form FRF, ``modal_constant`` in that unit times rad^2/s^2. ``plane[i, j]`` is the
    loss factor from the i-th point below and the j-th point above the resonance (nearest first),
    ``diagonal`` its main diagonal and ``eta`` the diagonal's median (the identified loss factor);
    ``eta_angle_fit`` is the loss factor of the angle-law fit used to refine the resonance.
    ``points`` are the window's FRF values after the neighbouring-mode correction.
    """

    f_requested_hz: float
    f_r_hz: float
    eta: float
    eta_angle_fit: float
    centre: complex
    radius: float
    rms: float
    phi_r: float
    sense: int
    modal_constant: complex
    offset: complex
    freqs_hz: np.ndarray
    points: np.ndarray
    f_below_hz: np.ndarray
    f_above_hz: np.ndarray
    plane: np.ndarray
    diagonal: np.ndarray
    iterations: int = 0
    extra: dict = field(default_factory=dict)

    def modal_term(self, freqs_hz):
        """This mode's term ``A / (omega_r^2 (1 + i s eta) - omega^2)`` (Eq. 11) at ``freqs_hz`` (Hz),
        in the unit of the displacement-form FRF."""
        w2 = (2.0 * np.pi * np.asarray(freqs_hz, dtype=float)) ** 2
        wr2 = (2.0 * np.pi * self.f_r_hz) ** 2
        return _structural_mode(w2, wr2, self.eta, self.sense, self.modal_constant)


#: A peak of |H| counts as a resonance when its prominence in ln|H| (after a 5-point running mean)
#: exceeds this many local standard deviations of the noise on ln|H| (see :func:`find_resonances`).
PEAK_NOISE_FACTOR = 5.0


def find_resonances(freqs_hz, H, count=None, kind="displacement"):
    """Frequencies (Hz, ascending) of the ``count`` most prominent resonance peaks of ``|H|`` in
    displacement form: starting resonances for Section 3.2.2 (and the measured natural frequencies of
    Section 3.1 when read from an FRF). ``H`` of the given ``kind``.

    Noise-aware: peaks are sought on ``ln|H|`` smoothed by a 5-point running mean (scipy.ndimage, the
    ends padded with the end values), and a peak counts only when its prominence there exceeds
    ``PEAK_NOISE_FACTOR`` (5) times the local standard
    deviation of the noise on ``ln|H|`` (from the residual about the running mean, running median of
    its square over 31 points): a single-bin noise spike is averaged down by sqrt(5) and stays below
    that, a resonance spanning several bins does not (a weak mode 10 times below its neighbours, 0.66
    in ln|H|, against noise bumps up to 0.1 at 5 % noise). Peaks are ranked by their prominence in the
    smoothed ``|H|`` (scipy.signal.find_peaks); the frequency returned is that of the largest ``|H|`` within
    two points of the smoothed peak. Without noise (or with fewer than 15 points) every interior
    maximum of ``|H|`` counts. Lines where ``H`` is exactly 0 (a dropout or a line the exporter masked:
    noise alone never gives an exact 0) are left out, as missing (:func:`without_zero_lines`), and a peak next
    to a block of at least :data:`ZERO_BLOCK_LINES` of them is no resonance (the mode's own peak may lie inside).

    Raises
    ------
    ModelError
        No resonance; fewer significant peaks than ``count`` (naming those found): two modes
        closer than their bandwidth show as one peak, a weak mode may sink into the noise.
    """
    f, H = _without_dc(array_1d("freqs_hz", freqs_hz, min_len=5), H)
    edge = _block_edges(H) if np.ndim(H) == 1 and np.size(H) == f.size else None
    f, H = without_zero_lines(f, H)
    Hd = np.abs(to_displacement_form(f, H, kind))
    if count is not None:
        count = integer("count", count, 1)
    if f.size < 3:  # (all but a line or two missing: no interior maximum)
        peaks, prominences, noted = np.empty(0, int), np.empty(0), ""
    elif f.size >= 15 and np.all(Hd > 0.0):
        L = np.log(Hd)
        Ls = uniform_filter1d(L, 5, mode="nearest")  # (the ends padded with the end values)
        r = L - Ls
        sig = np.sqrt(median_filter(r * r, 31, mode="nearest") / 0.455)  # (median of chi^2 with one degree: 0.455)
        peaks, props = find_peaks(Ls, prominence=0.0)
        keep = props["prominences"] >= PEAK_NOISE_FACTOR * sig[peaks]
        cand = peaks[keep]
        # ranked by the prominence of the smoothed |H| (a noisy sample's own prominence is the noise's)
        lin = find_peaks(np.exp(Ls), prominence=0.0)
        lin_prom = dict(zip(lin[0].tolist(), lin[1]["prominences"].tolist()))
        prominences = np.array([lin_prom.get(int(p), 0.0) for p in cand])
        # the frequency: the largest raw |H| within two points of the smoothed peak
        peaks = np.array([max(0, p - 2) + int(np.argmax(Hd[max(0, p - 2) : p + 3])) for p in cand], dtype=int)
        noted = f" (of {keep.size} local maxima of the smoothed |H|, {np.count_nonzero(~keep)} within the noise)"
    else:
        peaks, props = find_peaks(Hd, prominence=0.0)
        prominences = props["prominences"]
        noted = ""
    if edge is not None and peaks.size:  # (a block of missing lines: the mode's own peak may lie inside it)
        at_edge = edge[peaks]
        if np.any(at_edge):
            noted += (
                f" ({np.count_nonzero(at_edge)} peak(s) at {', '.join(f'{v:.6g}' for v in f[peaks[at_edge]])} Hz left "
                f"out: next to {ZERO_BLOCK_LINES} or more missing lines, exactly 0, where the resonance's own peak "
                "may lie)"
            )
            peaks, prominences = peaks[~at_edge], prominences[~at_edge]
    if peaks.size == 0:
        raise ModelError(
            "H", "FRF without a peak", "needs at least one resonance (interior maximum of |H| above the noise)" + noted
        )
    order = np.argsort(prominences)[::-1]
    if count is not None:
        if peaks.size < count:
            found = ", ".join(f"{v:.6g}" for v in np.sort(f[peaks]))
            raise ModelError(
                "count",
                count,
                f"the FRF has only {peaks.size} resonance peak(s) above its noise, at {found} Hz{noted}: two modes "
                "closer than their half-power bandwidth show as one peak and a weak one may sink into the noise; "
                "give the resonances themselves (f_res_hz, --freqs) or a smaller count",
            )
        order = order[:count]
    return np.sort(f[peaks[order]])


def spectrum_peaks(x, fs, count=None):
    """Frequencies (Hz, ascending) of the ``count`` most prominent peaks of the amplitude spectrum of
    the record ``x`` (any unit, sampled at ``fs`` Hz; every peak above the noise when ``count`` is None):
    start frequencies for :func:`~.wavelet.wavelet_damping` of an impulse response.

    The spectrum is |FFT| of ``x`` through the periodic Hann window (``scipy.signal.get_window``, as
    the package's PSDs and band levels take it), without its 0 Hz and Nyquist lines; its peaks are
    :func:`find_resonances`' (noise-aware, ranked by prominence).

    Raises
    ------
    ModelError
        ``x`` whose spectrum has no peak above its noise; a ``count`` larger than the number of
        peaks it has (naming that number).
    """
    from scipy.signal import get_window

    x = array_1d("x", x, min_len=12)  # (the 5 lines find_resonances needs between 0 Hz and Nyquist)
    fs = number("fs", fs, gt=0, unit="Hz")
    if count is not None:
        count = integer("count", count, 1)
    X = np.abs(np.fft.rfft(x * get_window("hann", x.size)))
    f = np.fft.rfftfreq(x.size, 1.0 / fs)
    try:
        found = find_resonances(f[1:-1], X[1:-1])  # (every peak above the noise, in frequency order)
    except ModelError as exc:  # (no peak at all: said of the record, not of an FRF)
        if exc.key != "H":
            raise
        raise ModelError("x", plain("the record"), "has no peak above its noise in its amplitude spectrum") from None
    if count is None:
        return found
    if found.size < count:
        raise ModelError(
            "count",
            count,
            f"must be at most {found.size}: the amplitude spectrum of the record has {found.size} peak(s) above "
            "its noise",
        )
    return find_resonances(f[1:-1], X[1:-1], count=count)


def _half_power_eta(f, A, j, lo, hi):
    """Loss factor estimate from the half-power points of |H| around its peak at index j, sought
    within indices lo..hi (the search band, which stops halfway to a neighbouring requested mode).
    Half-power points at ``omega_r^2 (1 -+ eta)``: from both sides ``(f_hi^2 - f_lo^2) / (2 f_j^2)``;
    where |H| does not fall to half power on one side within the band (a neighbour of opposite sign
    keeps it high between the two peaks), from the side where it does, ``|f_side^2 - f_j^2| / f_j^2``.
    None when it falls on neither side."""
    half = A[j] / np.sqrt(2.0)
    below = np.nonzero(A[lo:j] <= half)[0]
    above = np.nonzero(A[j + 1 : hi + 1] <= half)[0]
    widths = []
    if below.size:
        widths.append(f[j] ** 2 - f[lo + below[-1]] ** 2)
    if above.size:
        widths.append(f[j + 1 + above[0]] ** 2 - f[j] ** 2)
    if not widths:
        return None
    return float(np.mean(widths)) / f[j] ** 2


def _modal_estimate(f, Hd, fc, eta0, bandwidths, lo_hz, hi_hz):
    """Resonance (Hz) and loss factor of one structural mode ``A / (omega_r^2 (1 + i eta) - omega^2) + B``
    fitted to the displacement-form FRF by complex least squares (A, B eliminated: variable projection),
    over ``omega^2`` within ``omega_r^2 (1 +- bandwidths eta)`` of the current estimate, window and fit
    iterated until they settle. This sets the circle's window; it does not depend on the height of
    the one sample at the peak, as the half-power estimate does (10 % noise on |H| took that window
    to 11 points and the loss factor 74 % low). Returns the start values when the fit fails."""
    w2_all = (2.0 * np.pi * f) ** 2
    fr, eta = float(fc), float(eta0)
    sgn = None  # the sign convention (+1: 1 + i eta, -1: conjugate data), chosen on the first window
    for _ in range(8):
        wr2 = (2.0 * np.pi * fr) ** 2
        m = (w2_all >= wr2 * (1.0 - bandwidths * eta)) & (w2_all <= wr2 * (1.0 + bandwidths * eta))
        m &= (f >= lo_hz) & (f <= hi_hz)
        if m.sum() < 6:
            break
        w2, z = w2_all[m], Hd[m] / (np.max(np.abs(Hd[m])) or 1.0)  # (scaled: least_squares' gtol is absolute)
        best = None
        for sg in (1.0, -1.0) if sgn is None else (sgn,):

            def res(p, w2=w2, z=z, sg=sg):
                d = _structural_mode(w2, p[0], p[1], sg)
                M = np.column_stack([d, np.ones_like(d)])
                coef = np.linalg.lstsq(M, z, rcond=None)[0]
                r = M @ coef - z
                return np.concatenate([r.real, r.imag])

            try:
                sol = least_squares(
                    res,
                    [min(max(wr2, w2[0]), w2[-1]), min(max(eta, 1e-6), 1.0)],
                    x_scale=[wr2 * eta, eta],
                    bounds=([w2[0], 1e-6], [w2[-1], 1.0]),
                    xtol=1e-10,
                    ftol=1e-12,
                )
            except (ValueError, np.linalg.LinAlgError):
                continue
            if best is None or sol.cost < best[0].cost:
                best = (sol, sg)
        if best is None:
            break
        sol, sgn = best
        fr_new, eta_new = float(np.sqrt(sol.x[0]) / (2.0 * np.pi)), float(sol.x[1])
        done = abs(eta_new - eta) <= 1e-3 * eta and abs(fr_new - fr) <= 1e-4 * eta * fr
        fr, eta = fr_new, eta_new
        if done:
            break
    if not (np.isfinite(fr) and np.isfinite(eta) and eta > 0 and lo_hz <= fr <= hi_hz):
        return float(fc), float(eta0)
    return fr, eta


def _without_dc(f, H):
    """``f`` and ``H`` without a 0 Hz (DC) line: an analyser's export often starts with one, whose
    displacement form is undefined for every kind but ``"displacement"`` (``-omega^2`` times an
    apparent mass that is infinite there, or a division by ``omega``) and which no resonance uses."""
    H = np.asarray(H)
    if f[0] == 0.0 and H.ndim == 1 and H.size == f.size:
        return f[1:], H[1:]
    return f, H


#: Least number of consecutive exact-zero lines that :func:`find_resonances` takes for a block of missing lines
#: (a masked band), next to which a peak is no resonance: the mode's own peak may lie inside the block. Shorter
#: runs are dropouts, whose neighbours stay resonances (30 % of the lines zeroed at random, 200 draws: with 8 every
#: peak of three modes found, with 5 two draws refused and one wrong, with 3 a third of the draws lost a mode).
ZERO_BLOCK_LINES = 8


def _block_edges(H):
    """For each line of ``H`` that is not exactly 0, whether it borders a run of at least
    :data:`ZERO_BLOCK_LINES` exact zeros (in the order of :func:`without_zero_lines`' kept lines)."""
    z = np.concatenate([[False], np.asarray(H) == 0, [False]]).astype(np.int8)
    d = np.diff(z)
    starts, ends = np.flatnonzero(d == 1), np.flatnonzero(d == -1)  # (a run is H[starts:ends])
    near = np.zeros(z.size - 2, dtype=bool)
    for a, b in zip(starts, ends):
        if b - a >= ZERO_BLOCK_LINES:
            if a > 0:
                near[a - 1] = True
            if b < near.size:
                near[b] = True
    return near[np.asarray(H) != 0]


def without_zero_lines(f, H):
    """``f`` and ``H`` without the lines where ``H`` is exactly 0 (0 + 0i): a dropout, or a line the exporter
    masked (overload rejection, a band cut off). Noise alone never gives an exact 0, so such a line is no
    measurement; as a point of the FRF it would be one at the origin (a circle's outlier) and a hole of
    ``ln|H|`` (one made the peak search count every noise wiggle as a resonance). The fits leave these
    lines out, as missing; the readers name them (``uff_io``). ``H`` of another length than ``f`` is
    returned as it is (the caller refuses it)."""
    H = np.asarray(H)
    if H.ndim != 1 or H.size != np.size(f):
        return f, H
    kept = H != 0
    return (f, H) if kept.all() else (f[kept], H[kept])


def _nearest_peak(f, A, f0, search):
    """``(band, j)``: the indices of ``f`` within +-search of f0 (Hz) and the local maximum of ``A`` (|H|) there
    nearest f0, not the band's largest (a stronger neighbour within the band would take the request of a weaker
    mode); the band's largest when it has no interior maximum."""
    band = np.nonzero((f >= f0 * (1.0 - search)) & (f <= f0 * (1.0 + search)))[0]
    if band.size < 3:
        return band, None
    inner = band[1:-1]
    peaks = inner[(A[inner] >= A[inner - 1]) & (A[inner] >= A[inner + 1])]
    return band, (peaks[np.argmin(np.abs(f[peaks] - f0))] if peaks.size else band[np.argmax(A[band])])


def _fit_one(f, Hd, f0, search, lo_hz, hi_hz, eta_prev, fr_prev, bandwidths, min_side, missing=()):
    """Circle, resonance and loss-factor plane of the mode near f0 on displacement-form data Hd: its
    peak is the one nearest f0 within +-search, which must lie within lo_hz..hi_hz (no further than
    halfway to a neighbouring request), where its half-power points and one-mode fit are sought; the
    loss factor by Eq. 45 (the module docstring's step 4). ``missing``: the frequencies (Hz) of the
    lines left out as exact zeros (:func:`without_zero_lines`), named in a refusal for too few points
    when the window lost some."""
    A = np.abs(Hd)
    if fr_prev is None:
        band, j = _nearest_peak(f, A, f0, search)
        if band.size < 3:
            raise ModelError("f_res_hz", float(f0), f"fewer than 3 FRF points within +-{100 * search:g} %")
        if j == band[0] or j == band[-1]:
            raise ModelError(
                "f_res_hz",
                float(f0),
                f"no resonance in the window {f[band[0]]:g}..{f[band[-1]]:g} Hz: |H| has no "
                "interior maximum there (give the frequency of a peak)",
            )
        if not lo_hz <= f[j] <= hi_hz:
            other = 2.0 * (lo_hz if f[j] < lo_hz else hi_hz) - f0  # (the halfway point's other request)
            if _nearest_peak(f, A, other, search)[1] == j:
                why = (
                    f"the requests at {min(f0, other):.6g} and {max(f0, other):.6g} Hz share this one peak: two modes "
                    "closer than about their half-power bandwidth merge into one (or one mode is requested twice), "
                    "which no circle fit separates; request one of them (its eta then holds the other's share too, "
                    "which its uncertainty does not cover: two equal modes 0.4 bandwidths apart gave eta +25 %)"
                )
            else:
                why = "give each mode once, at its own peak"
            raise ModelError(
                "f_res_hz",
                float(f0),
                f"the peak of |H| nearest it, at {f[j]:g} Hz, lies beyond halfway to the neighbouring request at "
                f"{other:.6g} Hz ({lo_hz:g}..{hi_hz:g} Hz): {why}",
            )
        own = np.nonzero((f >= lo_hz) & (f <= hi_hz))[0]
        eta0 = _half_power_eta(f, A, j, own[0], own[-1])
        if eta0 is None or eta0 <= 0.0:  # (the band's half-width in omega^2, as bandwidths eta)
            eta0 = (hi_hz**2 - lo_hz**2) / (2.0 * f[j] ** 2) / bandwidths
        fc = f[j]
    else:
        eta0, fc = eta_prev, fr_prev
    fc, eta0 = _modal_estimate(f, Hd, fc, eta0, bandwidths, lo_hz, hi_hz)
    lo2 = fc**2 * (1.0 - bandwidths * eta0)
    hi2 = fc**2 * (1.0 + bandwidths * eta0)
    win = np.nonzero((f**2 >= lo2) & (f**2 <= hi2))[0]
    if win.size < 2 * min_side + 1:
        gone = int(np.count_nonzero((np.asarray(missing) ** 2 >= lo2) & (np.asarray(missing) ** 2 <= hi2)))
        if gone:  # (lines the FRF lacks, not a resolution or noise matter)
            raise ModelError(
                "freqs_hz",
                f"{win.size} points near {f0:g} Hz",
                f"{gone} lines of the FRF within {np.sqrt(max(lo2, 0)):g}..{np.sqrt(max(hi2, 0)):g} Hz (the circle's "
                f"window, {bandwidths:g} half-power bandwidths eta f_r wide, of the one-mode estimate, eta = "
                f"{eta0:.3g}) are missing: exactly 0 in the FRF (a dropout or lines the exporter masked), left out; "
                f"the circle needs at least {2 * min_side + 1} points there: measure the resonance again, or leave "
                "this mode out",
            )
        raise ModelError(
            "freqs_hz",
            f"{win.size} points near {f0:g} Hz",
            f"too coarse a resolution, or too noisy an FRF: the circle needs at least {2 * min_side + 1} points "
            f"within {np.sqrt(max(lo2, 0)):g}..{np.sqrt(max(hi2, 0)):g} Hz (a window {bandwidths:g} half-power "
            f"bandwidths eta f_r wide, f_r +-{bandwidths / 2:g} eta f_r, of the one-mode estimate, eta = {eta0:.3g}, "
            f"at df = {float(np.median(np.diff(f))):.4g} Hz); "
            "noise on H can take that estimate far below the mode's loss factor though the lines are fine "
            "enough for it (10 % complex noise, 17 lines per bandwidth: 5 of 200 draws): average more, or give "
            "a larger bandwidths",
        )
    fw, zw = f[win], Hd[win]
    c, R, rms = fit_circle(zw)
    phi = np.unwrap(np.angle(zw - c))
    w2 = (2.0 * np.pi * fw) ** 2
    sense = 1 if phi[-1] < phi[0] else -1
    wr2 = (2.0 * np.pi * fc) ** 2  # (the modal estimate: the window's centre)
    phi_r0 = float(np.interp(wr2, w2, phi))
    spread = float(np.ptp(phi))
    eta_init = max(eta0, 1e-6)

    def law(p):
        ph_r, wr2_, et = p
        return ph_r + sense * 2.0 * np.arctan((wr2_ - w2) / (et * wr2_)) - phi

    sol = least_squares(
        law,
        [phi_r0, wr2, eta_init],
        x_scale=[1.0, wr2 * eta_init, eta_init],
        bounds=([-np.inf, w2[0], 1e-9], [np.inf, w2[-1], np.inf]),
        xtol=1e-14,
        ftol=1e-14,
        gtol=1e-14,
    )
    phi_r, wr2, eta_fit = (float(v) for v in sol.x)
    wr2_sd = _resonance_sd(zw, c, R, phi, sol)
    below = np.nonzero(w2 < wr2)[0][::-1]  # nearest first
    above = np.nonzero(w2 > wr2)[0]
    if below.size < min_side or above.size < min_side:
        raise ModelError(
            "f_res_hz",
            float(f0),
            f"no resonance in the window {fw[0]:g}..{fw[-1]:g} Hz: the angle on the fitted circle sweeps fastest "
            f"at {np.sqrt(wr2) / (2 * np.pi):g} Hz, with fewer than {min_side} circle points on one side",
        )
    # The paper's Eq. 45, in Ewins' half-angle form (module docstring, step 4): the loss-factor plane
    tb = np.tan(np.abs(phi[below] - phi_r) / 2.0)
    ta = np.tan(np.abs(phi[above] - phi_r) / 2.0)
    plane = (w2[above][None, :] - w2[below][:, None]) / (wr2 * (ta[None, :] + tb[:, None]))
    m = min(below.size, above.size)
    diag = plane[np.arange(m), np.arange(m)]
    eta = float(np.median(diag))
    ephi = np.exp(1j * phi_r)
    mode_const = 2.0 * R * ephi * 1j * sense * eta * wr2
    return dict(
        f_r_hz=float(np.sqrt(wr2) / (2 * np.pi)),
        eta=eta,
        eta_angle_fit=eta_fit,
        centre=c,
        radius=R,
        rms=rms,
        phi_r=phi_r,
        sense=sense,
        modal_constant=mode_const,
        offset=c - R * ephi,
        freqs_hz=fw,
        points=zw,
        f_below_hz=fw[below],
        f_above_hz=fw[above],
        plane=plane,
        diagonal=diag,
        spread=spread,
        f_r_sd=float(np.sqrt(wr2) / (2 * np.pi) * wr2_sd / (2.0 * wr2)),
    )


def _resonance_sd(z, c, R, phi, sol):
    """Standard deviation of the fitted omega_r^2 (rad^2/s^2) for noise on the circle's points ``z``: the
    circle (centre ``c``, radius ``R``) and the angle law (``sol``: phi_r, omega_r^2, eta) taken as one
    least-squares problem in the points' radial and tangential residuals (each the noise's component
    along it), ``s^2 (J^T J)^-1`` with ``s^2`` their sum of squares over (2 points - 6 parameters). The
    centre's error, which the angle law alone does not see, enters through the tangential rows."""
    d = np.abs(z - c)
    cs, sn = np.cos(phi), np.sin(phi)
    n = z.size
    J = np.zeros((2 * n, 6))
    J[:n, 0], J[:n, 1], J[:n, 2] = -cs, -sn, -1.0  # radial: |z - c| - R
    J[n:, 0], J[n:, 1] = R * sn / d, -R * cs / d  # tangential: R (angle(z - c) - law)
    J[n:, 3:] = -R * sol.jac
    r = np.concatenate([d - R, -R * sol.fun])
    dof = 2 * n - 6
    try:
        cov = np.linalg.inv(J.T @ J) * (float(r @ r) / dof)
    except np.linalg.LinAlgError:
        return np.inf
    return float(np.sqrt(abs(cov[4, 4])))


def loss_factor_circle(
    freqs_hz,
    H,
    f_res_hz=None,
    kind="displacement",
    count=None,
    bandwidths=BANDWIDTHS,
    search=SEARCH,
    correct_neighbours=True,
    max_iter=MAX_ITER,
    min_side=3,
    window_tau=None,
):
    """Loss factors of the resonances of an FRF from Nyquist circles (Section 3.2.2, Eq. 45, Fig. 13).

    Parameters
    ----------
    freqs_hz : array (n,)
        Strictly increasing frequencies (Hz).
    H : complex array (n,)
        The FRF (any of :data:`FRF_KINDS`; the paper's TRFAM is ``"apparent_mass"``, kg).
    f_res_hz : array or None
        Approximate resonance frequencies (Hz); None takes the ``count`` most prominent peaks.
    kind : str
        FRF type, see :func:`to_displacement_form`.
    bandwidths : float
        Full width of the fitted window in half-power bandwidths ``B = eta f_r``: ``omega^2`` within
        ``omega_r^2 (1 +- bandwidths * eta)``, so ``f`` within about ``f_r +- (bandwidths / 2) B``
        (2: ``f_r +- B``, centre angles up to about +-127 degrees; 1: the half-power points, +-90).
    search : float
        Relative half-width (0 < search < 1) around each ``f_res_hz`` searched for the peak of ``|H|``
        and its one-mode estimate; the search stops halfway to the neighbouring requests.
    correct_neighbours : bool
        Subtract the fitted terms of the other requested modes, and of resonance peaks within
        ``+-search`` of a request that were not requested, and refit (module docstring, step 5).
    max_iter : int
        Limit of correction sweeps (default :data:`MAX_ITER`, 500).
    min_side : int
        Least number of circle points required below and above the resonance.
    window_tau : float or None
        Time constant (s) of an exponential window ``exp(-t / tau)`` applied to the response (impact
        testing) before the FRF was computed. It moves every pole by ``i / tau``: a mode
        ``omega_r^2 (1 + i eta)`` (Eq. 11) is measured as ``lambda_obs^2`` with
        ``lambda_obs = omega_r sqrt(1 + i eta) + i / tau``, i.e. ``eta`` about ``2 / (tau omega_r)``
        too high (a viscous mode's ``zeta`` by ``1 / (tau omega_r)``, and ``eta ~ 2 zeta``). The
        shift is taken off exactly: ``lambda = lambda_obs - i / tau``, ``omega_r^2 = Re lambda^2``,
        ``eta = Im lambda^2 / Re lambda^2``; ``f_r_hz`` and ``eta`` are then the structure's, the
        measured ones in ``extra["f_r_windowed_hz"]``, ``extra["eta_windowed"]`` (the circle, plane
        and ``modal_constant`` stay those of the windowed FRF). None: no window.

    Returns
    -------
    list of :class:`CircleFitResult`, ascending in frequency order of ``f_res_hz``.
    ``extra["eta_rel_uncertainty"]`` estimates the loss factor's relative random error,
    ``2.8 (rms / R) / sqrt(points)``; ``extra["f_r_uncertainty_hz"]`` is one standard deviation of
    ``f_r`` (Hz) for noise on H (circle and angle law as one least-squares problem: :func:`_resonance_sd`;
    about 0.95 of the scatter over noise draws alone, 0.68 beside a neighbour 1.5 half-power bandwidths
    away, whose fit's noise the neighbour correction does not carry into it: docs/identification.md);
    ``extra["lines_per_bandwidth"]`` is ``eta f_r / df``, ``extra["leakage_bias"]`` the relative bias of
    eta a Hann window's leakage would cause, were the FRF a Welch estimate (:func:`_leakage_bias`);
    ``extra["unrequested_hz"]`` the resonances fitted and subtracted without being requested;
    ``extra["settled"]`` is False when the neighbour correction stopped at ``max_iter`` sweeps with the
    loss factors still changing (a warning says so), ``extra["correction_change"]`` that last sweep's
    largest relative change of a loss factor (about the error left; 0 when settled).
    A 0 Hz line of ``freqs_hz`` is left out, and so are lines where ``H`` is exactly 0 (a dropout or a masked
    line: :func:`without_zero_lines`).

    Warns
    -----
    ModelWarning
        A circle whose rms radial residual exceeds 5 % of its radius (noise or a distorted circle:
        the loss factor's random error is then above about 2 %), and fewer than 14 frequency lines
        per half-power bandwidth (if the FRF is a Welch estimate with a Hann window its leakage
        biases eta by about ``+2 (df / B)^2`` at the true bandwidth B, above 1 %), and a loss factor above
        :data:`VISCOUS_ETA_WARN` (were the damping viscous, eta / 2 would be above zeta by more than
        1 %, and f_r below f_n: :data:`VISCOUS_BIAS`), and a neighbour correction that has not
        settled after ``max_iter`` sweeps (close modes: the loss factors are then off by about the
        last sweep's change).

    Raises
    ------
    ModelError
        Frequencies not increasing, mismatched lengths, an FRF of real values only (a magnitude:
        no circle), ``bandwidths`` not a finite number > 0,
        ``search`` not in (0, 1), no resonance (interior peak / fastest angle sweep) in a window, too
        few points for the circle (a resolution too coarse, or noise), two requests of one resonance
        (fitted within :data:`SAME_POLE_BANDWIDTHS` of a half-power bandwidth).
    """
    bandwidths = number("bandwidths", bandwidths, gt=0)
    search = number("search", search, gt=0, lt=1)
    min_side = integer("min_side", min_side, 1)
    max_iter = integer("max_iter", max_iter, 0)
    f, Hc = _without_dc(array_1d("freqs_hz", freqs_hz, min_len=7), H)
    Hc = array_1d("H", Hc, min_len=7, complex_ok=True).astype(complex)
    if Hc.size != f.size:
        raise ModelError("H", f"{Hc.size} values", f"must have one value per frequency ({f.size})")
    if not np.any(Hc.imag):  # (a magnitude-only export: its |H| peaks, but it has no Nyquist circle)
        raise ModelError(
            "H",
            plain("an FRF of real values only (its imaginary part 0 at every frequency)"),
            "a circle fit needs the complex FRF, real and imaginary parts (or magnitude and phase): a magnitude "
            "|H| alone draws no Nyquist circle; export the complex FRF (natural frequencies for the modulus can "
            "still be taken from the peaks of a magnitude)",
        )
    if np.any(np.diff(f) <= 0):
        k = int(np.argmax(np.diff(f) <= 0))
        raise ModelError(
            "freqs_hz",
            f"{float(f[k])!r} then {float(f[k + 1])!r} at index {k + 1}",
            "frequencies must be strictly increasing (no repeats)",
        )
    f_all, H_all = f, Hc
    missing = f[Hc == 0]  # (named where a circle's window lost lines to them)
    f, Hc = without_zero_lines(f, Hc)  # (a dropout's or a masked line's exact 0: missing, not a point at 0)
    Hd = to_displacement_form(f, Hc, kind)
    if f_res_hz is None:  # (on the lines with their zeros: a peak at the edge of a block of them is no resonance)
        f_res = find_resonances(f_all, H_all, count=count, kind=kind)
    else:
        f_res = np.sort(np.atleast_1d(np.asarray(f_res_hz, dtype=float)))
        bad = (f_res <= f[0]) | (f_res >= f[-1]) | ~np.isfinite(f_res)
        if np.any(bad):
            raise ModelError(
                "f_res_hz", float(f_res[bad][0]), f"must lie inside the FRF's frequency range ({f[0]:g}, {f[-1]:g}) Hz"
            )
    if np.any(np.diff(f_res) == 0.0):
        raise ModelError("f_res_hz", f_res.tolist(), "must name each mode once (a frequency is given twice)")
    requested = f_res
    others = _unrequested_peaks(f, Hd, f_res, search) if correct_neighbours else np.empty(0)
    f_res = np.sort(np.concatenate([f_res, others]))
    try:
        fits, it, change = _fit_all(f, Hd, f_res, search, bandwidths, min_side, correct_neighbours, max_iter, missing)
    except ModelError as exc:
        if not others.size:
            raise
        listed = ", ".join(f"{v:.6g}" for v in others)
        raise ModelError(
            exc.key,
            exc.value,
            f"{exc.allowed} ({listed} Hz: a resonance peak within +-{100 * search:g} % of a request but not requested, "
            "fitted to subtract its tail: request it at its own peak, or give a smaller search)",
        ) from None
    if window_tau is not None:
        window_tau = number("window_tau", window_tau, gt=0, unit="s")
    out = []
    for f0, r in zip(f_res, fits):
        if f0 not in requested:
            continue
        spread = r.pop("spread")
        f_r_sd = r.pop("f_r_sd")
        npts = r["freqs_hz"].size
        ratio = r["rms"] / r["radius"] if r["radius"] > 0 else np.inf
        df = float(np.median(np.diff(r["freqs_hz"])))
        lines = r["eta"] * r["f_r_hz"] / df
        extra = {
            "angle_span": spread,
            "eta_rel_uncertainty": float(2.8 * ratio / np.sqrt(npts)),
            "f_r_uncertainty_hz": f_r_sd,
            "lines_per_bandwidth": float(lines),
            "unrequested_hz": [r2["f_r_hz"] for g, r2 in zip(f_res, fits) if g not in requested],
            "settled": change == 0.0,
            "correction_change": change,
        }
        if ratio > RMS_RATIO_WARN:
            warnings.warn(
                f"the circle at {r['f_r_hz']:.6g} Hz scatters by rms/R = {ratio:.3g} (above {RMS_RATIO_WARN:g}) "
                f"over its {npts} points: if that is noise on the FRF, eta = {r['eta']:.4g} carries a random "
                f"error of about {100 * extra['eta_rel_uncertainty']:.2g} % (average more); if the FRF is not noisy "
                "(a model's, or many averages), the mode is not one circle there (a close mode's tail, "
                "nonlinearity): check the circle plot",
                ModelWarning,
                stacklevel=2,
            )
        bias = _leakage_bias(lines)
        extra["leakage_bias"] = bias
        if bias > LEAKAGE_BIAS_WARN:
            if np.isfinite(bias):
                size = (
                    f"its leakage widens the true bandwidth B to B (1 + 2 (df / B)^2), so B is about "
                    f"{np.sqrt(2.0 / bias) * df:.4g} Hz ({np.sqrt(2.0 / bias):.3g} lines) and eta about "
                    f"{100 * bias:.2g} % too high"
                )
            else:
                size = "its leakage alone spans more than that (2.8 lines at least): eta may be twice too high or more"
            warnings.warn(
                f"the resonance at {r['f_r_hz']:.6g} Hz spans only {lines:.3g} frequency lines (df = {df:.4g} Hz) "
                f"in its fitted half-power bandwidth eta f_r = {r['eta'] * r['f_r_hz']:.4g} Hz: if the FRF is a "
                f"Welch estimate with a Hann window, {size}; a finer resolution (longer segments, at least "
                f"{np.sqrt(2.0 / LEAKAGE_BIAS_WARN):.0f} lines per bandwidth) keeps that below 1 %",
                ModelWarning,
                stacklevel=2,
            )
        if window_tau is not None:
            lam = (2.0 * np.pi * r["f_r_hz"]) * np.sqrt(1.0 + 1j * r["sense"] * r["eta"]) - 1j * r["sense"] / window_tau
            lam2 = lam * lam
            extra["eta_windowed"], extra["f_r_windowed_hz"] = r["eta"], r["f_r_hz"]
            eta_s = r["sense"] * lam2.imag / lam2.real
            if not (lam2.real > 0 and eta_s > 0):
                raise ModelError(
                    "window_tau",
                    window_tau,
                    f"taking the window's decay 1/tau = {1 / window_tau:.4g} 1/s off the mode at {r['f_r_hz']:.6g} Hz "
                    f"(eta = {r['eta']:.4g} measured) leaves no damping: give the window's time constant in s",
                )
            r["eta"], r["f_r_hz"] = float(eta_s), float(np.sqrt(lam2.real) / (2.0 * np.pi))
        if r["eta"] > VISCOUS_ETA_WARN:
            table = np.array(VISCOUS_BIAS)
            b_eta, b_f = (np.interp(r["eta"], table[:, 0], table[:, k]) for k in (1, 2))
            more = " or more" if r["eta"] > table[-1, 0] else ""
            warnings.warn(
                f"eta = {r['eta']:.4g} at {r['f_r_hz']:.6g} Hz is large: the circle fit assumes structural "
                f"damping; were the damping viscous, eta / 2 would be about {100 * b_eta:+.2g} %{more} off zeta and "
                f"f_r {100 * b_f:+.2g} %{more} off the natural frequency (docs/identification.md, Limits): for "
                "viscous damping take zeta from the wavelet ridges of an impulse response (identify damping)",
                ModelWarning,
                stacklevel=2,
            )
        out.append(CircleFitResult(f_requested_hz=float(f0), iterations=it, extra=extra, **r))
    return out


def _leakage_bias(lines):
    """Relative bias of eta from a Hann window's leakage, ``2 (df / B)^2`` at the true half-power bandwidth
    ``B``, from the fitted bandwidth in lines ``L = B_fit / df`` (``extra["lines_per_bandwidth"]``): the
    leakage widens ``B`` to ``B (1 + 2 (df / B)^2)``, so ``L = x + 2 / x`` with ``x = B / df`` and
    ``x = (L + sqrt(L^2 - 8)) / 2`` (evaluated at the fitted ``L`` instead, the bias came out 9.8 % and
    15 % where it was 12.5 % and 25 %). inf below ``L = sqrt 8`` (2.8 lines), the least this law widens
    any bandwidth to: the bias is then 100 % or more."""
    if not lines**2 >= 8.0:
        return np.inf
    x = 0.5 * (lines + np.sqrt(lines**2 - 8.0))
    return 2.0 / x**2


def _unrequested_peaks(f, Hd, f_res, search):
    """Resonance peaks of |H| (:func:`find_resonances`) within +-search of a request other than the
    request's own (the peak nearest it): neighbours whose tails the correction subtracts too."""
    try:
        peaks = find_resonances(f, Hd)
    except ModelError:  # (no peak at all: each request's own search says so)
        return np.empty(0)
    near = [peaks[np.abs(peaks - f0) <= search * f0] for f0 in f_res]
    own = {float(p[np.argmin(np.abs(p - f0))]) for p, f0 in zip(near, f_res) if p.size}
    return np.array(sorted({float(q) for p in near for q in p} - own))


def _fit_all(f, Hd, f_res, search, bandwidths, min_side, correct_neighbours, max_iter, missing=()):
    """Every mode of ``f_res`` (ascending) fitted, then refitted with the other modes' fitted terms
    subtracted until the loss factors settle (module docstring, step 5). Each mode's peak and modal
    estimate are sought within +-search of it and no further than halfway to its neighbours in
    ``f_res``. Returns (fits, correction sweeps, the last sweep's largest relative change of a loss factor
    when the sweeps ran out before the loss factors settled, else 0)."""
    lo, hi = f_res * (1.0 - search), f_res * (1.0 + search)
    mids = 0.5 * (f_res[1:] + f_res[:-1])
    lo[1:], hi[:-1] = np.maximum(lo[1:], mids), np.minimum(hi[:-1], mids)
    fits = [
        _fit_one(f, Hd, f0, search, a, b, None, None, bandwidths, min_side, missing) for f0, a, b in zip(f_res, lo, hi)
    ]
    it = 0
    changes, unsettled = [], 0.0
    if correct_neighbours and len(fits) > 1 and max_iter > 0:
        for it in range(1, max_iter + 1):  # noqa: B007  (it is the count read after the loop)
            terms = [
                _structural_mode(
                    (2.0 * np.pi * f) ** 2, (2.0 * np.pi * r["f_r_hz"]) ** 2, r["eta"], r["sense"], r["modal_constant"]
                )
                for r in fits
            ]
            total = np.sum(terms, axis=0)
            new = [
                _fit_one(
                    f,
                    Hd - (total - terms[i]),
                    f0,
                    search,
                    lo[i],
                    hi[i],
                    r["eta"],
                    r["f_r_hz"],
                    bandwidths,
                    min_side,
                    missing,
                )
                for i, (f0, r) in enumerate(zip(f_res, fits))
            ]
            for f0, r in zip(f_res, new):
                if not r["eta"] > 0.0:
                    raise ModelError(
                        "f_res_hz",
                        float(f0),
                        f"the mode's loss factor came out {r['eta']:.3g} once its neighbours' fitted terms were "
                        "subtracted: the modes overlap too much for circles (try --no-correction, "
                        "correct_neighbours=False, or fewer modes)",
                    )
            change = max(abs(a["eta"] - b["eta"]) / b["eta"] for a, b in zip(new, fits))
            fits = new
            if change < 1e-7:
                break
            changes.append(change)
        else:
            _warn_unsettled(changes, max_iter, f_res)
            unsettled = changes[-1]
    # (checked on the final fits: a first fit next to a strong neighbour, 1.4 bandwidths away, sits near
    # it until the neighbour's term is subtracted)
    _check_distinct(f_res, fits, search)
    return fits, it, unsettled


#: Two fitted resonances closer than this share of a half-power bandwidth (eta f_r) are one pole found
#: twice. Two requests of one mode (the second at a noise spike 0.8-1.6 Hz above a 100 Hz mode, eta
#: 0.02) land within 0.002 bandwidths of each other; two real modes 0.75 and 1 bandwidth apart (100 and
#: 101.5 or 102 Hz, eta 0.02) are fitted to their truth once the neighbour correction has settled.
SAME_POLE_BANDWIDTHS = 0.1


def _warn_unsettled(changes, max_iter, f_res):
    """A ModelWarning when the neighbour correction stops at ``max_iter`` sweeps with the loss factors
    still changing: close modes converge slowly, swinging above and below their values (100 and 101.5 Hz
    at eta 0.02, 0.75 bandwidths apart: 451 sweeps; after 50 the loss factors were 4.7 % off and still
    changed by 9 % per sweep), and the last sweep's change is about the error left."""
    where = ", ".join(f"{v:.6g}" for v in f_res)
    warnings.warn(
        f"the neighbouring-mode correction (modes at {where} Hz) did not settle in max_iter = {max_iter} sweeps: "
        f"the loss factors still changed by {changes[-1]:.2g} (relative) in the last sweep, an error of about "
        "that size (close modes converge slowly): give a larger max_iter (the CLI's --max-iter)",
        ModelWarning,
        stacklevel=4,
    )


def _check_distinct(f_res, fits, search):
    """Each requested mode's fitted resonance lies within +-search of its request, and no two
    requests found the same resonance (their resonances closer than :data:`SAME_POLE_BANDWIDTHS`
    of a half-power bandwidth): a :class:`ModelError` naming them otherwise, rather than one mode
    reported twice. Close modes (a bandwidth apart and less) are not refused: the neighbour
    correction separates them."""
    for f0, r in zip(f_res, fits):
        if abs(r["f_r_hz"] - f0) > search * f0:
            raise ModelError(
                "f_res_hz",
                float(f0),
                f"the circle near it has its resonance at {r['f_r_hz']:.6g} Hz, outside +-{100 * search:g} % of "
                "the request: give the frequency of this mode's own peak",
            )
    order = np.argsort([r["f_r_hz"] for r in fits])
    for i, j in zip(order[:-1], order[1:]):
        a, b = fits[i], fits[j]
        width = max(a["eta"], b["eta"], 0.0) * max(a["f_r_hz"], b["f_r_hz"])
        if abs(b["f_r_hz"] - a["f_r_hz"]) < SAME_POLE_BANDWIDTHS * width:
            raise ModelError(
                "f_res_hz",
                [float(f_res[i]), float(f_res[j])],
                f"found the same resonance ({a['f_r_hz']:.6g} and {b['f_r_hz']:.6g} Hz, within "
                f"{SAME_POLE_BANDWIDTHS:g} of a half-power bandwidth, {width:.3g} Hz): request each mode once, at "
                "its own peak",
            )
