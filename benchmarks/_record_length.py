"""The shortest record whose Table 3 band levels a benchmark can take, checked before it runs.

A band needs at least one FFT line, so the samples kept after ``--skip`` must span at least 1 / the
narrowest band's width (octave 1, 11-22 Hz: 0.0909 s). ``studies.octave_rms`` refuses a shorter
record with a ModelError, which a benchmark would meet only after its runs."""

import math

import numpy as np

from cablecasing_core.studies import octave_bands


def shortest_band_record(bands="table3"):
    """The shortest record (s) that holds one FFT line in every band of ``bands``, and the
    narrowest band's label and edges (Hz)."""
    b = octave_bands(bands)
    i = int(np.argmin(b.upper - b.lower))
    return float(1.0 / (b.upper[i] - b.lower[i])), b.labels[i], float(b.lower[i]), float(b.upper[i])


def require_band_record(parser, duration, skip):
    """``parser.error`` (a usage message, exit status 2) unless ``duration - skip`` s holds the
    shortest record of the Table 3 band levels."""
    need, label, lower, upper = shortest_band_record()
    if not duration - skip >= need:
        least = math.ceil((skip + need) * 1e4) / 1e4  # rounded up, so that the figure printed is enough
        parser.error(
            f"--duration {duration:g} with --skip {skip:g} leaves {duration - skip:.4g} s for the band levels; "
            f"they need at least {need:.4g} s (one FFT line in band {label}, {lower:g}-{upper:g} Hz): "
            f"--duration at least {least:g} s"
        )
