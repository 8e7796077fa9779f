"""Units of time and of frequency a data file may give, and their factors to s and Hz.

The one table of each: a CSV record's time column (``time [ms]``, ``time_ms``; :func:`.files.time_column`)
and a UFF 58 time record's abscissa label are read through :func:`time_factor`; a CSV FRF's frequency
column (``frequency [rad/s]``; ``identification.uff_io.frequency_column``) and a UFF 58 FRF's abscissa
label through :func:`frequency_factor`. The package computes in s and Hz; these only convert what a file
states. How a unit's spellings compare (``m/s^2`` is ``m/s2``): :func:`unit_key`.
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


def unit_key(label: str, fold_case: bool = True) -> str:
    """``label`` (a unit as a file or a record states it) in the form unit labels compare in: no spaces,
    no brackets around the whole label, no ``^`` or ``**``, ``²`` as 2 (``m/s^2``, ``m/s**2``, ``m/s²``,
    ``[m/s2]`` are ``m/s2``; ``(m/s)^2``, a squared velocity, stays ``(m/s)2``), and in
    lower case unless ``fold_case`` is False. The package's one rule of unit spellings: the FRF kind by a UFF
    record's labels (``uff.MOTION_LABELS``) compares with the case folded (vendors write ``G``, ``M/S^2``);
    the units the transfer functions need (``nvh.transfer``), the units of the dB references
    (``nvh.spectra.reference``) and the terms of a summed column (``Records``) compare with it kept, since
    the case carries a prefix's factor there (``mN`` and ``MN`` differ by 1e9)."""
    key = label.strip()
    if len(key) > 1 and key[0] + key[-1] in ("[]", "()") and not any(c in key[1:-1] for c in "()[]"):
        key = key[1:-1]  # (only brackets around the whole label: (m/s)^2 is a squared velocity, not m/s2)
    key = (key.lower() if fold_case else key).replace("²", "2").replace("**", "").replace("^", "")
    return key.replace(" ", "")
