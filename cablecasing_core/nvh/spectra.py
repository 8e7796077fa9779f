"""Spectra and levels of a time record: power spectral density (Welch) and levels in decibels.

* :func:`psd`: one-sided power spectral density by Welch's method (``scipy.signal.welch``: Hann
  window, 50 % overlap, mean removed per segment), in unit^2/Hz, so that integrating it over
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
  ========= ================ ==============================================================

  A PSD level is ``10 log10(G / x_ref^2)`` in dB re x_ref^2/Hz (e.g. dB re 1 N^2/Hz).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy import signal

from ..errors import ModelError
from ..model.validators import array_1d, number

#: Reference values (in the unit itself) of levels in dB, by unit (module docstring).
REFERENCES = {"N": 1.0, "N.m": 1.0, "m/s2": 1e-6, "m/s": 1e-9, "m": 1e-12}


def reference(unit: str, ref: float | None = None) -> float:
    """The reference value of levels of a quantity in ``unit`` (:data:`REFERENCES`), or ``ref``
    when given (a positive number in that unit)."""
    if ref is not None:
        return number("--ref", ref, gt=0, unit=unit)
    if unit not in REFERENCES:
        raise ModelError("--ref", None, f"must be given for a quantity in '{unit}' (known: {', '.join(REFERENCES)})")
    return REFERENCES[unit]


def level_db(x: ArrayLike, ref: float, power: bool = False) -> np.ndarray:
    """Level in dB of amplitudes ``x`` (RMS; ``20 log10(x / ref)``) or, with ``power``, of power
    quantities such as a PSD (``10 log10(x / ref**2)``). Zero gives -inf."""
    x = np.asarray(x, float)
    with np.errstate(divide="ignore"):
        return 10 * np.log10(x / ref**2) if power else 20 * np.log10(x / ref)


@dataclass(frozen=True)
class PSD:
    """A one-sided power spectral density: ``f_hz`` (Hz), ``density`` (unit^2/Hz), ``unit`` of the
    signal, ``name``, ``fs`` (Hz), ``nperseg`` (samples per segment; resolution fs / nperseg Hz),
    ``n_averages`` (segments) and ``enbw`` (Hz, the window's equivalent noise bandwidth)."""

    f_hz: np.ndarray
    density: np.ndarray
    unit: str
    name: str
    fs: float
    nperseg: int
    n_averages: int
    enbw: float

    def mean_square(self, f_low: float = 0.0, f_high: float = np.inf) -> float:
        """The mean square (unit^2) between ``f_low`` and ``f_high`` (Hz): the PSD integrated by the
        rectangle rule over the bins (Parseval)."""
        df = self.f_hz[1] - self.f_hz[0]
        sel = (self.f_hz >= f_low) & (self.f_hz <= f_high)
        return float(np.sum(self.density[sel]) * df)

    def level_db(self, ref: float | None = None) -> np.ndarray:
        """The PSD in dB re ref^2/Hz (default reference of the unit, :data:`REFERENCES`)."""
        return level_db(self.density, reference(self.unit, ref), power=True)


def psd(
    x: ArrayLike,
    fs: float,
    nperseg: int | None = None,
    window="hann",
    overlap: float = 0.5,
    unit: str = "",
    name: str = "",
) -> PSD:
    """Power spectral density of ``x`` (sampled at ``fs`` Hz) by Welch's method.

    nperseg: samples per segment (default: the power of two nearest fs, i.e. about 1 Hz resolution,
    but at most the largest power of two <= n / 8, so at least 15 averages, and at least 256 or the
    record's largest power of two); window: a
    ``scipy.signal.get_window`` spec (default Hann); overlap: the segments' overlap fraction (0 to
    < 1). The density is one-sided, unit^2/Hz (``scaling="density"``), so ``sum(density) df`` is the
    mean square of x (less its mean, removed per segment).
    """
    x = array_1d("x", x, min_len=16)
    fs = number("fs", fs, gt=0, unit="Hz")
    number("overlap", overlap, ge=0, lt=1)
    if nperseg is None:
        nperseg = int(2 ** np.round(np.log2(fs)))  # ~1 Hz
        nperseg = max(min(256, 2 ** int(np.log2(x.size))), min(nperseg, 2 ** int(np.log2(max(x.size // 8, 1)))))
    nperseg = int(nperseg)
    if not 8 <= nperseg <= x.size:
        raise ModelError("nperseg", nperseg, f"must be between 8 and the record length ({x.size} samples)")
    noverlap = int(round(overlap * nperseg))
    try:
        f, G = signal.welch(x, fs=fs, window=window, nperseg=nperseg, noverlap=noverlap, detrend="constant")
        w = signal.get_window(window, nperseg)
    except (ValueError, TypeError) as exc:
        raise ModelError("window", window, f"must be a scipy.signal.get_window spec ({exc})") from None
    n_avg = 1 + (x.size - nperseg) // (nperseg - noverlap)
    enbw = fs * np.sum(w**2) / np.sum(w) ** 2
    return PSD(f, G, unit, name, fs, nperseg, int(n_avg), float(enbw))
