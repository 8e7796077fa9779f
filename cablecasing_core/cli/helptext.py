"""Help texts of the command line that the model schema writes: an option that stands for a model
key says what the key is, its unit and its default (a module of its own, imported by every command
module)."""

from __future__ import annotations

from ..model.schema import lookup


def key_help(key, what=None):
    """The help of an option that overrides model key ``key``: ``what`` (default: the key's
    description), its unit and 'default: the model's <key>'."""
    spec = lookup(key)
    unit = f"{spec.unit}; " if spec.unit not in ("", "1") else ""
    return f"{what or spec.description} ({unit}default: the model's {key})"


ASSIGNMENT_HELP = "KEY=VALUE: a dotted model key (see 'cablecasing keys') and a TOML value, e.g. contact.friction=0.2"


def add_window_argument(parser):
    """``--window`` of the band levels (``bands``, ``ensemble``, ``study``): Hann's, the default of
    ``studies.octave_rms``, or the rectangular window of the docs' tables before 2026-12-06."""
    parser.add_argument(
        "--window",
        choices=["hann", "boxcar"],
        default="hann",
        help="window of the band levels: Hann's (mean removed), or the rectangular one, whose leakage biases weak "
        "bands upward (docs/time_domain.md, 'The window of the band levels')",
    )
