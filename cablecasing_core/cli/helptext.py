"""Help texts, choices and defaults of the command line's options that the core writes: an option
that stands for a model key says what the key is, its unit and its default (the model schema); an
option whose choices or default are a constant of the API takes it from there (:class:`FromApi`),
read when first needed, so that building the parser imports no sub-command's modules (a module of
its own, imported by every command module)."""

from __future__ import annotations

import functools
import importlib

from ..model.schema import lookup


def key_help(key, what=None):
    """The help of an option that overrides model key ``key``: ``what`` (default: the key's
    description), its unit and 'default: the model's <key>'."""
    spec = lookup(key)
    unit = f"{spec.unit}; " if spec.unit not in ("", "1") else ""
    return f"{what or spec.description} ({unit}default: the model's {key})"


ASSIGNMENT_HELP = "KEY=VALUE: a dotted model key (see 'cablecasing keys') and a TOML value, e.g. contact.friction=0.2"


class FromApi:
    """The constant ``name`` of the module ``cablecasing_core.<module>`` (``FromApi("frequency.trfam",
    "DAMPING_MODELS")``) as an option's choices or default, imported when first used: when the help
    shows it, a value given is checked against it, or the command runs (:func:`taking_api_defaults`).
    Building the parser then imports none of those modules, so that a command's start-up loads only
    what it runs (tests/cli/test_static_cli.py). As choices it is the constant's sequence; as a default
    the help shows its value (``%(default)s``)."""

    def __init__(self, module, name):
        self.module, self.name = module, name

    @functools.cached_property
    def value(self):
        return getattr(importlib.import_module(f"cablecasing_core.{self.module}"), self.name)

    def __iter__(self):
        return iter(self.value)

    def __contains__(self, item):
        return item in self.value

    def __str__(self):
        return str(self.value)

    def __repr__(self):
        return f"FromApi({self.module!r}, {self.name!r})"


class ApiText(FromApi):
    """A text written from the module ``cablecasing_core.<module>`` (``text(module)``), read when the
    help that holds it is shown (:data:`API_TEXTS`), as :class:`FromApi`'s constants."""

    def __init__(self, module, text):
        self.module, self.name, self.text = module, text.__name__, text

    @functools.cached_property
    def value(self):
        return self.text(importlib.import_module(f"cablecasing_core.{self.module}"))


def _references(m):
    return ", ".join(f"{ref:g} {unit}" for unit, ref in m.REFERENCES.items() if unit != "1")


#: Placeholders a help text may hold, ``[NAME]``, each a fact of the API that the help restates (a
#: default the core applies, a range of its tables): the command line's help formatter writes it in
#: when the help is shown (:func:`expand_api_texts`), so the help says what the core does.
API_TEXTS = {
    "[LEAST_SKIP]": ApiText("timedomain.start_skip", lambda m: f"{m.LEAST_SKIP:g} s"),
    "[REFERENCES]": ApiText("nvh.spectra", _references),
    "[TABLE3_RANGE]": ApiText("nvh.bands", lambda m: f"{m.TABLE3_LOWER[0]:g}-{m.TABLE3_UPPER[-1]:g} Hz"),
    "[IEC_F_MIN]": ApiText("nvh.bands", lambda m: f"{m.IEC_F_MIN:g} Hz"),
    "[IEC_F_MAX]": ApiText("nvh.bands", lambda m: f"{m.IEC_F_MAX:g} Hz"),
}


def expand_api_texts(text):
    """``text`` with each placeholder of :data:`API_TEXTS` it holds written out."""
    for mark, value in API_TEXTS.items():
        if mark in text:
            text = text.replace(mark, str(value))
    return text


def choice_argument(parser, *flags, choices, **kwargs):
    """``parser.add_argument(*flags, choices=choices, **kwargs)`` with ``choices`` a :class:`FromApi`
    that the parser does not read while it is built (argparse lists an option's choices to check a
    metavar it is not given: the option gets one for that check, then none, so that its help and
    usage list the choices as argparse's do). Returns the action."""
    action = parser.add_argument(*flags, choices=choices, metavar="", **kwargs)
    action.metavar = None
    return action


def taking_api_defaults(command):
    """The command ``command(args)`` with every argument whose value is a :class:`FromApi` (the
    default of an option not given) given the constant's value first."""

    @functools.wraps(command)
    def run(args):
        for name, value in vars(args).items():
            if isinstance(value, FromApi):
                setattr(args, name, value.value)
        return command(args)

    return run


def add_window_argument(parser):
    """``--window`` of the band levels (``bands``, ``ensemble``, ``study``): one of the band levels'
    windows (``nvh.bands.WINDOWS``), Hann's by default (``nvh.bands.octave_rms``'s)."""
    choice_argument(
        parser,
        "--window",
        choices=FromApi("nvh.bands", "WINDOWS"),
        default="hann",
        help="window of the band levels: Hann's (mean removed), or the rectangular one, whose leakage biases weak "
        "bands upward (docs/time_domain.md, 'The window of the band levels')",
    )


def name_by_choices(sub):
    """Name the sub-command argument ``sub`` (what ``add_subparsers`` returns, its parsers added) by
    its choices, ``{damping,loss-factor,modulus}``, as its usage line shows it: argparse's error for a
    missing sub-command names it so, instead of by its ``dest``, an internal name (``identify_command``)."""
    sub.metavar = "{" + ",".join(sub.choices) + "}"
