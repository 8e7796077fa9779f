"""Output paths of the command line, checked before a long run (a module of its own: every command
module imports it, and it imports nothing of theirs)."""

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
