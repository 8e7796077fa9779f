"""Writing files atomically: the one place where the package's output files are written.

A file is written under a temporary name in its target folder and renamed over the target only
when it is complete (``os.replace``, atomic on POSIX and Windows within a folder). An error or an
interrupt (Ctrl-C) while writing leaves the target as it was, the previous version intact, and no
half-written file; the temporary file is removed.

>>> with atomic_path("results.npz") as tmp:    # a writer that takes a path (numpy, pyuff, matplotlib)
...     np.savez(tmp, x=x)
>>> write_text("report.html", html)            # text in one call
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike):
    """Yield a temporary path in ``path``'s folder with the same suffix (writers such as
    ``numpy.savez`` and ``savefig`` go by it); when the block ends without an exception, the file
    written there is flushed to disk and renamed to ``path``. On any exception (KeyboardInterrupt
    too) it is deleted and ``path`` is left as it was."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=f".part{path.suffix}", dir=path.parent)
    os.close(fd)
    os.remove(tmp)  # the writer creates it (some refuse or append to an existing file)
    try:
        yield tmp
        with open(tmp, "rb+") as fh:
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.remove(tmp)
        raise


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically (see :func:`atomic_path`); returns the path."""
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", newline="") as fh:
        fh.write(text)
    return Path(path)
