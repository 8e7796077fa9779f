"""Speed of the FMU in its hosts: the default scenario (35 + 35 elements, contact with friction,
random excitation at casing A z and the cable's 50 Hz axial excitation) with a 1e-4 s
communication step, against the core's own engine on the same steps, all measured in one run.

Prints ``name: value`` lines:

* ``engine_us_per_step``: the core alone, ``Engine.advance`` per communication step with the same
  input reconstruction the FMU uses (the FMU's outputs equal these bit for bit);
* ``fmpy_us_per_step`` and ``fmu_overhead_fmpy``: a whole communication step through fmpy's
  ``FMU2Slave`` in this process, as fmpy's own ``simulate_fmu`` sets inputs
  (``simulation.Input.apply``): ``fmi2SetReal`` of the 36 inputs, ``fmi2DoStep``, ``fmi2GetReal``
  of the 26 Real outputs, on ctypes arrays made once; and its ratio to the engine (the package is
  imported here before the FMU is loaded: the FMU uses this copy, whose sources are its own);
* ``fmpy_list_set_get_us``: the same inputs and outputs through fmpy's convenience calls
  ``setReal(vrs, list)`` and ``getReal(vrs)``, which build new ctypes arrays at every call (fmpy's
  own cost, outside the FMU);
* ``fmpy_driver_us_per_step`` and ``fmu_overhead_fmpy_driver``: the test driver's loop
  (``tests/fmu/fmu_driver.py``, a fresh process, the FMU's own bundled code; the driver's Python
  per step included: outputs by name, statuses);
* ``fmusim_us_per_step`` and ``fmu_overhead_fmusim``: the same through fmusim (Reference FMUs, in
  the folder of the C hosts: ``--hosts``, else the environment variable ``CABLECASING_HOSTS``, else
  ``../shared/hosts`` beside the repository; where it finds no fmusim it prints a line
  ``# fmusim: not found at PATH ...`` instead of every ``fmusim_*`` and ``rtf_fmusim*`` line) in the
  plain environment: the wall time from the first ``fmi2DoStep`` to
  ``fmi2Terminate`` over the calls, from the FMU's own log line at ``fmi2Terminate`` (so process
  start, Python start and instantiation are left out), and its ratio to the engine;
* ``fmusim_host_us_per_step``: the part of it spent outside ``fmi2DoStep`` (fmusim's own work and
  its other calls into the FMU), from the same log line;
* ``rtf_fmusim``: simulated over wall seconds of fmusim's stepping (the same difference), and
  ``rtf_fmusim_whole_run``: of a whole ``--stop-time`` run including its start. fmusim looks up its
  input file from the first row at every step (``FMIApplyInput``, ``FMINextInputEvent`` of
  Reference-FMUs v0.0.39), so its own cost per step grows with the file's length;
* ``fmusim_drive_us_per_step``, ``rtf_fmusim_drive``: the default scenario in fmusim without an
  input file, the FMU driving its supports with the model's own scenario (``scenario.drive``),
  measured the same way (fmusim's own cost is then ~1 µs per step), and its ratio to the engine
  driven by the same scenario with its random record computed ahead, as the slave does in initialisation
  (``engine_drive_prepared_us_per_step``; ``engine_drive_us_per_step``: evaluated within the steps,
  chunk by chunk, as the core's ``simulate`` does);
* ``fmusim_drive_longest_call_ms`` and ``fmusim_drive_late_calls``: the longest doStep call of that
  run and the calls that took longer than their communication step (a real-time master's missed
  deadlines), from the FMU's log line at ``fmi2Terminate`` (the least of the runs);
* ``fmusim_drive_realtime_us_per_step``, ``rtf_fmusim_drive_realtime``: the same fmusim run with
  ``solver.dt`` = ``--realtime-dt`` (default 2e-5 s, five Newmark steps per communication step),
  the setting docs/fmu.md ("Real time") gives a real-time master, whose expected band levels are
  within 0.5 % of a fine step up to 1.4 kHz and 4.1 % in the top octave (docs/time_domain.md, "The
  time step on 456 seeds"), with its longest call and late calls;
* ``fmusim_installed_realtime_us_per_step``, ``rtf_fmusim_installed_realtime``: the installed
  specimen (``model_file`` = installed) driven by its own scenario in fmusim at its real-time
  setting, ``solver.dt`` = 1/30000 s (docs/time_domain.md, "Real time on the installed specimen"),
  with its longest call and late calls;
* ``instantiate_cold_s``: loading the FMU (unzipped) through ``fmi2Instantiate``, initialisation
  and the first step with an empty per-user cache (no numba cache, no copy of the code), and
  ``instantiate_warm_s`` with both in place;
* ``mean_active_contacts``: cable nodes in contact, averaged over the steps;
* ``engine_clips_us_per_step``, ``fmpy_clips_us_per_step`` and ``fmu_overhead_fmpy_clips``: the same
  as ``engine_us_per_step`` / ``fmpy_us_per_step`` for the FMU built for
  ``examples/clipped_specimen.toml`` (``build_fmu.py --model``: 45 inputs, 39 outputs, the excited
  clip driven by its own scenario's 150 Hz) and its engine.

The machine is shared: each figure is the fastest of ``--repeat`` runs, taken alternately. The FMU
timed is dist/CableCasing.fmu, built again (``build_fmu.py``, written over the one there) when it is
older than its sources.

Run: .venv/bin/python benchmarks/bench_fmu.py [--duration 1.0] [--repeat 3] [--hosts DIR]
(docs/performance.md: ``--duration 1.0 --repeat 3``)
"""

import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _options import checked, integer, parser, seconds, time_step

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests" / "fmu"))
sys.path.insert(0, str(ROOT))

import fmu_driver  # noqa: E402

import build_fmu  # noqa: E402
import cablecasing_core as cc  # noqa: E402
from cablecasing_core.model.schema import CHANNELS, OUTPUTS  # noqa: E402
from cablecasing_core.timedomain.engine import Engine  # noqa: E402
from cablecasing_core.timedomain.scenario import scenario_motion  # noqa: E402
from cablecasing_core.timedomain.support_motion import GridMotion, SupportReconstruction  # noqa: E402

FMU = ROOT / "dist" / "CableCasing.fmu"
CLIPPED = ROOT / "examples" / "clipped_specimen.toml"  # the model of the FMU built with --model
#: The folder of the C hosts (fmusim) when neither --hosts nor CABLECASING_HOSTS names one.
HOSTS = ROOT.parent / "shared" / "hosts"
FMUSIM = HOSTS / "fmusim"  # (set by main from --hosts)
NCH = len(CHANNELS)
PLAIN = {"HOME": os.environ.get("HOME", "/root"), "PATH": "/usr/bin:/bin"}
PLAIN |= {k: v for k, v in os.environ.items() if k.startswith("OPENBLAS_")}  # (as tests/fmu/test_hosts.py)


def engine_run(model, table, h, drive=False, prepared=False):
    """Wall time (s) of the core's engine over the communication steps with the FMU's reconstruction
    and outputs (``Engine.advance_reconstructed``, what the FMU's slave calls, on input buffers that
    persist from step to step as the FMU's do, so its remembered context serves every step; the
    first two steps, which load the kernels, factorise and take the general path, are left out).
    ``drive``: the scenario's motion added as the slave's ``scenario.drive`` does; with ``prepared``
    its random record computed ahead for the whole run (``GridMotion.prepare``, as the slave does in
    initialisation), else block by block within the steps."""
    eng = Engine(model, ledger=False)
    nch = len(eng.channels)  # (12, or more with excited clips)
    rec = SupportReconstruction(nch)
    out = np.zeros(len(eng.output_names))
    u, v, a = np.zeros(nch), np.zeros(nch), np.zeros(nch)
    base = GridMotion(scenario_motion(model, dt=eng.dt), eng.dt) if drive else None  # as the slave's
    if base is not None and prepared:
        base.prepare(len(table) * h)

    def step(row):
        u[:], v[:], a[:] = row[:nch], row[nch : 2 * nch], row[2 * nch :]
        eng.advance_reconstructed(h, rec, u, v, a, out, base)

    step(table[0])  # loads the kernels, factorises (the general path: the one-call step's arguments are built)
    step(table[1])  # (the one-call step's first: its context is built)
    t0 = time.perf_counter()
    for row in table[2:]:
        step(row)
    return time.perf_counter() - t0


def fmpy_run(table, h, fmu=FMU):
    """(s per step of set inputs + doStep + get outputs through fmpy's ctypes bindings on arrays
    made once, s per step of fmpy's setReal(list) + getReal) on a fresh FMU2Slave of ``fmu`` in
    this process (every input in the modelDescription's order, the table's; every Real output); the
    first two steps are left out as in :func:`engine_run`; then the time of the first two steps and of the
    first alone, s)."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave, fmi2Real, fmi2True, fmi2ValueReference

    md = read_model_description(str(fmu))
    in_vr = [v.valueReference for v in md.modelVariables if v.causality == "input"]
    out_vr = [v.valueReference for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
    assert len(in_vr) == table.shape[1]
    s = FMU2Slave(
        guid=md.guid, unzipDirectory=extract(str(fmu)), modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="bench",
    )  # fmt: skip
    s.instantiate(loggingOn=False)
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    vin, vout = (fmi2ValueReference * len(in_vr))(*in_vr), (fmi2ValueReference * len(out_vr))(*out_vr)
    xin, xout = (fmi2Real * len(in_vr))(), (fmi2Real * len(out_vr))()
    view, nin, nout, c = np.ctypeslib.as_array(xin), len(in_vr), len(out_vr), s.component
    set_real, do_step, get_real = s.fmi2SetReal, s.fmi2DoStep, s.fmi2GetReal
    t = 0.0
    t_start = time.perf_counter()
    for k, row in enumerate(table):
        if k == 1:
            t_first = time.perf_counter()
        if k == 2:
            t0 = time.perf_counter()
        view[:] = row
        set_real(c, vin, nin, xin)
        do_step(c, t, h, fmi2True)
        get_real(c, vout, nout, xout)
        t += h
    t1 = time.perf_counter()
    for row in table[: len(table) // 5]:
        s.setReal(in_vr, list(row))
        s.getReal(out_vr)
    t2 = time.perf_counter()
    s.terminate()
    s.freeInstance()
    return (t1 - t0) / (len(table) - 2), (t2 - t1) / (len(table) // 5), t0 - t_start, t_first - t_start


def write_fmusim_inputs(path, table, h):
    cols = [j for j in range(3 * NCH) if np.any(table[:, j] != 0)]
    with open(path, "w") as f:
        f.write(",".join(['"time"'] + [f'"{fmu_driver.INPUTS[j]}"' for j in cols]) + "\n")
        for k, row in enumerate(table):
            f.write(",".join([repr(k * h)] + [repr(float(row[j])) for j in cols]) + "\n")


def fmusim_wall(inputs, stop, h, out, *extra):
    """(wall time (s) of one fmusim run to ``stop`` s with communication step ``h`` s, the wall time
    (s) from its first fmi2DoStep to fmi2Terminate, the calls, the part of that time spent outside
    fmi2DoStep (s: fmusim's own work and its other calls), the longest call (s) and the calls that
    took longer than h, from the FMU's own log lines)."""
    cmd = [str(FMUSIM), "--interface-type", "cs", "--stop-time", repr(stop), "--output-interval", repr(h)]
    if inputs is not None:
        cmd += ["--input-file", str(inputs)]
    cmd += ["--logging-on", "--log-level", "ok"]
    t0 = time.perf_counter()
    res = subprocess.run(
        [*cmd, *extra, "--output-file", str(out), str(FMU)], env=PLAIN, check=True, capture_output=True
    )
    wall = time.perf_counter() - t0
    log = res.stdout.decode() + res.stderr.decode()
    m = re.search(r"(\d+) doStep calls took ([0-9.]+) s inside the FMU .*?; ([0-9.]+) s passed from the first", log)
    late = re.search(r"the longest doStep call took ([0-9.]+) ms .*?; (\d+) of \d+ calls took longer", log)
    stepping, inside = float(m.group(3)), float(m.group(2))
    return wall, stepping, int(m.group(1)), stepping - inside, 1e-3 * float(late.group(1)), int(late.group(2))


def fmusim_figures(runs):
    """(s per call from the first fmi2DoStep to fmi2Terminate, s per call outside fmi2DoStep, wall
    s of a whole run), each the fastest of the ``fmusim_wall`` runs."""
    per_step = min(r[1] / r[2] for r in runs)
    host = min(r[3] / r[2] for r in runs)
    return per_step, host, min(r[0] for r in runs)


def late_figures(runs):
    """The longest call (ms) and the calls longer than their step, each the least of the runs."""
    return f"{min(r[4] for r in runs) * 1e3:.2f}", min(r[5] for r in runs)


def main():
    global FMUSIM
    p = parser(__doc__)
    p.add_argument("--duration", type=float, default=1.0, help="simulated time of the long runs (s)")
    p.add_argument("--repeat", type=int, default=3, help="runs of each kind; the fastest counts (shared machine)")
    p.add_argument("--step", type=float, default=1e-4, help="communication step (s)")
    p.add_argument("--realtime-dt", type=float, default=2e-5, help="solver.dt of the real-time fmusim run (s)")
    p.add_argument(
        "--hosts",
        default=None,
        help=f"folder of the C hosts, holding fmusim (default: $CABLECASING_HOSTS, else {HOSTS})",
    )
    args = p.parse_args()
    h = args.step
    with checked(p):
        seconds("--duration", args.duration)
        integer("--repeat", args.repeat, 1)
        seconds("--step", h)
        time_step("--realtime-dt", args.realtime_dt)
    if not args.duration >= 20 * h:
        p.error(f"--step {h!r}: must be positive and at most a twentieth of --duration ({args.duration!r} s)")
    hosts = Path(args.hosts or os.environ.get("CABLECASING_HOSTS") or HOSTS)
    FMUSIM = hosts / "fmusim"
    if args.hosts is not None and not FMUSIM.is_file():
        p.error(f"--hosts = {args.hosts!r}: must be a folder holding fmusim ({FMUSIM} is not a file)")

    model = cc.load_model()
    n = int(round(args.duration / h))
    if not FMU.exists() or FMU.stat().st_mtime < max(q.stat().st_mtime for q in build_fmu.sources()):
        subprocess.run([sys.executable, str(ROOT / "build_fmu.py")], check=True)
    table = np.hstack(scenario_motion(model)(h * np.arange(n + 1)))  # the master's samples at t = k h
    eng_s, eng_drive_s, lean_s, lists_s, fmpy_s, sim_long, drive_long, cold, warm, first_s = ([] for _ in range(10))
    first_one_s = []
    realtime_long, installed_long, prep_s = [], [], []
    clips_eng_s, clips_fmpy_s = [], []
    clipped = cc.load_model(CLIPPED)
    clips_table = np.hstack(scenario_motion(clipped)(h * np.arange(n + 1)))
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        clips_fmu = tmp / "CableCasing-clipped.fmu"
        subprocess.run(
            [sys.executable, str(ROOT / "build_fmu.py"), "--model", str(CLIPPED), "--output", str(clips_fmu)],
            check=True, capture_output=True,
        )  # fmt: skip
        write_fmusim_inputs(tmp / "inputs.csv", table, h)
        fmu_driver.run(tmp, "run", FMU, inputs=table[:2], h=h, outputs=["casing.B.Fz"])  # warm the caches
        for k in range(args.repeat):
            eng_s.append(engine_run(model, table[:n], h) / (n - 2))
            eng_drive_s.append(engine_run(model, np.zeros_like(table[:n]), h, drive=True) / (n - 2))
            prep_s.append(engine_run(model, np.zeros_like(table[:n]), h, drive=True, prepared=True) / (n - 2))
            lean, lists, first, first_one = fmpy_run(table[:n], h)
            lean_s.append(lean)
            lists_s.append(lists)
            first_s.append(first)
            first_one_s.append(first_one)
            res = fmu_driver.run(tmp, "run", FMU, inputs=table[:n], h=h, outputs=list(OUTPUTS))
            assert np.all(res["status"] == 0), res["log"]
            fmpy_s.append(float(res["run_s"]) / (n - 1))
            warm.append(float(res["first_step_s"]))
            if FMUSIM.exists():
                sim_long.append(fmusim_wall(tmp / "inputs.csv", n * h, h, tmp / "long.csv"))
                drive = ("--start-value", "scenario.drive", "true")
                drive_long.append(fmusim_wall(None, n * h, h, tmp / "dlong.csv", *drive))
                rt = (*drive, "--start-value", "solver.dt", repr(args.realtime_dt))
                realtime_long.append(fmusim_wall(None, n * h, h, tmp / "rtlong.csv", *rt))
                inst = (*drive, "--start-value", "model_file", "installed", "--start-value", "solver.dt")
                installed_long.append(fmusim_wall(None, n * h, h, tmp / "ilong.csv", *inst, repr(1 / 30000)))
            env = {key: v for key, v in os.environ.items() if key != "NUMBA_CACHE_DIR"}
            env["XDG_CACHE_HOME"] = str(tmp / f"empty-cache-{k}")
            res_cold = fmu_driver.run(tmp, "run", FMU, inputs=table[:2], h=h, outputs=["casing.B.Fz"], env=env)
            cold.append(float(res_cold["first_step_s"]))
            clips_eng_s.append(engine_run(clipped, clips_table[:n], h) / (n - 2))
            clips_fmpy_s.append(fmpy_run(clips_table[:n], h, clips_fmu)[0])
    engine = min(eng_s)
    print(f"communication_step_s: {h:g}")
    print(f"engine_us_per_step: {engine * 1e6:.1f}")
    print(f"fmpy_us_per_step: {min(lean_s) * 1e6:.1f}")
    print(f"fmu_overhead_fmpy: {min(lean_s) / engine:.3f}")
    print(f"first_two_dosteps_ms: {min(first_s) * 1e3:.2f} (the kernels are loaded in initialisation)")
    print(f"first_dostep_ms: {min(first_one_s) * 1e3:.3f}, the largest of the repeats {max(first_one_s) * 1e3:.3f}")
    print(f"fmpy_list_set_get_us: {min(lists_s) * 1e6:.1f}")
    print(f"fmpy_driver_us_per_step: {min(fmpy_s) * 1e6:.1f}")
    print(f"fmu_overhead_fmpy_driver: {min(fmpy_s) / engine:.3f}")
    if sim_long:
        per_step, host, whole = fmusim_figures(sim_long)
        print(f"fmusim_us_per_step: {per_step * 1e6:.1f}")
        print(f"fmu_overhead_fmusim: {per_step / engine:.3f}")
        print(f"rtf_fmusim: {h / per_step:.3f}")
        print(f"fmusim_host_us_per_step: {host * 1e6:.1f} (outside fmi2DoStep: fmusim's input-file lookup, its calls)")
        print(f"rtf_fmusim_whole_run: {n * h / whole:.3f}")
        per_step, host, whole = fmusim_figures(drive_long)
        print(f"fmusim_drive_us_per_step: {per_step * 1e6:.1f}")
        print(f"engine_drive_us_per_step: {min(eng_drive_s) * 1e6:.1f} (the scenario evaluated within the steps)")
        print(f"engine_drive_prepared_us_per_step: {min(prep_s) * 1e6:.1f} (record computed ahead, as the FMU)")
        print(f"fmu_overhead_fmusim_drive: {per_step / min(prep_s):.3f}")
        print(f"rtf_fmusim_drive: {h / per_step:.3f}")
        print(f"fmusim_drive_host_us_per_step: {host * 1e6:.1f}")
        longest, late = late_figures(drive_long)
        print(f"fmusim_drive_longest_call_ms: {longest}")
        print(f"fmusim_drive_late_calls: {late} of {n}")
        print(f"rtf_fmusim_drive_whole_run: {n * h / whole:.3f}")
        per_step = fmusim_figures(realtime_long)[0]
        print(f"realtime_dt_s: {args.realtime_dt:g}")
        print(f"fmusim_drive_realtime_us_per_step: {per_step * 1e6:.1f}")
        print(f"rtf_fmusim_drive_realtime: {h / per_step:.3f}")
        longest, late = late_figures(realtime_long)
        print(f"fmusim_drive_realtime_longest_call_ms: {longest}")
        print(f"fmusim_drive_realtime_late_calls: {late} of {n}")
        per_step = fmusim_figures(installed_long)[0]
        print(f"fmusim_installed_realtime_us_per_step: {per_step * 1e6:.1f} (solver.dt = 1/30000 s)")
        print(f"rtf_fmusim_installed_realtime: {h / per_step:.3f}")
        longest, late = late_figures(installed_long)
        print(f"fmusim_installed_realtime_longest_call_ms: {longest}")
        print(f"fmusim_installed_realtime_late_calls: {late} of {n}")
    else:
        where = "--hosts" if args.hosts else "CABLECASING_HOSTS" if os.environ.get("CABLECASING_HOSTS") else "default"
        print(
            f"# fmusim: not found at {FMUSIM} ({where}): no fmusim_* and rtf_fmusim* lines; "
            "--hosts DIR or CABLECASING_HOSTS=DIR names the folder of the C hosts"
        )
    print(f"rtf_engine: {h / engine:.3f}")
    print(f"instantiate_cold_s: {min(cold):.2f}")
    print(f"instantiate_warm_s: {min(warm):.2f}")
    print(f"mean_active_contacts: {res['out'][:, OUTPUTS.index('contact.active')].mean():.2f}")
    print(f"engine_clips_us_per_step: {min(clips_eng_s) * 1e6:.1f}")
    print(f"fmpy_clips_us_per_step: {min(clips_fmpy_s) * 1e6:.1f}")
    print(f"fmu_overhead_fmpy_clips: {min(clips_fmpy_s) / min(clips_eng_s):.3f}")


if __name__ == "__main__":
    main()
