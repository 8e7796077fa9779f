"""dist/CableCasing.fmu in the hosts users have: third-party C hosts (fmusim, the FMU Compliance
Checker) in the plain environment an engineer has (HOME and PATH=/usr/bin:/bin, no venv, no
LD_PRELOAD), plain fmpy scripts and the fmpy command line, each in fresh processes; every run must
exit with status 0. Also what a careless master does, and a host without the Python packages.

The C hosts are the ones in $CABLECASING_HOSTS, else ../shared/hosts (see its README), built from their public sources.
"""

import os
import re
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.model.schema import CHANNELS, OUTPUTS, inputs_of, outputs_of
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion
from cablecasing_core.timedomain.support_motion import SupportReconstruction

pytestmark = pytest.mark.slow  # every test starts processes that load the FMU

ROOT = Path(__file__).resolve().parents[2]
H = 1e-4
NCH = len(CHANNELS)
# The plain environment: HOME and PATH, and the machine's own OpenBLAS settings where it has them
# (OPENBLAS_CORETYPE, OPENBLAS_L2_SIZE: set machine-wide on some processors, so an engineer's shell
# has them too). They choose OpenBLAS's kernels, which round LAPACK's small factors differently, and
# the contact response is chaotic: a host without them computes another, equally valid, record.


def fmusim_inputs(path, model, n):
    """The model's scenario's support motion at t = k h (k = 0..n) as fmusim's input CSV: one column
    per input that moves (of ``inputs_of(model)``), values written with repr (exact doubles);
    returns the (n + 1, 3 x channels) table (36 columns for the built-in specimen)."""
    t = np.array([k * H for k in range(n + 1)])
    table = np.hstack(scenario_motion(model)(t))
    names = inputs_of(model)
    cols = [j for j in range(len(names)) if np.any(table[:, j] != 0)]
    with open(path, "w") as f:
        f.write(",".join(['"time"'] + [f'"{names[j]}"' for j in cols]) + "\n")
        for k in range(n + 1):
            f.write(",".join([repr(float(t[k]))] + [repr(float(table[k, j])) for j in cols]) + "\n")
    return table


def read_csv(path):
    with open(path) as f:
        names = [c.strip('"') for c in f.readline().strip().split(",")]
    return names, np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


@pytest.fixture(scope="module")
def scenario_csv(tmp_path_factory):
    folder = tmp_path_factory.mktemp("hosts")
    table = fmusim_inputs(folder / "inputs.csv", cc.load_model(), 400)
    return folder, table


def test_fmusim_plain_environment_equals_fmpy(c_hosts, fmu, scenario_csv, fmu_driver, plain_env):
    """Five fresh fmusim processes in the plain environment: exit 0 each, and casing.B.Fz equal to
    fmpy's given the same calls: the same inputs and fmusim's steps, doStep(t_k, t_(k+1) - t_k) with
    t_k = k h in double (which differ from h in the last bits, and the contact response is chaotic,
    so other steps would not do). fmusim writes 16 significant digits, so 1e-12 relative leaves
    room only for a different computation."""
    folder, table = scenario_csv
    outs = []
    for k in range(5):
        out, log = folder / f"fmusim{k}.csv", folder / f"fmusim{k}.log"
        proc = subprocess.run(
            [
                str(c_hosts / "fmusim"),
                "--interface-type",
                "cs",
                "--stop-time",
                repr(400 * H),
                "--output-interval",
                repr(H),
                "--input-file",
                str(folder / "inputs.csv"),
                "--output-file",
                str(out),
                "--log-file",
                str(log),
                "--logging-on",
                str(fmu),
            ],
            env=plain_env,
            capture_output=True,
            text=True,
            timeout=300,
        )
        assert proc.returncode == 0, f"run {k}: exit {proc.returncode}\n{proc.stderr}\n{log.read_text()}"
        names, data = read_csv(out)
        outs.append(data[:, names.index("casing.B.Fz")])
        # the FMU says which interpreter it uses, its version whole (it was once cut inside "[GCC …]")
        assert re.search(rf"started Python {sys.version.split()[0]} from ", log.read_text()), log.read_text()[:500]
    assert all(np.array_equal(o, outs[0]) for o in outs)
    steps = np.diff(np.arange(401) * H)
    res = fmu_driver.run(folder, "steps", fmu, inputs=table[:400], h=H, steps=steps.tolist(), outputs=["casing.B.Fz"])
    ref = res["out"][:, 0]  # after step k: at t_(k+1)
    fz = outs[0][1:401]
    assert np.max(np.abs(ref)) > 0.01
    assert np.max(np.abs(fz - ref)) <= 1e-12 * np.max(np.abs(ref))


def test_fmusim_runs_the_real_time_setting_as_the_core(c_hosts, fmu, tmp_path, plain_env):
    """The real-time setting of docs/fmu.md in fmusim, plain environment, no input file: the FMU
    drives its supports with the default scenario (scenario.drive) at solver.dt = 2e-5 s, five
    Newmark steps per 1e-4 s call. Exit 0, and casing.B.Fz after each call equals the core's run of
    the same scenario at dt = 2e-5 (cc.simulate) at the same times to 1e-12 relative (fmusim writes
    16 digits; fmusim's steps t_(k+1) - t_k differ from 1e-4 in the last bits, and the engine still
    takes exactly five steps of 2e-5 per call, on the grid the core evaluates the scenario on).
    fmusim gives no stop time, so the FMU computes the random record over the scenario's duration
    (1 s: one block of 65,536 samples at 2e-5 s) ahead in initialisation (GridMotion.prepare) and
    says so; at fmi2Terminate it reports its longest call and the calls that took longer than their
    step, no more than it made."""
    n = 400
    out, log = tmp_path / "rt.csv", tmp_path / "rt.log"
    proc = subprocess.run(
        [str(c_hosts / "fmusim"), "--interface-type", "cs", "--stop-time", repr(n * H), "--output-interval", repr(H),
         "--start-value", "scenario.drive", "true", "--start-value", "solver.dt", "2e-5",
         "--output-file", str(out), "--log-file", str(log), "--logging-on", str(fmu)],
        env=plain_env, capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert proc.returncode == 0, f"exit {proc.returncode}\n{proc.stderr}\n{log.read_text()[-3000:]}"
    names, data = read_csv(out)
    j = OUTPUTS.index("casing.B.Fz")
    ref = cc.simulate(cc.load_model(), duration=n * H, dt=2e-5).support_forces[4::5, j]
    got = data[1 : n + 1, names.index("casing.B.Fz")]  # (row k + 1: after step k)
    assert len(ref) == n and np.max(np.abs(ref)) > 0.1
    assert np.max(np.abs(got - ref)) <= 1e-12 * np.max(np.abs(ref))
    text = log.read_text()
    assert "computed ahead up to t = 1.31072 s (no stopTime: scenario.duration = 1 s)" in text, text[-3000:]
    longest, late, calls = real_time_line(text)
    assert 0 < longest and 0 <= late <= calls == n


def test_fmusim_saves_and_restores_a_state_file(c_hosts, fmu, tmp_path, plain_env):
    """fmusim's --final-fmu-state-file and --initial-fmu-state-file, plain environment: fmusim 0.0.39
    passes the state itself to fmi2FreeFMUstate, which takes its address; the FMU tells the two apart
    (it crashed fmusim with SIGSEGV). A run to 1 ms saved and continued to 2 ms from the file gives
    the outputs of one run to 2 ms, to the bit (fmusim writes 16 digits of the same doubles)."""
    fmusim = [str(c_hosts / "fmusim"), "--interface-type", "cs", "--output-interval", repr(H)]
    drive = ["--start-value", "scenario.drive", "true"]
    state = tmp_path / "state.bin"
    runs = {
        "first": ["--stop-time", "0.001", "--final-fmu-state-file", str(state)],
        "rest": ["--start-time", "0.001", "--stop-time", "0.002", "--initial-fmu-state-file", str(state)],
        "whole": ["--stop-time", "0.002"],
    }
    for name, args in runs.items():
        log = tmp_path / f"{name}.log"
        proc = subprocess.run(
            fmusim + drive + args + ["--output-file", str(tmp_path / f"{name}.csv"), "--log-file", str(log), str(fmu)],
            env=plain_env, capture_output=True, text=True, timeout=300,
        )  # fmt: skip
        assert proc.returncode == 0, f"{name}: exit {proc.returncode}\n{proc.stderr}\n{log.read_text()[-3000:]}"
        assert state.stat().st_size > 1000
    names, whole = read_csv(tmp_path / "whole.csv")
    _, rest = read_csv(tmp_path / "rest.csv")
    j = names.index("casing.B.Fz")
    assert rest[0, 0] == 0.001 and len(rest) == 11 and np.max(np.abs(whole[-11:, j])) > 0
    np.testing.assert_array_equal(rest[:, j], whole[-11:, j])


def test_fmusim_ends_at_an_input_it_cannot_take_instead_of_retrying_it_for_ever(c_hosts, fmu, tmp_path, plain_env):
    """A NaN in fmusim's input file: the step is discarded, fmusim repeats it from
    fmi2LastSuccessfulTime with the same input, and the FMU, asked for the same step again, asks to
    end the simulation (fmi2Terminated); fmusim stops there, exit 0, with the reasons in its log. (It
    repeated the step for ever, 38 million log lines in 5 minutes.)"""
    inp, out, log = tmp_path / "nan.csv", tmp_path / "out.csv", tmp_path / "nan.log"
    rows = [f"{k * H!r},{'nan' if 48 <= k <= 50 else repr(1e-6 * k)}" for k in range(101)]
    inp.write_text('"time","casing.A.z"\n' + "\n".join(rows) + "\n")
    proc = subprocess.run(
        [str(c_hosts / "fmusim"), "--interface-type", "cs", "--stop-time", "0.01", "--output-interval", repr(H),
         "--input-file", str(inp), "--output-file", str(out), "--log-file", str(log), str(fmu)],
        env=plain_env, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    text = log.read_text()
    assert proc.returncode == 0, f"exit {proc.returncode}\n{proc.stderr}\n{text[-3000:]}"
    assert "input casing.A.z = nan" in text and "asked for again with the same inputs" in text, text[-3000:]
    assert len(text.splitlines()) < 20
    _, data = read_csv(out)
    assert 0.0045 < data[-1, 0] < 0.0051  # where the input turned NaN


def real_time_line(log):
    """(the longest doStep call in s, the calls longer than their step, the calls) from the FMU's
    log line at fmi2Terminate."""
    m = re.search(r"the longest doStep call took ([0-9.]+) ms .*?; (\d+) of (\d+) calls took longer", log)
    assert m, log[-3000:]
    return 1e-3 * float(m.group(1)), int(m.group(2)), int(m.group(3))


def test_fmusim_hears_of_every_call_that_took_longer_than_its_step(c_hosts, fmu, tmp_path, plain_env):
    """A master that asks for communication steps of 1e-6 s (solver.dt 1e-6 s: one Newmark step per
    call) cannot be served in real time: no call into Python and a Newmark step with contact take
    less than 1 us, so every call of the run (fmusim makes ~90 over its 1e-4 s) is reported as late,
    and the longest took at least 1 us."""
    log = tmp_path / "late.log"
    proc = subprocess.run(
        [str(c_hosts / "fmusim"), "--interface-type", "cs", "--stop-time", "1e-4", "--output-interval", "1e-6",
         "--start-value", "solver.dt", "1e-6", "--output-file", str(tmp_path / "late.csv"),
         "--log-file", str(log), "--logging-on", str(fmu)],
        env=plain_env, capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert proc.returncode == 0, f"exit {proc.returncode}\n{proc.stderr}\n{log.read_text()[-3000:]}"
    longest, late, calls = real_time_line(log.read_text())
    assert calls >= 90 and late == calls and longest >= 1e-6


def test_compliance_checker_plain_environment(c_hosts, fmu, scenario_csv, plain_env):
    """The FMU Compliance Checker (FMI Library) imports, validates and simulates the FMU: exit 0 in
    five fresh processes, no error in its report, and outputs with contact."""
    folder, _ = scenario_csv
    for k in range(5):
        out, log = folder / f"check{k}.csv", folder / f"check{k}.log"
        proc = subprocess.run(
            [
                str(c_hosts / "fmuCheck.linux64"),
                "-h",
                repr(H),
                "-s",
                "0.04",
                "-i",
                str(folder / "inputs.csv"),
                "-o",
                str(out),
                "-l",
                "4",
                "-e",
                str(log),
                str(fmu),
            ],
            env=plain_env,
            capture_output=True,
            text=True,
            timeout=300,
        )
        assert proc.returncode == 0, (
            f"run {k}: exit {proc.returncode}\n{proc.stdout[-2000:]}\n{log.read_text()[-3000:]}"
        )
        assert "0 Error(s)" in log.read_text()
    names, data = read_csv(out)
    assert data[:, names.index("contact.active")].max() >= 1


def test_the_fmu_for_a_model_file_runs_in_fmusim_and_the_checker(c_hosts, model_fmu, tmp_path, fmu_driver, plain_env):
    """The FMU built for the clipped specimen's model file in both C hosts, plain environment: its
    scenario (random casing A z, the cable's axial drive, dash.y on the excited clip) as fmusim's
    input file, which names dash.y, dash.vy, dash.ay among its columns; both exit with 0, the
    checker reports no error, and fmusim's forces through the excited clip and at casing B equal
    fmpy's given the same calls (its steps t_(k+1) - t_k) to 1e-12 relative (16 digits written)."""
    path, _, model = model_fmu
    table = fmusim_inputs(tmp_path / "inputs.csv", model, 200)
    assert '"dash.ay"' in (tmp_path / "inputs.csv").read_text().splitlines()[0]
    out, log = tmp_path / "fmusim.csv", tmp_path / "fmusim.log"
    proc = subprocess.run(
        [str(c_hosts / "fmusim"), "--interface-type", "cs", "--stop-time", repr(200 * H), "--output-interval", repr(H),
         "--input-file", str(tmp_path / "inputs.csv"), "--output-file", str(out), "--log-file", str(log),
         "--logging-on", str(path)],
        env=plain_env, capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert proc.returncode == 0, f"exit {proc.returncode}\n{proc.stderr}\n{log.read_text()[-3000:]}"
    names, data = read_csv(out)
    watch = ["casing.clip1.Fy", "casing.B.Fz"]
    steps = np.diff(np.arange(201) * H)
    res = fmu_driver.run(
        tmp_path, "steps", path, inputs=table[:200], h=H, steps=steps.tolist(), outputs=watch,
        input_names=list(inputs_of(model)),
    )  # fmt: skip
    assert np.all(res["status"] == 0)
    for k, name in enumerate(watch):
        ref, got = res["out"][:, k], data[1:201, names.index(name)]  # (fmusim's row k + 1: after step k)
        assert np.max(np.abs(ref)) > 1e-3, name
        assert np.max(np.abs(got - ref)) <= 1e-12 * np.max(np.abs(ref)), name
    assert set(outputs_of(model)) <= set(names)  # fmusim writes every output, the clips' forces too
    check, clog = tmp_path / "check.csv", tmp_path / "check.log"
    proc = subprocess.run(
        [str(c_hosts / "fmuCheck.linux64"), "-h", repr(H), "-s", "0.02", "-i", str(tmp_path / "inputs.csv"),
         "-o", str(check), "-l", "4", "-e", str(clog), str(path)],
        env=plain_env, capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert proc.returncode == 0, f"exit {proc.returncode}\n{proc.stdout[-2000:]}\n{clog.read_text()[-3000:]}"
    assert "0 Error(s)" in clog.read_text()
    names, data = read_csv(check)
    assert np.max(np.abs(data[:, names.index("casing.clip1.Fy")])) > 1e-3


PLAIN_SCRIPT = """
import sys
import fmpy
import numpy as np
fmu = sys.argv[1]
t = np.arange(0, 0.03, 1e-4)
w = 2 * np.pi * 60
sig = np.array(list(zip(t, 4e-4 * np.sin(w * t), 4e-4 * w * np.cos(w * t), -4e-4 * w * w * np.sin(w * t))),
               dtype=[("time", float), ("cable.A.x", float), ("cable.A.vx", float), ("cable.A.ax", float)])
for mu in (0.05, 0.15, 0.3):
    r = fmpy.simulate_fmu(fmu, stop_time=0.03, step_size=1e-4, input=sig, start_values={"contact.friction": mu},
                          output=["casing.B.Fx", "contact.dissipated_energy"])
    print("sweep", mu, repr(float(r["casing.B.Fx"][-1])), repr(float(r["contact.dissipated_energy"][-1])))
try:
    fmpy.simulate_fmu(fmu, stop_time=0.01, step_size=1e-4, start_values={"casing.E": -1.0})
except Exception as exc:
    print("raised", type(exc).__name__, exc)
else:
    print("bad parameter accepted")
"""


def test_plain_fmpy_script_sweep_in_fresh_processes(fmu, tmp_path):
    """A user's script as users write it (no os._exit): three simulate_fmu calls on the .fmu path
    in one process (a friction sweep), then a bad parameter, which must raise; in five fresh
    processes, each must exit with 0, and each sweep point must equal a fresh process's run."""
    script = tmp_path / "sweep.py"
    script.write_text(PLAIN_SCRIPT)
    results = []
    for k in range(5):
        proc = subprocess.run(
            [sys.executable, str(script), str(fmu)], capture_output=True, text=True, timeout=600, cwd=tmp_path
        )
        assert proc.returncode == 0, f"run {k}: exit {proc.returncode}\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}"
        lines = proc.stdout.splitlines()
        sweep = [line.split()[1:] for line in lines if line.startswith("sweep ")]
        assert len(sweep) == 3
        assert any(line.startswith("raised FMICallException") for line in lines), proc.stdout[-2000:]
        # the reason reaches the user through the FMU's log (fmpy prints it before raising)
        assert "invalid parameter casing.E = -1.0: must be a number in (0, 1e+16] in Pa" in proc.stdout  # (issue 26)
        results.append(sweep)
    assert all(r == results[0] for r in results)
    energy = [float(p[2]) for p in results[0]]
    assert energy[0] != energy[1] != energy[2]  # the friction really changed each run
    # each point of the sweep equals a process that ran only that point
    one = tmp_path / "one.py"
    one.write_text(PLAIN_SCRIPT.replace("(0.05, 0.15, 0.3)", "(0.3,)"))
    proc = subprocess.run([sys.executable, str(one), str(fmu)], capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    alone = [line.split()[1:] for line in proc.stdout.splitlines() if line.startswith("sweep ")]
    assert alone == [results[0][2]]


def test_fmpy_command_line_exits_cleanly(fmu, tmp_path):
    fmpy_cli = Path(sys.executable).parent / "fmpy"
    for k in range(3):
        proc = subprocess.run(
            [
                str(fmpy_cli),
                "simulate",
                str(fmu),
                "--stop-time",
                "0.01",
                "--output-file",
                str(tmp_path / f"out{k}.csv"),
            ],
            capture_output=True,
            text=True,
            timeout=300,
        )
        assert proc.returncode == 0, f"run {k}: exit {proc.returncode}\n{proc.stdout[-2000:]}\n{proc.stderr[-2000:]}"
        assert (tmp_path / f"out{k}.csv").stat().st_size > 0


@pytest.mark.parametrize("case", ["empty_venv", "missing", "other_version"])
def test_a_host_without_the_packages_gets_one_message(c_hosts, fmu, tmp_path, case, plain_env):
    """fmusim with logging off and a Python that cannot run the model: one message on stderr that
    names what is missing and how to fix it, and fmusim ends normally (an error status, no signal)."""
    env = dict(plain_env)
    if case == "empty_venv":
        subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(tmp_path / "venv")], check=True)
        env["CABLECASING_PYTHON"] = str(tmp_path / "venv" / "bin" / "python")
        expected = ["numpy is not installed", "numba is not installed", "pip install", "CABLECASING_PYTHON"]
    elif case == "missing":
        env["CABLECASING_PYTHON"] = str(tmp_path / "no" / "python3.11")
        expected = ["CABLECASING_PYTHON", "does not run as a Python interpreter"]
    else:
        mine = f"python{sys.version_info.major}.{sys.version_info.minor}"
        # (pyenv's shims need pyenv, so look for the real executables beside this Python's prefix)
        found = sorted(Path(sys.base_prefix).parent.glob("3.*/bin/python3.*")) + sorted(
            Path("/usr/bin").glob("python3.*")
        )
        other = next((str(p) for p in found if p.name != mine and p.name[-1].isdigit() and os.access(p, os.X_OK)), None)
        if other is None:
            pytest.skip("no Python of another minor version here")
        env["CABLECASING_PYTHON"] = other
        expected = ["but this FMU was built for CPython"]
    proc = subprocess.run(
        [str(c_hosts / "fmusim"), "--interface-type", "cs", "--stop-time", "0.001", str(fmu)],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode > 0, (proc.returncode, proc.stderr)  # failed, but not killed by a signal
    for words in expected:
        assert words in proc.stderr, proc.stderr
    # said once (review W W4: the bridge logged it, and fmi2Instantiate again)
    assert proc.stderr.count(expected[0]) == 1, proc.stderr


def test_the_hosts_python_variables_do_not_disturb_it(c_hosts, fmu, tmp_path, plain_env):
    """PYTHONHOME at a virtual environment (which kills an embedded CPython in init_fs_encoding)
    and a PYTHONPATH full of nothing: the FMU starts its interpreter isolated from them, so fmusim
    runs and exits with 0."""
    env = dict(plain_env, PYTHONHOME=str(Path(sys.executable).parent.parent), PYTHONPATH="/nonexistent:/tmp")
    proc = subprocess.run(
        [str(c_hosts / "fmusim"), "--interface-type", "cs", "--stop-time", "0.002", "--output-file",
         str(tmp_path / "out.csv"), str(fmu)],
        env=env, capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert len((tmp_path / "out.csv").read_text().splitlines()) == 22  # header, t = 0 and 20 steps


def test_fmusim_with_a_read_only_home_runs_on_the_kernels_the_fmu_ships(
    c_hosts, fmu, tmp_path, unprivileged, read_only, plain_env
):
    """fmusim in the plain environment of a user whose HOME cannot be written (review AL, M1/M2: it
    compiled every kernel, 170 s, and blamed the CPU): the FMU takes a folder of the user's own in
    the temporary folder, seeds it with the machine code it ships (nothing is compiled), says why
    in the log, and exits 0 with every step."""
    home, tmp = tmp_path / "home", tmp_path / "tmp"
    home.mkdir()
    tmp.mkdir()
    read_only(home)
    out, log = tmp_path / "out.csv", tmp_path / "log.txt"
    proc = subprocess.run(
        [*unprivileged, str(c_hosts / "fmusim"), "--interface-type", "cs", "--stop-time", "0.002", "--output-interval",
         repr(H), "--output-file", str(out), "--log-file", str(log), "--logging-on", str(fmu)],
        env=dict(plain_env, HOME=str(home), TMPDIR=str(tmp)), capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    text = log.read_text()
    assert proc.returncode == 0, f"exit {proc.returncode}\n{proc.stderr}\n{text[-3000:]}"
    assert len(out.read_text().splitlines()) == 22  # header, t = 0 and 20 steps
    base = tmp / f"cablecasing-{os.getuid()}"
    assert f"cached in {base}/numba/kernels-" in text and f"{home}/.cache/cablecasing/numba (Permission denied)" in text
    assert "files copied from the FMU" in text and "(0 files copied" not in text
    assert "compiling the model's numba kernels" not in text, text[-3000:]


def test_the_advice_for_a_missing_package_fits_an_externally_managed_python(monkeypatch):
    """A Python whose packages the system manages (PEP 668: Debian's /usr/bin/python3) refuses
    'pip install' (review AL, L6): the advice is then a virtual environment with every package,
    and, in a C host, CABLECASING_PYTHON at its interpreter (a Python host runs the FMU in its own
    interpreter, so the host must run from the environment); elsewhere pip into that Python."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("bridge", ROOT / "fmu_src" / "cablecasing_fmi2_bridge.py")
    bridge = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bridge)
    requirements = "numpy>=1.24;scipy>=1.11;numba>=0.59"
    monkeypatch.setattr(bridge, "externally_managed", lambda: True)
    c_host = bridge.install_advice(["numba>=0.59"], requirements, python_host=False)
    assert "PEP 668" in c_host and f"'{sys.executable} -m venv ENV && ENV/bin/python -m pip install " in c_host
    assert '"numpy>=1.24" "scipy>=1.11" "numba>=0.59"' in c_host and "CABLECASING_PYTHON" in c_host
    python_host = bridge.install_advice(["numba>=0.59"], requirements, python_host=True)
    assert "-m venv ENV" in python_host and "run the host with ENV/bin/python" in python_host
    assert "CABLECASING_PYTHON" not in python_host
    monkeypatch.setattr(bridge, "externally_managed", lambda: False)
    assert bridge.install_advice(["numba>=0.59"], requirements, python_host=False) == (
        f"Install it with '{sys.executable} -m pip install \"numba>=0.59\"', or point CABLECASING_PYTHON at a "
        "Python that has them"
    )


def test_fmusim_with_the_systems_python_advises_a_virtual_environment(c_hosts, fmu, plain_env):
    """CABLECASING_PYTHON at the system's own Python, externally managed and without the packages
    (here /usr/bin/python3.11 of Debian): the one message says to make a virtual environment and
    point CABLECASING_PYTHON at it, not to pip install into that Python, which refuses."""
    python = Path(f"/usr/bin/python{sys.version_info.major}.{sys.version_info.minor}")
    ask = "import os, sys, sysconfig; print(sys.prefix == sys.base_prefix and os.path.isfile(os.path.join("
    ask += "sysconfig.get_path('stdlib'), 'EXTERNALLY-MANAGED')))"
    marker = subprocess.run([str(python), "-c", ask], capture_output=True, text=True) if python.exists() else None
    if marker is None or marker.stdout.strip() != "True":
        pytest.skip(f"{python} is not an externally managed Python (PEP 668) here")
    proc = subprocess.run(
        [str(c_hosts / "fmusim"), "--interface-type", "cs", "--stop-time", "0.001", str(fmu)],
        env=dict(plain_env, CABLECASING_PYTHON=str(python)), capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    if "cannot run this FMU" not in proc.stderr:
        pytest.skip(f"{python} has the packages (or cannot be started): {proc.stderr[-500:]}")
    assert proc.returncode > 0, (proc.returncode, proc.stderr)  # failed, but not killed by a signal
    assert f"'{python} -m venv ENV && ENV/bin/python -m pip install" in proc.stderr, proc.stderr
    assert "set CABLECASING_PYTHON to the full path of ENV/bin/python" in proc.stderr
    assert f"'{python} -m pip install" not in proc.stderr


def test_the_bridge_names_old_and_missing_packages():
    import importlib.util

    spec = importlib.util.spec_from_file_location("bridge", ROOT / "fmu_src" / "cablecasing_fmi2_bridge.py")
    bridge = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bridge)
    problems = bridge.missing_packages("numpy>=999.0;no-such-package-xyz>=1;scipy>=1.0")
    assert len(problems) == 2
    assert problems[0].startswith("numpy ") and "is too old (needs numpy>=999.0)" in problems[0]
    assert problems[1] == "no-such-package-xyz is not installed (needs no-such-package-xyz>=1)"


# ------------------------------------------------------------------------------ careless masters
@pytest.fixture(scope="module")
def careless(fmu, tmp_path_factory, fmu_driver):
    model = cc.load_model()
    table = np.hstack(scenario_motion(model)(H * np.arange(8)))
    return fmu_driver.run(
        tmp_path_factory.mktemp("careless"), "careless", fmu, inputs=table, h=H, outputs=list(OUTPUTS)
    )


@pytest.mark.parametrize(
    "case, status, words",
    [
        ("non_utf8", 3, ["model_file", "not valid UTF-8"]),
        ("null_string", 3, ["model_file = NULL"]),
        ("strings_init", 0, []),
        ("strings_step", 0, []),
        ("nan_time", 3, ["currentCommunicationPoint = nan", "finite"]),
        ("nan_step", 3, ["communicationStepSize = nan", "finite"]),
        ("huge_step", 2, ["1000000000000.0 s refused", "at most 1000000 internal steps"]),
        ("bad_restore", 3, ["cannot be restored", "unchanged"]),
        ("after_bad_restore_step", 0, []),
        ("late_parameter", 3, ["contact.friction = 0.3 refused", "fixed after initialisation"]),
        ("same_parameter", 0, []),
        ("step_after_terminate", 3, ["fmi2DoStep is not allowed", "terminated"]),
        ("set_after_terminate", 3, ["fmi2SetReal is not allowed", "terminated"]),
        ("nan_start", 3, ["startTime = nan", "finite"]),
        ("nan_clock_restore", 3, ["start time nan s is not a finite number", "unchanged"]),
        ("after_nan_clock_step", 0, []),
        ("failed_state_restore", 3, ["cannot be restored", "did not initialise", "event_substeps", "unchanged"]),
        ("after_failed_state_step", 0, []),
        ("short_step", 2, ["h = 5e-09 s refused, nothing computed", "set solver.dt to at most 5e-06 s"]),
        ("rounding_step", 0, []),
        ("get_instantiated", 3, ["fmi2GetReal is not allowed", "instantiated"]),
        ("get_bool_instantiated", 3, ["fmi2GetBoolean is not allowed", "instantiated"]),
    ],
)
def test_careless_master(careless, case, status, words):
    assert int(careless[f"{case}_status"]) == status, careless[f"{case}_log"]
    text = " ".join(careless[f"{case}_log"])
    for w in words:
        assert w in text, text


def test_the_state_of_an_instance_that_did_not_initialise_is_not_restored(careless):
    """Its initialisation was refused (fmi2Error), so its state would refuse every step of the instance
    it is set into: the restore is refused as a whole (the instance steps on, case above)."""
    assert int(careless["failed_init_status"]) == 3


def test_a_pointer_that_is_no_instance_is_an_error_not_a_crash(careless):
    """docs/fmu.md: any call with a pointer that is not an instance of this FMU is fmi2Error; the
    pointer is looked up among the live instances before it is read (0xdeadbeef is unmapped)."""
    assert int(careless["bogus_component_status"]) == 3 and int(careless["freed_component_status"]) == 3


def test_a_freed_state_passed_where_its_address_belongs_and_another_copys_instance_are_refused(careless):
    """fmusim's calling convention of fmi2FreeFMUstate (the state itself where the address of one
    belongs) frees the state once and refuses the freed handle the second time, without reading
    through it (a host's double free crashed it); and a second copy of the binary in the process (a
    second FMU, or this one unpacked twice), with an instance of its own: the two instances' handles
    differ and each copy refuses the other's instance (both were the first handle of their copy, the
    same number, which each copy took for its own)."""
    assert list(careless["quirk_free"]) == [0, 3]
    assert bool(careless["twin_handles_differ"]) and list(careless["other_copy_status"]) == [3, 3]


def test_a_freed_instance_is_refused_even_after_a_new_one_took_its_memory(careless):
    """docs/fmu.md: the host holds a handle that is never given twice, so a step on a freed
    instance's pointer is fmi2Error even when the allocator has given its memory to a new instance
    (the step went to the new instance with fmi2OK when the host held the memory's address)."""
    stale = careless["stale_component"]
    assert stale.shape == (20, 2)
    assert np.all(stale[:, 0] == 3) and not np.any(stale[:, 1])


def test_careless_master_leaves_the_instance_usable(careless):
    assert str(careless["model_file_after"]) == ""  # refused strings were not stored
    assert np.all(careless["after_refusals_status"] == 0)
    np.testing.assert_array_equal(careless["after_bad_restore_out"], careless["before_bad_restore_out"])


def test_memory_is_bounded_whatever_the_step_sizes(fmu, tmp_path, fmu_driver):
    """1500 steps of random size (each distinct, none a multiple of solver.dt): the resident memory
    after the first 500 steps grows by less than 20 MB (without a bound: ~0.77 MB per step size)."""
    res = fmu_driver.run(tmp_path, "memory", fmu, steps=1500)
    rss = res["rss"]
    assert rss[-1] - rss[5] < 20e6, (rss[5], rss[-1])


def test_getters_give_the_model_files_values(fmu, tmp_path, fmu_driver):
    """With model_file set, the parameter getters return the file's values; a parameter set to the
    built-in specimen's value is applied (the run equals the core with that model)."""
    base = cc.load_model()
    changed = base.with_overrides({"casing.E": 6.5e9, "contact.friction": 0.4})
    (tmp_path / "m.toml").write_text(changed.to_toml())
    table = np.hstack(scenario_motion(base)(H * np.arange(300)))
    res = fmu_driver.run(
        tmp_path,
        "model_file",
        fmu,
        inputs=table,
        h=H,
        outputs=["casing.B.Fz"],
        model_file="m.toml",
        friction=0.15,
        cwd=tmp_path,
    )
    assert res["E_builtin"] == 5e9 and res["E_file"] == 6.5e9 and res["friction_file"] == 0.4
    assert res["friction_set"] == 0.15
    assert str(res["model_file"]) == str(tmp_path / "m.toml")  # relative: from the host's working folder
    ref, _ = _core_as_the_fmu(changed.with_overrides({"contact.friction": 0.15}), table)
    np.testing.assert_array_equal(res["out"][:, 0], ref)


def _core_as_the_fmu(model, table, output="casing.B.Fz"):
    """(``output`` after each step of H, the engine) of the core driven by the rows of ``table``
    (the 36 inputs) as the FMU reconstructs them."""
    eng, rec = Engine(model, ledger=False), SupportReconstruction(NCH)
    ref = np.zeros(len(table))
    for k, row in enumerate(table):
        m = rec.motion(eng.time, H, row[:NCH], row[NCH : 2 * NCH], row[2 * NCH :])
        eng.advance(H, m)
        rec.accept(m)
        ref[k] = eng.outputs()[output]
    return ref, eng


def test_no_test_or_driver_leaves_with_os_exit():
    """Leaving with os._exit (or _exit) hides a crash at exit: no test, driver, benchmark, example or
    package module may do it."""
    offenders = []
    for folder in ("tests", "benchmarks", "examples", "cablecasing_core", "fmu_src"):
        for path in (ROOT / folder).rglob("*"):
            if path.suffix not in (".py", ".c") or path == Path(__file__):
                continue
            text = path.read_text(errors="replace")
            for word in ("os._exit(", "_exit(0", "_exit(rc"):
                if word in text:
                    offenders.append(f"{path.relative_to(ROOT)}: {word}")
    assert not offenders, offenders


def test_a_c_host_of_our_own_in_the_plain_environment(fmu, tmp_path, fmu_driver, plain_env):
    """A 60-line C host (dlopen, instantiate, step, free, dlclose, return from main: every library
    destructor runs) without Python of its own and without any environment variable but HOME and
    PATH: exit 0 and the same outputs as through fmpy, bit for bit."""
    import fmpy
    from fmpy import extract, read_model_description

    compiler = shutil.which("cc") or shutil.which("gcc")
    if compiler is None or not sys.platform.startswith("linux"):
        pytest.skip("needs a C compiler on Linux")
    (tmp_path / "host.c").write_text(textwrap.dedent(C_HOST))
    inc = Path(fmpy.__file__).parent / "c-code"
    subprocess.run(
        [compiler, "-O1", f"-I{inc}", "-o", str(tmp_path / "host"), str(tmp_path / "host.c"), "-ldl"],
        check=True,
        capture_output=True,
    )
    n = 200
    model = cc.load_model()
    table = np.hstack(scenario_motion(model)(H * np.arange(n)))
    c = CHANNELS.index("casing.A.z")
    np.ascontiguousarray(table[:, [c, NCH + c, 2 * NCH + c]]).tofile(tmp_path / "inputs.bin")
    md = read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    unzip = Path(extract(str(fmu), unzipdir=tmp_path / "unzip"))
    proc = subprocess.run(
        [
            str(tmp_path / "host"),
            str(unzip / "binaries" / "linux64" / "CableCasing.so"),
            md.guid,
            (unzip / "resources").as_uri(),
            str(tmp_path / "inputs.bin"),
            str(n),
            repr(H),
            str(vr["casing.A.z"]),
            str(vr["casing.A.vz"]),
            str(vr["casing.A.az"]),
            str(vr["casing.B.Fz"]),
        ],
        capture_output=True,
        text=True,
        env=plain_env,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    y = np.array([float(line.split()[1]) for line in proc.stdout.splitlines() if line.startswith("y ")])
    only_z = np.zeros_like(table)
    for j in (c, NCH + c, 2 * NCH + c):
        only_z[:, j] = table[:, j]
    ref = fmu_driver.run(tmp_path, "run", fmu, inputs=only_z, h=H, outputs=["casing.B.Fz"])
    assert len(y) == n and np.array_equal(y, ref["out"][:, 0])
    assert np.max(np.abs(y)) > 0


def test_a_c_host_that_calls_from_a_new_thread_each_time_keeps_its_memory(fmu, tmp_path, plain_env):
    """A C host that calls fmi2DoStep from a new native thread every step (std::async, a thread per
    task), in the plain environment: every step fmi2OK, and the resident memory from step 500 to
    step 4000 grows by under 2 MB (a Python thread state kept for every new thread, as before, is
    ~4.4 kB: 15 MB over these 3500 threads; the first 64 threads keep one, 0.3 MB)."""
    from fmpy import extract, read_model_description

    compiler = shutil.which("cc") or shutil.which("gcc")
    if compiler is None or not sys.platform.startswith("linux"):
        pytest.skip("needs a C compiler on Linux")
    import fmpy

    (tmp_path / "threads.c").write_text(textwrap.dedent(C_THREAD_HOST))
    inc = Path(fmpy.__file__).parent / "c-code"
    exe = tmp_path / "threads"
    cmd = [compiler, "-O1", f"-I{inc}", "-o", str(exe), str(tmp_path / "threads.c"), "-ldl", "-lpthread"]
    subprocess.run(cmd, check=True, capture_output=True)
    unzip = Path(extract(str(fmu), unzipdir=tmp_path / "unzip"))
    so = unzip / "binaries" / "linux64" / "CableCasing.so"
    guid = read_model_description(str(fmu)).guid
    args = [str(exe), str(so), guid, (unzip / "resources").as_uri(), "4000"]
    proc = subprocess.run(args, capture_output=True, text=True, env=plain_env, timeout=600)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    rss = {int(w[1]): int(w[2]) for w in (line.split() for line in proc.stdout.splitlines()) if w[0] == "rss"}
    assert rss[4000] - rss[500] < 2048, rss  # kB


def test_instances_stepped_at_once_on_threads_equal_their_serial_runs(fmu, tmp_path, fmu_driver, plain_env):
    """A master's thread pool in C, in the plain environment: three instances, two of them alike,
    the third of another casing.E, stepped at once, a thread each, give the records of the same three
    stepped one after the other, bit for bit, twice (the step's kernels run outside the interpreter
    lock, docs/fmu.md "Several instances": nothing they write may be shared, even between instances
    of one model); and the two moduli give two records (else the test could not tell them apart)."""
    cmd = fmu_driver.pool_host_command(fmu, tmp_path, 300, H, 2, (5e9, 6e9, 5e9), "casing.E")
    if cmd is None:
        pytest.skip("needs a C compiler on Linux")
    proc = subprocess.run(cmd, capture_output=True, text=True, env=plain_env, timeout=600)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    y = {}
    for line in proc.stdout.splitlines():
        if line.startswith("y "):
            _, i, v = line.split()
            y.setdefault(int(i), []).append(float(v))
    assert sorted(y) == [0, 1, 2] and all(len(r) == 300 for r in y.values())
    assert np.max(np.abs(y[0])) > 0 and not np.array_equal(y[0], y[1])
    assert np.array_equal(y[0], y[2])  # (the same parameters: what two instances could share, they read only)


C_THREAD_HOST = r"""
    /* Steps one instance from a new thread per fmi2DoStep; prints "rss STEP kB" at steps 500, 4000. */
    #include <dlfcn.h>
    #include <pthread.h>
    #include <stdio.h>
    #include <stdlib.h>
    #include <string.h>
    #include "fmi2Functions.h"

    static void logger(fmi2ComponentEnvironment e, fmi2String n, fmi2Status s, fmi2String c, fmi2String m, ...) {}
    static fmi2DoStepTYPE *do_step;
    static fmi2Component comp;
    static double t = 0.0;
    static fmi2Status status;
    static void *step(void *arg) { status = do_step(comp, t, 1e-4, fmi2True); return NULL; }
    static long rss_kb(void) {
        char line[256]; long kb = -1; FILE *f = fopen("/proc/self/status", "r");
        while (f && fgets(line, sizeof line, f)) if (!strncmp(line, "VmRSS:", 6)) kb = atol(line + 6);
        if (f) fclose(f);
        return kb;
    }
    int main(int argc, char **argv) {   /* so guid resources_uri n */
        void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
        if (!lib) { printf("dlopen failed: %s\n", dlerror()); return 1; }
        fmi2InstantiateTYPE *instantiate = (fmi2InstantiateTYPE *)dlsym(lib, "fmi2Instantiate");
        do_step = (fmi2DoStepTYPE *)dlsym(lib, "fmi2DoStep");
        fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
        comp = instantiate("threads", fmi2CoSimulation, argv[2], argv[3], &cb, fmi2False, fmi2False);
        if (!comp) { printf("instantiate failed\n"); return 2; }
        ((fmi2SetupExperimentTYPE *)dlsym(lib, "fmi2SetupExperiment"))(comp, fmi2False, 0.0, 0.0, fmi2False, 0.0);
        ((fmi2EnterInitializationModeTYPE *)dlsym(lib, "fmi2EnterInitializationMode"))(comp);
        ((fmi2ExitInitializationModeTYPE *)dlsym(lib, "fmi2ExitInitializationMode"))(comp);
        int n = atoi(argv[4]);
        for (int k = 1; k <= n; k++) {
            pthread_t th;
            pthread_create(&th, NULL, step, NULL);
            pthread_join(th, NULL);
            if (status != fmi2OK) { printf("step %d status %d\n", k, status); return 3; }
            t += 1e-4;
            if (k == 500 || k == n) printf("rss %d %ld\n", k, rss_kb());
        }
        ((fmi2TerminateTYPE *)dlsym(lib, "fmi2Terminate"))(comp);
        ((fmi2FreeInstanceTYPE *)dlsym(lib, "fmi2FreeInstance"))(comp);
        dlclose(lib);
        return 0;
    }
"""


C_HOST = r"""
    /* A minimal FMI 2.0 co-simulation host in C: loads the FMU's binary, drives inputs in_u, in_v,
       in_a from a file of n x 3 doubles with steps of h, prints one output per step, unloads it. */
    #include <dlfcn.h>
    #include <stdarg.h>
    #include <stdio.h>
    #include <stdlib.h>
    #include "fmi2Functions.h"

    static void logger(fmi2ComponentEnvironment e, fmi2String name, fmi2Status s, fmi2String cat,
                       fmi2String msg, ...) {
        va_list ap; va_start(ap, msg); printf("log %d: ", s); vprintf(msg, ap); printf("\n"); va_end(ap);
    }
    #define LOAD(f) f##TYPE *f = (f##TYPE *)dlsym(lib, #f); if (!f) { printf("missing %s\n", #f); return 2; }

    int main(int argc, char **argv) {   /* so guid resources_uri inputs.bin n h in_u in_v in_a out */
        void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
        if (!lib) { printf("dlopen failed: %s\n", dlerror()); return 1; }
        LOAD(fmi2Instantiate) LOAD(fmi2SetupExperiment) LOAD(fmi2EnterInitializationMode)
        LOAD(fmi2ExitInitializationMode) LOAD(fmi2SetReal) LOAD(fmi2GetReal) LOAD(fmi2DoStep)
        LOAD(fmi2Terminate) LOAD(fmi2FreeInstance)
        int n = atoi(argv[5]);
        double h = atof(argv[6]), t = 0.0, y;
        fmi2ValueReference in[3] = {atoi(argv[7]), atoi(argv[8]), atoi(argv[9])}, out = atoi(argv[10]);
        double *u = malloc(sizeof(double) * 3 * n);
        FILE *f = fopen(argv[4], "rb");
        if (!f || fread(u, sizeof(double), 3 * n, f) != (size_t)(3 * n)) { printf("cannot read inputs\n"); return 3; }
        fclose(f);
        fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
        fmi2Component c = fmi2Instantiate("chost", fmi2CoSimulation, argv[2], argv[3], &cb, fmi2False, fmi2True);
        if (!c) { printf("instantiate failed\n"); return 4; }
        if (fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) || fmi2EnterInitializationMode(c)
            || fmi2ExitInitializationMode(c)) { printf("initialisation failed\n"); return 5; }
        for (int k = 0; k < n; k++) {
            fmi2SetReal(c, in, 3, u + 3 * k);
            fmi2Status s = fmi2DoStep(c, t, h, fmi2True);
            if (s != fmi2OK) { printf("doStep status %d\n", s); return 6; }
            t += h;
            fmi2GetReal(c, &out, 1, &y);
            printf("y %.17g\n", y);
        }
        fmi2Terminate(c);
        fmi2FreeInstance(c);
        dlclose(lib);
        free(u);
        return 0;
    }
"""


def test_a_model_file_with_isolators_and_an_excited_clip_runs_as_the_core(fmu, tmp_path, fmu_driver):
    """issue 24: a model file whose casing ends sit on isolators and which has a clip with its own
    excitation. The FMU's inputs drive the isolators' supports; the excited clip's channels are not
    inputs of the FMU built without a model file (its variables are the built-in specimen's), so
    its support stays at rest, as in the core driven by the same 12 channels; casing.B.Fz is the
    force through isolator B (with the FMU built for such a file: test_model_fmu.py)."""
    import copy

    data = copy.deepcopy(cc.load_model().data)
    iso = {"stiffness": [4e5, 1e5, 1e5], "rotational_stiffness": 5.0, "damping": 25.0}
    data["casing"]["supports"] = {"A": "isolator", "B": "isolator"}
    data["casing"]["isolator"] = {"A": iso, "B": iso}
    data["casing"]["clip"] = [{"at": 0.4, "stiffness": 5e4, "damping": 8.0, "excitation": "tunnel"}]
    mounted = cc.model_from_dict(data)
    (tmp_path / "m.toml").write_text(mounted.to_toml())
    base = cc.load_model()
    table = np.hstack(scenario_motion(base)(H * np.arange(300)))
    res = fmu_driver.run(
        tmp_path, "model_file", fmu, inputs=table, h=H, outputs=["casing.B.Fz"], model_file="m.toml", friction=0.15,
        cwd=tmp_path,
    )  # fmt: skip
    ref, eng = _core_as_the_fmu(mounted, table)
    assert eng.channels[NCH:] == ("tunnel.x", "tunnel.y", "tunnel.z")
    assert np.abs(ref).max() > 0.0
    np.testing.assert_array_equal(res["out"][:, 0], ref)
