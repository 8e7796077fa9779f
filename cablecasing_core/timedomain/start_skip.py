"""The start of a run's record that its band levels and spectra leave out by default: at least
:data:`LEAST_SKIP` and the supports' fade-in (``scenario.ramp``, :func:`least_skip`), lengthened so
that the rest holds whole periods of the scenario's harmonic lines (:func:`skip_for_whole_periods`).

The scenario's rule (:func:`~cablecasing_core.timedomain.scenario.whole_period_skip`, for the runs
of an ensemble or a study) and a record's (``records.Records.default_skip``, from the lines and the
fade-in the record states) are these two functions. They import nothing of the engine, so a record
read without one (``cablecasing bands``) does not pay the kernels' import.
"""

from __future__ import annotations

import math
from fractions import Fraction

#: The least start of a record left out of its band levels by default (s): the supports' fade-in
#: (``scenario.ramp``, 0.01 s in the specimens) and the first transient.
LEAST_SKIP = 0.05


def least_skip(ramp_s: float = 0.0) -> float:
    """The least start (s) the band levels leave out by default: :data:`LEAST_SKIP`, or the
    supports' fade-in ``ramp_s`` (s, ``scenario.ramp``) where that is longer."""
    return max(LEAST_SKIP, float(ramp_s))


def skip_for_whole_periods(lines_hz, length: float, dt: float, least: float = LEAST_SKIP) -> float:
    """The least skip (s) at or above ``least`` (s) after which the rest of a record ``length`` s long
    (its last time less its first) holds whole periods of every line of ``lines_hz`` (Hz): of their
    common period, 1 / the greatest common divisor of the frequencies read as fractions, on the grid
    of the step ``dt`` (s): the step nearest to it (whole periods to within dt / 2), or, when that
    step lies before ``least``, the first one after it. A line of whole periods lies on a bin of
    the record's FFT, so ``nvh.bands.octave_rms`` keeps it in its band (in its bin with the
    rectangular window, in its bin and the two beside it with Hann's); 47.5 periods of the
    specimens' 50 Hz drive (a skip of 0.05 s of 1 s) leak it into the neighbouring bands
    (docs/time_domain.md, "The record's length"). So 1 s with a 50 Hz line keeps 0.94 s, 0.5 s
    keeps 0.44 s. Without lines, or when their common period is longer than what ``least``
    leaves (50 and 50.5 Hz: 2 s), it is ``least``."""
    lines = [Fraction(float(f)).limit_denominator(10**6) for f in lines_hz if f > 0]
    if not lines:
        return float(least)
    # (the gcd of fractions p_i / q_i is gcd(p_i L / q_i) / L over L = lcm(q_i); numpy's gcd is of integers)
    common = math.lcm(*(f.denominator for f in lines))
    f0 = Fraction(math.gcd(*(int(f * common) for f in lines)), common)
    periods = math.floor((length - least) * f0 + 1e-9)
    if periods < 1:
        return float(least)
    k = round((length - float(periods / f0)) / dt)  # (the nearest step: whole periods to within dt / 2)
    if k * dt < least * (1 - 1e-9):  # (but never less than least: the step after it)
        k = math.ceil(least / dt * (1 - 1e-12))
    return round(k * dt, 12)  # (0.06, not 6000 * 1e-5 = 0.060000000000000005)
