"""The Python half of CableCasing.fmu's binary (``native/cablecasing_fmi2.c``): one
:class:`Instance` per ``fmi2Instantiate``.

The C side calls the methods below and returns the status each returns (an ``int``, FMI's
``fmi2Status``: 0 OK, 1 warning, 2 discard, 3 error). Value references and values cross as C
addresses (``ctypes``), so no list is built for a call. The support inputs and the outputs live
in two numpy arrays of the slave whose addresses the C side reads and writes directly.

What happens once per process and FMU (keyed by the FMU's GUID):

* the host Python is checked for the packages the model needs (numpy, scipy, numba) at the
  versions recorded at build time; a missing or old package stops the instantiation with one
  message, to the host's logger and to stderr;
* the bundled Python tree (``cablecasing_core``, the slave, pythonfmu's runtime) is copied from
  ``resources/`` to a per-user folder named by the GUID (``<cache>/fmu/<GUID>``, the cache folder
  the core's rule gives: the per-user cache folder, else this user's folder in the temporary folder)
  and imported from there, so a host that deletes the unpack folder after a run (fmpy's
  ``simulate_fmu``) can load the FMU again in the same process: the modules stay imported and every
  file they read later is still there. Copies no process has used for :data:`PRUNE_AFTER_DAYS` are
  deleted (never one a process holds: :func:`_hold`; never one made by an FMU built before the
  copies were locked: :data:`LOCKED_MARK`);
* the numba cache shipped in ``resources/numba_cache`` seeds the kernels' cache folder (the core
  chooses it: ``kernels/_numba_cache.py``; a fallback is logged as a warning naming the folders that
  cannot be written), so a first start does not compile; where no folder can be written the kernels
  load the shipped machine code from the unpack folder itself. If it does not fit (another CPU,
  Python or numba), numba compiles and this module says so in the log while it happens, and whether
  later starts will load it: once per process (whichever CableCasing FMUs it holds), in the log of
  the instance whose call compiles (:class:`_CompileNotice`).
"""

from __future__ import annotations

import ctypes
import errno
import importlib.machinery
import importlib.util
import os
import shutil
import sys
import tempfile
import threading
import time
import traceback
import types
import warnings

OK, WARNING, DISCARD, ERROR = 0, 1, 2, 3
_LOG_FN = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_char_p, ctypes.c_int)
_CATEGORY = {OK: b"logAll", WARNING: b"logStatusWarning", DISCARD: b"logStatusDiscard", ERROR: b"logStatusError"}
_LOADED = {}  # GUID -> the slave module of that FMU, imported once per process
# Held while an FMU's code is looked up or loaded: a master that instantiates on several threads at
# once (a thread pool on a cold cache) loads it once, the others wait and take that module.
_LOAD_LOCK = threading.Lock()
# The slave's lock of the process's warning filters (CableCasing.py: catch_warnings swaps them for the
# whole process), shared by every FMU of the process on the warnings module.
_WARNINGS_LOCK = warnings.__dict__.setdefault("_cablecasing_fmu_lock", threading.RLock())
# The beginning of the kernels' warning that their cache folder is not the preferred one
# (_numba_cache.CacheChoice.note): the FMU logs that itself, with what it means for the FMU.
_CACHE_WARNING = "(the model's compiled kernels are cached in|no folder for the model's compiled kernels)"


def _sources_digest(package):
    """SHA-256 over the relative paths and bytes of every .py file below ``package`` (a folder)."""
    import hashlib

    h = hashlib.sha256()
    for root, dirs, files in os.walk(package):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for name in sorted(f for f in files if f.endswith(".py")):
            path = os.path.join(root, name)
            h.update(os.path.relpath(path, package).encode())
            with open(path, "rb") as f:
                h.update(f.read())
    return h.hexdigest()


class FMUStartError(Exception):
    """The FMU cannot start in this process (the reason has been logged)."""


def _read_environment(resources):
    """resources/python-environment.txt as a dict (written by build_fmu.py)."""
    out = {}
    try:
        with open(os.path.join(resources, "python-environment.txt"), encoding="utf-8") as f:
            for line in f:
                key, sep, value = line.rstrip("\n").partition("=")
                if sep:
                    out[key.strip()] = value.strip()
    except OSError:
        pass
    return out


def _version_tuple(text):
    parts = []
    for piece in text.split(".")[:3]:
        digits = "".join(c for c in piece if c.isdigit())
        if not digits:
            break
        parts.append(int(digits))
    return tuple(parts)


def missing_packages(requirements):
    """Problems with ``requirements`` ('numpy>=1.24;scipy>=1.11;...') in this Python: list of texts."""
    from importlib import metadata

    problems = []
    for req in filter(None, (r.strip() for r in requirements.split(";"))):
        name, _, minimum = req.partition(">=")
        try:
            have = metadata.version(name)
        except metadata.PackageNotFoundError:
            problems.append(f"{name} is not installed (needs {req})")
            continue
        if minimum and _version_tuple(have) < _version_tuple(minimum):
            problems.append(f"{name} {have} is too old (needs {req})")
    return problems


def externally_managed():
    """Whether this Python's packages are managed by the system (PEP 668: an ``EXTERNALLY-MANAGED``
    file in its standard library's folder, outside a virtual environment), where pip refuses to
    install (Debian's and Ubuntu's /usr/bin/python3)."""
    import sysconfig

    if sys.prefix != sys.base_prefix:  # (a virtual environment: pip installs into it)
        return False
    return os.path.isfile(os.path.join(sysconfig.get_path("stdlib"), "EXTERNALLY-MANAGED"))


def install_advice(needed, requirements, python_host):
    """How to get the packages ``needed`` (requirement texts such as 'numba>=0.59'), in a sentence:
    pip into this Python; where the system manages its packages (PEP 668, :func:`externally_managed`),
    a virtual environment with every package of ``requirements`` instead, which a C host then runs
    through CABLECASING_PYTHON (a Python host runs the FMU in its own interpreter: it is the host that
    must run from the environment)."""
    quoted = " ".join(f'"{r}"' for r in needed)
    if not externally_managed():
        return f"Install {'it' if len(needed) == 1 else 'them'} with '{sys.executable} -m pip install {quoted}'" + (
            "" if python_host else ", or point CABLECASING_PYTHON at a Python that has them"
        )
    every = " ".join(f'"{r.strip()}"' for r in requirements.split(";") if r.strip())
    venv = f"'{sys.executable} -m venv ENV && ENV/bin/python -m pip install {every}'"
    if python_host:
        return (
            f"This Python's packages are managed by the system (PEP 668: pip refuses to install into it): make a "
            f"virtual environment with them, {venv}, and run the host with ENV/bin/python"
        )
    return (
        f"This Python's packages are managed by the system (PEP 668: pip refuses to install into it): make a "
        f"virtual environment with them, {venv}, and set CABLECASING_PYTHON to the full path of ENV/bin/python"
    )


def _cache_module(resources):
    """The FMU's own ``cablecasing_core/timedomain/kernels/_numba_cache.py``, loaded by its path as a
    private module (not in ``sys.modules``), for the rule of where cablecasing's caches go
    (``cache_bases``: the per-user cache folder, else this user's folder in the temporary folder).
    It is needed to place the lasting copy of the code (:func:`_stable_copy`) before that package
    can be imported, and seeds the kernels' cache folder with the shipped machine code
    (``seed_cache``); only its functions are used (this private copy installs no locator: the
    kernels' is the imported package's), so the rule and the seeding have one implementation."""
    path = os.path.join(resources, "cablecasing_core", "timedomain", "kernels", "_numba_cache.py")
    spec = importlib.util.spec_from_file_location("_cablecasing_fmu_cache_rule", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


#: A copy of the FMU's code not used for this long (its ``.complete`` marker's mtime, renewed at each
#: load) is deleted by the next load of any CableCasing FMU (:func:`_prune_copies`), unless in use.
PRUNE_AFTER_DAYS = 14
#: What this bridge writes in a copy's ``.complete``: the copy is held under a lock while in use
#: (:func:`_hold`). Copies without it (made by FMUs built before the bridge locked them, which may
#: be in use unlocked by a running host) are never pruned.
LOCKED_MARK = b"cablecasing fmu copy, held under flock while in use\n"
_INTERRUPTED = {}  # GUID (the copy's folder name) -> the exception that interrupted its import in this process
_HELD = []  # open .complete markers of the copies this process uses, each under a shared lock (flock)


def _undo_interrupted_import(before):
    """Remove from ``sys.modules`` what an interrupted import left half-done (``before``: the names there
    before it), so that the next import runs afresh: the pure-Python modules added since ``before`` whose
    enclosing package is no longer in ``sys.modules``. Python itself removes each module whose code raised
    (a package whose ``__init__`` was running when the interruption came: ``numba``), but keeps the
    submodules that package had completed; a new import of the package then finds them, in an order its
    own import never produces, and fails ("partially initialized module 'numba.core.caching'").

    Kept: the modules whose packages all completed (as after any failed import in Python: a later
    import of what failed goes on from them; numpy and scipy when a later module was interrupted), and
    every extension module (compiled). An extension module cannot be taken back: numpy's refuse a second
    load in a process ("cannot load module more than once per process"), and others keep what their first
    initialisation took from Python modules. No complete package is removed either: one kept holds
    references to the classes of the packages it imported (numba to llvmlite's), which fresh copies of
    those would not match. What remains possible: an interruption inside numpy's own first import (a
    Python host that had not imported numpy) cannot be undone, since numpy's compiled core then holds
    the first copies of numpy's Python modules: the next import fails and says so (start the host again).
    Checked by interrupting the slave's import at numba's, scipy's, numpy's, llvmlite's, pythonfmu's and
    cablecasing_core's modules (``tests/fmu/test_plain_c_host.py`` holds three)."""
    for name in set(sys.modules) - before:
        parts = name.split(".")
        orphan = any(".".join(parts[:k]) not in sys.modules for k in range(1, len(parts)))
        if orphan and not _is_extension(sys.modules.get(name)):
            sys.modules.pop(name, None)


def _is_extension(module):
    """Whether ``module`` is an extension module (compiled, loaded from a shared library)."""
    spec = getattr(module, "__spec__", None)
    return isinstance(getattr(spec, "loader", None), importlib.machinery.ExtensionFileLoader)


def _hold(dest):
    """Take a shared lock on ``dest/.complete`` for the rest of the process (the copy is in use: no
    prune deletes it), and mark its last use (the marker's mtime). Returns False when ``dest`` went
    away meanwhile (a prune of another process renamed it just now), True otherwise (also where
    there are no locks: not POSIX)."""
    marker = os.path.join(dest, ".complete")
    try:
        import fcntl
    except ImportError:
        return os.path.isfile(marker)
    try:
        fd = os.open(marker, os.O_RDONLY)
    except OSError:
        return False
    for _ in range(200):  # (a prune holds its exclusive lock only while it renames the folder)
        try:
            fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
            break
        except OSError as exc:
            if exc.errno not in (errno.EWOULDBLOCK, errno.EAGAIN):
                break  # (no locks on this filesystem, ENOLCK or EOPNOTSUPP: used unlocked; no prune locks it either)
            time.sleep(0.01)
    try:
        if os.stat(marker).st_ino != os.fstat(fd).st_ino:
            os.close(fd)
            return False
    except OSError:
        os.close(fd)
        return False
    try:
        os.utime(marker)
    except OSError:  # (a copy in a folder that is no longer writable: still used, not marked)
        pass
    _HELD.append(fd)
    return True


def _prune_copies(root, keep):
    """Delete the copies of FMU code under ``root`` (``.../cablecasing/fmu``) not used for
    :data:`PRUNE_AFTER_DAYS` and not in use (no process holds their marker's lock: :func:`_hold`),
    and temporary folders of copies that were stopped half-way a day ago; never ``keep``, nor a copy
    whose marker does not hold :data:`LOCKED_MARK` (made by an older bridge that does not lock it). Each is
    renamed under an exclusive lock first, then removed. Best effort: anything that fails is kept."""
    try:
        import fcntl
    except ImportError:
        return
    now = time.time()
    try:
        names = os.listdir(root)
    except OSError:
        return
    for name in names:
        path = os.path.join(root, name)
        if name == keep:
            continue
        try:
            if name.startswith(".") and name.endswith((".tmp", ".old")):
                # (no lock guards a copy being written: another process may be writing this one now. Its
                # folder's mtime is renewed by each entry it adds, .complete the last, so a day's age is
                # one that was stopped, never one in progress)
                if now - os.lstat(path).st_mtime > 86400:
                    shutil.rmtree(path, ignore_errors=True)
                continue
            marker = os.path.join(path, ".complete")
            if name.startswith(".") or now - os.stat(marker).st_mtime < PRUNE_AFTER_DAYS * 86400:
                continue
            fd = os.open(marker, os.O_RDONLY)
            try:
                if os.read(fd, len(LOCKED_MARK) + 1) != LOCKED_MARK:
                    continue  # (an older bridge's copy: it may be in use without a lock)
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)  # (fails while a process holds it: in use)
                gone = os.path.join(root, f".{name}.{os.getpid()}.old")
                os.rename(path, gone)
            finally:
                os.close(fd)
            shutil.rmtree(gone, ignore_errors=True)
        except OSError:
            continue


#: The file in a copy of the FMU's code that lists what makes it whole: each file copied (its path
#: relative to the copy, tab, its size in bytes), written before the copy is renamed into place. (Not in
#: ``.complete``, whose content the prune compares with :data:`LOCKED_MARK` as a whole.)
CONTENTS = ".contents"


def _list_contents(folder):
    """``CONTENTS``'s text for ``folder``: every file below it but the markers and ``__pycache__``."""
    lines = []
    for root, dirs, files in os.walk(folder):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for name in sorted(files):
            path = os.path.join(root, name)
            rel = os.path.relpath(path, folder)
            if rel not in (".complete", CONTENTS):
                lines.append(f"{rel}\t{os.path.getsize(path)}")
    return "\n".join(lines) + "\n"


def _damage(dest):
    """Why the copy ``dest`` cannot be used as it is (None when whole): no ``.complete`` marker (a copy
    is renamed into place with it, so a folder without it lost it), no :data:`CONTENTS`, or a file it
    lists that is missing or of another size (a cleaner of old files in the temporary folder, a hand).
    One ``stat`` per file (~150): cheap beside the import it precedes."""
    if not os.path.isfile(os.path.join(dest, ".complete")):
        return "it has no .complete marker"
    try:
        with open(os.path.join(dest, CONTENTS), encoding="utf-8") as f:
            listed = [line.rsplit("\t", 1) for line in f.read().splitlines() if line]
    except OSError:
        return f"it has no {CONTENTS} list of its files"
    for rel, size in listed:
        try:
            have = os.path.getsize(os.path.join(dest, rel))
        except OSError:
            return f"{rel} is missing"
        if str(have) != size:
            return f"{rel} has {have} bytes, not {size}"
    return None


def _set_aside(root, guid, dest):
    """Remove the damaged copy ``dest``: renamed away under an exclusive lock of ``root`` (so that of
    processes that find it damaged at once, one renames it and the others then find the new copy
    whole), then deleted. A process that holds it keeps the modules it imported. Returns why it was
    set aside, or None when another process has put a whole copy there meanwhile."""
    try:
        import fcntl
    except ImportError:
        fcntl = None
    fd = os.open(root, os.O_RDONLY)
    try:
        if fcntl is not None:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX)
            except OSError:  # (no locks on this filesystem: renamed unlocked)
                pass
        why = _damage(dest) if os.path.isdir(dest) else None
        if why is None:
            return None
        gone = os.path.join(root, f".{guid}.{os.getpid()}.damaged.old")
        os.rename(dest, gone)
    finally:
        os.close(fd)
    shutil.rmtree(gone, ignore_errors=True)
    return why


def _stable_copy(resources, guid, names, bases, say=None):
    """The folder holding a copy of ``names`` (files and folders of resources/) that outlives the
    unpack folder: ``<base>/fmu/<guid>`` for the first of ``bases`` (``[(folder, reason it cannot be
    had, or None)]``, the core's ``cache_bases()``) where it is or can be written; written once,
    atomically (a temporary folder renamed into place: a folder, which ``files.atomic_path`` does
    not write, and before the core can be imported), with the list of its files (:data:`CONTENTS`);
    checked against that list at each use, and a damaged copy (:func:`_damage`) replaced by a new one,
    ``say`` (a function of one text) told why; held by this process (:func:`_hold`), and old unused
    copies beside it pruned (:func:`_prune_copies`). Returns (the folder, or ``resources`` when none
    can be written; ``[(root, reason)]`` of the roots that failed)."""
    tried = []
    for base, why in bases:
        root = os.path.join(base, "fmu")
        if why is not None:
            tried.append((base, why))
            continue
        dest = os.path.join(root, guid)
        try:
            for _attempt in range(2):  # (again once if a prune took the copy between the check and the hold)
                damage = _damage(dest) if os.path.isdir(dest) else None
                if damage is not None:
                    damage = _set_aside(root, guid, dest)
                    if damage is not None and say is not None:
                        say(
                            f"the copy of the model's Python code in {dest} was damaged ({damage}): it was "
                            "deleted and is copied again from the FMU"
                        )
                if not os.path.isfile(os.path.join(dest, ".complete")):
                    os.makedirs(root, exist_ok=True)
                    tmp = tempfile.mkdtemp(prefix=f".{guid}.", suffix=".tmp", dir=root)  # (unique in any process)
                    for name in names:
                        src = os.path.join(resources, name)
                        if os.path.isdir(src):
                            shutil.copytree(src, os.path.join(tmp, name), ignore=shutil.ignore_patterns("__pycache__"))
                        elif os.path.isfile(src):
                            shutil.copy2(src, os.path.join(tmp, name))
                    with open(os.path.join(tmp, CONTENTS), "w", encoding="utf-8") as f:
                        f.write(_list_contents(tmp))
                    with open(os.path.join(tmp, ".complete"), "wb") as f:
                        f.write(LOCKED_MARK)
                    try:
                        os.rename(tmp, dest)
                    except OSError:  # another process was first: use its copy
                        shutil.rmtree(tmp, ignore_errors=True)
                if _hold(dest):
                    _prune_copies(root, guid)
                    return dest, tried
            tried.append((root, "its copy was deleted while it was being loaded"))
        except OSError as exc:
            tried.append((root, exc.strerror or str(exc)))
    return resources, tried


def _compile_fate(choice, caches, resources):
    """What becomes of kernels compiled in this process, for the compile notice: whether later starts
    load them, and if not, why (the folders that cannot be written) and what to set. ``choice``: the
    imported package's ``cache_choice()`` (None from a host's copy of the package too old to have it)."""
    if choice is None:
        return f"and later starts load them from {', '.join(caches) or 'nowhere'}"
    hint = "set NUMBA_CACHE_DIR to a writable folder"
    if choice.mode != "write":
        failed = choice.failed()
        return f"and every start compiles them again: nothing can be saved ({failed} cannot be written); {hint}"
    if os.path.realpath(choice.folder).startswith(os.path.join(os.path.realpath(resources), "")):
        return (
            f"and they are saved in the unpack folder ({choice.folder}) because {choice.failed()} cannot be "
            f"written: a host that deletes that folder after the run (fmusim does) compiles them again at every "
            f"start; {hint}"
        )
    if not choice.preferred:
        return (
            f"and later starts load them from {choice.folder} while it lasts (a fallback: {choice.failed()} cannot "
            "be written)"
        )
    return f"and later starts load them from {choice.folder}"


def kernel_cache_dirs():
    """The cache folders of the numba kernels of the imported cablecasing_core (each cached
    dispatcher knows its own; numba compiles lazily, so none is read before the first call)."""
    dirs = set()
    for name, module in list(sys.modules.items()):
        if name.split(".")[0] == "cablecasing_core" and module is not None:
            for obj in vars(module).values():
                path = getattr(getattr(obj, "_cache", None), "_cache_path", None)
                if isinstance(path, str) and hasattr(obj, "stats"):
                    dirs.add(path)
    return sorted(dirs)


# The compile notice's state, one per process: every FMU (every GUID) of a process imports this file
# as a bridge module of its own, so it is kept on the sys module, the one thing they all share (as the
# slave keeps its warnings lock on the warnings module).
_NOTICE = sys.__dict__.setdefault(
    "_cablecasing_fmu_compile_notice",
    types.SimpleNamespace(lock=threading.Lock(), live=[], caller=threading.local(), listener=None, said_in=None),
)


class _CompileNotice:
    """The notice that numba compiles the model's kernels (no cached machine code fits this CPU,
    Python and numba): said once per process, while it happens, as the first message of the
    compilation, whichever instance of whichever CableCasing FMU compiles. One numba event listener
    serves every instance of the process (:data:`_NOTICE`); it is registered while an instance lives
    and unregistered with the last (nothing of it outlives fmi2FreeInstance). The notice goes to the
    instance whose FMI call runs on the compiling thread (``_NOTICE.caller``, set by
    :meth:`Instance._guard`), else to the oldest live instance; an instance whose call compiles after
    the notice was said in another one gets one short line (info). Compilations of other code (the
    host's own numba functions) are not the model's and are not announced."""

    @staticmethod
    def join(instance):
        """``instance`` lives: it may hear the notice; the listener is registered with the first."""
        with _NOTICE.lock:
            _NOTICE.live.append(instance)
            if _NOTICE.listener is None:
                try:
                    from numba.core import event

                    class Listener(event.Listener):
                        def on_start(self, ev):
                            _CompileNotice.compiling(ev)

                        def on_end(self, ev):
                            pass

                    listener = Listener()
                    event.register("numba:compile", listener)
                    _NOTICE.listener = listener
                except Exception:  # noqa: BLE001  (a numba without the event API: no notice, nothing else changes)
                    pass

    @staticmethod
    def leave(instance):
        """``instance`` is freed; the listener goes with the last live instance."""
        with _NOTICE.lock:
            if instance in _NOTICE.live:
                _NOTICE.live.remove(instance)
            listener = _NOTICE.listener if not _NOTICE.live else None
            if listener is not None:
                _NOTICE.listener = None
                try:
                    from numba.core import event

                    event.unregister("numba:compile", listener)
                except Exception:  # noqa: BLE001
                    pass

    @staticmethod
    def compiling(ev):
        dispatcher = (ev.data or {}).get("dispatcher")
        module = str(getattr(getattr(dispatcher, "py_func", None), "__module__", None) or "")
        if module.split(".")[0] != "cablecasing_core":  # (the host's own numba code)
            return
        with _NOTICE.lock:
            instance = getattr(_NOTICE.caller, "instance", None)
            if instance is None or instance not in _NOTICE.live:
                instance = _NOTICE.live[0] if _NOTICE.live else None
            if instance is None or instance._compile_told:
                return
            instance._compile_told = True
            first, _NOTICE.said_in = _NOTICE.said_in is None, _NOTICE.said_in or instance._name
        name = getattr(dispatcher, "__qualname__", "?")
        if first:
            instance._log(
                WARNING,
                "compiling the model's numba kernels for this machine (no cached machine code in "
                f"{instance._cache_text} fits this model's kernels on this CPU, Python and numba: the FMU ships "
                f"those of its base model, the installed specimen and gravity); this takes 30-60 s, "
                f"{instance._module.numba_cache_fate} (first kernel: {name}; said once per process)",
            )
        else:
            instance._log(
                OK,
                f"compiling more of the model's numba kernels (first: {name}); said in full once per process, "
                f"in the log of instance {_NOTICE.said_in!r}",
            )


class LiveState:
    """The slave's state that an FMU state of the binary holds (one per fmi2GetFMUstate or
    fmi2DeSerializeFMUstate, released by fmi2FreeFMUstate or with its instance by fmi2FreeInstance);
    :attr:`live` counts those not released in this process (of this FMU build), for tests."""

    __slots__ = ("value",)
    live = 0
    _lock = threading.Lock()

    def __init__(self, value):
        self.value = value
        with LiveState._lock:
            LiveState.live += 1

    def __del__(self):
        with LiveState._lock:
            LiveState.live -= 1


def _c_strings(addr, n):
    return (ctypes.c_void_p * n).from_address(addr)


class Instance:
    """One FMU instance: the slave and the C buffers' addresses (see the module docstring)."""

    def __init__(self, name, guid, resources, visible, logging_on, log_addr, handle, python_note, fmi_version):
        self._log_c = _LOG_FN(log_addr)
        self._handle = handle
        if python_note.startswith("attached") and getattr(sys, "_cablecasing_started_by_fmu", False):
            # (the C side found an interpreter running: the one a CableCasing binary started before it was
            # unloaded and loaded again, not a Python host's; that binary marked it)
            python_note = python_note.replace("attached to the host process's Python", "uses the Python") + (
                " that CableCasing.fmu started earlier in this process (its binary was unloaded and loaded again)"
            )
        self._in_python_host = python_note.startswith("attached")  # (the C side's note: "attached to the host ...")
        self._keep = []  # strings handed to C by get_string, alive until the next call
        self._name = name
        env = _read_environment(resources)
        built_for = f" built for the model file {env['model']}" if env.get("model") else ""
        self._log(
            OK,
            f"CableCasing.fmu {env.get('version', '?')}{built_for} (FMI {fmi_version}): {python_note}; "
            f"Python executable {sys.executable}",
        )
        if env.get("guid") and guid != env["guid"]:
            self._fail(
                f"fmuGUID {guid!r} does not match this FMU's {env['guid']!r}: the modelDescription.xml "
                "the host read belongs to another build of CableCasing.fmu"
            )
        requirements = env.get("requirements", "numpy;scipy;numba")
        problems = missing_packages(requirements)
        if problems:
            # (only what is missing or too old is to be installed: each requirement checked alone)
            needed = [r.strip() for r in requirements.split(";") if r.strip() and missing_packages(r)]
            self._fail(
                f"the Python at {sys.executable} cannot run this FMU: "
                + "; ".join(problems)
                + ". "
                + install_advice(needed, requirements, self._in_python_host)
            )
        with _LOAD_LOCK:
            module = _LOADED.get(guid)
            if module is None:
                module = self._load(resources, guid)
        self._module = module
        self._cache_text = ", ".join(module.numba_cache_dirs) or "any folder (none can be written or read)"
        self._compile_told = False  # (told of numba compiling: _CompileNotice, once per instance at most)
        self._slave = None
        _CompileNotice.join(self)
        outer, _NOTICE.caller.instance = getattr(_NOTICE.caller, "instance", None), self
        try:
            self._slave = module.CableCasing(instance_name=name, resources=resources, visible=visible)
        except BaseException:
            _CompileNotice.leave(self)
            raise
        finally:
            _NOTICE.caller.instance = outer
        self._slave.attach_log_sink(self._log)
        # the binary calls this every step: the slave's own method, which raises nothing (an
        # exception that escapes anyway is fmi2Error with its message in the C side)
        self.do_step = self._slave.fmi2_do_step
        self._bind()

    # ---------------------------------------------------------------------------------- start-up
    def _load(self, resources, guid):
        try:
            rule = _cache_module(resources)
        except (OSError, ImportError, SyntaxError) as exc:
            self._fail(f"the model's Python code in {resources} is incomplete or unreadable: {exc}")
        names = [n for n in os.listdir(resources) if n != "numba_cache"]
        home, tried = _stable_copy(resources, guid, names, rule.cache_bases(), lambda text: self._log(WARNING, text))
        if home == resources:
            failed = "; ".join(f"{root}: {why}" for root, why in tried)
            self._log(
                WARNING,
                f"cannot write a lasting copy of the model's Python code ({failed}): it is imported from the "
                "unpack folder, so loading this FMU again in this process after that folder is deleted may fail",
            )
        t0 = time.perf_counter()
        spec = importlib.util.spec_from_file_location(
            f"_cablecasing_slave_{guid.replace('-', '_')}", os.path.join(home, "CableCasing.py")
        )
        module = importlib.util.module_from_spec(spec)
        before = set(sys.modules)
        sys.path.insert(0, home)  # the slave imports cablecasing_core and pythonfmu from there
        try:
            # (the kernels' import warns where their cache folder is not the preferred one: said below, in the log)
            with _WARNINGS_LOCK, warnings.catch_warnings():
                warnings.filterwarnings("ignore", message=_CACHE_WARNING)
                spec.loader.exec_module(module)
        except BaseException as exc:  # noqa: BLE001  (KeyboardInterrupt too: undone, then said: _import_failed)
            self._fail(self._import_failed(home, resources, exc, before))
        finally:
            sys.path.remove(home)
        _INTERRUPTED.pop(guid, None)
        here = os.path.dirname(os.path.abspath(module.cc.__file__))
        hosts = os.path.dirname(here) != os.path.abspath(home)
        if not hosts:  # (the advice concerns a Python host only: a C host has no other copy to compare)
            advice = (
                ": in a Python host, a later 'import cablecasing_core' in the same process gets this copy; to "
                "compare the FMU with your own copy of the package, import it before the first FMU is loaded"
            )
            self._log(OK, f"cablecasing_core imported from this FMU ({here}){advice if self._in_python_host else ''}")
        else:
            own = os.path.join(home, "cablecasing_core")
            same = _sources_digest(here) == _sources_digest(own)
            self._log(
                OK if same else WARNING,
                f"cablecasing_core was already imported from {here} before this FMU was loaded; "
                + (
                    "that copy is used (its Python sources are the FMU's own)"
                    if same
                    else f"that copy is used, not the FMU's own (in {home}), and its sources differ"
                ),
            )
        # where the kernels' machine code is cached in this process (the imported package's choice)
        used = sys.modules.get("cablecasing_core.timedomain.kernels._numba_cache")
        choice = used.cache_choice() if hasattr(used, "cache_choice") else None
        caches, seeded = kernel_cache_dirs(), 0
        if choice is None or choice.mode == "write":
            for cache in caches:
                try:
                    seeded += rule.seed_cache(os.path.join(resources, "numba_cache", os.path.basename(cache)), cache)
                except OSError as exc:
                    self._log(WARNING, f"cannot copy the shipped numba cache to {cache}: {exc}")
        module.numba_cache_dirs = caches
        module.numba_cache_fate = _compile_fate(choice, caches, resources)
        _LOADED[guid] = module
        self._log(
            OK,
            f"slave code imported from {home}"
            + (f", model code the host's cablecasing_core ({here})" if hosts else "")
            + f" in {time.perf_counter() - t0:.2f} s; numba cache "
            f"{', '.join(caches) or '(none)'} ({seeded} files copied from the FMU)",
        )
        if choice is not None and choice.note():
            self._log(WARNING, choice.note())
        return module

    def _import_failed(self, home, resources, exc, before):
        """The message of an import of the model's code from ``home`` that raised ``exc``. An interruption
        (KeyboardInterrupt: a Ctrl-C in a Python host's main thread; SystemExit) is undone first, as far as
        it can be (:func:`_undo_interrupted_import`; ``before``: the names in ``sys.modules`` before), so
        that the next fmi2Instantiate imports afresh: a half-imported numba otherwise made every later
        instantiation fail with "partially initialized module". An ordinary exception (a SyntaxError, a
        missing module) is not undone: importing again would raise it again, and it is reported as itself
        at every instantiation."""
        text = str(exc) or type(exc).__name__
        guid = os.path.basename(home) if home != resources else ""
        if not isinstance(exc, Exception):  # (KeyboardInterrupt, SystemExit)
            _undo_interrupted_import(before)
            _INTERRUPTED[guid] = type(exc).__name__
            return (
                f"the import of the model's Python code from {home} was interrupted ({type(exc).__name__}); "
                "the modules it had left half-imported were unloaded, so the next fmi2Instantiate imports them again"
            )
        if guid in _INTERRUPTED:  # (what the interruption left may be the cause: a new process is the remedy)
            hint = (
                f"; an earlier import of it in this process was interrupted ({_INTERRUPTED[guid]}), which may have "
                "left this: start the host again"
                + (
                    f", and if it fails the same way then, delete {home} (the next start copies it again)"
                    if home != resources
                    else ""
                )
            )
        elif home != resources:
            hint = f"; if that folder was damaged, delete it: the next start copies it again from {resources}"
        else:
            hint = ""
        return f"the model's Python code cannot be imported from {home}: {type(exc).__name__}: {text}{hint}"

    def _bind(self):
        s = self._slave
        self.input_address = s.inputs_buffer.ctypes.data
        self.output_address = s.outputs_buffer.ctypes.data
        self.input_vr0, self.input_count = s.input_vr0, len(s.inputs_buffer)
        self.output_vr0, self.output_count = s.output_vr0, len(s.outputs_buffer)
        ints = s.integer_output_vrs
        self.integer_output_count = len(ints)
        for k, vr in enumerate(ints):
            setattr(self, f"integer_output_vr{k}", vr)

    def _log(self, status, message, stderr=False):
        """To the host's logger now (through the C side), and to stderr when ``stderr``."""
        if not isinstance(message, bytes):
            message = str(message).encode("utf-8", "backslashreplace")
        self._log_c(self._handle, status, _CATEGORY.get(status, b"logAll"), message, 1 if stderr else 0)

    def _fail(self, message):
        """Refuse to start: the C side logs the message once, to the host's logger and to stderr
        (``fmi2Instantiate``: "CableCasing.fmu cannot be instantiated: ...")."""
        raise FMUStartError(message)

    def _guard(self, what, fn, *args):
        """Run ``fn`` as this instance's call (the compile notice's hearer: _CompileNotice); an
        exception becomes fmi2Error with its traceback in the log."""
        caller = _NOTICE.caller
        outer, caller.instance = getattr(caller, "instance", None), self
        try:
            return fn(*args)
        except Exception as exc:  # noqa: BLE001
            self._log(ERROR, f"internal error in {what}: {exc!r}\n{traceback.format_exc()}")
            return ERROR
        finally:
            caller.instance = outer

    # ---------------------------------------------------------------------------------- life cycle
    def setup_experiment(self, tol_defined, tol, start, stop_defined, stop):
        return self._guard(
            "fmi2SetupExperiment",
            self._slave.fmi2_setup_experiment,
            start,
            stop if stop_defined else None,
            tol if tol_defined else None,
        )

    def enter_initialization_mode(self):
        return self._guard("fmi2EnterInitializationMode", self._slave.fmi2_enter_initialization_mode)

    def exit_initialization_mode(self):
        return self._guard("fmi2ExitInitializationMode", self._slave.fmi2_exit_initialization_mode)

    def terminate(self):
        return self._guard("fmi2Terminate", self._slave.fmi2_terminate)

    def reset(self):
        return self._guard("fmi2Reset", self._slave.fmi2_reset)

    def free(self):
        _CompileNotice.leave(self)  # (the last instance takes the process's numba listener along)
        # The slave, its engine and this instance go at once, by reference counting, not at the
        # cyclic garbage collector's next run (a C host's instance per run held every engine until
        # then): the slave drops its variables' closures (which refer back to it), and this instance
        # its references to the slave (do_step is its bound method).
        slave, self._slave, self.do_step = self._slave, None, None
        if slave is not None:
            slave.fmi2_free_instance()
        return OK

    def last_successful_time(self):
        return float(self._slave.last_successful_time())

    def terminated(self):
        return bool(self._slave.terminated())

    def phase(self):
        """The life-cycle phase (0 instantiated, 1 initialisation mode, 2 stepping, 3 terminated):
        the binary asks after fmi2SetFMUstate, which restores the phase the state was saved in."""
        return float(self._slave.phase)

    # ---------------------------------------------------------------------------------- variables
    def get_real(self, vr_addr, n, out_addr):
        vrs = (ctypes.c_uint * n).from_address(vr_addr)
        out = (ctypes.c_double * n).from_address(out_addr)
        return self._guard("fmi2GetReal", self._slave.fmi2_get, "Real", vrs, out)

    def get_integer(self, vr_addr, n, out_addr):
        vrs = (ctypes.c_uint * n).from_address(vr_addr)
        out = (ctypes.c_int * n).from_address(out_addr)
        return self._guard("fmi2GetInteger", self._slave.fmi2_get, "Integer", vrs, out)

    def get_boolean(self, vr_addr, n, out_addr):
        vrs = (ctypes.c_uint * n).from_address(vr_addr)
        out = (ctypes.c_int * n).from_address(out_addr)
        return self._guard("fmi2GetBoolean", self._slave.fmi2_get, "Boolean", vrs, out)

    def get_string(self, vr_addr, n, out_addr):
        vrs = (ctypes.c_uint * n).from_address(vr_addr)
        values = [None] * n
        status = self._guard("fmi2GetString", self._slave.fmi2_get, "String", vrs, values)
        if status <= WARNING:
            keep = [ctypes.create_string_buffer(str(v).encode("utf-8")) for v in values]
            ptrs = _c_strings(out_addr, n)
            for k, buf in enumerate(keep):
                ptrs[k] = ctypes.addressof(buf)
            self._keep = keep  # valid until the next call (FMI 2.0)
        return status

    def set_real(self, vr_addr, n, in_addr):
        vrs = (ctypes.c_uint * n).from_address(vr_addr)
        values = list((ctypes.c_double * n).from_address(in_addr))
        return self._guard("fmi2SetReal", self._slave.fmi2_set, "Real", vrs, values)

    def set_integer(self, vr_addr, n, in_addr):
        vrs = (ctypes.c_uint * n).from_address(vr_addr)
        values = list((ctypes.c_int * n).from_address(in_addr))
        return self._guard("fmi2SetInteger", self._slave.fmi2_set, "Integer", vrs, values)

    def set_boolean(self, vr_addr, n, in_addr):
        vrs = (ctypes.c_uint * n).from_address(vr_addr)
        values = list((ctypes.c_int * n).from_address(in_addr))  # (ints: the slave refuses one that is not 0 or 1)
        return self._guard("fmi2SetBoolean", self._slave.fmi2_set, "Boolean", vrs, values)

    def set_string(self, vr_addr, n, in_addr):
        vrs = (ctypes.c_uint * n).from_address(vr_addr)
        values = []
        for ptr in _c_strings(in_addr, n):
            if ptr is None:
                values.append(None)  # refused by the slave, by name
                continue
            raw = ctypes.string_at(ptr)
            try:
                values.append(raw.decode("utf-8"))
            except UnicodeDecodeError:
                values.append(raw)  # bytes: refused by the slave, by name
        return self._guard("fmi2SetString", self._slave.fmi2_set, "String", vrs, values)

    # ---------------------------------------------------------------------------------- FMU state
    def get_state(self):
        return LiveState(self._slave.fmi2_get_state())

    def set_state(self, state):
        return self._guard("fmi2SetFMUstate", self._slave.fmi2_set_state, state.value)

    def serialize_state(self, state):
        return self._slave.serialize_state(state.value)

    def deserialize_state(self, data):
        state = self._slave.deserialize_state(data)
        return LiveState(state) if state is not None else False
