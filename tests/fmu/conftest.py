"""The FMU's test driver as a fixture: tests/fmu/fmu_driver.py runs each scenario in a fresh
process (it is a script; the test process only prepares inputs and reads the results); the core's
run of an FMU's input table; the FMU built for a model file with clips; tests/fmu/fmu_probe.py, a
host of FMUs in a process of its own that a test sends requests to (``fmu_probe``)."""

import contextlib
import importlib.util
import json
import os
import select
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def fmu_driver():
    """The module tests/fmu/fmu_driver.py (``run``, ``INPUTS``), loaded from its file."""
    spec = importlib.util.spec_from_file_location("fmu_driver", Path(__file__).with_name("fmu_driver.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="session")
def core_run():
    """``core_run(model, table, h=1e-4, dt=None, contact=None)``: the core's own simulation of an
    FMU's run: Engine.advance per communication step of h (s) with the same input reconstruction
    the FMU uses, ``table`` (n, 3 x channels: u, v, a of ``channels_of(model)`` at t = k h); the
    outputs (n, len(outputs_of(model))) after each step."""
    from cablecasing_core.timedomain.engine import Engine
    from cablecasing_core.timedomain.support_motion import SupportReconstruction

    def run(model, table, h=1e-4, dt=None, contact=None):
        eng = Engine(model, dt=dt, contact=contact, ledger=False)
        n = len(eng.channels)
        rec = SupportReconstruction(n)
        out = np.zeros((len(table), len(eng.output_names)))
        for k, row in enumerate(table):
            motion = rec.motion(eng.time, h, row[:n], row[n : 2 * n], row[2 * n :])
            eng.advance(h, motion)
            rec.accept(motion)
            o = eng.outputs()
            out[k] = [o[name] for name in eng.output_names]
        return out

    return run


@pytest.fixture(scope="session")
def model_fmu(tmp_path_factory, clipped_specimen):
    """(path of the FMU built for examples/clipped_specimen.toml, that file, its Model): built once
    per session with ``build_fmu.py --model FILE --output PATH`` in a fresh process."""
    toml = Path(clipped_specimen.source)
    path = tmp_path_factory.mktemp("model_fmu") / "CableCasing-clipped.fmu"
    subprocess.run(
        [sys.executable, str(ROOT / "build_fmu.py"), "--model", str(toml), "--output", str(path)],
        check=True,
        cwd=ROOT,
        capture_output=True,
    )
    return path, toml, clipped_specimen


@pytest.fixture(scope="session")
def installed_fmu(tmp_path_factory):
    """The path of the FMU built for the built-in installed specimen (``build_fmu.py --model
    installed``): the default FMU's variables, another model."""
    path = tmp_path_factory.mktemp("installed_fmu") / "CableCasing-installed.fmu"
    subprocess.run(
        [sys.executable, str(ROOT / "build_fmu.py"), "--model", "installed", "--output", str(path)],
        check=True,
        cwd=ROOT,
        capture_output=True,
    )
    return path


class ProbeHost:
    """A running tests/fmu/fmu_probe.py (a Python host of FMUs in a process of its own):
    ``call(op, **arguments)`` sends one request and returns its answer (a dict); a host that died
    (the FMU crashed it) or stays silent past ``timeout`` s fails the test with its exit status and
    stderr."""

    def __init__(self, env=None, timeout=120.0, folder=None):
        self.timeout = timeout
        self.err = tempfile.TemporaryFile(mode="w+")
        self.proc = subprocess.Popen(
            [sys.executable, str(Path(__file__).with_name("fmu_probe.py")), *([str(folder)] if folder else [])],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=self.err,
            text=True,
            env=env,
        )

    def _died(self, what):
        self.err.seek(0)
        return f"the FMU's host {what} (exit status {self.proc.poll()}):\n{self.err.read()[-4000:]}"

    def call(self, op, **arguments):
        self.proc.stdin.write(json.dumps({"op": op, **arguments}) + "\n")
        self.proc.stdin.flush()
        ready, _, _ = select.select([self.proc.stdout], [], [], self.timeout)
        if not ready:
            self.proc.kill()
            pytest.fail(self._died(f"did not answer {op} {arguments} within {self.timeout} s"))
        line = self.proc.stdout.readline()
        if not line:
            self.proc.wait(10)
            pytest.fail(self._died(f"died in {op} {arguments}"))
        answer = json.loads(line)
        assert answer.pop("ok"), answer["error"]
        return answer

    def close(self):
        """Ends the host (its stdin closed: it exits; killed past 30 s) and closes every pipe to it, so
        no handle is left for the garbage collector to warn of in a later test."""
        with contextlib.suppress(BrokenPipeError):  # (a host that died: nothing is left to flush)
            self.proc.stdin.close()
        try:
            self.proc.wait(30)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self.proc.stdout.close()
        self.err.close()
        return self.proc.returncode


@pytest.fixture
def fmu_probe(tmp_path):
    """``start(env=None, timeout=120)``: a new :class:`ProbeHost` (its FMUs unpacked under the test's
    ``tmp_path``); the test's hosts are closed after it, each of which must then exit with status 0
    (no crash at the end of the process either)."""
    hosts = []

    def start(env=None, timeout=120.0):
        hosts.append(ProbeHost(env, timeout, folder=tmp_path))
        return hosts[-1]

    yield start
    codes = [h.close() for h in hosts]
    assert codes == [0] * len(codes), codes


@pytest.fixture(scope="session")
def c_hosts():
    """The folder of the C hosts (fmusim, the FMU Compliance Checker; built from their public sources, see
    its README): the environment variable ``CABLECASING_HOSTS``, as ``benchmarks/bench_fmu.py`` reads it,
    else ``../shared/hosts`` beside the repository. A test that runs them is skipped, saying where it
    looked, when that folder has no fmusim."""
    folder = Path(
        os.environ.get("CABLECASING_HOSTS") or Path(__file__).resolve().parents[2].parent / "shared" / "hosts"
    )
    if not (folder / "fmusim").exists():
        pytest.skip(f"the C hosts are not in {folder} (set CABLECASING_HOSTS to their folder)")
    return folder


@pytest.fixture(scope="session")
def plain_env(tmp_path_factory):
    """The plain environment of a host an engineer runs (HOME and PATH=/usr/bin:/bin, no venv, no
    LD_PRELOAD, and the machine's own OpenBLAS settings where it has them), with a HOME of this test
    session's own: the FMU's per-user copies of its code and the kernels' numba cache land there, once
    a session (they went to the real HOME, ~3 MB for each FMU build, kept for 14 days)."""
    env = {"HOME": str(tmp_path_factory.mktemp("plain_home")), "PATH": "/usr/bin:/bin"}
    return env | {k: v for k, v in os.environ.items() if k.startswith("OPENBLAS_")}


@pytest.fixture
def kernels_cache_copy(tmp_path):
    """``copy(leave_out="")``: a NUMBA_CACHE_DIR of the test's own (under ``tmp_path``) holding a copy
    of this user's kernels' cache folder, numba's files only (``*.nbi``, ``*.nbc``; not the temporary
    file of one another process is writing) and without those whose names contain ``leave_out`` if
    given; empty when this user has none yet. Builds that read it see no kernel another process (a
    test worker) compiles meanwhile."""
    import shutil

    from cablecasing_core.timedomain.kernels import kernels_cache_dir

    def copy(leave_out=""):
        root, folder = tmp_path / "numba", kernels_cache_dir()
        root.mkdir(exist_ok=True)
        if folder and os.path.isdir(folder):

            def others(_, names):
                return [n for n in names if not n.endswith((".nbi", ".nbc")) or (leave_out and leave_out in n)]

            shutil.copytree(folder, root / Path(folder).name, ignore=others)
        return root

    return copy


@pytest.fixture(scope="session")
def compiled_c_host():
    """:func:`_compiled_c_host`, for the tests' C hosts (a fixture: test modules do not import conftest)."""
    return _compiled_c_host


def _compiled_c_host(fmu, folder, source, flags=()):
    """A C host of the FMU for the tests that drive its binary by hand: ``source`` (a .c file)
    compiled with the FMI 2.0 headers fmpy ships (``-O1``, ``flags``, linked with -ldl) into
    ``folder``, and the FMU unpacked there. Returns ``(the head of its command line: the executable,
    the binary, the GUID and the resources' URI; the model description)``; skips where there is no C
    compiler or the platform is not Linux (the binary is linux64's)."""
    import shutil

    compiler = shutil.which("cc") or shutil.which("gcc")
    if compiler is None or not sys.platform.startswith("linux"):
        pytest.skip("needs a C compiler on Linux")
    import fmpy
    from fmpy import extract, read_model_description

    exe = Path(folder) / Path(source).stem
    inc = Path(fmpy.__file__).parent / "c-code"
    subprocess.run([compiler, "-O1", *flags, f"-I{inc}", "-o", str(exe), str(source), "-ldl"], check=True)
    unzip = Path(extract(str(fmu), unzipdir=Path(folder) / "unzip"))
    md = read_model_description(str(fmu))
    head = [str(exe), str(unzip / "binaries" / "linux64" / "CableCasing.so"), md.guid, (unzip / "resources").as_uri()]
    return head, md
