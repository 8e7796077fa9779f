"""The executor of the studies: one sample in this process or on a dask.distributed worker, and the
loop over all samples, serial, on threads of this process or on dask (the Monte-Carlo study and the
seed ensemble both run through :func:`execute`).

On threads (``scheduler="threads"``) the samples run at once in this process, one per thread: the
time domain's step loop runs outside the interpreter's lock, so they overlap as far as the runs'
Python (their motion's chunks, their records, the band levels) leaves them (docs/studies.md, "Where
the samples run"). Python's warning filters are the process's, so a sample on a thread does not swap
them (``warnings.catch_warnings`` in two threads at once restores each other's): the loop sets them
once for all its samples and gives each warning to the sample whose thread warned it
(:func:`_warnings_by_thread`). An ``evaluate`` of the user's own must not change the filters then.

Failures are told apart by where they happen. A sample whose evaluation raises is a *model* failure:
:func:`evaluate_sample` catches it and returns a row of status ``failed`` with the exception. Any
exception of a dask future itself (a worker killed while it ran the sample, the scheduler lost, the
task cancelled) is an *infrastructure* failure: no row is written for it, the sample is passed to
``lost`` with its cause (the study keeps them in ``<csv>.lost.log``) and the same command runs it
again; the loop ends with an :class:`~cablecasing_core.errors.InfrastructureError` (exit status 3).
When no sample finishes within ``progress_timeout`` seconds (:data:`PROGRESS_TIMEOUT`: every worker
dead or stalled, the scheduler gone) the loop ends with an InfrastructureError that names the
cause. A scheduler address is connected to within :data:`CONNECT_TIMEOUT` seconds, before a study
creates any file (:class:`Workers`).

The warnings a sample's evaluation gives (the model's, a run's: a contact Newton that did not
converge, a tolerance not met) are kept with its row, in this process or on a worker, and said
again here, prefixed with the sample's label (``sample 3``, an ensemble's ``seed 3``); a message
that several samples give word for word (a model warning) is said once, for the first of them.
Every sample's own are kept in its row as one line (``row["warnings"]``), which the study's CSV
and the ensemble store, so that the samples that warned can be told afterwards.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import contextlib
import importlib
import logging
import math
import os
import sys
import threading
import time
import warnings

from ..errors import NOT_SHOWN, InfrastructureError, ModelError
from ..extras import install_hint
from ..model.limits import PROGRESS_TIMEOUT
from ..model.validators import integer
from ..timedomain.engine import stop_runs_on

#: Seconds to reach a scheduler address.
CONNECT_TIMEOUT = 10.0


def missing_packages(scheduler=None, salib=True):
    """The optional packages that a study (``salib``: its Saltelli design and Sobol' indices need
    SALib) or an ensemble (``salib=False``) on ``scheduler`` needs and that cannot be imported: SALib,
    and dask's distributed unless ``scheduler`` is ``"serial"`` or ``"threads"`` (a run in this
    process needs no dask)."""
    wanted = ([("SALib", "SALib")] if salib else []) + (
        [] if _in_process(scheduler) else [("distributed", "dask[distributed]")]
    )
    missing = []
    for module, name in wanted:
        try:
            importlib.import_module(module)
        except ImportError:
            missing.append(name)
    return missing


def check_packages(scheduler=None, salib=True, key="scheduler", name="study"):
    """Refuse, before anything is created, a study (``salib``) or an ensemble (not ``salib``) whose
    optional packages are not installed (:func:`missing_packages`): a ModelError naming ``key`` (the
    option or argument of the scheduler) and its value when dask is missing, else ``name`` (what
    needs SALib), with the packages and the extra to install (:func:`~cablecasing_core.extras.install_hint`)."""
    missing = missing_packages(scheduler, salib)
    if not missing:
        return
    what = "a study" if salib else "an ensemble"
    pkgs = " and ".join(missing)
    packages = (
        f"the optional package{'' if len(missing) == 1 else 's'} {pkgs}, which {'is' if len(missing) == 1 else 'are'}"
    )
    if "dask[distributed]" not in missing:  # (SALib alone: its design and Sobol' indices, whatever the scheduler)
        raise ModelError(name, NOT_SHOWN, f"needs {packages} not installed: {install_hint('study', missing)}")
    where = "a local dask cluster" if scheduler in (None, "local") else "a dask scheduler"
    serial = f"; or {key} serial, which needs {'SALib only' if salib else 'no dask'}" if len(missing) == 1 else ""
    raise ModelError(
        key,
        "local" if scheduler is None else scheduler,
        f"{what} on {where} needs {packages} not installed: {install_hint('study', missing)}{serial}",
    )


#: The environment variables that choose the floating-point kernels of a process (OpenBLAS's core
#: type, numpy's SIMD dispatch, numba's target CPU): :func:`kernel_environment` records them.
KERNEL_VARIABLES = (
    "OPENBLAS_CORETYPE",
    "NPY_DISABLE_CPU_FEATURES",
    "NPY_ENABLE_CPU_FEATURES",
    "NUMBA_CPU_NAME",
    "NUMBA_CPU_FEATURES",
)


def kernel_environment() -> dict:
    """What decides the floating-point kernels of a sample run in this process (a study's rows are
    bitwise those of another process only where this is the same; docs/studies.md, "Where the samples run"):
    the versions of numpy, scipy and numba, the machine (``platform.machine()``) and its CPU model
    (``/proc/cpuinfo``'s model name, else ``platform.processor()``), and the variables of
    :data:`KERNEL_VARIABLES` that are set. A dict of str, JSON-serialisable."""
    import platform

    env = {"machine": platform.machine(), "cpu": _cpu_model()}
    for name in ("numpy", "scipy", "numba"):
        try:
            env[name] = importlib.import_module(name).__version__
        except ImportError:
            env[name] = "not installed"
    env.update({k: os.environ[k] for k in KERNEL_VARIABLES if k in os.environ})
    return env


def _cpu_model():
    """The CPU's model name (``/proc/cpuinfo``; ``platform.processor()`` where there is none)."""
    import platform

    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as fh:
            for line in fh:
                if line.lower().startswith(("model name", "cpu model", "hardware")):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def kernel_environments(workers) -> list:
    """The distinct :func:`kernel_environment` of the processes that run the samples on ``workers``
    (a :class:`Workers`): this process when serial, else every dask worker connected now (none
    when the scheduler does not answer)."""
    if workers.client is None:
        return [kernel_environment()]
    try:
        found = workers.client.run(kernel_environment).values()
    except Exception:  # (a lost scheduler: the run says so)
        return []
    out = []
    for env in found:
        if env not in out:
            out.append(env)
    return out


#: The schedulers that run the samples in this process: one after the other, or on threads.
IN_PROCESS = ("serial", "threads")


def _kind(scheduler):
    """``"serial"``, ``"threads"`` (this process) or None (dask), of a scheduler or a :class:`Workers`."""
    name = getattr(scheduler, "scheduler", scheduler)
    return name if isinstance(name, str) and name in IN_PROCESS else None


def _in_process(scheduler):
    return _kind(scheduler) is not None


def check_scheduler(scheduler):
    """Refuse, with a ModelError naming ``scheduler``, what :class:`Workers` cannot run samples on:
    anything but None, ``"serial"``, ``"threads"``, ``"local"``, an address (a str) or a
    ``distributed.Client`` (its class or a subclass, told by the class's name and module, so that
    distributed, which a run in this process does without, is not imported for it)."""
    client = any(c.__name__ == "Client" and c.__module__.startswith("distributed.") for c in type(scheduler).__mro__)
    if not (scheduler is None or isinstance(scheduler, str) or client):
        raise ModelError(
            "scheduler",
            scheduler,
            "must be None, 'serial', 'threads', 'local', an address 'tcp://host:8786' or a distributed.Client",
        )
    named = (*IN_PROCESS, "local")
    if isinstance(scheduler, str) and scheduler not in named and ":" not in scheduler:
        from ..errors import closest  # (no port: no address dask connects to, a typo such as 'lcoal')

        close = closest(scheduler, named)
        raise ModelError(
            "scheduler",
            scheduler,
            "must be 'serial', 'threads', 'local' or a scheduler address with its port, such as tcp://host:8786"
            + (f" (did you mean {close[0]!r}?)" if close else ""),
        )


def resolve_evaluate(spec):
    """The per-sample function of the study (Section 4.4) named by ``spec``: a callable (returned as
    is) or ``"package.module:function"`` (also ``"package.module.function"``). Raises ModelError if
    it cannot be imported."""
    if callable(spec):
        return spec
    if not isinstance(spec, str) or not spec:
        raise ModelError("evaluate", spec, "must be a callable or a dotted import path 'package.module:function'")
    mod_name, sep, attr = spec.partition(":")
    if not sep:
        mod_name, _, attr = spec.rpartition(".")
    try:
        fn = getattr(importlib.import_module(mod_name), attr)
    except (ImportError, AttributeError, ValueError) as exc:
        raise ModelError(
            "evaluate", spec, f"must name an importable function 'package.module:function' ({exc})"
        ) from None
    if not callable(fn):
        raise ModelError("evaluate", spec, "must name a callable")
    return fn


def spec_name(spec):
    if isinstance(spec, str):
        return spec
    return f"{getattr(spec, '__module__', '?')}:{getattr(spec, '__qualname__', repr(spec))}"


def evaluate_sample(spec, kwargs, index, overrides, outputs):
    """Run one sample (in the main process or on a dask worker); never raises for an Exception. A
    row is ``failed`` when evaluate raises, returns no dict, no value of an output or one that is not
    a finite number (NaN, inf: ``ValueError: evaluate returned nan for oct5``)."""
    t0 = time.perf_counter()
    row = {"index": index, "status": "ok", "error": ""}
    said = []
    try:
        with _recorded() as said:  # (said again by the executor: _say)
            res = resolve_evaluate(spec)(dict(overrides), **kwargs)
        if not isinstance(res, dict):
            raise TypeError(f"evaluate returned {type(res).__name__}, expected dict of output name -> float")
        missing = [o for o in outputs if o not in res]
        if missing:
            raise KeyError(f"evaluate returned no value for {missing}; it gave {sorted(res)}")
        for o in outputs:
            row[o] = float(res[o])
            if not math.isfinite(row[o]):  # (an ok row's outputs are numbers: the statistics use them all)
                raise ValueError(f"evaluate returned {row[o]!r} for {o}")
    except Exception as exc:  # a failed sample is recorded, the study goes on
        row = {"index": index, "status": "failed", "error": f"{type(exc).__name__}: {exc}".replace("\n", " | ")}
    row["elapsed_s"] = time.perf_counter() - t0
    row[WARNINGS] = [(w.category, str(w.message)) for w in said]
    return row


#: What a thread of the threads scheduler knows: ``on`` (it runs samples) and ``said`` (the warnings
#: of its sample in progress, or None).
_THREAD = threading.local()


@contextlib.contextmanager
def _recorded():
    """The warnings given inside the block, as a list of ``warnings.WarningMessage``, all of them
    (``"always"``): on a thread of the threads scheduler, those its own thread warns
    (:func:`_warnings_by_thread` hands them over); elsewhere by ``warnings.catch_warnings``."""
    if getattr(_THREAD, "on", False):
        outer, said = getattr(_THREAD, "said", None), []  # (a study inside a sample: the outer one's list back after)
        _THREAD.said = said
        try:
            yield said
        finally:
            _THREAD.said = outer
    else:
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            yield said


@contextlib.contextmanager
def _warnings_by_thread():
    """For samples on threads: the process's warning filters set to ``"always"`` for the block, and
    each warning shown while a thread's sample is in progress given to that sample's list (the
    others shown as before); yields the filters in force before, which say whether a model's own
    warning is said once (:func:`_say`). Python's own ``catch_warnings`` swaps process-wide state, which two
    threads' blocks would restore in each other's stead (Python 3.14's context-aware warnings would
    make this per thread by itself)."""
    with warnings.catch_warnings():
        outer = list(warnings.filters)
        warnings.simplefilter("always")
        shown = warnings.showwarning

        def show(message, category, filename, lineno, file=None, line=None):
            said = getattr(_THREAD, "said", None)
            if said is None:
                shown(message, category, filename, lineno, file, line)
            else:
                said.append(warnings.WarningMessage(message, category, filename, lineno, file, line))

        warnings.showwarning = show
        yield outer


def _sample_thread(stop):
    """The initializer of the threads scheduler's threads: their runs end when ``stop`` is set."""
    _THREAD.on = True
    stop_runs_on(stop)


#: The key of a row from :func:`evaluate_sample` that holds its warnings, (category, message) each;
#: taken out of the row before it is written.
WARNINGS = "_warnings"


#: What joins a sample's messages in the one line ``row["warnings"]`` (``""`` when it gave none).
WARNING_SEPARATOR = " | "


def _say(row, label, said, filters=None):
    """Warn, in this process, what the sample of ``row`` gave (its WARNINGS, taken out of the row
    and kept in it as the line ``row["warnings"]``, every message, for the results), each message
    prefixed with ``label(index)``; a message already in the set ``said`` is not said again (several
    samples of one model give its warnings word for word). A message of the model itself, not of
    the run (a ModelPropertyWarning), is said once per process: not again by the next study of the
    same model (``ensemble --against``, ``report``) nor after its direct run or its loading said it
    (errors.warn_once_per_process). ``filters``: the caller's warning filters, when the process's are
    not theirs (the threads scheduler's "always" block): a message they ignore is not said, one they
    make an error raises, as the process's filters do in serial."""
    from ..errors import ModelPropertyWarning, _filter_action, warn_once_per_process

    given = row.pop(WARNINGS, ())
    for category, message in given:
        if message not in said:
            said.add(message)
            text = f"{label(row['index'])}: {message}"
            # (the frame warnings.warn's stacklevel=3 names below: a filter by module matches as there)
            action = None if filters is None else _filter_action(text, category, sys._getframe(2), filters)
            if action == "ignore":
                continue
            if action == "error":
                raise category(text)
            if issubclass(category, ModelPropertyWarning):
                warn_once_per_process(text, category, stacklevel=3, key=message, filters=filters)
            else:
                warnings.warn(text, category, stacklevel=3)
    row["warnings"] = WARNING_SEPARATOR.join(" ".join(str(m).split()) for _, m in given)


#: The options of the project's local dask clusters: worker processes of one thread, no dashboard.
#: (dashboard_address=None leaves out the dashboard, but distributed's scheduler still opens its HTTP
#: routes, on port 8787, and warns "Port 8787 is already in use" into the run's output when another
#: cluster holds it: a port the system picks on this machine's loopback keeps two studies at once quiet.)
LOCAL_CLUSTER_OPTIONS = {
    "threads_per_worker": 1,
    "processes": True,
    "dashboard_address": None,
    "scheduler_kwargs": {"dashboard_address": "127.0.0.1:0"},
}


class _ShutdownNoise(logging.Filter):
    """Drops the two records a worker of the package's own LocalCluster logs when the cluster is
    closed under it (a Ctrl-C, a timeout): its heartbeat finding the scheduler gone (ERROR, with a
    traceback) and a sample cancelled in flight (WARNING). The caller says what was kept and what was
    lost (the study's message, ``study.csv.lost.log``), so these are no news; every other record
    passes."""

    def filter(self, record):
        text = record.getMessage()
        return not (
            text.startswith("Failed to communicate with scheduler during heartbeat")
            or (text.startswith("Async instruction for") and text.endswith("ended with CancelledError"))
        )


def _quiet_shutdown_class():
    """:class:`QuietShutdown`, a ``distributed.WorkerPlugin`` (imported only with a cluster)."""
    from distributed import WorkerPlugin

    class QuietShutdown(WorkerPlugin):
        """Installs :class:`_ShutdownNoise` on the worker's loggers, in the worker's process."""

        name = "cablecasing-quiet-shutdown"

        def setup(self, worker):
            for name in ("distributed.worker", "distributed.worker.state_machine"):
                logger = logging.getLogger(name)
                if not any(isinstance(f, _ShutdownNoise) for f in logger.filters):
                    logger.addFilter(_ShutdownNoise())

    QuietShutdown.__module__ = __name__
    QuietShutdown.__qualname__ = "QuietShutdown"
    return QuietShutdown


def __getattr__(name):  # (QuietShutdown by name, so that a worker unpickles it without importing dask first)
    if name == "QuietShutdown":
        cls = _quiet_shutdown_class()
        globals()["QuietShutdown"] = cls
        return cls
    raise AttributeError(name)


def _cluster_deaf_to_ctrl_c(LocalCluster, n_workers):
    """A LocalCluster whose processes do not take SIGINT or SIGHUP, started so that a Ctrl-C meanwhile
    still stops this process. A Ctrl-C at the terminal reaches the whole process group: each worker
    printed its KeyboardInterrupt traceback while this process closed the cluster and said what was
    kept; a closed terminal's SIGHUP killed multiprocessing's resource tracker, which was restarted
    during the shutdown with tracebacks on stderr.

    While the cluster starts, both signals are blocked in the main thread (signal handlers live
    there), so the threads it starts (dask's event loop, which starts the workers, and restarts
    them later) and every process started from them (a spawned or forked worker, the resource
    tracker) inherit them blocked and never take them; the resource tracker is started first, in
    the window, since starting it unblocks SIGINT in the calling thread. A signal that arrives
    meanwhile is kept: pending while blocked, or recorded by a handler when another thread of this
    process takes it. After the start the previous handlers and mask are restored and a signal that
    arrived is delivered again, so that the caller's way out runs (a KeyboardInterrupt, the command
    line's exit status 130; the cluster is closed then). A signal that was ignored stays ignored."""
    import signal
    import threading

    def start():
        return LocalCluster(n_workers=n_workers, **LOCAL_CLUSTER_OPTIONS)

    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "pthread_sigmask"):
        return start()  # pragma: no cover - (another thread; Windows)
    from multiprocessing import resource_tracker

    stops = {signal.SIGINT} | ({signal.SIGHUP} if hasattr(signal, "SIGHUP") else set())
    arrived = []
    before = {s: signal.getsignal(s) for s in stops if signal.getsignal(s) is not signal.SIG_IGN}
    for s in before:
        signal.signal(s, lambda signum, frame: arrived.append(signum))
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, stops)
    cluster = None
    try:
        resource_tracker.ensure_running()
        signal.pthread_sigmask(signal.SIG_BLOCK, stops)
        cluster = start()
    finally:
        try:
            for s, handler in before.items():
                signal.signal(s, signal.SIG_DFL if handler is None else handler)
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)  # (a pending signal is delivered here)
            for s in dict.fromkeys(arrived):
                signal.raise_signal(s)
        except BaseException:  # (the caller's handler stopped it: the cluster is not returned)
            if cluster is not None:
                cluster.close()
            raise
    return cluster


class Workers:
    """Where the samples run: ``"serial"`` (this process, one after the other), ``"threads"`` (this
    process, ``n_workers`` threads, default one per core), ``None``/``"local"`` (a LocalCluster of
    ``n_workers`` processes, default one per core), an address ``"tcp://host:8786"`` (reached within
    :data:`CONNECT_TIMEOUT` s, or a :class:`ModelError`) or a ``distributed.Client`` (used, left open).
    A context manager: a cluster or client it made is closed at the end."""

    def __init__(self, scheduler=None, n_workers=None):
        self.scheduler, self.client, self._own, self._cluster = scheduler, None, None, None
        self.n_workers = None if n_workers is None else integer("n_workers", n_workers, 1)
        check_scheduler(scheduler)
        if _in_process(scheduler):
            return
        if isinstance(scheduler, str) or scheduler is None:  # (a Client passed in: distributed is there)
            check_packages(scheduler, salib=False)
        from distributed import Client, LocalCluster

        if scheduler is None or scheduler == "local":
            nw = os.cpu_count() if self.n_workers is None else self.n_workers
            self._cluster = _cluster_deaf_to_ctrl_c(LocalCluster, nw)
            self.client = self._own = Client(self._cluster)
            self.client.register_plugin(__getattr__("QuietShutdown")())  # (our own cluster's workers only)
        elif isinstance(scheduler, str):
            try:
                self.client = self._own = Client(scheduler, timeout=f"{CONNECT_TIMEOUT:g}s")
            except (OSError, ValueError, TimeoutError) as exc:
                raise ModelError(
                    "scheduler",
                    scheduler,
                    "must be 'serial', 'threads', 'local' or a scheduler address such as tcp://host:8786 that answers "
                    f"within {CONNECT_TIMEOUT:g} s ({type(exc).__name__})",
                ) from None
        else:  # (a distributed.Client: check_scheduler)
            self.client = scheduler

    def close(self):
        for thing in (self._own, self._cluster):
            if thing is not None:
                try:
                    thing.close()
                except Exception:  # (a lost scheduler: nothing left to close)
                    pass
        self._own = self._cluster = None

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb):
        if exc_type is not None and issubclass(exc_type, KeyboardInterrupt):  # (Ctrl-C, cli's Terminated)
            # A worker still in a sample is killed after dask's grace of 4 s, on purpose (the rows are
            # written by this process, not by it): dask's warning that it killed it is no news then.
            nanny = logging.getLogger("distributed.nanny")
            level = nanny.level
            nanny.setLevel(logging.ERROR)
            try:
                self.close()
            finally:
                nanny.setLevel(level)
        else:
            self.close()


def execute(
    todo,
    evaluate,
    kwargs,
    outputs,
    writer,
    bar,
    scheduler,
    n_workers=None,
    max_in_flight=None,
    *,
    progress_timeout=PROGRESS_TIMEOUT,
    lost=None,
    label=None,
):
    """Evaluate the samples ``todo`` = [(index, overrides), ...] with ``evaluate(overrides, **kwargs)``
    in this process (``scheduler="serial"``, or ``"threads"``: ``n_workers`` threads, default one
    per core) or on dask (``scheduler``: as :class:`Workers` takes it, or a :class:`Workers`),
    passing each row to ``writer.write`` as it completes and counting it
    on ``bar``. A sample whose evaluation fails is a row with status "failed"; one lost to the
    infrastructure is passed to ``lost(index, cause)`` and no row is written (module docstring).
    The samples' warnings are said here, each prefixed with ``label(index)`` (default
    ``"sample <index>"``), a message several samples give once. ``progress_timeout`` (s): how long
    dask's workers may go without finishing a sample before the loop ends (module docstring;
    default :data:`PROGRESS_TIMEOUT`)."""
    said = set()
    label = label or (lambda i: f"sample {i}")

    def write(row, filters=None):
        _say(row, label, said, filters)
        writer.write(row)

    if _kind(scheduler) == "serial":
        for i, p in todo:
            write(evaluate_sample(evaluate, kwargs, i, p, outputs))
            bar.update(1)
        return
    if _kind(scheduler) == "threads":
        threads = getattr(scheduler, "n_workers", None) or n_workers
        _run_threads(todo, evaluate, kwargs, outputs, write, bar, _cores() if threads is None else threads)
        return
    if isinstance(scheduler, Workers):
        _run_dask(todo, evaluate, kwargs, outputs, write, bar, scheduler.client, max_in_flight, progress_timeout, lost)
        return
    with Workers(scheduler, n_workers) as workers:
        _run_dask(todo, evaluate, kwargs, outputs, write, bar, workers.client, max_in_flight, progress_timeout, lost)


def _cores():
    """The cores this process may run on (its CPU affinity, which a container or ``taskset`` limits;
    else the machine's)."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):  # (not on every platform)
        return os.cpu_count() or 1


def _run_threads(todo, evaluate, kwargs, outputs, write, bar, n_threads):
    """The samples on ``n_threads`` threads of this process (at most that many in flight), each row
    written here, in the calling thread, as it completes. Ctrl-C (or an error that ends the loop)
    cancels the samples not begun and stops those in progress at their run's next chunk of steps
    (:func:`~cablecasing_core.timedomain.engine.stop_runs_on`; an ``evaluate`` that runs no engine
    ends on its own, and the process waits for it before it exits); their rows are dropped. No
    progress timeout: a sample that never ends holds the command (dask's ``progress_timeout`` is for
    lost workers, which a thread cannot be)."""
    n_threads = integer("n_workers", n_threads, 1)
    pending = iter(todo)
    stop = threading.Event()
    pool = concurrent.futures.ThreadPoolExecutor(
        n_threads, "cablecasing-sample", initializer=_sample_thread, initargs=(stop,)
    )
    running = set()

    def submit_next():
        item = next(pending, None)
        if item is not None:
            running.add(pool.submit(evaluate_sample, evaluate, kwargs, item[0], item[1], outputs))

    interrupted = False
    with _warnings_by_thread() as outer:
        try:
            for _ in range(n_threads):
                submit_next()
            while running:
                done, _ = concurrent.futures.wait(running, return_when=concurrent.futures.FIRST_COMPLETED)
                for fut in sorted(done, key=lambda f: f.result()["index"]):
                    running.discard(fut)
                    write(fut.result(), outer)  # (evaluate_sample never raises)
                    bar.update(1)
                    submit_next()
        except KeyboardInterrupt:
            interrupted = True
            raise
        finally:
            # the samples in progress stopped, and waited for here, their warnings still theirs, when the
            # loop ended by an error (a warning the caller's filters make one); not after Ctrl-C
            stop.set()
            pool.shutdown(wait=not interrupted, cancel_futures=True)


def _cause(exc):
    """An infrastructure failure as one line."""
    name = type(exc).__name__
    if name == "KilledWorker":
        return "KilledWorker: the worker running it died (killed, out of memory or crashed)"
    if name in ("CancelledError", "FutureCancelledError"):
        return f"{name}: the task was cancelled (the scheduler was lost or restarted)"
    return f"{name}: {' '.join(str(exc).split())[:200]}"


def _diagnose(client):
    """Why no sample finished: the scheduler does not answer, no worker is left, or the workers stall."""
    pool = concurrent.futures.ThreadPoolExecutor(1)
    try:
        threads = pool.submit(client.nthreads).result(timeout=5.0)
    except Exception:  # (a timeout or a closed connection)
        return f"the dask scheduler does not answer (client {client.status})"
    finally:
        pool.shutdown(wait=False)
    if not threads:
        return "no dask worker is left (all died or were stopped)"
    n = len(threads)
    return f"{n} dask worker{' is' if n == 1 else 's are'} connected but none finished a sample (stalled)"


def _lost_scheduler(exc, n_lost=0):
    lost = f"; the {n_lost} samples in flight are lost (no row)" if n_lost else ""
    return InfrastructureError(
        f"the dask scheduler was lost ({_cause(exc)}){lost}; run the same command again to go on (the finished rows "
        "are kept)"
    )


def _run_dask(todo, evaluate, kwargs, outputs, write, bar, client, max_in_flight, progress_timeout, lost):
    """Submit the samples to dask.distributed and ``write`` each result row as it completes (the errors
    of the client's calls are the infrastructure's; those of ``write`` are not caught)."""
    from distributed import wait

    if not todo:
        return
    timeout = float(progress_timeout)
    lost_here = []
    try:
        nthreads = max(1, sum(client.nthreads().values()))
    except Exception as exc:
        raise _lost_scheduler(exc) from None
    window = max_in_flight or 4 * nthreads
    pending = iter(todo)
    keyed = {}

    def lose_in_flight(cause):
        """Every sample still in flight passed to ``lost`` with ``cause`` (the run stops: no row of
        them); returns how many."""
        n = len(keyed)
        if lost is not None:
            for i in keyed.values():
                lost(i, cause)
        keyed.clear()
        return n

    def scheduler_lost(exc, lost_already=0):
        """The InfrastructureError of a lost scheduler, the samples in flight passed to ``lost`` first
        (``lost_already``: those passed before, counted in the message)."""
        return _lost_scheduler(exc, lost_already + lose_in_flight(f"the dask scheduler was lost ({_cause(exc)})"))

    def submit_next():
        item = next(pending, None)
        if item is not None:
            i, p = item
            try:
                fut = client.submit(evaluate_sample, evaluate, kwargs, i, p, outputs, pure=False)
            except Exception as exc:
                raise scheduler_lost(exc) from None
            keyed[fut] = i

    for _ in range(window):
        submit_next()
    while keyed:
        try:
            done, _ = wait(list(keyed), timeout=timeout, return_when="FIRST_COMPLETED")
        except TimeoutError:
            why = _diagnose(client)
            n = lose_in_flight(f"no sample finished within {timeout:g} s: {why}")
            raise InfrastructureError(
                f"no sample finished within {timeout:g} s: {why}; {n} sample{' was' if n == 1 else 's were'} in flight "
                "or queued on the workers (lost: no row); run the same command again to go on (the finished rows are "
                "kept)"
            ) from None
        except (Exception, asyncio.CancelledError) as exc:  # (FuturesCancelledError: the scheduler is gone)
            raise scheduler_lost(exc) from None
        for fut in done:
            i = keyed.pop(fut)
            try:
                row = fut.result()
            except (Exception, asyncio.CancelledError) as exc:  # (evaluate_sample never raises)
                lost_here.append((i, _cause(exc)))
                if lost is not None:
                    lost(i, _cause(exc))
                if client.status != "running":  # the scheduler is gone: the rest would wait for nothing
                    raise scheduler_lost(exc, lost_already=1) from None
            else:
                write(row)
                bar.update(1)
            fut.release()
            submit_next()
    if lost_here:
        i, cause = lost_here[0]
        raise InfrastructureError(
            f"{len(lost_here)} samples were lost to the infrastructure (sample {i}: {cause}); they have no row and "
            "the same command runs them again"
        )
