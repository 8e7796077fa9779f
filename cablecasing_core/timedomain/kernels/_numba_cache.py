"""Where the kernels' machine code is cached: one folder per content of this package.

numba's own locators key a function's cache by its source file (``__pycache__`` beside it, or
``NUMBA_CACHE_DIR/<folder>_<hash of the folder path>``) and check only that file's stamp. Two
things go wrong with that here. A kernel inlines or calls kernels of other files of this package,
and numba does not invalidate its cache when one of those changes (it would load machine code
compiled from the old callee). And the FMU is unpacked into a new temporary folder each time, so
every run would compile again (tens of seconds).

So every ``cache=True`` kernel of this package is cached in one folder keyed by the content of the
whole package, :func:`kernels_cache_dir`::

    <root>/kernels-<KERNELS_HASH>/

with root ``NUMBA_CACHE_DIR`` if set, else the per-user cache folder
``<platformdirs.user_cache_dir("cablecasing")>/numba`` (``~/.cache/cablecasing/numba`` without
platformdirs). :data:`KERNELS_HASH` (16 hex digits of a SHA-256 over the names and contents of
every ``.py`` file of the package) is also the source stamp numba checks, so an edited package
never loads stale code, and copies with the same sources (the development install and the FMU's
bundled copy) share one cache. :func:`install` puts the locator first in numba's list, before any
kernel is decorated (the locator is chosen at decoration; nothing is compiled before a kernel's
first call). When that folder cannot be written, numba's next locator takes over, as without it.

Importing this module compiles nothing (and does not import numba until :func:`install`).
"""

from __future__ import annotations

import hashlib
import os

PACKAGE_DIR = os.path.dirname(os.path.realpath(__file__))


def _package_hash(folder):
    digest = hashlib.sha256()
    for name in sorted(os.listdir(folder)):
        if name.endswith(".py"):
            with open(os.path.join(folder, name), "rb") as f:
                digest.update(name.encode() + b"\0" + f.read() + b"\0")
    return digest.hexdigest()[:16]


#: 16 hex digits of a SHA-256 over the names and contents of the package's source files.
KERNELS_HASH = _package_hash(PACKAGE_DIR)


def cache_root() -> str:
    """``NUMBA_CACHE_DIR`` if set, else the per-user cache folder ``.../cablecasing/numba``."""
    root = os.environ.get("NUMBA_CACHE_DIR")
    if root:
        return root
    try:
        from platformdirs import user_cache_dir

        base = user_cache_dir("cablecasing", appauthor=False)
    except ImportError:
        base = os.path.join(os.path.expanduser("~"), ".cache", "cablecasing")
    return os.path.join(base, "numba")


def kernels_cache_dir() -> str:
    """The folder of this package's numba cache: ``<cache_root()>/kernels-<KERNELS_HASH>``."""
    return os.path.join(cache_root(), f"kernels-{KERNELS_HASH}")


def install():
    """Put the locator of this package's kernels first in numba's list of cache locators (once per
    copy of the package in a process). Returns the locator class."""
    from numba.core.caching import CacheImpl, _CacheLocator

    for cls in CacheImpl._locator_classes:
        if getattr(cls, "package_dir", None) == PACKAGE_DIR:
            return cls

    class KernelsCacheLocator(_CacheLocator):
        """numba cache locator of the kernels package (see the module docstring)."""

        package_dir = PACKAGE_DIR

        def __init__(self, py_func, py_file):
            self._lineno = py_func.__code__.co_firstlineno
            self._cache_path = kernels_cache_dir()

        def get_cache_path(self):
            return self._cache_path

        def get_source_stamp(self):
            return KERNELS_HASH

        def get_disambiguator(self):
            return str(self._lineno)

        @classmethod
        def from_function(cls, py_func, py_file):
            if os.path.dirname(os.path.realpath(py_file)) != cls.package_dir:
                return None
            self = cls(py_func, py_file)
            try:
                self.ensure_cache_path()
            except OSError:  # not writable: numba's next locator takes over
                return None
            return self

    CacheImpl._locator_classes.insert(0, KernelsCacheLocator)
    return KernelsCacheLocator
