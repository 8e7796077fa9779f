"""Spectra and levels of a time record: power spectral density (Welch) and levels in decibels.

* :func:`psd`: one-sided power spectral density by Welch's method (``scipy.signal.welch``: Hann
  window, overlap of at least 50 % raised so that the segments span the record, mean removed per
  segment), in unit^2/Hz, so that integrating it over
  frequency gives the mean square (Parseval; the tests check it for sums of sines and white noise).
* :func:`level_db`: a level ``20 log10(x / x_ref)`` dB of an amplitude (RMS) or ``10 log10(G / G_ref)``
  of a power quantity, with the reference of the quantity's unit from :data:`REFERENCES`:

  ========= ================ ==============================================================
  unit      reference        source
  ========= ================ ==============================================================
  N         1 N              the usual reference of force levels in vehicle NVH ("dB re 1 N")
  N.m       1 N.m            likewise for moments
  m/s2      1e-6 m/s2        ISO 1683:2015 (acceleration)
  m/s       1e-9 m/s         ISO 1683:2015 (velocity)
  m         1e-12 m          ISO 1683:2015 (displacement)
  1         1                a count or a ratio (``contact.active``)
  ========= ================ ==============================================================

  A PSD level is ``10 log10(G / x_ref^2)`` in dB re x_ref^2/Hz (e.g. dB re 1 N^2/Hz).
* :func:`band_sums` over :func:`bin_edges`: a spectrum's lines summed over bands, a line that
  straddles a band's edge split in proportion (Parseval); the PSD's :meth:`PSD.mean_square`, the band
  RMS of :mod:`~cablecasing_core.nvh.bands` and ``frequency.trfam_band_rms`` sum by it.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy import signal

from ..errors import ModelError, ModelWarning
from ..identification.frf import welch_averages, welch_overlap
from ..model.validators import array_1d, integer, number
from ..units import unit_key

#: The fewest Welch averages the default resolution keeps, and below which psd() warns: the
#: normalized random error of a PSD line is about 1/sqrt(averages) (Bendat & Piersol 11.5), 38 % at 7.
MIN_AVERAGES = 7
#: The fewest lines the default resolution puts within f_min..f_max (``psd(..., f_max=)``).
LINES_PER_RANGE = 16

#: The fewest samples of a PSD's Welch segment (a resolution of at most fs / 8 Hz).
MIN_PSD_SEGMENT = 8

#: The lowest frequency, in lines (df), from which the PSD's lines hold a tone's power (:meth:`PSD.covered`).
COVERED_FROM_DF = 2.0

#: Reference values (in the unit itself) of levels in dB, by unit (module docstring).
REFERENCES = {"N": 1.0, "N.m": 1.0, "m/s2": 1e-6, "m/s": 1e-9, "m": 1e-12, "1": 1.0}
#: REFERENCES by :func:`..units.unit_key` (the case kept), as :func:`reference` looks a unit up
_REFERENCE_KEYS = {unit_key(k, False): v for k, v in REFERENCES.items()}


def level_reference(unit: str, ref: float | None = None) -> float:
    """The reference of levels in dB of a signal in ``unit``: ``ref`` when given, else the unit's
    (:func:`reference`), or 1 (dB re 1 of the signal's unit) when the unit is not known (``""``)."""
    return reference(unit, ref) if unit or ref is not None else 1.0


def finest_segment_resolution(fs: float, n: int, averages: int = 1) -> float:
    """The finest resolution (Hz) of Welch segments of a power of two samples that leave at least
    ``averages`` half-overlapping averages of ``n`` samples at ``fs`` Hz (k averages span (k + 1) / 2
    segments: a segment of at most 2 n / (k + 1) samples)."""
    return fs / 2 ** int(np.log2(max(2 * n // (averages + 1), 1)))


def segment_for_resolution(
    key: str, resolution_hz: float, fs: float, n: int, averages: int = 1, least: int = MIN_PSD_SEGMENT
) -> int:
    """Samples per Welch segment for a resolution of ``resolution_hz`` Hz (the nearest power of two
    of samples at ``fs`` Hz) in a record of ``n`` samples, leaving at least ``averages``
    half-overlapping averages (a transfer function's coherence needs 3: from one it is 1 whatever
    the signals); a finer resolution raises :class:`ModelError` naming ``key`` (``resolution_hz``,
    the command line's ``--resolution``) and the finest the record allows
    (:func:`finest_segment_resolution`), and so does a coarser one than a segment of ``least``
    samples allows (fs / least Hz: :data:`MIN_PSD_SEGMENT` for a PSD, ``nvh.transfer.MIN_SEGMENT``
    for a transfer function)."""
    ratio = fs / resolution_hz  # (samples per segment before rounding; inf for a resolution of 5e-324 Hz)
    seg = int(2 ** np.round(np.log2(ratio))) if ratio < 2.0**62 else 2**62  # (2**62: longer than any record)
    if seg < least:
        raise ModelError(
            key,
            resolution_hz,
            f"must be below {fs / least * math.sqrt(2):.4g} Hz at {fs:.6g} Hz sampling: it is taken as the nearest "
            f"power of two of samples per Welch segment, at least {least} samples ({fs / least:.4g} Hz)",
        )
    if seg > 2 * n // (averages + 1):  # (k averages of half-overlapping segments span (k + 1) / 2 of them)
        what = "one segment" if averages == 1 else f"{averages} averages of half-overlapping segments"
        why = "" if averages == 1 else "; from one the coherence is 1 whatever the signals"
        raise ModelError(
            key,
            resolution_hz,
            f"must be at least {finest_segment_resolution(fs, n, averages):.4g} Hz for the {n / fs:.4g} s of record "
            f"after the skip ({what} of a power of two samples{why})",
        )
    return seg


def reference(unit: str, ref: float | None = None) -> float:
    """The reference value of levels of a quantity in ``unit`` (:data:`REFERENCES`, its spellings alike:
    ``m/s^2`` is ``m/s2``, :func:`..units.unit_key`), or ``ref``
    when given (a positive number in that unit). A :class:`ModelError` names ``ref`` (the command
    line renames it ``--ref``)."""
    if ref is not None:
        return number("ref", ref, gt=0, unit=unit)
    key = unit_key(unit, False)  # (m/s^2 is m/s2: units.unit_key)
    if key not in _REFERENCE_KEYS:
        raise ModelError("ref", None, f"must be given for a quantity in '{unit}' (known: {', '.join(REFERENCES)})")
    return _REFERENCE_KEYS[key]


def squared(unit: str) -> str:
    """``unit`` squared as text: ``N^2``, and a compound one in brackets, ``(m/s2)^2``, ``(N.m)^2``."""
    return f"({unit})^2" if any(c in unit for c in "./ ") else f"{unit}^2"


def level_unit(ref: float, unit: str, power: bool = False) -> str:
    """What a level in dB is relative to: ``dB re 1e-06 m/s2`` for an amplitude, ``dB re (1e-06
    m/s2)^2/Hz`` for a density (the reference squared, per Hz; ``dB re 1 N^2/Hz`` where the
    reference is 1 in a simple unit)."""
    if not power:
        return f"dB re {ref:g} {unit}".rstrip()
    simple = ref == 1.0 and squared(unit) == f"{unit}^2"
    return f"dB re 1 {squared(unit)}/Hz" if simple else f"dB re {squared(f'{ref:g} {unit}'.rstrip())}/Hz"


def level_db(x: ArrayLike, ref: float, power: bool = False) -> np.ndarray:
    """Level in dB of amplitudes ``x`` (RMS; ``20 log10(x / ref)``) or, with ``power``, of power
    quantities such as a PSD (``10 log10(x / ref**2)``). Zero gives -inf. ``ref`` > 0 in x's unit."""
    ref = number("ref", ref, gt=0)
    x = np.asarray(x, float)
    with np.errstate(divide="ignore"):
        return 10 * np.log10(x / ref**2) if power else 20 * np.log10(x / ref)


def bin_edges(n, fs):
    """Boundaries (Hz, length n//2 + 2) of the one-sided FFT bins: bin k covers [E_k, E_k+1],
    i.e. [f_k - df/2, f_k + df/2] clipped to [0, fs/2]."""
    nb = n // 2 + 1
    df = fs / n
    return np.concatenate([[0.0], (np.arange(1, nb) - 0.5) * df, [fs / 2]])


def band_sums(P, E, lower, upper):
    """Sum of P (per bin, e.g. a mean square in unit^2) over each band [lower, upper] (Hz) of bins
    whose boundaries are ``E`` (Hz, ``P.size + 1``, :func:`bin_edges`), edge bins split
    proportionally; also the (fractional) number of bins. Direct sums per band (no cumulative sum:
    no cancellation against a large 0 Hz component)."""
    ms = np.zeros(lower.size)
    bins = np.zeros(lower.size)
    nb = P.size
    for j, (lo, up) in enumerate(zip(lower, upper)):
        k0 = max(int(np.searchsorted(E, lo, side="right")) - 1, 0)
        k1 = min(int(np.searchsorted(E, up, side="left")) - 1, nb - 1)
        if k1 < k0:
            continue
        a, b = E[k0 : k1 + 1], E[k0 + 1 : k1 + 2]
        frac = np.clip(np.minimum(b, up) - np.maximum(a, lo), 0.0, None) / (b - a)
        ms[j] = frac @ P[k0 : k1 + 1]
        bins[j] = frac.sum()
    return ms, bins


@dataclass(frozen=True)
class PSD:
    """A one-sided power spectral density: ``f_hz`` (Hz), ``density`` (unit^2/Hz), ``unit`` of the
    signal, ``name``, ``fs`` (Hz), ``nperseg`` (samples per segment; resolution fs / nperseg Hz),
    ``n_averages`` (segments), ``enbw`` (Hz, the window's equivalent noise bandwidth) and ``noverlap``
    (samples the segments overlap by, at least half a segment by default: ``psd``'s overlap)."""

    f_hz: np.ndarray
    density: np.ndarray
    unit: str
    name: str
    fs: float
    nperseg: int
    n_averages: int
    enbw: float
    noverlap: int

    @property
    def df(self) -> float:
        """The line spacing (Hz), fs / nperseg."""
        return self.fs / self.nperseg

    def covered(self, f_low: float = 0.0, f_high: float = np.inf) -> tuple[float, float]:
        """The part of ``[f_low, f_high]`` (Hz) that the lines measure: from 2 df (:data:`COVERED_FROM_DF`)
        up to the Nyquist frequency fs/2. Below 2 df the per-segment mean removal and the Hann
        window's weighting within a segment (its main lobe, 4 df wide, reaches the 0 Hz line) leave
        the lines, all of them summed, with 0.38 of a sine's power at 0.6 df, 0.83 to 1.17 at 1 df
        (by the sine's phase: at 1 df every segment sees it alike), 1.21 at 1.5 df; from 2 df with
        its power within 1.2 % (0.5 % from 4 df; Welch with nperseg 1024 over 16384 samples, the
        extremes over 8 phases, ``tests/nvh/test_review_passband.py``)."""
        f_low, f_high = _limits(f_low, f_high)
        return max(f_low, COVERED_FROM_DF * self.df), min(f_high, self.fs / 2)

    def mean_square(self, f_low: float | None = None, f_high: float = np.inf) -> float:
        """The mean square (unit^2) between ``f_low`` and ``f_high`` (Hz): the PSD integrated over
        the lines, each line standing for ``[f_k - df/2, f_k + df/2]`` and a line that straddles
        an edge split in proportion, as the band levels split their FFT bins
        (:func:`band_sums`), so that the mean squares of adjacent
        ranges add up to that of their union (Parseval). Without ``f_low`` it integrates from 0 Hz,
        and without either limit every line: the mean square of the signal less the mean of each
        segment. A range from below :meth:`covered`'s lower limit (2 df; ``f_low`` below it, or
        absent with ``f_high`` below fs/2) warns
        (:class:`~cablecasing_core.errors.ModelWarning`, naming the covered range): the lines there
        hold a tone's power only in part, or more than it; ``mean_square(*p.covered(f_low, f_high))``
        integrates what the lines measure. A limit that is not a number, NaN, negative, or
        ``f_low`` >= ``f_high`` raises :class:`~cablecasing_core.errors.ModelError` naming it
        (``f_high`` may be ``inf``)."""
        f_low, f_high = _limits(0.0 if f_low is None else f_low, f_high, none_low=f_low is None)
        whole = f_low is None and f_high >= self.fs / 2  # (every line: Parseval's total, no warning)
        f_low = 0.0 if f_low is None else f_low
        if not whole:
            low, high = self.covered(f_low, f_high)
            if f_low < low * (1 - 1e-9):  # (within round-off of 2 df: p.mean_square(2 * p.df) does not warn)
                warnings.warn(
                    f"{self.name or 'PSD'}: mean_square from f_low = {f_low:g} Hz reaches below the lines that "
                    f"measure, {low:.4g}-{high:.4g} Hz (from 2 df, df = {self.df:.4g} Hz): lines below 2 df hold "
                    "only part of a tone's power, or more than it; mean_square(*covered(f_low, f_high)) integrates "
                    "the covered range",
                    ModelWarning,
                    stacklevel=2,
                )
        lo, hi = max(f_low, 0.0), min(f_high, self.fs / 2)
        if not hi > lo:  # (a range wholly above fs/2: no line lies there)
            return 0.0
        ms, _ = band_sums(self.density * self.df, bin_edges(self.nperseg, self.fs), np.array([lo]), np.array([hi]))
        return float(ms[0])

    def level_db(self, ref: float | None = None) -> np.ndarray:
        """The PSD in dB re ref^2/Hz (default: the reference of the unit, :data:`REFERENCES`, or 1 for a
        PSD without a unit: :func:`level_reference`, as band levels take it)."""
        return level_db(self.density, level_reference(self.unit, ref), power=True)


def _limits(f_low, f_high, none_low=False):
    """The frequency limits (Hz) of :meth:`PSD.mean_square` and :meth:`PSD.covered` checked: numbers,
    0 <= f_low < f_high, f_high may be inf; ``none_low``: f_low was left out (returned as None)."""
    f_low = number("f_low", f_low, ge=0, unit="Hz")
    if f_high != np.inf:
        f_high = number("f_high", f_high, gt=0, unit="Hz")
    if not f_low < f_high:
        raise ModelError("f_low/f_high", (f_low, f_high), "need f_low < f_high (Hz)")
    return (None if none_low else f_low), f_high


def psd(
    x: ArrayLike,
    fs: float,
    nperseg: int | None = None,
    window="hann",
    overlap: float = 0.5,
    unit: str = "",
    name: str = "",
    f_min: float = 1.0,
    f_max: float | None = None,
) -> PSD:
    """Power spectral density of ``x`` (sampled at ``fs`` Hz) by Welch's method.

    nperseg: samples per segment (resolution fs / nperseg Hz). Default: the power of two that
    resolves ``f_min`` (Hz, default 1: the lines measure from 2 df, :meth:`PSD.covered`, at or below
    f_min) and, with ``f_max`` (Hz), puts at least :data:`LINES_PER_RANGE` lines within
    f_min..f_max (a narrow range gets lines, and its edges cut little of a line's window leakage,
    so its RMS agrees with the band levels over it), but at most the largest power of two <= n / 4,
    so at least :data:`MIN_AVERAGES` averages (the measured range then starts between f_min and
    2 f_min where the first line, df, is still at or below f_min); when that cap puts the first line
    above f_min, a warning names where the lines start and the record length that would resolve
    f_min. Lines above fs / 2 do not exist: f_max beyond it counts the lines up to fs / 2. Fewer than
    :data:`MIN_AVERAGES` averages (an nperseg asked for) warn
    too. window: a ``scipy.signal.get_window`` spec (default Hann); overlap: the segments' least
    overlap fraction (0 to < 1; in samples, rounded up), raised just enough that the segments span the
    record, from its first sample to within a few of its last (``identification.frf.welch_overlap``: 44000 samples in
    segments of 8192 overlap by 51.4 %, 10 averages, and leave out 6 samples; at exactly 50 % the
    last 3040 would be left out). The density is one-sided, unit^2/Hz (``scaling="density"``), so
    ``sum(density) df`` is the mean square of x (less its mean, removed per segment). ``name``
    (the record's column) names the signal in every message.
    """
    what = name or "x"
    x = array_1d(what, x, min_len=16)
    fs = number("fs", fs, gt=0, unit="Hz")
    number("overlap", overlap, ge=0, lt=1)
    number("f_min", f_min, gt=0, unit="Hz")
    if nperseg is None:
        want = int(2 ** np.ceil(np.log2(fs / f_min) - 1e-9))  # first line fs / want <= f_min
        lines = int(COVERED_FROM_DF) * want  # (covered from 2 df <= f_min where the record allows)
        if f_max is not None:
            # (the lines within f_min..f_max that exist: none lies above fs / 2)
            top = min(number("f_max", f_max, gt=f_min, unit="Hz"), fs / 2)
            if top > f_min:
                lines = max(lines, int(2 ** np.ceil(np.log2(LINES_PER_RANGE * fs / (top - f_min)) - 1e-9)))
        cap = 2 ** int(np.log2(max(x.size // 4, MIN_PSD_SEGMENT)))
        nperseg = max(MIN_PSD_SEGMENT, min(lines, cap))
        if nperseg < want:
            warnings.warn(
                f"{what}: the PSD measures from {COVERED_FROM_DF * fs / nperseg:.4g} Hz (2 lines, df = "
                f"{fs / nperseg:.4g} Hz), above f_min = {f_min:g} Hz: its "
                f"segments are kept to at most a quarter of the {x.size / fs:.4g} s record ({nperseg / fs:.4g} s) "
                f"so that it averages at least {MIN_AVERAGES} of them; a record of {8 * want / fs:.4g} s resolves "
                f"{f_min:g} Hz (or ask for a finer resolution, fewer averages)",
                ModelWarning,
                stacklevel=2,
            )
    nperseg = integer("nperseg", nperseg, MIN_PSD_SEGMENT, x.size, why=f" (the record's length, {x.size} samples)")
    # (the least overlap rounded up, at least the fraction asked for: 4 of 9 samples would be 44 %; the factor keeps a
    # product whole but for its last bit, 0.55 * 100 = 55.00000000000001, from rounding up to 56)
    least = min(int(np.ceil(overlap * nperseg * (1 - 1e-12))), nperseg - 1)
    noverlap = welch_overlap(x.size, nperseg, least)
    try:
        f, G = signal.welch(x, fs=fs, window=window, nperseg=nperseg, noverlap=noverlap, detrend="constant")
        w = signal.get_window(window, nperseg)
    except (ValueError, TypeError) as exc:
        raise ModelError("window", window, f"must be a scipy.signal.get_window spec ({exc})") from None
    n_avg = welch_averages(x.size, nperseg, noverlap)
    if n_avg < MIN_AVERAGES:
        more = f" or more: they overlap by {noverlap / nperseg:.0%}" if n_avg > 1 and noverlap > nperseg // 2 else ""
        warnings.warn(
            f"{what}: the PSD averages only {n_avg} segment(s) of {nperseg / fs:.4g} s: each line's random error is "
            f"about {1 / np.sqrt(n_avg):.0%} (1/sqrt(averages){more}); a coarser resolution or a longer record gives "
            "more",
            ModelWarning,
            stacklevel=2,
        )
    enbw = fs * np.sum(w**2) / np.sum(w) ** 2
    return PSD(f, G, unit, name, fs, nperseg, int(n_avg), float(enbw), int(noverlap))
