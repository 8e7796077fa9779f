"""The FMU in a plain C host of our own (tests/fmu/plain_c_host.c: no Python of its own, HOME and PATH
only) for what only such a host shows (review AR): SIGINT stays the host's, the timing report leaves
a clock's rounding steps out, a reload names the interpreter it finds, a host without a logger is
not written to when logging is off; and, through fmpy in fresh processes, FMU states freed with their
instance, a Ctrl-C during the first import that the next instantiation recovers from, an exception
without a message named by its type. Also the per-user copy of the FMU's code repaired when damaged."""

import importlib.util
import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow  # every test starts processes that load the FMU

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def host(fmu, tmp_path_factory, plain_env, compiled_c_host):
    """``run(mode, *args)``: plain_c_host.c, compiled, on the FMU unpacked, in the plain environment;
    the CompletedProcess."""
    source = Path(__file__).with_name("plain_c_host.c")
    head, _ = compiled_c_host(fmu, tmp_path_factory.mktemp("plain_c_host"), source, ["-lpthread"])

    def run(*args):
        return subprocess.run(head + list(args), capture_output=True, text=True, env=plain_env, timeout=600)

    return run


def test_ctrl_c_stops_a_c_host_that_leaves_sigint_at_its_default(host):
    """A host with SIGINT at SIG_DFL (fmusim, most C simulators): the FMU's start leaves it there
    (CPython's signal module installed its handler at its first import, and numba imports it), and a
    SIGINT 0.3 s into a doStep of 1 s (~2 s of work) kills the process, as it does with a C FMU: the
    doStep does not return (it returned fmi2Error 'internal error in doStep: ' and the host went on).
    The host says when the step starts and when it returns: the signal came during the step."""
    proc = host("signal", "default")
    assert "sigint before default after default" in proc.stdout, proc.stdout + proc.stderr
    assert proc.returncode == -signal.SIGINT, (proc.returncode, proc.stdout[-2000:], proc.stderr[-2000:])
    assert "step starts" in proc.stdout and "doStep returned" not in proc.stdout, proc.stdout


def test_python_code_that_saves_and_restores_sigint_leaves_a_c_hosts_default(host):
    """Python code run in the interpreter the FMU started (a model's plug-in, a later dependency) that
    does what Python code does with SIGINT, old = signal.signal(SIGINT, h) ... signal.signal(SIGINT,
    old), and asyncio.run: SIGINT stays at the host's SIG_DFL, and Python's record says SIG_DFL. The
    default was put back behind Python's back, so Python still recorded its own handler and both
    installed it again (Ctrl-C no longer stopped the host)."""
    proc = host("python")
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    assert "python: getsignal <Handlers.SIG_DFL: 0>" in proc.stdout, proc.stdout + proc.stderr
    assert "python: rc 0 sigint default" in proc.stdout, proc.stdout + proc.stderr


def test_a_c_hosts_own_sigint_handler_is_kept_and_called(host):
    """A host that handles SIGINT itself keeps its handler, which is called, and the step is taken."""
    proc = host("signal", "handler")
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    assert "sigint before host after host" in proc.stdout and "doStep 0 handler 2" in proc.stdout, proc.stdout


def test_the_timing_report_counts_steps_taken_not_a_clocks_rounding(host):
    """Three steps of 1e-4 s and two of 1e-12 s (<= 1e-6 solver.dt: fmi2OK, the clock moves, no step):
    the report counts three calls (it counted five, and every rounding step as a missed deadline)."""
    proc = host("steps")
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    assert proc.stdout.count("-> 0") == 5, proc.stdout
    assert "3 doStep calls took" in proc.stdout and " of 3 calls took longer" in proc.stdout, proc.stdout


def test_a_reloaded_binary_names_the_python_it_started_before(host):
    """After dlclose and dlopen the interpreter the FMU started is still running: the first line says
    so, not that a Python host's interpreter was found."""
    proc = host("reload")
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    first = [line for line in proc.stdout.splitlines() if "(FMI 2.0)" in line]
    assert len(first) == 2 and "started Python" in first[0], first
    assert "that CableCasing.fmu started earlier in this process" in first[1] and "attached" not in first[1], first


def test_a_host_without_a_logger_is_not_written_to_when_logging_is_off(host):
    """No logger (FMI 2.0 does not allow it): with logging off nothing reaches stderr; with logging on
    the informational lines do (so the first check can fail)."""
    off, on = host("nulllogger", "off"), host("nulllogger", "on")
    assert off.returncode == 0 and on.returncode == 0, off.stdout + off.stderr + on.stdout + on.stderr
    assert "step -> 0" in off.stdout and off.stderr == "", off.stderr
    assert "[CableCasing OK] CableCasing.fmu" in on.stderr, on.stderr


FMPY_SCRIPT = """
import gc, sys
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
fmu, mode, at = sys.argv[1], sys.argv[2], sys.argv[3:4]
md = read_model_description(fmu)
unzip = extract(fmu)
from ctypes import byref
from fmpy import calloc, free
from fmpy.fmi2 import (fmi2CallbackFunctions, fmi2CallbackLoggerTYPE, fmi2CallbackAllocateMemoryTYPE,
                       fmi2CallbackFreeMemoryTYPE)
from fmpy.logging import addLoggerProxy
log = []
def logger(env, name, status, category, message):
    log.append(message.decode())
cb = fmi2CallbackFunctions()
cb.logger = fmi2CallbackLoggerTYPE(logger)
cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
addLoggerProxy(byref(cb))
def make(name):
    s = FMU2Slave(guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier,
                  instanceName=name)
    s.instantiate(callbacks=cb, loggingOn=True)
    return s
def bridge():
    return next(m for k, m in sys.modules.items() if k.startswith("_cablecasing_fmi2_bridge_"))
if mode == "states":
    counts = []
    for i in range(20):
        s = make(f"i{i}")
        s.setupExperiment(startTime=0.0); s.enterInitializationMode(); s.exitInitializationMode()
        s.doStep(0.0, 1e-4)
        for _ in range(10):
            s.getFMUstate()
        counts.append(bridge().LiveState.live)
        s.terminate(); s.freeInstance()
    gc.collect()
    print("live", counts[0], counts[-1], bridge().LiveState.live)
elif mode == "interrupt":
    class Interrupt:  # (at the first look-up of that module: Ctrl-C once)
        def find_spec(self, name, path=None, target=None):
            if [name] == at:
                sys.meta_path.remove(self)
                raise KeyboardInterrupt
    sys.meta_path.insert(0, Interrupt())
    try:
        make("first")
        print("first instantiated")
    except Exception:
        print("first failed")
    s = make("second")
    s.setupExperiment(startTime=0.0); s.enterInitializationMode(); s.exitInitializationMode()
    s.doStep(0.0, 1e-4)
    print("second step ok")
    s.terminate(); s.freeInstance()
elif mode == "error":
    class Broken:  # (at every look-up of that module: a module of the copy that does not compile)
        def find_spec(self, name, path=None, target=None):
            if [name] == at:
                raise SyntaxError("invalid syntax planted by the test")
    sys.meta_path.insert(0, Broken())
    for name in ("first", "second"):
        try:
            make(name)
            print(name, "instantiated")
        except Exception:
            print(name, "failed")
elif mode == "empty":
    s = make("e")
    s.setupExperiment(startTime=0.0); s.enterInitializationMode(); s.exitInitializationMode()
    inst = next(o for o in gc.get_objects() if type(o).__name__ == "Instance" and hasattr(o, "_slave"))
    def boom():
        raise KeyboardInterrupt
    inst._slave.fmi2_get_state = boom
    try:
        s.getFMUstate()
    except Exception:
        print("get state failed")
for line in log:
    print("LOG", line)
"""


def _fmpy(fmu, mode, tmp_path, *args):
    script = tmp_path / "script.py"
    script.write_text(textwrap.dedent(FMPY_SCRIPT))
    env = dict(os.environ, HOME=str(tmp_path / "home"))
    env.pop("NUMBA_CACHE_DIR", None)
    proc = subprocess.run(
        [sys.executable, str(script), str(fmu), mode, *args], capture_output=True, text=True, env=env, timeout=600
    )
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return proc.stdout


def test_fmu_states_are_freed_with_their_instance(fmu, tmp_path):
    """FMI 2.0, fmi2FreeInstance frees all memory the FMU's functions allocated: 20 instances that each
    take 10 states (~30 kB each) and are freed without freeing them leave none (they were all kept:
    RSS grew ~30 MB per 100 instances of 10). While an instance lives its 10 states are counted."""
    out = _fmpy(fmu, "states", tmp_path)
    assert "live 10 10 0" in out, out


# (in numba's own import; in scipy's, after numpy's new modules (numpy.random, ...) and numba; in the
# model's package, after all of them)
@pytest.mark.parametrize("at", ["numba.core.caching", "scipy.sparse", "cablecasing_core.timedomain.scenario"])
def test_an_interrupted_first_import_is_undone_and_the_next_instantiation_works(fmu, tmp_path, at):
    """A KeyboardInterrupt (Ctrl-C in a Python host's main thread) in the middle of the first
    fmi2Instantiate's import of the model's code: that one fails, saying so by name, and the next
    imports afresh and steps. Every later one failed: 'partially initialized module' when nothing was
    undone, and 'cannot load module more than once per process' when numpy's new modules were unloaded
    with the rest (an interruption after them: scipy.sparse, the model's package)."""
    out = _fmpy(fmu, "interrupt", tmp_path, at)
    assert "first failed" in out and "second step ok" in out, out
    assert "was interrupted (KeyboardInterrupt)" in out, out


def test_an_import_error_is_reported_as_itself_at_each_instantiation(fmu, tmp_path):
    """A module of the model's code that raises an ordinary exception (a SyntaxError: a same-size edit
    of the per-user copy, which its size check cannot see) fails each fmi2Instantiate with that
    exception. The second said 'ImportError: cannot load module more than once per process' (the first
    had unloaded numpy's new modules), and the hints did not fit it."""
    out = _fmpy(fmu, "error", tmp_path, "cablecasing_core.timedomain.scenario")
    assert "first failed" in out and "second failed" in out, out
    said = [line for line in out.splitlines() if "cannot be instantiated" in line]
    assert len(said) == 2 and all("SyntaxError: invalid syntax planted by the test" in line for line in said), said
    assert said[0] == said[1] and "if that folder was damaged, delete it" in said[0], said
    assert "interrupted" not in out and "more than once" not in out, out


def test_an_exception_without_a_message_is_logged_by_its_type(fmu, tmp_path):
    """An exception whose text is empty (KeyboardInterrupt()) is logged by its type name (the log said
    'internal error in doStep: ' and nothing after)."""
    out = _fmpy(fmu, "empty", tmp_path)
    assert "get state failed" in out and "internal error in get_state: KeyboardInterrupt" in out, out


# ------------------------------------------------------------------ the per-user copy of the code


@pytest.fixture
def bridge():
    spec = importlib.util.spec_from_file_location("bridge", ROOT / "fmu_src" / "cablecasing_fmi2_bridge.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    yield module
    for fd in module._HELD:
        os.close(fd)


@pytest.mark.parametrize("damage", ["a file missing", "a file cut short", "no .complete"])
def test_a_damaged_copy_of_the_code_is_copied_again_and_said(bridge, tmp_path, damage):
    """A copy in the per-user cache with a file missing or shorter (a cleaner of old files, a hand) was
    trusted for ever (every instantiation failed: 'No module named ...'); one without .complete was
    passed over at each start for the temporary folder, silently. Now it is copied again where it
    was, with one warning naming what was wrong."""
    resources = tmp_path / "resources"
    (resources / "pkg" / "sub").mkdir(parents=True)
    (resources / "pkg" / "sub" / "engine.py").write_text("x = 1\n" * 10)
    (resources / "top.py").write_text("y = 2\n")
    base = [(str(tmp_path / "base"), None), (str(tmp_path / "fallback"), None)]
    dest, _ = bridge._stable_copy(str(resources), "guid", ["pkg", "top.py"], iter(base))
    copy = Path(dest)
    assert copy == tmp_path / "base" / "fmu" / "guid"
    said = []
    assert bridge._stable_copy(str(resources), "guid", ["pkg", "top.py"], iter(base), said.append)[0] == dest
    assert said == []  # (a whole copy is used as it is)
    if damage == "a file missing":
        (copy / "pkg" / "sub" / "engine.py").unlink()
    elif damage == "a file cut short":
        (copy / "pkg" / "sub" / "engine.py").write_text("x = 1\n")
    else:
        (copy / ".complete").unlink()
    again, tried = bridge._stable_copy(str(resources), "guid", ["pkg", "top.py"], iter(base), said.append)
    assert again == dest and tried == []
    assert (copy / "pkg" / "sub" / "engine.py").read_text() == "x = 1\n" * 10
    assert (copy / ".complete").read_bytes() == bridge.LOCKED_MARK
    assert len(said) == 1 and f"in {dest} was damaged" in said[0], said
    words = {"a file missing": "engine.py is missing", "a file cut short": "has 6 bytes, not 60"}
    assert words.get(damage, "no .complete marker") in said[0], said
    assert sorted(p.name for p in (tmp_path / "base" / "fmu").iterdir()) == ["guid"]  # (nothing left aside)
