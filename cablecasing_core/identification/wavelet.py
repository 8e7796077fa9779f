"""Continuous Morlet (Gabor) wavelet transform and damping identification from its ridges.

Section 3.2.1 of the paper ("Identification of the damping ratio"), after Slavič, Simonovski and
Boltežar, J. Sound Vib. 262 (2003) 291-307 (the paper's Ref. [34]).

Wavelet and normalisation
-------------------------
The wavelet at centre frequency ``f`` (Hz, ``omega_c = 2 pi f``) is the analytic Morlet/Gabor
wavelet, defined by its Fourier transform

    G(omega) = 2 exp(-(omega - omega_c)^2 / (2 sigma_w^2))  for omega > 0,   0 for omega <= 0,
    sigma_w = omega_c / gamma,

i.e. in time ``g(t) = (2 sigma_w / sqrt(2 pi)) exp(-sigma_w^2 t^2 / 2) exp(i omega_c t)``, a Gaussian
envelope of standard deviation ``sigma_t = gamma / omega_c`` (s) under a carrier at ``omega_c``.
``gamma`` (dimensionless) is the classical Morlet parameter (``omega_0`` of Torrence & Compo, the
ratio ``omega_psi / sigma`` of the Gabor wavelet): ``gamma / (2 pi)`` carrier periods fit into one
``sigma_t``. The transform is

    W(u, f) = integral x(t) conj(g(t - u)) dt,

which is a constant-Q Gaussian band-pass filter (L1, "amplitude" normalisation): a harmonic
``a cos(omega_c t + phi)`` gives ``|W| = a`` on its ridge, and a complex exponential
``exp((-sigma + i omega_d) t)`` gives

    |W(u, omega_c)| = 2 exp(-sigma u) exp((sigma^2 - (omega_d - omega_c)^2) gamma^2 / (2 omega_c^2)).

Consequences used below (benchmarks.md, "Damping identification"):

* along any fixed frequency, ``ln|W|`` falls with slope ``-sigma = -zeta omega_n`` (s^-1);
* the ridge (maximum over ``omega_c``) lies at ``omega_ridge = omega_d - sigma^2 / omega_d`` for every
  ``gamma`` ("ridge-frequency correction": ``omega_d = (omega_ridge + sqrt(omega_ridge^2 + 4 sigma^2)) / 2``,
  ``omega_n^2 = omega_d^2 + sigma^2``);
* ``ln|W|`` is exactly a parabola in ``1 / omega_c``, so a three-point parabola in ``1/f`` locates the
  ridge between grid frequencies without bias.

Implementation choice: the transform is computed by FFT (frequency-domain multiplication by the
exact ``G(omega)``, all frequencies of a block in one vectorised numpy pass, zero padding of eight
``sigma_t`` against circular wrap-around). ``scipy.signal.cwt`` was removed from SciPy, and
PyWavelets' ``cwt`` with ``cmor`` wavelets samples the wavelet on a finite grid and converts scales
to frequencies through a tabulated centre frequency, so its amplitude and ridge location carry
discretisation errors; the exact Gaussian filter keeps the closed-form ridge correction exact and
needs only numpy/scipy (PyWavelets is an optional dependency of this package).

Edges and noise
---------------
The record's start (the impulse) and end (zero padding) spoil ``W`` within a few ``sigma_t`` of
each end: samples closer than ``edge_factor * sigma_t`` (default 3, where the missing Gaussian mass
is about 1e-3) to either end are left out. The noise floor of ``|W|`` (about the rms of the noise in
``W``) is estimated over the last quarter of the usable interval as ``median(|W|)`` times the scatter
of ``ln|W|`` about a straight line relative to that of pure noise (pi/sqrt(24) = 0.64), capped at 1:
the noise level where noise dominates, the noise riding on the mode where the mode still stands out,
nearly zero for a clean record (or a value given by the caller). The fit stops where the ridge
first sinks below ``floor_factor`` (default 5) times that floor. The straight line through
``ln|W|`` is weighted by ``|W|`` (additive noise gives ``ln|W|`` a standard deviation ~ noise / |W|).

This module is over 400 lines because it is one method (transform, ridge, window, fit) whose
steps share their arrays and checks.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft

from ..errors import ModelError, ModelWarning
from ..model.validators import array_1d, frequencies, number

#: Default Morlet parameter gamma: sigma_t = 12 / omega_c, i.e. about two carrier periods per sigma_t.
#: It separates modes 25 % apart in frequency by more than 1e-3 in |W| and keeps the edge
#: (3 sigma_t ~ 5.7 periods) short enough for damping ratios of a few per cent.
DEFAULT_GAMMA = 12.0
#: Largest departure (nepers) of ln|W| from the fitted line in the fit window that is accepted when it
#: also exceeds DEPARTURE_NOISE times the noise's scatter there (floor / |W|). On Table 1's record the
#: largest departures were 0.15 (clean, at the window's end) and, at 40-10 dB SNR, at most 5.7 times
#: the noise's scatter; a second hit of 5-50 % 0.02-0.2 s after the first (zeta 7-85 % off) gave
#: 0.38-3.9 nepers at 18-300 times the scatter.
MAX_DEPARTURE = 0.25
#: The ridge search band, widened by this many wavelet bandwidths (f / gamma, the Gaussian's standard
#: deviation), must stay below a mode's alias at fs - f (1 + search): at 4 the Gaussian passes the alias
#: with weight exp(-8) = 3.4e-4 (fs >= 2.45 f with the defaults). The review measured the damping of a
#: single mode 1-1.7 % off at fs = 2.2-2.3 f, 19-86 % at 2.12-2.15 f, and ln|W| beating with the alias
#: by 0.5 nepers at 2.4 f.
ALIAS_BANDWIDTHS = 4.0
DEPARTURE_NOISE = 10.0
#: Memory (bytes) of |W| that :func:`wavelet_damping` holds for the ridge search: one block of rows
#: (time) takes a quarter of it, the blocks kept at most all of it (class ``_Scalogram``).
SCALOGRAM_BYTES = 64e6
#: Smallest gamma accepted: below it the Gaussian reaches 0 Hz (leak 2 exp(-gamma^2/2) > 0.02).
MIN_GAMMA = 3.0
#: Default edge left out at each end of the record and after the impulse, in the wavelet's time
#: spread sigma_t = gamma / (2 pi f): at 3 sigma_t the Gaussian's weight beyond the edge is 1 %.
EDGE_FACTOR = 3.0
#: Default relative half-width of the frequency band searched for each ridge (+-5 %).
SEARCH = 0.05


def wavelet_time_spread(f_hz, gamma=DEFAULT_GAMMA):
    """Standard deviation ``sigma_t = gamma / (2 pi f)`` (s) of the wavelet's Gaussian envelope at ``f_hz`` (Hz)
    (the Morlet wavelet of Section 3.2.1; ``gamma`` dimensionless)."""
    spread = number("gamma", gamma, gt=0) / (2.0 * np.pi * frequencies("f_hz", f_hz))
    return float(spread[0]) if np.ndim(f_hz) == 0 else spread


def edge_length(f_hz, gamma=DEFAULT_GAMMA, edge_factor=3.0):
    """Length (s) at each end of a record spoiled by edge effects at ``f_hz`` (Hz): ``edge_factor * sigma_t``
    (for an undamped signal; :func:`wavelet_damping` adds ``sigma sigma_t^2`` for a decay rate sigma), Section 3.2.1."""
    return number("edge_factor", edge_factor, gt=0) * wavelet_time_spread(f_hz, gamma)


def cwt_morlet(x, fs, freqs_hz, gamma=DEFAULT_GAMMA, max_block_bytes=64e6, magnitude=False):
    """Continuous wavelet transform with the analytic Morlet (Gabor) wavelet, computed by FFT.

    Parameters
    ----------
    x : array (n,)
        Sampled signal (any unit; real or complex; a complex signal keeps only its positive-frequency part).
    fs : float
        Sampling rate (Hz).
    freqs_hz : array (m,)
        Centre frequencies (Hz), each in the open interval (0, fs/2).
    gamma : float
        Morlet parameter (dimensionless, >= 3): envelope standard deviation ``gamma / (2 pi f)`` s,
        bandwidth (standard deviation) ``f / gamma`` Hz.
    max_block_bytes : float
        Memory bound of one vectorised block of frequencies (bytes).
    magnitude : bool
        Return ``|W|`` (float, half the memory of W), taken block by block.

    Returns
    -------
    W : complex array (n, m) (float ``|W|`` with ``magnitude``)
        ``W[k, j] = sum_i x_i conj(g_j(t_i - t_k)) dt`` (time x frequency), in the unit of ``x``;
        amplitude normalisation: ``|W| = a`` on the ridge of ``a cos(2 pi f t)``. See the module
        docstring for the wavelet, and Section 3.2.1 / Fig. 10 of the paper for its use.

    Raises
    ------
    ModelError
        ``fs`` not positive, ``gamma`` below 3, a frequency outside (0, fs/2), a non-finite signal.
    """
    x = array_1d("x", x, min_len=2, complex_ok=True)
    fs = number("fs", fs, gt=0, unit="Hz")
    gamma = number("gamma", gamma, gt=0, le=1e3)  # (larger: a wavelet of more samples than any record)
    if gamma < MIN_GAMMA:
        raise ModelError("gamma", gamma, f"must be at least {MIN_GAMMA:g} (the Gaussian must vanish at 0 Hz)")
    f = frequencies("freqs_hz", freqs_hz, fs)
    n = x.size
    pad = int(np.ceil(8.0 * gamma / (2.0 * np.pi * f.min()) * fs))  # 8 sigma_t: wrap-around below exp(-32)
    nfft = sfft.next_fast_len(n + pad)
    X = sfft.fft(x, nfft)
    omega = 2.0 * np.pi * sfft.fftfreq(nfft, 1.0 / fs)
    positive_bins = omega > 0.0
    om = omega[positive_bins]
    Xp = X[positive_bins]
    out = np.empty((n, f.size), dtype=float if magnitude else complex)
    block = max(1, int(max_block_bytes // (16 * nfft)))
    for j0 in range(0, f.size, block):
        wc = 2.0 * np.pi * f[j0 : j0 + block, None]
        spec = np.zeros((wc.shape[0], nfft), dtype=complex)
        spec[:, positive_bins] = Xp * (2.0 * np.exp(-0.5 * ((om - wc) * (gamma / wc)) ** 2))
        w = sfft.ifft(spec, axis=1)[:, :n].T
        out[:, j0 : j0 + block] = np.abs(w) if magnitude else w
    return out


class _Scalogram:
    """``|W|`` (float) of a record at the frequencies ``1 / inv_f``, computed by blocks of rows (time)
    when the whole would exceed ``budget`` bytes: block ``[lo, hi)`` from the samples
    ``[lo - pad, hi + pad)``, ``pad`` ten sigma_t at the lowest frequency (the Gaussian's weight beyond
    it below exp(-50), as :func:`cwt_morlet`'s own zero padding), so every row equals the whole
    record's transform to rounding; a record that fits in one block is transformed whole. Blocks
    are kept up to ``budget`` bytes in all (the first, where the fit windows lie, are the ones used
    again). A 60 s record at 25.6 kHz held a complex (n x 41) transform, 1.8 GB, of which the fit
    used less than 1 s."""

    def __init__(self, x, fs, inv_f, gamma, budget=None):
        budget = SCALOGRAM_BYTES if budget is None else budget
        self.x, self.fs, self.f, self.gamma = x, fs, 1.0 / inv_f, gamma
        self.pad = int(np.ceil(10.0 * gamma / (2.0 * np.pi * self.f.min()) * fs))
        self.rows = max(4 * self.pad, int(budget // 4 // (8 * self.f.size)))
        self.budget, self.kept = budget, {}

    def block(self, b):
        if b in self.kept:
            return self.kept[b]
        n = self.x.size
        lo, hi = b * self.rows, min(n, (b + 1) * self.rows)
        s0, s1 = max(0, lo - self.pad), min(n, hi + self.pad)  # (the record whole when it fits in one block)
        a = cwt_morlet(self.x[s0:s1], self.fs, self.f, self.gamma, magnitude=True)[lo - s0 : hi - s0]
        if (len(self.kept) + 1) * a.nbytes <= self.budget:
            self.kept[b] = a
        return a

    def blocks(self, mask):
        """``(row indices, |W| rows)`` of the blocks holding the rows where ``mask`` is True."""
        idx = np.nonzero(mask)[0]
        for b in np.unique(idx // self.rows):
            lo = b * self.rows
            sel = idx[(idx >= lo) & (idx < lo + self.rows)]
            yield sel, self.block(int(b))[sel - lo]

    def energy(self, mask):
        """``sum |W|^2`` over the rows where ``mask`` is True, at each frequency."""
        return sum((np.sum(a**2, axis=0) for _, a in self.blocks(mask)), np.zeros(self.f.size))


@dataclass(frozen=True)
class RidgeResult:
    """Damping identified on one wavelet ridge (Section 3.2.1, Fig. 11).

    Frequencies in Hz, ``slope`` in 1/s, times in s, ``noise_floor`` in the unit of the signal.
    ``log_w`` is ``ln|W(t, f_ridge_hz)|`` over the whole record and ``ridge_hz`` the frequency of
    the maximum of ``|W|`` at each time of the fit window (nan elsewhere); ``fit_mask`` marks the samples
    of the straight-line fit ``log_w ~ intercept + slope * t``. ``t`` is on the record's own time
    axis (``t0 + k / fs``; the impulse at t = 0). ``max_departure`` (nepers) is the largest
    ``|ln|W| - line|`` in the fit window (the linearity check); with an exponential window
    (``window_tau``, s) ``slope`` and ``sigma_observed`` (1/s) are the windowed record's decay and
    ``zeta`` the structure's, ``(sigma_observed - 1/window_tau) / omega_n``. ``valid_from_s`` is the
    first time past the impulse's (and any clipping's) edge. ``zeta_sd`` is one standard deviation of ``zeta``
    for noise on the record, the line's slope's over ``omega_n`` (:func:`_slope_sd`).
    """

    f_requested_hz: float
    f_ridge_hz: float
    f_damped_hz: float
    f_natural_hz: float
    zeta: float
    slope: float
    intercept: float
    edge_s: float
    noise_floor: float
    gamma: float
    t: np.ndarray
    log_w: np.ndarray
    ridge_hz: np.ndarray
    fit_mask: np.ndarray
    max_departure: float = float("nan")
    window_tau: float | None = None
    sigma_observed: float = float("nan")
    valid_from_s: float = 0.0
    zeta_sd: float = float("nan")

    @property
    def t_fit(self):
        """(start, end) of the fitted interval (s)."""
        tt = self.t[self.fit_mask]
        return float(tt[0]), float(tt[-1])


def _parabola_vertex(xs, ys):
    """Abscissa and value of the vertex of the parabola through three points (any spacing)."""
    x0, x1, x2 = xs
    y0, y1, y2 = ys
    d01, d12, d02 = x0 - x1, x1 - x2, x0 - x2
    a = (y0 / (d01 * d02)) - (y1 / (d01 * d12)) + (y2 / (d02 * d12))
    b = (y1 - y0) / (x1 - x0) - a * (x0 + x1)
    if a >= 0.0:  # not a maximum: keep the middle point
        return x1, y1
    xv = -b / (2.0 * a)
    c = y1 - a * x1 * x1 - b * x1
    return xv, a * xv * xv + b * xv + c


def _ridge_of_profile(inv_f, logp, f0):
    """Interior local maximum of a profile over a 1/f grid, nearest to f0; parabola in 1/f."""
    interior = np.nonzero((logp[1:-1] > logp[:-2]) & (logp[1:-1] >= logp[2:]))[0] + 1
    if interior.size == 0:
        return None
    j = interior[np.argmin(np.abs(1.0 / inv_f[interior] - f0))]
    xv, _ = _parabola_vertex(inv_f[j - 1 : j + 2], logp[j - 1 : j + 2])
    return 1.0 / xv


def _ridge_per_time(inv_f, logA):
    """Ridge frequency (Hz) at every row of ``logA`` (time x 1/f grid), parabola in 1/f at the arg-max;
    nan at a row whose three points are not all finite (|W| = 0, ln|W| = -inf: a quantised record's
    tail that rounds to zero)."""
    j = np.clip(np.argmax(logA, axis=1), 1, logA.shape[1] - 2)
    rows = np.arange(logA.shape[0])
    x0, x1, x2 = inv_f[j - 1], inv_f[j], inv_f[j + 1]
    y0, y1, y2 = logA[rows, j - 1], logA[rows, j], logA[rows, j + 1]
    finite = np.isfinite(y0) & np.isfinite(y1) & np.isfinite(y2)
    y0, y1, y2 = (np.where(finite, y, 0.0) for y in (y0, y1, y2))
    d01, d12, d02 = x0 - x1, x1 - x2, x0 - x2
    a = (y0 / (d01 * d02)) - (y1 / (d01 * d12)) + (y2 / (d02 * d12))
    b = (y1 - y0) / (x1 - x0) - a * (x0 + x1)
    with np.errstate(divide="ignore", invalid="ignore"):
        xv = np.where(a < 0.0, -b / (2.0 * a), x1)
    return np.where(finite, 1.0 / xv, np.nan)


#: Standard deviation of ln|W| for pure (complex Gaussian) noise: ln of a Rayleigh variable, pi / sqrt(24).
_LN_RAYLEIGH_STD = np.pi / np.sqrt(24.0)


def _tail_noise_floor(t, w, valid):
    """Noise level of |W| on a ridge, estimated over the last quarter of the usable interval.

    With complex noise of rms ``s_W`` in W: where noise dominates, |W| is Rayleigh distributed
    (median 0.83 s_W) and ln|W| scatters about its trend with standard deviation pi/sqrt(24) = 0.64;
    where a mode of amplitude S dominates, ln|W| scatters by s_W / (S sqrt(2)). The estimate
    ``median(|W|) * min(1, scatter / 0.64)`` is therefore about s_W in both cases (0.83 s_W and
    1.1 s_W) and goes to zero for a clean record; the scatter is taken about a straight line.
    """
    idx = np.nonzero(valid)[0]
    tail = idx[int(0.75 * idx.size) :]
    w_tail = w[tail]
    if tail.size < 4 or np.any(w_tail <= 0.0):
        return float(np.median(w_tail)) if tail.size else 0.0
    lt = np.log(w_tail)
    scatter = float(np.std(lt - np.polyval(np.polyfit(t[tail], lt, 1), t[tail])))
    return float(np.median(w_tail)) * min(1.0, scatter / _LN_RAYLEIGH_STD)


def _ridge_and_window(x, fs, t, A, inv_f, f0, gamma, valid, noise_floor, floor_factor, need, edge, search, min_cycles):
    """Ridge frequency from the energy profile over the fit window, and the window from the noise
    floor of |W| on that ridge; alternated until the ridge settles (two or three passes). The first
    window is that of |W| at the requested frequency (the whole usable interval when that leaves too
    little), so the scalogram ``A`` is needed only where the mode stands above the noise, not over
    the rest of a long record."""
    w0 = np.abs(cwt_morlet(x, fs, [f0], gamma)[:, 0])
    floor0 = _tail_noise_floor(t, w0, valid) if noise_floor is None else number("noise_floor", noise_floor, gt=0)
    below0 = valid & (w0 < floor_factor * floor0)
    fit = valid.copy()
    fit[int(np.argmax(below0)) if below0.any() else t.size :] = False
    if fit.sum() < 8 or (t[fit][-1] - t[fit][0]) < need:
        fit = valid.copy()
    f_r = None
    for _ in range(4):
        with np.errstate(divide="ignore"):
            prof = np.log(A.energy(fit))
        f_new = _ridge_of_profile(inv_f, prof, f0)
        if f_new is None:
            raise ModelError("freqs_hz", float(f0), _no_ridge(prof, f0, search))
        w_r = np.abs(cwt_morlet(x, fs, [f_new], gamma)[:, 0])
        if noise_floor is None:
            floor = _tail_noise_floor(t, w_r, valid)
        else:
            floor = number("noise_floor", noise_floor, gt=0)
        below = valid & (w_r < floor_factor * floor)
        stop = int(np.argmax(below)) if below.any() else t.size
        fit = valid.copy()
        fit[stop:] = False
        if fit.sum() < 8 or (t[fit][-1] - t[fit][0]) < need:
            raise ModelError(
                "x",
                f"record at {f0:g} Hz",
                f"the mode sinks into the noise floor (|W| ~ {floor:.3g}) before the edge "
                f"effect ends ({edge:g} s): fewer than {min_cycles:g} periods remain; "
                "give a cleaner or longer record, a smaller gamma or a noise_floor"
                + _late_rise_hint(t, w_r, valid, edge),
            )
        done = f_r is not None and abs(f_new - f_r) <= 1e-9 * f0
        f_r = f_new
        if done:
            break
    return f_r, w_r, fit, floor


def _no_ridge(prof, f0, search):
    """What a ModelError says when the energy profile ``prof`` (over 1/f ascending: its last value at the
    band's lower edge) has no interior maximum within +-search of f0: where |W| is largest, and for
    the lower edge that heavy damping puts the ridge below the natural frequency (module docstring:
    omega_ridge = omega_d - sigma^2 / omega_d = (1 - 2 zeta^2) / sqrt(1 - zeta^2) omega_n, 6 % below at
    zeta = 0.2, 14 % at 0.3)."""
    text = f"no ridge (local maximum of |W|) within +-{100 * search:g} % of this frequency"
    if not np.all(np.isfinite(prof)) or np.argmax(prof) not in (0, prof.size - 1):
        return text + ": give the frequency of a mode present in the record"
    if np.argmax(prof) == prof.size - 1:
        return (
            f"{text}: |W| is largest at the band's lower edge, {f0 * (1 - search):.6g} Hz. A heavily damped "
            "mode's ridge lies below its natural frequency, at (1 - 2 zeta^2) / sqrt(1 - zeta^2) f_n (6 % below "
            "at zeta = 0.2, 14 % at 0.3): widen the search band (search, the CLI's --search, e.g. "
            f"{min(2 * search, 0.45):g}), or give the frequency of a mode present in the record"
        )
    return (
        f"{text}: |W| is largest at the band's upper edge, {f0 * (1 + search):.6g} Hz (a mode above the band): "
        "give the frequency of a mode present in the record, or widen the search band (search, the CLI's --search)"
    )


def _late_rise_hint(t, w, valid, edge):
    """Extra text for a failed window when |W| on the ridge peaks well after the start of the usable
    interval: a free decay is largest at its start, so a late maximum means the record starts
    before the impulse (a pre-trigger segment) or holds a second impact."""
    idx = np.nonzero(valid)[0]
    if idx.size < 2:
        return ""
    k = idx[int(np.argmax(w[idx]))]
    if t[k] - t[idx[0]] <= edge:
        return ""
    return (
        f"; but |W| rises until t = {t[k]:.4g} s, {t[k] - t[idx[0]]:.3g} s after the edge: the record seems to "
        "start before the impulse (a pre-trigger segment: give its time axis, t0 = the first sample's time "
        "with the impulse at t = 0) or to hold a second impact (a double hit: cut the record before it)"
    )


#: A record is a pulse, not a free decay (:func:`_pulse`), when every sample further than PULSE_LEVEL of
#: the largest departure from its median lies within PULSE_SPAN of the record and crosses the median at
#: most twice there (a decay of zeta 0.2 at 100 Hz within 1 % in 37 ms crosses it 7 times).
PULSE_LEVEL, PULSE_SPAN = 0.01, 0.05


def refuse_pulse(x, fs, t0=0.0):
    """A :class:`ModelError` naming ``x`` when the record (samples ``x`` at ``fs`` Hz from ``t0`` s) is a pulse
    (:func:`_pulse`), not a free decay: a force channel, which the ridges would take as clipped and too short."""
    pulse = _pulse(np.asarray(x, dtype=float))
    if pulse is not None:
        a, b = pulse
        raise ModelError(
            "x",
            f"{len(x)} samples ({len(x) / fs:g} s from t = {t0:g} s)",
            f"not a decay: all of it but its level lies in a pulse of {b - a + 1} samples "
            f"({(b - a + 1) / fs * 1e3:.3g} ms, t = {1e3 * (t0 + a / fs):.4g} .. {1e3 * (t0 + b / fs):.4g} ms) that "
            "does not oscillate, then nothing: the force (a hammer's channel), not the response; pick the response "
            "channel (the CLI's --channel)",
        )


def _pulse(x):
    """``(first, last)`` sample of the pulse a record is, or None: every sample departing from the record's
    median by more than PULSE_LEVEL of the largest departure lies in a span of at most PULSE_SPAN of the
    record, in which it changes sign about the median at most twice (a force pulse, a hammer's half-sine,
    then the record's level; a response oscillates). Review Q: an impact UFF whose first channel was the
    1 ms force was diagnosed as clipped (4134 samples at its minimum, the zeros) and too short."""
    d = x - np.median(x)
    peak = float(np.max(np.abs(d)))
    if peak == 0.0:
        return None
    big = np.nonzero(np.abs(d) > PULSE_LEVEL * peak)[0]
    a, b = int(big[0]), int(big[-1])
    if b - a + 1 > PULSE_SPAN * x.size:
        return None
    signs = np.sign(d[big])
    return (a, b) if np.count_nonzero(signs[1:] != signs[:-1]) <= 2 else None


def _clipped_samples(x):
    """Indices of samples stuck at the record's extreme values (a clipped ADC): a rail (the maximum or
    the minimum, to 1e-9 of the range) counts when the record sits on it in two or more separate flat
    runs, as a clipped decay does over consecutive cycles. A run of L samples is flat when L >= 2 and
    its phase span (L - 1) theta exceeds twice the most a sine keeps within one quantisation step q of
    its crest, 2 sqrt(2 q / a) (a the rail's distance from the mean, theta = omega / fs the phase step
    per sample; the factor 2 for theta's estimate); an unclipped quantised decay reaches its top code
    at single samples of several crests (a 12-bit record at 90 % of full scale, zeta 2e-5: four
    crests), or at a few when it is sampled finely. ``theta^2`` is
    the record's own, ``-sum(x'' x) / sum(x^2)`` with the second difference for x'' (a sine obeys
    x'' = -theta^2 x; for several modes their power-weighted mean). Empty otherwise."""
    span = float(np.ptp(x))
    if span == 0.0:
        return np.zeros(0, dtype=int)
    tol = 1e-9 * span
    step = max(_quantisation_step(x), tol)
    xc = x - np.mean(x)
    theta2 = -np.sum(xc[1:-1] * np.diff(x, 2)) / max(np.sum(xc[1:-1] ** 2), 1e-300)
    stuck = []
    for rail, level in ((x >= x.max() - tol, x.max()), (x <= x.min() + tol, x.min())):
        on = np.nonzero(rail)[0]
        runs = np.split(on, np.nonzero(np.diff(on) > 1)[0] + 1)
        a = abs(level - np.mean(x))
        sine_span = 2.0 * np.sqrt(2.0 * step / a) if a > 0 else np.inf  # (radians)
        flat = [r for r in runs if r.size >= 2 and (r.size - 1) * np.sqrt(max(theta2, 0.0)) > 2.0 * sine_span]
        if len(flat) >= 2:
            stuck.append(on)
    return np.sort(np.concatenate(stuck)) if stuck else np.zeros(0, dtype=int)


def _quantisation_step(x):
    """The record's step q (unit of x): its values all whole multiples of q, at most 2**24 steps
    across its range (an ADC's grid); 0 for a record that is not quantised."""
    v = np.unique(x)
    if v.size < 3:
        return 0.0
    q = float(np.min(np.diff(v)))
    if not q > 0.0 or (v[-1] - v[0]) / q > 2.0**24:
        return 0.0
    k = (v - v[0]) / q
    if np.max(np.abs(k - np.round(k))) > 1e-6:
        return 0.0
    return q


def _quantisation_floor(q, f0, fs, gamma):
    """|W| (unit of x) that the rounding of a record quantised in steps of q leaves on the ridge at
    f0 (Hz): white noise of rms q / sqrt(12) through the wavelet's gain |Psi(f)| = 2 exp(-((f - f0)
    gamma / f0)^2 / 2) of :func:`cwt_morlet`: rms = q / sqrt(12) * 2 pi^(1/4) sqrt(f0 / (gamma fs)).
    A clean record whose tail rounds to zero then has this floor instead of none."""
    return q / np.sqrt(12.0) * 2.0 * np.pi**0.25 * np.sqrt(f0 / (gamma * fs))


def _floor3(v):
    """``v`` rounded down to 3 significant digits, as text (a time suggested as a bound)."""
    if v <= 0:
        return f"{v:.3g}"
    e = 10.0 ** (np.floor(np.log10(v)) - 2)
    return f"{np.floor(v / e) * e:.3g}"


#: Least number of exact zeros ending a record that :func:`trailing_padding` takes for padding.
PAD_MIN_SAMPLES = 8


def trailing_padding(x, q=None):
    """The index of the first of the exact zeros that end the record ``x`` when they are padding (a capture
    zero-filled to its length, a power of two), else None: at least :data:`PAD_MIN_SAMPLES` of them, after
    samples that are not a decay rounding to zero (the record is not quantised, its step ``q`` 0, or the 64
    samples before the zeros reach beyond 4 of its steps q: a clean decay below the ADC's step rounds to 0
    from +-1 or 2 steps, and that tail is fitted, :func:`_quantisation_floor`). ``q`` None: the record's
    own step (:func:`_quantisation_step`)."""
    x = np.asarray(x, dtype=float)
    q = _quantisation_step(x) if q is None else q
    nonzero = np.flatnonzero(x)
    k = int(nonzero[-1]) + 1 if nonzero.size else 0
    if x.size - k < PAD_MIN_SAMPLES or k == 0:
        return None
    if q > 0.0 and np.max(np.abs(x[max(0, k - 64) : k])) <= 4.0 * q:
        return None
    return k


def wavelet_damping(
    x,
    fs,
    freqs_hz,
    gamma=DEFAULT_GAMMA,
    edge_factor=EDGE_FACTOR,
    search=SEARCH,
    n_search=41,
    noise_floor=None,
    floor_factor=5.0,
    t_max=None,
    min_cycles=3.0,
    t0=0.0,
    window_tau=None,
    max_departure=MAX_DEPARTURE,
):
    """Damping ratios from the ridges of the Morlet wavelet transform of an impulse response.

    Implements the paper's Section 3.2.1 (Figs. 10-11, Table 1) after Slavič et al. (2003): for a
    mode ``exp(-zeta omega_n t) cos(omega_d t)``, ``ln|W|`` along the ridge falls with slope
    ``-zeta omega_n``; the ridge frequency is corrected to the damped and undamped natural
    frequencies (module docstring). The ``(f_natural_hz, zeta)`` pairs feed Eqs. (41)-(44)
    (:func:`~cablecasing_core.identification.rayleigh.rayleigh_fit`).

    Parameters
    ----------
    x : array (n,)
        Impulse (free) response (any unit), sampled at ``t0 + k / fs``.
    fs : float
        Sampling rate (Hz).
    freqs_hz : array
        Approximate natural frequencies (Hz) of the modes to identify; each, with its ridge search
        band ``f (1 + search)``, must satisfy ``fs >= f (1 + search) (2 + 4 / gamma)`` (see Raises).
    gamma : float
        Morlet parameter (see :func:`cwt_morlet`).
    edge_factor : float
        Samples within ``edge_factor * gamma / (2 pi f)`` s of either end (and of the impulse) are
        left out.
    search : float
        Relative half-width of the frequency band searched for the ridge (0.05: +-5 %).
    n_search : int
        Number of wavelet frequencies (uniform in 1/f) across that band.
    noise_floor : float or None
        Level of ``|W|`` due to noise (signal unit); None estimates it from the record's tail.
    floor_factor : float
        The fit stops where ``|W|`` first falls below ``floor_factor * noise_floor``.
    t_max : float or None
        Optional latest time (s, on the record's time axis) used in the fit (a ModelError naming
        ``t_max`` when it leaves fewer than ``min_cycles`` periods after the edge). In a record ending in a
        padding of exact zeros (:func:`trailing_padding`) the padding's start counts as the record's end,
        the fit ending an edge before it whatever ``t_max`` (a ModelWarning naming the padding when it,
        not ``t_max``, ends the fit).
    min_cycles : float
        Least number of periods that must remain between the edges (and above the noise floor).
    t0 : float
        Time (s) of the first sample, the impulse being at t = 0: a record with a pre-trigger
        segment has ``t0 < 0`` (a UFF 58 abscissa that starts at -0.02 s) and the fit starts an
        edge after t = 0, not after the first sample; a record that starts after the impulse
        (``t0 > 0``) is fitted from its first sample.
    window_tau : float or None
        Time constant (s) of an exponential window ``exp(-t / tau)`` the analyser applied to the
        response (from the impulse): it adds ``1 / tau`` to every decay rate, which is taken off,
        ``sigma = sigma_observed - 1 / tau`` (so ``zeta`` would otherwise be ``1 / (tau omega_n)``
        too high). None: no window.
    max_departure : float or None
        Largest ``|ln|W| - fitted line|`` (nepers) allowed in the fit window (default 0.25, a factor
        1.28 in ``|W|``) where it also exceeds ten times the noise's scatter of ``ln|W|``
        (``noise_floor / |W|``); None skips the check. A free decay of one mode is a straight line there; a
        second impact, a pre-trigger segment or beating with a close mode is not. Late in the window,
        where ``|W|`` is below 1e-2 of its maximum, a departure passes while ``ln|W|`` comes back up
        to the line within +-pi sigma_t (a neighbour's leakage beating with the mode), not where it
        stays below it (a line tilted by a second impact).

    Returns
    -------
    list of :class:`RidgeResult`, one per requested frequency, in the given order.

    Raises
    ------
    ModelError
        A record too short for a requested frequency (edge effects and fewer than ``min_cycles``
        periods), a frequency outside (0, fs/2) or one whose ridge search band comes within four
        wavelet bandwidths (4 f / gamma) of its alias at ``fs - f (1 + search)`` (below
        ``fs = f (1 + search)(2 + 4 / gamma)``, 2.45 f with the defaults: at 2.15 f the damping
        came out 83 % low), no ridge near a requested frequency (heavy damping puts it below f_n:
        6 % at zeta = 0.2; the message then suggests a wider ``search``), a mode that sinks into the noise
        floor before the edge effect ends, a response that grows, ``ln|W|`` departing from the
        fitted line by more than ``max_departure`` (not a single free decay: a double hit, a
        pre-trigger, a close mode), a window time constant that leaves no damping.

    Warns
    -----
    ModelWarning
        Samples stuck at the record's extreme values (clipping): the fit then starts an edge
        after the last of them. A padding of exact zeros that ends the fit (naming where it starts).
    """
    x = array_1d("x", x, min_len=8)
    fs = number("fs", fs, gt=0, unit="Hz")
    gamma = number("gamma", gamma, gt=0, le=1e3)  # (larger: a wavelet of more samples than any record)
    edge_factor = number("edge_factor", edge_factor, gt=0)
    floor_factor = number("floor_factor", floor_factor, gt=0)
    search = number("search", search, gt=0)
    t0 = number("t0", t0, unit="s")
    if t_max is not None:
        t_max = number("t_max", t_max, unit="s")
    if window_tau is not None:
        window_tau = number("window_tau", window_tau, gt=0, unit="s")
    if max_departure is not None:
        max_departure = number("max_departure", max_departure, gt=0)
    if search >= 0.5:
        raise ModelError("search", search, "must be a relative half-width below 0.5")
    if int(n_search) < 5:
        raise ModelError("n_search", n_search, "must be at least 5")
    f_req = frequencies("freqs_hz", freqs_hz, fs)
    n = x.size
    T = n / fs
    t = t0 + np.arange(n) / fs
    t_impulse = max(t0, 0.0)  # (the impulse at t = 0 when the record holds it, else its first sample)
    refuse_pulse(x, fs, t0)
    clipped = _clipped_samples(x)
    if clipped.size:
        t_clip = float(t[clipped[-1]])
        warnings.warn(
            f"x: {clipped.size} samples sit at the record's extreme values ({x.max():.6g} / {x.min():.6g}; "
            f"samples {_index_list(clipped)}, t = {t[clipped[0]]:.4g} .. {t_clip:.4g} s): the record looks "
            "clipped (the ADC's range exceeded), which flattens the decay; the fit starts an edge after the "
            "last of them. Measure again with a larger input range",
            ModelWarning,
            stacklevel=2,
        )
        t_impulse = max(t_impulse, t_clip)
    q = _quantisation_step(x)  # (the record's, once for all its modes)
    t_last = t0 + T  # (where the record ends: its padding's start, if padded)
    pad = trailing_padding(x, q)
    if pad is not None:
        t_last = t0 + pad / fs
        edge0 = edge_factor * wavelet_time_spread(float(np.min(f_req)) * (1.0 - search), gamma)
        if t_max is None or float(t_max) > t_last - edge0:  # (the padding, not t_max, ends the fit: said)
            asked = "" if t_max is None else f" (t_max = {float(t_max):g} s reaches beyond that)"
            warnings.warn(
                f"x: exactly 0 from t = {t_last:.6g} s to its end ({n - pad} samples, {100 * (n - pad) / n:.3g} % "
                "of the record): padding (a capture zero-filled to its length), not part of the decay; the fit "
                f"ends an edge before it, at t = {_floor3(t_last - edge0)} s or earlier (the wavelet's edge, "
                f"{edge0:.3g} s at {float(np.min(f_req)):g} Hz){asked}",
                ModelWarning,
                stacklevel=2,
            )
    results = []
    for f0 in f_req:
        f_hi = f0 * (1.0 + search)
        fs_min = f_hi * (2.0 + ALIAS_BANDWIDTHS / gamma)
        if fs < fs_min:
            raise ModelError(
                "freqs_hz",
                float(f0),
                f"is too close to fs/2 = {fs / 2:g} Hz: its alias at fs - f(1 + search) = {fs - f_hi:g} Hz lies "
                f"within {ALIAS_BANDWIDTHS:g} wavelet bandwidths ({ALIAS_BANDWIDTHS:g} f / gamma) of the ridge search "
                f"band (up to {f_hi:g} Hz) and biases the decay; needs fs >= f (1 + search)(2 + {ALIAS_BANDWIDTHS:g} / "
                f"gamma) = {fs_min:g} Hz (fs = {fs:g} Hz): "
                "sample faster, or give a smaller search or a larger gamma",
            )
        sigma_t = wavelet_time_spread(f0 * (1.0 - search), gamma)
        inv_f = np.linspace(1.0 / (f0 * (1.0 + search)), 1.0 / (f0 * (1.0 - search)), int(n_search))
        A = None
        sigma = 0.0
        for _ in range(5):  # the edge depends on the decay rate: edge_factor sigma_t + sigma sigma_t^2
            edge = edge_factor * sigma_t + max(sigma, 0.0) * sigma_t**2
            t_begin = t_impulse + edge
            t_end = t_last - edge if t_max is None else min(t_last - edge, float(t_max))
            need = min_cycles / f0
            if t_end - t_begin < need and t_max is not None and t_last - edge - t_begin >= need:
                raise ModelError(
                    "t_max",
                    float(t_max),
                    f"cuts the record too short for {f0:g} Hz with gamma = {gamma:g}: the fit needs {min_cycles:g} "
                    f"periods ({need:g} s) after the impulse's edge effect, so t_max >= {t_begin + need:g} s "
                    f"(the record itself runs to {t0 + T:g} s)",
                )
            if t_end - t_begin < need:
                late = ""
                if t_impulse != t0:
                    after_clip = clipped.size and t_impulse > max(t0, 0.0)
                    what = "last clipped sample" if after_clip else "impulse"
                    late = f" (counting from t = {t_impulse:g} s, the {what})"
                raise ModelError(
                    "x",
                    f"{n} samples ({T:g} s from t = {t0:g} s)",
                    f"too short for {f0:g} Hz with gamma = {gamma:g}{late}: needs at least "
                    f"{2 * edge + need:g} s (edge effects of {edge:g} s at each end plus "
                    f"{min_cycles:g} periods)",
                )
            if A is None:
                A = _Scalogram(x, fs, inv_f, gamma)
            valid = (t >= t_begin) & (t <= t_end)
            f_r, w_r, fit, floor = _ridge_and_window(
                x, fs, t, A, inv_f, f0, gamma, valid, noise_floor, floor_factor, need, edge, search, min_cycles
            )
            with np.errstate(divide="ignore"):
                log_w = np.log(w_r)
            slope, intercept = np.polyfit(t[fit], log_w[fit], 1, w=w_r[fit])
            sigma_new = -float(slope)
            done = abs(sigma_new - sigma) <= 1e-6 * abs(sigma_new)
            sigma = sigma_new
            if done:
                break
        if sigma < 0.0:
            raise ModelError(
                "x",
                f"record at {f0:g} Hz",
                f"ln|W| grows along the ridge (slope {slope:g} 1/s): not a decaying free response",
            )
        signed = log_w[fit] - (intercept + slope * t[fit])
        dev = np.abs(signed)
        departure = float(dev.max())
        # beyond max_departure and beyond DEPARTURE_NOISE times the noise's scatter of ln|W| (floor / |W|)
        wf = w_r[fit]
        floor = max(floor, _quantisation_floor(q, f_r, fs, gamma))
        limit = np.inf if max_departure is None else max_departure
        bad = (dev > limit) & (dev * wf > DEPARTURE_NOISE * floor) & ~_leakage_late(signed, wf, limit, sigma_t, fs)
        if bad.any():
            k_dev = int(np.argmax(np.where(bad, dev, -1.0)))
            tf = t[fit]
            raise ModelError(
                "x",
                f"record at {f0:g} Hz",
                f"ln|W| on the ridge departs from the fitted straight line by {dev[k_dev]:.2f} nepers (a factor "
                f"{np.exp(dev[k_dev]):.3g} in |W|, {dev[k_dev] * wf[k_dev] / max(floor, 1e-300):.3g} times "
                f"the noise's scatter) at t = {tf[k_dev]:.4g} s, within the fit window {tf[0]:.4g}..{tf[-1]:.4g} s "
                f"(allowed: max_departure = {max_departure:g} nepers): not the single free decay the method "
                "needs. Likely a second impact (a double hit: cut the record (t_max) before it, or measure again), "
                "a record starting before the impulse (give t0) or a close mode beating with this one"
                + _close_mode_advice(f0, f_req, gamma)
                + ". Skipping the check (max_departure None, --max-departure off) is only for a clean record whose "
                "slower neighbour leaks into the window's end: with a close mode beating it gives wrong numbers "
                "(100 and 115 Hz at gamma 12: f_n 101.17 and 110.68 Hz, zeta +4 %)",
            )
        sigma_obs = sigma
        slope_sd = _slope_sd(t[fit], log_w[fit], wf, slope, intercept, wavelet_time_spread(f_r, gamma) * fs, floor)
        if window_tau is not None:
            sigma = sigma_obs - 1.0 / window_tau
            if sigma <= 0.0:
                raise ModelError(
                    "window_tau",
                    window_tau,
                    f"the record at {f0:g} Hz decays at {sigma_obs:.4g} 1/s, no faster than the window's "
                    f"1/tau = {1.0 / window_tau:.4g} 1/s: give the window's time constant in s (the decay "
                    "rate 1/tau it adds must be below the observed one)",
                )
        w_ridge = 2.0 * np.pi * f_r
        # the ridge's shift is set by the analysed (windowed) envelope, the natural frequency by the structure's
        w_d = 0.5 * (w_ridge + np.sqrt(w_ridge**2 + 4.0 * sigma_obs**2))
        w_n = np.sqrt(w_d**2 + sigma**2)
        ridge_hz = np.full(n, np.nan)
        for rows, a in A.blocks(fit):
            with np.errstate(divide="ignore"):
                ridge_hz[rows] = _ridge_per_time(inv_f, np.log(a))
        results.append(
            RidgeResult(
                f_requested_hz=float(f0),
                f_ridge_hz=float(f_r),
                f_damped_hz=float(w_d / (2 * np.pi)),
                f_natural_hz=float(w_n / (2 * np.pi)),
                zeta=float(sigma / w_n),
                zeta_sd=float(slope_sd / w_n),
                slope=float(slope),
                intercept=float(intercept),
                edge_s=float(edge),
                noise_floor=floor,
                gamma=float(gamma),
                t=t,
                log_w=log_w,
                ridge_hz=ridge_hz,
                fit_mask=fit,
                max_departure=departure,
                window_tau=window_tau,
                sigma_observed=float(sigma_obs),
                valid_from_s=float(t_begin),
            )
        )
    _check_distinct_ridges(results)
    return results


def _slope_sd(t, y, w, slope, intercept, spread_samples, floor):
    """Standard deviation (1/s) of the slope of the straight line ``y ~ intercept + slope t`` through ln|W| on
    the ridge, fitted with weights ``w`` = |W| (residuals times w): ``(X^T W^2 X)^-1`` times the larger of two
    estimates of the weighted residual's variance, the residuals' own (sum of squares over n - 2) and the
    noise's, ``floor^2 / 2`` (noise of rms ``floor`` in W scatters ln|W| by ``floor / (|W| sqrt 2)``; the
    residuals alone under-state it in a window of few wavelet lengths), and times the samples per independent
    one, ``2 sqrt(pi) sigma_t fs`` (``spread_samples`` = sigma_t fs): the noise in W is correlated over the
    wavelet's envelope as ``exp(-tau^2 / (4 sigma_t^2))``, whose integral that is."""
    n = t.size
    if n < 3:
        return float("inf")
    r = w * (y - (intercept + slope * t))
    X = np.column_stack([t - t.mean(), np.ones_like(t)]) * w[:, None]
    var = max(float(r @ r) / (n - 2), 0.5 * floor**2)
    corr = max(1.0, 2.0 * np.sqrt(np.pi) * spread_samples)
    return float(np.sqrt(abs(np.linalg.pinv(X.T @ X)[0, 0]) * var * corr))


#: A larger gamma separates two modes df apart once gamma >= CLOSE_MODE_GAMMA f / df (f the higher): 100
#: and 104 Hz at zeta 1 %, refused at gamma 12 (ln|W| beating by 3.5 nepers), came out 1.6 % low at
#: gamma 60, 0.6-1.2 % at 75 (3 f / df) and within 0.02 % at 100 (4 f / df); 100 and 110 Hz within 0.03 %
#: at 40, 100 and 115 Hz at 27.
CLOSE_MODE_GAMMA = 4.0


def _close_mode_advice(f0, f_req, gamma):
    """What a refusal for a departure from the line says about a close mode (Hz, ``f_req`` the requests):
    the gamma (``CLOSE_MODE_GAMMA f / df``) that separates ``f0`` from the nearest other request when that
    one is closer than the wavelet resolves at ``gamma``, else the rule itself."""
    others = np.asarray(f_req, dtype=float)
    others = others[others != f0]
    need = None
    if others.size:
        f1 = float(others[np.argmin(np.abs(others - f0))])
        need = CLOSE_MODE_GAMMA * max(f0, f1) / abs(f1 - f0)
    if need is not None and need > gamma:
        g = float(np.ceil(need))
        return (
            f" (the request at {f1:g} Hz, {abs(f1 - f0):.3g} Hz away, is closer than gamma = {gamma:g} resolves): "
            f"give a larger gamma (the CLI's --gamma), {g:g} or more ({CLOSE_MODE_GAMMA:g} f / df; 100 and 104 Hz "
            "at zeta 1 %: within 0.02 % at 100, 1.6 % low at 60), the record at least about "
            f"{2 * 3 * g / (2 * np.pi * min(f0, f1)) + 3 / min(f0, f1):.3g} s long (edges of 3 gamma / (2 pi f) s)"
        )
    return (
        f" (a larger gamma, the CLI's --gamma, separates modes df apart at gamma >= {CLOSE_MODE_GAMMA:g} f / df: "
        "100 and 104 Hz at zeta 1 % came out within 0.02 % at 100; give the neighbour's frequency too)"
    )


def _leakage_late(signed, wf, limit, sigma_t, fs):
    """Samples of the fit window whose departure from the line (``signed``, nepers) is a neighbouring
    mode's leakage late in the window, which the linearity check lets pass: where |W| (``wf``) is below
    1e-2 of its largest value in the window (the fit's weight, |W|^2, below 1e-4: the departure does not
    move the fit) *and* ln|W| comes back up to within ``limit`` of the line within +-pi sigma_t (s) of the
    sample. Leakage adds to the mode's |W| and beats with it, at least once per pi sigma_t for a
    neighbour a wavelet bandwidth (f / gamma) away, so |W| keeps reaching the line (an alias at
    fs = 2.5 f: 0.54 nepers above and below, zeta exact); a line tilted by a second impact leaves |W|
    below it for good (a hit 20 ms after the first at 30 %: 1.7 nepers below over the window's last
    0.7 s, zeta 5.8 % low), which is refused."""
    from scipy.ndimage import maximum_filter1d

    half = max(1, int(np.ceil(np.pi * sigma_t * fs)))
    comes_back = maximum_filter1d(signed, size=2 * half + 1, mode="nearest") >= -limit
    return (wf < 1e-2 * wf.max()) & comes_back


def _index_list(idx, most=6):
    """A few sample indices as text, '3, 4, 5, ... (20)' for long lists."""
    head = ", ".join(str(int(i)) for i in idx[:most])
    return head + (f", ... ({idx.size} in all)" if idx.size > most else "")


def _check_distinct_ridges(results):
    """No two requests found the same ridge (natural frequencies closer than a half-power bandwidth,
    2 zeta f_n): a :class:`ModelError` naming both, rather than one mode twice (which a Rayleigh fit
    of the results would take as two)."""
    order = sorted(results, key=lambda r: r.f_natural_hz)
    for a, b in zip(order[:-1], order[1:]):
        width = 2.0 * max(a.zeta, b.zeta, 0.0) * b.f_natural_hz
        if b.f_natural_hz - a.f_natural_hz < width:
            raise ModelError(
                "freqs_hz",
                [a.f_requested_hz, b.f_requested_hz],
                f"found the same ridge ({a.f_natural_hz:.6g} and {b.f_natural_hz:.6g} Hz, within a half-power "
                "bandwidth): request each mode once, near its own peak",
            )
