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

:data:`KERNELS_HASH` (16 hex digits of a SHA-256 over the names and contents of every ``.py`` file
of the package) is also the source stamp numba checks, so an edited package never loads stale code,
and copies with the same sources (the development install and the FMU's bundled copy) share one
cache. The root is the first of these whose ``kernels-<KERNELS_HASH>`` folder can be written
(:func:`cache_roots`), chosen once per process, when the package is imported:

1. ``NUMBA_CACHE_DIR``, if set;
2. the per-user cache folder ``<user_cache_base()>/numba``: ``platformdirs.user_cache_dir("cablecasing")``
   where platformdirs is installed, else ``$XDG_CACHE_HOME/cablecasing``, else ``~/.cache/cablecasing``
   (on Linux these are the same folder);
3. a folder of this user's in the temporary folder, ``<tempfile.gettempdir()>/cablecasing-<uid>/numba``
   (created 0700, only when the folders before it fail; used only while it is this user's and no one
   else can write it, and only in a temporary folder that is sticky or writable by its owner alone,
   this user or root, never the working folder ``tempfile`` falls back to: the machine code is
   loaded with pickle, so a folder another user can write, or rename and replace, would run their
   code here);
4. ``numba_cache`` beside the package, where a copy ships one (the FMU's ``resources/numba_cache``
   when the FMU imports the package from its unpack folder).

When a root is used after one that cannot be written but holds machine code (a read-only cache
prepared in advance: a container image), the functions it lacks are copied from there first
(:func:`seed_cache`), so nothing is compiled again. When the first is not the one used, the import
warns once (:class:`CacheFolderWarning`) naming the folders that could not be written and why. When
none can be written, nothing is saved: the machine code is loaded from the first of those folders
that holds some (read-only: a full cache in a read-only ``NUMBA_CACHE_DIR``, the FMU's read-only
unpack folder), and what is not there is compiled in every process; without any, every kernel is
compiled in every process (:func:`settle`). numba's own locators never serve these kernels (they
would key them by file: the stale callee above).

:func:`install` puts the locator first in numba's list, before any kernel is decorated (the locator
is chosen at decoration; nothing is compiled before a kernel's first call); :func:`settle`, after
they are, turns off saving where nothing can be written.

Importing this module compiles nothing (and does not import numba until :func:`install`); the FMU's
bridge loads this file by its path for :func:`cache_bases` and :func:`seed_cache` (before the
package can be imported).
"""

from __future__ import annotations

import hashlib
import os
import shutil
import stat
import sys
import tempfile
import warnings

PACKAGE_DIR = os.path.dirname(os.path.realpath(__file__))
#: ``numba_cache`` beside the package (``<folder of cablecasing_core>/numba_cache``): the FMU's resources/numba_cache
SHIPPED_ROOT = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(PACKAGE_DIR))), "numba_cache")


def _package_hash(folder):
    digest = hashlib.sha256()
    for name in sorted(os.listdir(folder)):
        if name.endswith(".py"):
            with open(os.path.join(folder, name), "rb") as f:
                digest.update(name.encode() + b"\0" + f.read() + b"\0")
    return digest.hexdigest()[:16]


#: 16 hex digits of a SHA-256 over the names and contents of the package's source files.
KERNELS_HASH = _package_hash(PACKAGE_DIR)


class CacheFolderWarning(UserWarning):
    """The kernels' machine code is not cached in the first folder of :func:`cache_roots` (it cannot
    be written): the message names the folders tried, why each failed, and the folder used (or that
    none is). Said once per process, at the import of the kernels."""


def user_cache_base() -> str:
    """The per-user cache folder of cablecasing: ``platformdirs.user_cache_dir("cablecasing")``
    where platformdirs is installed, else ``$XDG_CACHE_HOME/cablecasing`` (platformdirs' rule on
    Linux, so the two give the same folder there), else ``~/.cache/cablecasing``."""
    try:
        from platformdirs import user_cache_dir

        return user_cache_dir("cablecasing", appauthor=False)
    except ImportError:
        pass
    xdg = os.environ.get("XDG_CACHE_HOME", "")
    return os.path.join(xdg if xdg.strip() else os.path.join(os.path.expanduser("~"), ".cache"), "cablecasing")


def _temp_base_path():
    user = os.getuid() if hasattr(os, "getuid") else os.environ.get("USERNAME", "user")
    return os.path.join(tempfile.gettempdir(), f"cablecasing-{user}")


def _named_temp_folders():
    """The temporary folders a user or the system names: ``TMPDIR``, ``TEMP``, ``TMP`` and the usual
    ones (``/tmp``, ``/var/tmp``, ``/usr/tmp``), as real paths."""
    named = [os.environ.get(name) for name in ("TMPDIR", "TEMP", "TMP")]
    return {os.path.realpath(p) for p in named + ["/tmp", "/var/tmp", "/usr/tmp"] if p}


def _check_temp_parent(parent):
    """Raise PermissionError unless ``parent`` may hold this user's temporary cache folder: not the
    working folder that ``tempfile.gettempdir()`` falls back to when no temporary folder is usable,
    and sticky or writable by its owner alone (this user or root). Elsewhere another user could
    rename this user's checked folder away and put their own in its place (its machine code is
    loaded with pickle, the FMU's copy of the code imported)."""
    real = os.path.realpath(parent)
    if real == os.path.realpath(os.getcwd()) and real not in _named_temp_folders():
        raise PermissionError(f"{parent} is the working folder (there is no usable temporary folder)")
    if not hasattr(os, "getuid"):
        return
    st = os.stat(parent)
    if not st.st_mode & stat.S_ISVTX and (st.st_mode & 0o022 or st.st_uid not in (os.getuid(), 0)):
        raise PermissionError(f"{parent} is neither sticky nor writable by its owner alone (this user or root)")


def temp_cache_base() -> str:
    """This user's folder in the temporary folder, ``<tempfile.gettempdir()>/cablecasing-<uid>``,
    created 0700 when missing. Raises OSError (with a reason) when there is no usable temporary
    folder (``tempfile`` would give the working folder), when the temporary folder is neither sticky
    nor writable by its owner alone (this user or root), or when the folder is not this user's own:
    not a folder, another user's, or writable by others (its machine code is loaded with pickle: a
    folder another user can write, or rename, would run their code in this process)."""
    base = _temp_base_path()
    _check_temp_parent(os.path.dirname(base))
    try:
        os.mkdir(base, 0o700)
    except FileExistsError:
        pass
    st = os.lstat(base)
    if not stat.S_ISDIR(st.st_mode):
        raise NotADirectoryError(f"{base} is not a folder")
    if hasattr(os, "getuid") and (st.st_uid != os.getuid() or st.st_mode & 0o022):
        raise PermissionError(f"{base} is not this user's own (another user's, or others may write it)")
    return base


def cache_bases():
    """The per-user folders of cablecasing's caches, in order of preference, one at a time (an
    iterator: the temporary folder is checked and created only when asked for, after the first
    failed): ``(folder, None)`` for :func:`user_cache_base` and :func:`temp_cache_base`, ``(folder,
    reason)`` for one that cannot be had (no usable temporary folder, a folder that is not this
    user's). The kernels' root is ``<one of them>/numba``; the FMU's copy of its code goes to
    ``<one of them>/fmu``."""
    yield user_cache_base(), None
    try:
        base = temp_cache_base()
    except OSError as exc:
        try:
            where = _temp_base_path()
        except OSError:  # (no usable temporary folder at all)
            where = "the temporary folder"
        yield where, _reason(exc)
    else:
        yield base, None


def cache_root() -> str:
    """The preferred root of the kernels' cache: ``NUMBA_CACHE_DIR`` if set, else
    ``<user_cache_base()>/numba``. (The root in use may be another one: :func:`kernels_cache_dir`.)"""
    return os.environ.get("NUMBA_CACHE_DIR") or os.path.join(user_cache_base(), "numba")


def cache_roots():
    """The roots the kernels' cache may use, in order of preference, one at a time (an iterator, as
    :func:`cache_bases`): ``(root, why)`` with ``why`` None, or the reason a root cannot be had (see
    the module docstring for the order)."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        yield os.environ["NUMBA_CACHE_DIR"], None
    for base, why in cache_bases():
        yield (base if why else os.path.join(base, "numba")), why
    if os.path.isdir(SHIPPED_ROOT):
        yield SHIPPED_ROOT, None


def _reason(exc):
    """An OSError's reason in a few words: its strerror (Permission denied, Read-only file system),
    else its text."""
    return (exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)) or type(exc).__name__


def seed_cache(source, target):
    """Copy the numba cache of the folder ``source`` into ``target``, function by function: a function's
    index (``<base>.nbi``) with its data files (``<base>.<n>.nbc``), the index last, only where ``target``
    has no index of that function. Returns how many files were copied. numba's data files hold no key (the
    index says which numbered file holds the machine code of which signature, numbered in the order they
    were compiled), so an index of the target's own (kernels compiled there since) is kept with its own data
    files, never paired with another cache's file of the same number (one a save cut between index and data
    left missing); a data file no index of the target refers to is replaced. Each file through a temporary
    name of its own and a rename, as ``files.atomic_path`` writes, without its fsync and checks: a cache
    file lost in a crash is compiled again (this module imports nothing of the package: the FMU's bridge
    loads it by its path and seeds with it too)."""
    if not os.path.isdir(source) or os.path.realpath(source) == os.path.realpath(target):
        return 0
    os.makedirs(target, exist_ok=True)
    names = os.listdir(source)
    copied = 0
    for index in names:
        if not index.endswith(".nbi") or os.path.exists(os.path.join(target, index)):
            continue
        base = index[: -len(".nbi")]
        data = [n for n in names if n.startswith(base + ".") and n.endswith(".nbc") and n[len(base) + 1 : -4].isdigit()]
        for name in data + [index]:  # (the index last: it never names a data file not yet there)
            fd, tmp = tempfile.mkstemp(prefix=f".{name}.", suffix=".tmp", dir=target)  # (unique in any process)
            os.close(fd)
            try:
                shutil.copy2(os.path.join(source, name), tmp)
                os.replace(tmp, os.path.join(target, name))
            except BaseException:
                os.unlink(tmp)
                raise
            copied += 1
    return copied


def writable_folder(folder):
    """Create ``folder`` (and its parents) if missing and check that a file can be created in it, as
    numba's locators check theirs. Raises OSError when it cannot."""
    os.makedirs(folder, exist_ok=True)
    tempfile.TemporaryFile(dir=folder).close()


class CacheChoice:
    """Where this process caches the kernels' machine code (:func:`cache_choice`).

    ``folder``: the kernels' cache folder (``<root>/kernels-<KERNELS_HASH>``), None when they are
    not cached at all; ``mode``: ``"write"`` (loaded from and saved to ``folder``), ``"read"`` (loaded
    from ``folder``, which cannot be written: nothing is saved) or ``"none"``; ``preferred``: whether
    ``folder`` is under the first root of :func:`cache_roots`; ``tried``: ``[(root, reason)]`` of the
    roots before it that failed (every root for ``"read"`` and ``"none"``)."""

    def __init__(self, folder, mode, preferred, tried):
        self.folder, self.mode, self.preferred, self.tried = folder, mode, preferred, tried

    def failed(self) -> str:
        """The roots that could not be used, with why: ``A (Permission denied) and B (...)`` (as
        ``errors.and_joined`` joins them: this module imports nothing of the package)."""
        said = [f"{root} ({why})" for root, why in self.tried]
        return ", ".join(said[:-1]) + (" and " if len(said) > 1 else "") + (said[-1] if said else "")

    def note(self) -> str:
        """One line saying why the machine code is not cached in the preferred folder, naming the
        folders that could not be written and why, and what to set; '' when it is."""
        if self.preferred and self.mode == "write":
            return ""
        hint = "set NUMBA_CACHE_DIR to a writable folder"
        if self.mode == "write":
            return (
                f"the model's compiled kernels are cached in {self.folder}, because {self.failed()} cannot be "
                f"written; {hint} to choose where"
            )
        if self.mode == "read":
            return (
                f"no folder for the model's compiled kernels can be written ({self.failed()}): the machine code in "
                f"{self.folder} is loaded where it fits this CPU, Python and numba, and what it lacks is compiled "
                f"in every process (30-60 s, not saved); {hint}"
            )
        return (
            f"no folder for the model's compiled kernels can be written ({self.failed()}): they are compiled in "
            f"every process (30-60 s, not saved); {hint}"
        )


_CHOICE = None


def _has_index(folder):
    """Whether ``folder`` holds a numba index file that can be read."""
    try:
        names = os.listdir(folder)
    except OSError:
        return False
    return any(name.endswith(".nbi") and os.access(os.path.join(folder, name), os.R_OK) for name in names)


def cache_choice() -> CacheChoice:
    """Where the kernels' machine code is cached in this process (:class:`CacheChoice`): the first
    root of :func:`cache_roots` whose ``kernels-<KERNELS_HASH>`` folder can be written; if none can,
    the first whose folder holds machine code, read only; else none. Chosen once per process (the
    first call; the kernels' import makes it), creating that folder."""
    global _CHOICE
    if _CHOICE is None:
        env = os.environ.get("NUMBA_CACHE_DIR")
        tried, readable = [], None
        for k, (root, why) in enumerate(cache_roots()):
            shown = f"NUMBA_CACHE_DIR={root}" if k == 0 and env else root
            if why is None:
                folder = os.path.join(root, f"kernels-{KERNELS_HASH}")
                try:
                    writable_folder(folder)
                    if readable is not None:
                        try:
                            seed_cache(readable, folder)
                        except OSError:  # (best effort: what is not copied is compiled, and saved)
                            pass
                    _CHOICE = CacheChoice(folder, "write", k == 0, tried)
                    break
                except OSError as exc:
                    why = _reason(exc)
                    if readable is None and _has_index(folder):
                        readable = folder
            tried.append((shown, why))
        else:
            _CHOICE = CacheChoice(readable, "read" if readable else "none", False, tried)
    return _CHOICE


def kernels_cache_dir():
    """The folder of this package's numba cache in this process, ``<root>/kernels-<KERNELS_HASH>``
    (:func:`cache_choice`; None when no folder can be written or read: the kernels are not cached)."""
    return cache_choice().folder


def install():
    """Put the locator of this package's kernels first in numba's list of cache locators (once per
    copy of the package in a process), choosing the cache folder (:func:`cache_choice`; a warning,
    :class:`CacheFolderWarning`, when it is not the preferred one). Returns the locator class."""
    from numba.core.caching import CacheImpl, _CacheLocator

    for cls in CacheImpl._locator_classes:
        if getattr(cls, "package_dir", None) == PACKAGE_DIR:
            return cls
    choice = cache_choice()
    if choice.note():
        warnings.warn(choice.note(), CacheFolderWarning, stacklevel=2)

    class KernelsCacheLocator(_CacheLocator):
        """numba cache locator of the kernels package (see the module docstring)."""

        package_dir = PACKAGE_DIR

        def __init__(self, py_func, py_file):
            self._lineno = py_func.__code__.co_firstlineno
            # (no folder: a name numba never opens, settle() takes the cache away before any call)
            self._cache_path = choice.folder or os.path.join(cache_root(), f"kernels-{KERNELS_HASH}")
            self._py_file = py_file

        def get_cache_path(self):
            return self._cache_path

        def ensure_cache_path(self):
            if choice.mode == "write":
                super().ensure_cache_path()

        def get_source_stamp(self):
            return KERNELS_HASH

        def get_disambiguator(self):
            return str(self._lineno)

        @classmethod
        def from_function(cls, py_func, py_file):
            if os.path.dirname(os.path.realpath(py_file)) != cls.package_dir:
                return None
            return cls(py_func, py_file)

    CacheImpl._locator_classes.insert(0, KernelsCacheLocator)
    return KernelsCacheLocator


def _unsaved(*args):
    """A read-only cache's ``save_overload`` and ``flush``: nothing is written."""


def settle():
    """After the kernels are decorated: where the cache folder cannot be written, no kernel saves
    (numba would raise on the write after compiling); where there is no folder at all, no kernel
    has a cache (numba's NullCache: every kernel is compiled at its first call in each process).
    Returns how many kernels were changed."""
    choice = cache_choice()
    if choice.mode == "write":
        return 0
    from numba.core.caching import NullCache

    prefix = __name__.rpartition(".")[0] + "."
    changed = set()
    for name, module in list(sys.modules.items()):
        if not name.startswith(prefix) or module is None:
            continue
        for obj in list(vars(module).values()):
            cache = getattr(obj, "_cache", None)
            locator = getattr(getattr(cache, "_impl", None), "locator", None)
            if getattr(locator, "package_dir", None) != PACKAGE_DIR or id(obj) in changed:
                continue
            if choice.mode == "read":
                cache.save_overload = cache.flush = _unsaved
            else:
                obj._cache = NullCache()
            changed.add(id(obj))
    return len(changed)
