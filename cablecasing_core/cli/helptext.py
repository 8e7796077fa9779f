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
