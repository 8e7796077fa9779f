"""Input checks shared by the identification modules; every failure is a ModelError naming the field."""
from __future__ import annotations

import numpy as np

from ..errors import ModelError


def positive(key, value):
    """A finite float > 0."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ModelError(key, value, "must be a positive number") from None
    if not np.isfinite(v) or v <= 0.0:
        raise ModelError(key, value, "must be a positive finite number")
    return v


def signal_1d(key, x, min_len=2, complex_ok=False):
    """A finite 1-D float (or complex) array of at least ``min_len`` samples."""
    try:
        a = np.asarray(x)
    except Exception:  # pragma: no cover - numpy accepts almost anything
        raise ModelError(key, type(x).__name__, "must be a 1-D array of numbers") from None
    if a.ndim != 1:
        raise ModelError(key, f"array of shape {a.shape}", "must be a 1-D array")
    if np.iscomplexobj(a):
        if not complex_ok:
            raise ModelError(key, "complex array", "must be real")
        a = a.astype(complex)
    else:
        try:
            a = a.astype(float)
        except (TypeError, ValueError):
            raise ModelError(key, "non-numeric array", "must be a 1-D array of numbers") from None
    if a.size < min_len:
        raise ModelError(key, f"{a.size} samples", f"needs at least {min_len} samples")
    if not np.all(np.isfinite(a)):
        raise ModelError(key, "array with nan/inf", "must contain finite numbers only")
    return a


def frequencies_in_band(key, freqs_hz, fs):
    """1-D array of frequencies (Hz), each strictly inside (0, fs/2)."""
    f = np.atleast_1d(np.asarray(freqs_hz, dtype=float))
    if f.ndim != 1 or f.size == 0:
        raise ModelError(key, freqs_hz, "must be one or more frequencies in Hz")
    bad = ~np.isfinite(f) | (f <= 0.0) | (f >= fs / 2.0)
    if np.any(bad):
        raise ModelError(key, float(f[bad][0]),
                         f"every frequency must lie in the open interval (0, fs/2) = (0, {fs / 2.0:g}) Hz")
    return f
