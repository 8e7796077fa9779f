"""FRF estimation from time records: H1, H2, coherence.

Welch-averaged spectral densities (``scipy.signal.welch`` / ``scipy.signal.csd``, same window,
segment length and overlap for every density; the overlap at least half a segment, raised by
:func:`welch_overlap` so that the segments span the record) give, for input x and output y,

    H1 = G_xy / G_xx      (unbiased by noise on the output; biased low by noise on the input)
    H2 = G_yy / G_yx      (unbiased by noise on the input; biased high by noise on the output)
    gamma^2 = |G_xy|^2 / (G_xx G_yy) = H1 / H2   (ordinary coherence, 0..1)

with ``G_xy = csd(x, y)`` (SciPy's convention ``E[conj(X) Y]``), of arrays in any units. The apparent
mass of a run's record in the TRFAM's sign convention (Eq. 12, kg: the recorded support force is the
force the body exerts on its support, the TRFAM's the negative) is ``nvh.apparent_mass``, which takes
the record's columns by name; ``frf_estimate(a, F, fs).H1`` is F/a as given.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy import signal

from ..errors import ModelError
from ..model.validators import array_1d, number


@dataclass(frozen=True)
class FRFEstimate:
    """Frequencies ``f_hz`` (Hz), the estimators ``H1``, ``H2`` (unit of y / unit of x), the
    coherence (dimensionless), the auto spectral densities ``Gxx``, ``Gyy`` and the cross density ``Gxy``
    (unit^2/Hz), the segments averaged, ``n_averages``, and the independent averages they are worth,
    ``n_effective`` (fewer: they overlap)."""

    f_hz: np.ndarray
    H1: np.ndarray
    H2: np.ndarray
    coherence: np.ndarray
    Gxx: np.ndarray
    Gyy: np.ndarray
    Gxy: np.ndarray
    n_averages: int
    #: the independent averages the overlapping segments are worth (:func:`welch_effective_averages`)
    n_effective: float


def welch_overlap(n: int, nperseg: int, least: int | None = None) -> int:
    """The overlap (samples) of Welch segments of ``nperseg`` samples that span a record of ``n``
    samples: the first segment starts at its first sample and the last ends within
    ``welch_averages(n, nperseg) - 1`` samples of its last (6 of 44000 at nperseg 8192),
    overlapping by at least ``least`` samples (default half a segment, rounded up: at least 50 %).
    Welch's method (``scipy.signal.welch``) takes segments every ``nperseg - noverlap`` samples and
    leaves out the samples after the last whole one, up to a step less one (3040 of 44000 at 50 %).
    This returns the smallest overlap of at least ``least`` that leaves no more than those few:
    ``least`` itself when the segments at ``least`` already leave at most their number less one,
    else one segment more, the step shortened to ``(n - nperseg) // (segments - 1)`` (no overlap
    between these two leaves so few: they all take the segments of ``least``, and leave more
    than it does). A record of at most one segment gives ``least``."""
    least = -(-nperseg // 2) if least is None else int(least)
    if not 0 <= least < nperseg:
        raise ModelError("noverlap", least, f"must be 0 to nperseg - 1 ({nperseg - 1}) samples")
    span = n - nperseg
    if span <= 0:
        return least
    step = nperseg - least
    if span % step <= span // step:  # (the tail at least is within the segments' number less one)
        return least
    gaps = -(-span // step)  # (the fewest steps of at most nperseg - least that reach the end)
    return nperseg - span // gaps


def welch_effective_averages(nperseg: int, noverlap: int, n_averages: int, window="hann") -> float:
    """The number of independent averages whose mean has the variance of a Welch estimate from
    ``n_averages`` segments of ``nperseg`` samples overlapping by ``noverlap`` (Welch 1967, Eq. 18;
    Percival & Walden 1993, Eq. 292b, away from 0 Hz and fs / 2, for a Gaussian record):
    ``K / (1 + 2 sum_{j=1}^{K-1} (1 - j/K) rho(j))`` with ``rho(j) = [sum_n w(n) w(n + j S)]^2 /
    [sum_n w(n)^2]^2`` of the window ``w`` (a ``scipy.signal.get_window`` spec) and the step ``S =
    nperseg - noverlap``. Hann's window at 50 % overlap: 0.95 K for many segments; at 75 % 0.52 K.
    (Written here: scipy gives the window, not this sum.)"""
    w = signal.get_window(window, nperseg)
    step, k = nperseg - noverlap, int(n_averages)
    norm = np.sum(w * w) ** 2
    total = 1.0
    for j in range(1, min(k, -(-nperseg // step))):  # (segments j steps apart overlap while j S < nperseg)
        total += 2.0 * (1.0 - j / k) * np.sum(w[: nperseg - j * step] * w[j * step :]) ** 2 / norm
    return k / total


def welch_averages(n: int, nperseg: int, noverlap: int | None = None) -> int:
    """The number of segments Welch's method averages over ``n`` samples: segments of ``nperseg``
    overlapping by ``noverlap`` samples (default :func:`welch_overlap`'s, which span the record), as
    ``scipy.signal.welch`` takes them."""
    noverlap = welch_overlap(n, nperseg) if noverlap is None else noverlap
    return 1 + (n - nperseg) // (nperseg - noverlap)


def frf_estimate(
    x: ArrayLike, y: ArrayLike, fs: float, nperseg: int | None = None, window="hann", noverlap=None, detrend="constant"
) -> FRFEstimate:
    """H1 and H2 FRF estimates and the coherence from input ``x`` and output ``y`` (the measured
    TRFAM of Eq. (12) when x is a support acceleration and y a support force).

    Parameters
    ----------
    x, y : arrays (n,)
        Input and output records sampled at ``fs`` (any units; H is in unit(y)/unit(x)).
    fs : float
        Sampling rate (Hz).
    nperseg : int or None
        Segment length (samples; default n // 8, i.e. about 15 averages with 50 % overlap).
        Frequency resolution ``fs / nperseg`` Hz.
    window, detrend :
        As in ``scipy.signal.welch`` (default Hann, mean removed per segment).
    noverlap : int or None
        The least overlap of the segments (samples; default half a segment), raised by
        :func:`welch_overlap` so that the segments span the record to its last few samples.

    Returns
    -------
    :class:`FRFEstimate`. The densities are one-sided (``scaling="density"``); their common
    scale cancels in H1, H2 and the coherence.
    """
    x = array_1d("x", x, min_len=16)
    y = array_1d("y", y, min_len=16)
    if x.size != y.size:
        raise ModelError("y", f"{y.size} samples", f"must have as many samples as x ({x.size})")
    fs = number("fs", fs, gt=0, unit="Hz")
    if nperseg is None:
        nperseg = max(16, x.size // 8)
    nperseg = int(nperseg)
    if nperseg < 8 or nperseg > x.size:
        raise ModelError("nperseg", nperseg, f"must be between 8 and the record length ({x.size})")
    if np.ptp(x) == 0.0:  # (Gxx = 0 at every line: H1 and the coherence would be 0/0)
        raise ModelError("x", "a constant signal", "must vary: an FRF needs an input with power")
    noverlap = welch_overlap(x.size, nperseg, noverlap)
    kw = dict(fs=fs, window=window, nperseg=nperseg, noverlap=noverlap, detrend=detrend)
    f, Gxx = signal.welch(x, **kw)
    _, Gyy = signal.welch(y, **kw)
    _, Gxy = signal.csd(x, y, **kw)
    with np.errstate(divide="ignore", invalid="ignore"):
        H1 = Gxy / Gxx
        H2 = Gyy / np.conj(Gxy)
        coh = np.abs(Gxy) ** 2 / (Gxx * Gyy)
    n_avg = welch_averages(x.size, nperseg, noverlap)
    n_eff = welch_effective_averages(nperseg, noverlap, n_avg, window)
    return FRFEstimate(
        f_hz=f,
        H1=H1,
        H2=H2,
        coherence=np.real(coh),
        Gxx=Gxx,
        Gyy=Gyy,
        Gxy=Gxy,
        n_averages=int(n_avg),
        n_effective=n_eff,
    )


def random_error(coherence: ArrayLike, n_averages: float) -> np.ndarray:
    """Normalized random error of an H1 magnitude estimate (dimensionless), Bendat & Piersol,
    *Random Data* (4th ed.), Eq. (9.90): ``eps = sqrt(1 - gamma^2) / (|gamma| sqrt(2 n_d))`` with the
    ordinary coherence gamma^2 and ``n_d`` independent averages (of overlapping segments, the number
    they are worth: ``FRFEstimate.n_effective``); the standard deviation of |H1| / |H| - 1 (and of
    the phase, in rad) where the output's incoherent part is random noise."""
    g2 = np.clip(np.asarray(coherence, float), 1e-12, 1.0)
    return np.sqrt(1.0 - g2) / (np.sqrt(g2) * np.sqrt(2.0 * n_averages))
