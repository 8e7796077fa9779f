"""The benchmarks' parsers and the checks of their options, in one place.

Every benchmark's ``--help`` shows its module docstring as written (what it measures, the
``name: value`` lines it prints, the command the docs run), and a bad option ends the script before
any run as argparse ends it: the usage, one line ``script.py: error: --option = value: what is
allowed`` and exit status 2 (a typo or a value the runs would refuse only minutes later, or turn
into nonsense, is caught at once). The checks are the package's own validators
(:mod:`cablecasing_core.model.validators`, the model schema's rules for a time step or a seed),
each under the option's name as typed, inside :func:`checked`:

    p = parser(__doc__)
    p.add_argument("--duration", type=float, default=1.0, help="s simulated per run")
    args = p.parse_args()
    with checked(p):
        seconds("--duration", args.duration)
        integer("--repeat", args.repeat, 1)
"""

from __future__ import annotations

import argparse
import contextlib

from cablecasing_core.errors import ModelError
from cablecasing_core.model.validators import integer, seconds

__all__ = [
    "checked",
    "divides",
    "integer",
    "model",
    "output_file",
    "parser",
    "seconds",
    "seeds",
    "step_runs",
    "time_step",
    "whole_steps",
]


def parser(doc: str) -> argparse.ArgumentParser:
    """An ArgumentParser whose description is ``doc`` (the script's module docstring) laid out as
    written, and whose options' help shows their defaults (as the command line's does)."""
    from cablecasing_core.cli import HelpFormatter

    class Formatter(argparse.RawDescriptionHelpFormatter, HelpFormatter):
        pass

    return argparse.ArgumentParser(description=doc, formatter_class=Formatter)


@contextlib.contextmanager
def checked(p: argparse.ArgumentParser):
    """A :class:`~cablecasing_core.errors.ModelError` raised in the block (a check below, or a
    validator of the package) ends the script with ``p.error``: the usage, one line naming the
    option, its value and what is allowed, and exit status 2."""
    try:
        yield
    except ModelError as exc:
        p.error(str(exc))


def seeds(option: str, values) -> list[int]:
    """Each of ``values`` a seed of the random excitation (``scenario.seed``'s rule: a whole number
    from 0 to 2**63 - 1); returns them as a list."""
    from cablecasing_core.model.schema import lookup

    rule = lookup("scenario.seed")
    values = list(values) if isinstance(values, (list, tuple, range)) else [values]
    return [rule.check(v, option) for v in values]


def time_step(option: str, value) -> float:
    """A time step (s) by ``scenario.dt``'s rule (1e-10 to 1 s)."""
    from cablecasing_core.model.schema import lookup

    return lookup("scenario.dt").check(value, option)


def _whole(steps: float) -> bool:
    """Whether ``steps`` is a whole number >= 1 (to 1e-9 of a step per step: rounding)."""
    return abs(steps - round(steps)) <= 1e-9 * max(1.0, steps) and round(steps) >= 1


def divides(option: str, dt: float, whole_option: str, whole: float) -> None:
    """The step ``dt`` (s, the option named) divides ``whole`` (s) into a whole number of steps: a
    run of ``whole`` s at ``dt`` ends on its grid."""
    if not _whole(whole / dt):
        least = ", at least one" if whole / dt < 0.5 else ""
        raise ModelError(
            option,
            dt,
            f"must divide {whole_option} = {whole:g} s into whole steps{least} (it gives {whole / dt:.6g} steps)",
        )


def whole_steps(option: str, duration: float, dt: float) -> None:
    """The time ``duration`` (s, the option named) is a whole number of steps of ``dt`` s."""
    if not _whole(duration / dt):
        least = ", at least one" if duration / dt < 0.5 else ""  # (0 is whole, but a run of no step compares nothing)
        raise ModelError(
            option, duration, f"must be a whole number of {dt:g} s steps{least} (it is {duration / dt:.6g})"
        )


def step_runs(option: str, texts, on) -> list[tuple[float, int]]:
    """Runs given as ``DT`` or ``DT:SUBSTEPS`` (``contact.event_substeps``: the steps whose contact
    switches between stick and slip recomputed in that many sub-steps), each checked: DT by
    :func:`time_step`, SUBSTEPS by the model ``on``; returns [(dt s, substeps)] in their order."""
    runs = []
    for text in texts:
        d, _, n = text.partition(":")
        try:
            dt, nsub = float(d), int(n or 1)
        except ValueError:
            raise ModelError(option, text, "must be DT or DT:SUBSTEPS, e.g. 1e-5 or 1e-5:8") from None
        time_step(option, dt)
        try:
            on.with_overrides({"contact.event_substeps": nsub})
        except ModelError as exc:
            raise ModelError(option, text, f"SUBSTEPS is contact.event_substeps: {exc.allowed}") from None
        runs.append((dt, nsub))
    return runs


def model(option: str, source):
    """The model ``source`` (a model file or a built-in specimen's name) loaded; a model that does
    not load is refused under ``option``, with the reason (the missing file, the key it refuses)."""
    import cablecasing_core as cc

    try:
        return cc.load_model(source)
    except ModelError as exc:
        why = exc.allowed if exc.key == "model_file" else str(exc)
        raise ModelError(option, source, why) from None


def output_file(option: str, path, suffixes) -> None:
    """An output file checked before the runs: a name ending in one of ``suffixes`` (say ``.npz``:
    the name is written as given, nothing appended), in an existing folder where a file can be
    written (and matplotlib able to start, for a figure). None (no output asked for) passes. Write
    it with :func:`cablecasing_core.files.atomic_path` or
    :func:`cablecasing_core.plotting.save_figure` (atomically)."""
    from cablecasing_core.cli.paths import check_output_path

    check_output_path(option, path, suffixes)
