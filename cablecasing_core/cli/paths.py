"""Output paths of the command line, checked before a long run, and numeric tables written to them
or printed (a module of its own: every command module imports it, and it imports nothing of theirs)."""

from __future__ import annotations

from pathlib import Path

from ..errors import ModelError


def check_output_path(flag, path, suffixes=None):
    """Refuse an output file before a long run rather than after it: its folder must exist and, with
    ``suffixes``, its name must end in one of them. ``None`` (no output asked for) passes."""
    if path is None or path is True:
        return
    if suffixes and not str(path).endswith(tuple(suffixes)):
        raise ModelError(flag, path, "must end in " + " or ".join(suffixes))
    if not Path(path).resolve().parent.is_dir():
        raise ModelError(flag, path, "must be a file in an existing folder")


def emit_table(path, header, table, digits, note="#"):
    """A numeric table: written to ``path`` as CSV with the one-line ``header`` (atomically,
    ``digits`` significant digits) and a line ``<note> wrote <path>``; or printed when ``path`` is None."""
    import numpy as np

    from ..files import atomic_path

    if path:
        with atomic_path(path) as tmp:
            np.savetxt(tmp, table, delimiter=",", header=header, comments="", fmt=f"%.{digits}g")
        print(f"{note} wrote {path}".lstrip())
    else:
        print(header)
        for row in table:
            print(",".join(f"{v:.{digits}g}" for v in row))
