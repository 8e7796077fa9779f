"""Output paths of the command line, checked before a long run, and numeric tables written to them
or printed (a module of its own: every command module imports it, and it imports nothing of theirs)."""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import ModelError

#: The figures ``--plot`` writes (matplotlib's formats by suffix), checked before the run.
PLOT_SUFFIXES = (".png", ".pdf", ".svg")


def check_output_path(flag, path, suffixes=None):
    """Refuse an output file before a long run rather than after it: with ``suffixes``, its name
    must end in one of them, the optional package that writes its suffix must be installed (pyuff
    for ``.uff``), and a file must be writable there (:func:`~cablecasing_core.files.check_writable`:
    an existing folder, a regular file or none yet, a byte written and synced to a temporary file in
    the folder); a figure (:data:`PLOT_SUFFIXES`) needs matplotlib to start (:func:`check_plotting`).
    ``None`` (no output asked for) passes."""
    from ..files import check_writable

    if path is None or path is True:
        return
    suffix = Path(str(path)).suffix.lower()
    if suffixes and suffix not in tuple(suffixes):  # (".png" alone is a name, no suffix)
        raise ModelError(flag, path, "must be a name ending in " + " or ".join(suffixes))
    if suffix == ".uff":
        try:
            import pyuff  # noqa: F401
        except ImportError:
            from ..uff import PYUFF_MISSING

            others = [s for s in suffixes or () if s != ".uff"]
            instead = f" (or write {' or '.join(others)})" if others else ""
            raise ModelError(flag, path, f"writing UFF {PYUFF_MISSING}{instead}") from None
    check_writable(flag, path)
    if suffix in PLOT_SUFFIXES:  # (a figure: matplotlib must start, before the run rather than after it)
        check_plotting()


def check_plotting():
    """Refuse an environment in which matplotlib, which draws every figure (with Agg, whatever the
    environment names), cannot start: an ``MPLBACKEND`` it does not know makes its import fail. A
    :class:`ModelError` naming MPLBACKEND; called before a run that draws a figure, and by the
    command line's ``main`` to tell this cause of a failed import from a bug."""
    try:
        import matplotlib  # noqa: F401
    except ValueError:
        backend = os.environ.get("MPLBACKEND")
        if not backend:
            raise
        raise ModelError(
            "MPLBACKEND",
            backend,
            "must name a backend matplotlib knows (e.g. Agg) or be unset: matplotlib, which draws the figures "
            "(with Agg, whatever it names), does not start with it",
        ) from None


def check_distinct(*named):
    """Refuse two options naming the same file, ``named`` = (flag, path) pairs in order: ``--out``
    and ``--plot``, or an output and the input it is read from (the second write would replace the
    first, or the output its input). A path of None passes."""
    seen = {}
    for flag, path in named:
        if path in (None, True, False):
            continue
        key = Path(str(path)).resolve()
        if key in seen:
            raise ModelError(flag, str(path), f"must be another file than {seen[key]}'s (it would be written over)")
        seen[key] = flag


def _stamp(path):
    """What identifies the file at ``path`` now (its device, inode, size and modification time,
    through a symlink), or None when there is none: a file written since, atomically (a new file
    renamed over it), has another."""
    try:
        st = os.stat(path)
    except OSError:
        return None
    return (st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns)


class _Kept:
    """What an interrupt leaves of a command's output files: ``str()`` says it at the moment it is
    asked (when the interrupt comes), not when the command began. The files (``paths``; None: not
    asked for) are stamped at construction, before anything is written (:func:`_stamp`); then each
    one whose stamp has changed was written by this run (files are replaced atomically at the end
    of their write: one is either as it was or this run's whole), each one unchanged that existed
    is kept as it was, and the others were not written. ``what``: the line's start (``the run was
    stopped``)."""

    def __init__(self, what, *paths):
        self.what = what
        self.paths = [str(p) for p in paths if p not in (None, True, False)]
        self.before = {p: _stamp(p) for p in self.paths}

    def __str__(self):
        now = {p: _stamp(p) for p in self.paths}
        written = [p for p in self.paths if now[p] is not None and now[p] != self.before[p]]
        old = [p for p in self.paths if p not in written and now[p] is not None]
        new = [p for p in self.paths if p not in written and p not in old]
        parts = (
            ([f"{', '.join(written)} written by this run"] if written else [])
            + ([f"the previous {', '.join(old)} kept as {'it was' if len(old) == 1 else 'they were'}"] if old else [])
            + ([f"{', '.join(new)} not written"] if new else [])
        )
        return f"{self.what}: " + ("; ".join(parts) or "nothing was written")


def kept(what, *paths) -> _Kept:
    """What an interrupt leaves of the output files ``paths`` (None: not asked for), said when it
    comes (:class:`_Kept`): the command sets ``args.interrupted = kept("stopped", out, plot)`` before
    it writes anything, and the line then names the files it has written, those kept as they were
    and those not written."""
    return _Kept(what, *paths)


def emit_table(path, fields, table, digits, note="#"):
    """A numeric table: written to ``path`` as CSV under a one-line header of ``fields`` (the column
    names; one with a comma or a quote is quoted as the csv module writes it, so that a name such as
    ``acc, sensor 3`` stays one column), atomically, ``digits`` significant digits, and a line
    ``<note> wrote <path>``; or printed when ``path`` is None."""
    import numpy as np

    from ..files import atomic_path
    from ..records import csv_header

    header = csv_header(fields)

    if path:
        with atomic_path(path) as tmp:
            np.savetxt(tmp, table, delimiter=",", header=header, comments="", fmt=f"%.{digits}g")
        print(f"{note} wrote {path}".lstrip())
    else:
        print(header)
        for row in table:
            print(",".join(f"{v:.{digits}g}" for v in row))
