"""Where the FMU's numba kernels are cached: a per-user folder that survives the unpacked FMU.

An importer unpacks the FMU into a new temporary folder each time. numba's own locators key the
cache by the source file's folder (``NUMBA_CACHE_DIR/<folder name>_<sha1 of the folder path>``) or
write into ``__pycache__`` next to it, so every run would compile the kernels again (tens of
seconds). :func:`install` puts :class:`FMUCacheLocator` first in numba's locator list; it serves
only source files of the ``cablecasing_core`` package inside a registered resources folder and
keys their cache by the *content* of the file, not its path:

    <NUMBA_CACHE_DIR>/fmu/<module>-<sha256 of the source, 16 hex>/

The source stamp numba checks is the same content hash, so an edited package never loads stale
machine code, and different FMU versions keep separate caches side by side. Everything else numba
compiles in the host process is left to numba's usual locators.
"""
from __future__ import annotations

import hashlib
import os

_RESOURCE_PACKAGES: set = set()     # absolute paths of <resources>/cablecasing_core


def default_cache_dir():
    """The per-user cache folder for numba (platformdirs' user cache dir when available, else
    ``~/.cache``), sub-folder ``cablecasing/numba``."""
    try:
        from platformdirs import user_cache_dir
        base = user_cache_dir("cablecasing", appauthor=False)
    except ImportError:
        base = os.path.join(os.path.expanduser("~"), ".cache", "cablecasing")
    return os.path.join(base, "numba")


def install(resources):
    """Register ``<resources>/cablecasing_core`` and put the locator first in numba's list.

    Call after NUMBA_CACHE_DIR is set and before ``cablecasing_core.kernels`` is imported (the
    locator is chosen when a ``cache=True`` function is decorated). Idempotent."""
    _RESOURCE_PACKAGES.add(os.path.join(os.path.abspath(resources), "cablecasing_core"))
    from numba.core.caching import CacheImpl, _CacheLocator

    global FMUCacheLocator
    if "FMUCacheLocator" not in globals():
        FMUCacheLocator = _make_locator(_CacheLocator)
    if FMUCacheLocator not in CacheImpl._locator_classes:
        CacheImpl._locator_classes.insert(0, FMUCacheLocator)
    return FMUCacheLocator


def _make_locator(base):
    class _FMUCacheLocator(base):
        """numba cache locator for the FMU's bundled package (see the module docstring)."""

        def __init__(self, py_func, py_file):
            self._py_file = py_file
            self._lineno = py_func.__code__.co_firstlineno
            with open(py_file, "rb") as f:
                self._stamp = hashlib.sha256(f.read()).hexdigest()
            root = os.environ.get("NUMBA_CACHE_DIR") or default_cache_dir()
            module = os.path.splitext(os.path.basename(py_file))[0]
            self._cache_path = os.path.join(root, "fmu", f"{module}-{self._stamp[:16]}")

        def get_cache_path(self):
            return self._cache_path

        def get_source_stamp(self):
            return self._stamp

        def get_disambiguator(self):
            return str(self._lineno)

        @classmethod
        def from_function(cls, py_func, py_file):
            path = os.path.abspath(py_file)
            if not any(path.startswith(p + os.sep) for p in _RESOURCE_PACKAGES) or not os.path.isfile(path):
                return None
            self = cls(py_func, path)
            try:
                self.ensure_cache_path()
            except OSError:      # read-only home: numba's next locator takes over
                return None
            return self

    _FMUCacheLocator.__name__ = _FMUCacheLocator.__qualname__ = "FMUCacheLocator"
    return _FMUCacheLocator
