"""What made a report (report.html's header, runs.json's ``code``): the code, as a git commit with
its dirty flag when the package runs from a git checkout, else the installed package's version
(said so); the versions of Python and of the libraries the numbers go through; the command line.
A file's SHA-256 (the FMU of the demo) is :func:`sha256_of`."""

from __future__ import annotations

import hashlib
import importlib.metadata
import platform
import subprocess
from pathlib import Path

#: The libraries whose versions a report states: the numerics (numpy, scipy, numba), the figures
#: (matplotlib), the study (SALib) and the FMU's host (fmpy).
LIBRARIES = ("numpy", "scipy", "numba", "matplotlib", "SALib", "fmpy")


def _git(root: Path, *args: str) -> str | None:
    """``git -C root args...``'s stdout (stripped), or None when git is missing or fails."""
    try:
        r = subprocess.run(["git", "-C", str(root), *args], capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.SubprocessError):
        return None
    return r.stdout.strip() if r.returncode == 0 else None


def code_state(root: Path | None = None, exclude: str | Path | None = None) -> dict:
    """The code the package runs from: ``{"source": "git", "commit": 40 hex digits, "dirty": bool,
    "changed_paths": n}`` when its folder's parent ``root`` (default: that of the imported
    ``cablecasing_core``) is the top of a git work tree (``dirty``: ``git status --porcelain`` lists
    n > 0 paths, modified, staged or untracked and not ignored); else ``{"source": "package",
    "version": ..., "why": ...}``, the installed metadata's version (which a checkout's later commits
    do not change) and why no commit is given.

    ``exclude``: a folder whose files are not the code (a report's ``--out``, its staging folder in it),
    left out of the status (a pathspec ``:(exclude)``) when it lies inside the work tree, so that a
    report's earlier output there does not make the tree dirty; when it is the work tree's top, the
    names of the report's files (``report.REPORT_FILES``, its staging folders) are left out instead."""
    import cablecasing_core

    root = Path(cablecasing_core.__file__).resolve().parent.parent if root is None else Path(root)
    top = _git(root, "rev-parse", "--show-toplevel")
    version = cablecasing_core.__version__
    if top is None or Path(top).resolve() != root.resolve():
        why = "not run from a git checkout" if top is None else f"the package lies in {root}, not at the top of {top}"
        return {"source": "package", "version": version, "why": why}
    commit = _git(root, "rev-parse", "HEAD")
    status = _git(root, "status", "--porcelain", "--", ".", *_left_out(root.resolve(), exclude))
    if commit is None or status is None:
        return {"source": "package", "version": version, "why": "git could not read the checkout"}
    changed = len([line for line in status.splitlines() if line.strip()])
    return {"source": "git", "commit": commit, "dirty": changed > 0, "changed_paths": changed, "version": version}


def _left_out(top: Path, exclude) -> list[str]:
    """The pathspecs (relative to the work tree's top ``top``) that leave the folder ``exclude`` out
    of ``git status`` (see :func:`code_state`); [] when it lies outside the work tree."""
    if exclude is None:
        return []
    folder = Path(exclude).resolve()
    if folder == top:  # (the report's own names only: the rest of the top is the code)
        from . import REPORT_FILES, STAGE_PREFIX

        names = {n.split("/", 1)[0] for n in REPORT_FILES} | {f"{STAGE_PREFIX}*"}
        # (a name and what lies under it: git lists an untracked folder as one path, which `name` alone misses)
        return [f":(top,exclude,glob){n}{under}" for n in sorted(names) for under in ("", "/**")]
    if not folder.is_relative_to(top):
        return []
    return [f":(top,exclude,literal){folder.relative_to(top).as_posix()}"]


def describe_code(state: dict) -> str:
    """One line for the page: ``git commit <hash> (clean)`` / ``(dirty: n paths ...)``, or the
    package's version and why there is no commit."""
    if state["source"] == "git":
        if state["dirty"]:
            return (
                f"git commit {state['commit']}, dirty: {state['changed_paths']} path(s) differ from it "
                "(modified, staged or untracked; git status --porcelain)"
            )
        return f"git commit {state['commit']} (clean: the tree is that commit)"
    return f"cablecasing {state['version']} as installed (no git commit: {state['why']})"


def library_versions() -> dict:
    """{"Python": version, library: version or "not installed"} for :data:`LIBRARIES`."""
    out = {"Python": platform.python_version()}
    for name in LIBRARIES:
        try:
            out[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


def sha256_of(path) -> str:
    """The SHA-256 (hex) of the file at ``path``."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()
