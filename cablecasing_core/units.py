"""Units of time and of frequency a data file may give, and their factors to s and Hz.

The one table of each: a CSV record's time column (``time [ms]``, ``time_ms``; :func:`.files.time_column`)
and a UFF 58 time record's abscissa label are read through :func:`time_factor`; a CSV FRF's frequency
column (``frequency [rad/s]``; ``identification.uff_io.frequency_column``) and a UFF 58 FRF's abscissa
label through :func:`frequency_factor`. The package computes in s and Hz; these only convert what a file
states.
"""

from __future__ import annotations

import math

#: The units of time and their factors to s, looked up as given or in lower case (:func:`time_factor`).
TIME_UNITS = {
    "s": 1.0,
    "sec": 1.0,
    "second": 1.0,
    "seconds": 1.0,
    "ms": 1e-3,
    "msec": 1e-3,
    "us": 1e-6,
    "usec": 1e-6,
    "\u00b5s": 1e-6,  # (micro sign)
    "\u03bcs": 1e-6,  # (Greek mu)
}

#: The units of frequency and their factors to Hz, looked up in lower case with spaces removed
#: (:func:`frequency_factor`).
FREQUENCY_UNITS = {
    "Hz": 1.0,
    "1/s": 1.0,
    "cps": 1.0,
    "kHz": 1e3,
    "rad/s": 1.0 / (2.0 * math.pi),
    "rad/sec": 1.0 / (2.0 * math.pi),
    "rads/s": 1.0 / (2.0 * math.pi),
    "r/s": 1.0 / (2.0 * math.pi),
    "rpm": 1.0 / 60.0,
    "cpm": 1.0 / 60.0,
    "1/min": 1.0 / 60.0,
}
_FREQUENCY_KEYS = {k.lower(): v for k, v in FREQUENCY_UNITS.items()}


def time_factor(unit: str) -> float | None:
    """The factor from the time unit ``unit`` to s (:data:`TIME_UNITS`, as given or in lower case:
    ``ms``, ``MS``, ``sec``, ``µs``), None for a unit that is not one of time."""
    return TIME_UNITS.get(unit, TIME_UNITS.get(unit.lower()))


def time_units_text() -> str:
    """The units :func:`time_factor` converts, for a message: ``'s', 'sec', ...``."""
    return ", ".join(repr(k) for k in TIME_UNITS)


def frequency_factor(unit: str) -> float | None:
    """The factor from the frequency unit ``unit`` to Hz (:data:`FREQUENCY_UNITS`, in any case, spaces
    ignored: ``kHz``, ``KHZ``, ``rad / s``); 1.0 for no unit (""), None for a unit that is not one of
    frequency."""
    key = unit.lower().replace(" ", "")
    return 1.0 if not key else _FREQUENCY_KEYS.get(key)


def frequency_units_text() -> str:
    """The units :func:`frequency_factor` converts, for a message: ``'Hz', '1/s', ...``."""
    return ", ".join(repr(k) for k in FREQUENCY_UNITS)
