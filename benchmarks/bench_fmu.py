"""Speed of the FMU in its hosts: the default scenario (35 + 35 elements, contact with friction,
random excitation at casing A z and the cable's 50 Hz axial excitation) with a 1e-4 s
communication step, against the core's own engine on the same steps, all measured in one run.

Prints ``name: value`` lines:

* ``engine_us_per_step``: the core alone, ``Engine.advance`` per communication step with the same
  input reconstruction the FMU uses (the FMU's outputs equal these bit for bit);
* ``fmpy_us_per_step`` and ``fmu_overhead_fmpy``: a whole communication step through fmpy's
  ``FMU2Slave`` (set the 36 inputs, ``doStep``, get the outputs) and its ratio to the engine;
* ``fmusim_us_per_step`` and ``fmu_overhead_fmusim``: the same through fmusim (Reference FMUs,
  ``../shared/hosts``) in the plain environment, from the difference of a long and a short run
  (so process start, Python start and instantiation cancel), and its ratio to the engine;
* ``rtf_fmusim``: simulated over wall seconds of fmusim's stepping (the same difference), and
  ``rtf_fmusim_whole_run``: of a whole ``--stop-time`` run including its start. fmusim looks up its
  input file from the first row at every step (``FMIApplyInput``, ``FMINextInputEvent`` of
  Reference-FMUs v0.0.39), so its own cost per step grows with the file's length: these runs use
  the shortest file that covers them, and the short run's difference leaves most of it in;
* ``fmusim_drive_us_per_step``, ``rtf_fmusim_drive``: the default scenario in fmusim without an
  input file, the FMU driving its supports with the model's own scenario (``scenario.drive``), the
  same long-minus-short difference (fmusim's own cost is then ~1 µs per step);
* ``instantiate_cold_s``: loading the FMU (unzipped) through ``fmi2Instantiate``, initialisation
  and the first step with an empty per-user cache (no numba cache, no copy of the code), and
  ``instantiate_warm_s`` with both in place;
* ``mean_active_contacts``: cable nodes in contact, averaged over the steps.

The machine is shared: each figure is the fastest of ``--repeat`` runs, taken alternately.

Run: .venv/bin/python benchmarks/bench_fmu.py [--duration 1.0] [--repeat 3]
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests" / "fmu"))
sys.path.insert(0, str(ROOT))

import fmu_driver  # noqa: E402

import build_fmu  # noqa: E402
import cablecasing_core as cc  # noqa: E402
from cablecasing_core.model.schema import CHANNELS, OUTPUTS  # noqa: E402
from cablecasing_core.timedomain.engine import Engine  # noqa: E402
from cablecasing_core.timedomain.scenario import scenario_motion  # noqa: E402
from cablecasing_core.timedomain.support_motion import SupportReconstruction  # noqa: E402

FMU = ROOT / "dist" / "CableCasing.fmu"
FMUSIM = ROOT.parent / "shared" / "hosts" / "fmusim"
NCH = len(CHANNELS)
PLAIN = {"HOME": os.environ.get("HOME", "/root"), "PATH": "/usr/bin:/bin"}


def engine_run(model, table, h):
    """Wall time (s) of the core's engine over the communication steps with the FMU's reconstruction
    and outputs (``Engine.advance_reconstructed``, what the FMU's slave calls, on input buffers that
    persist from step to step as the FMU's do, so its remembered context serves every step; the
    first two steps, which load the kernels, factorise and take the general path, are left out)."""
    eng = Engine(model, ledger=False)
    rec = SupportReconstruction(NCH)
    out = np.zeros(len(OUTPUTS))
    u, v, a = np.zeros(NCH), np.zeros(NCH), np.zeros(NCH)

    def step(row):
        u[:], v[:], a[:] = row[:NCH], row[NCH : 2 * NCH], row[2 * NCH :]
        eng.advance_reconstructed(h, rec, u, v, a, out)

    step(table[0])  # loads the kernels, factorises
    step(table[1])  # (the first step takes the general path)
    t0 = time.perf_counter()
    for row in table[2:]:
        step(row)
    return time.perf_counter() - t0


def write_fmusim_inputs(path, table, h):
    cols = [j for j in range(3 * NCH) if np.any(table[:, j] != 0)]
    with open(path, "w") as f:
        f.write(",".join(['"time"'] + [f'"{fmu_driver.INPUTS[j]}"' for j in cols]) + "\n")
        for k, row in enumerate(table):
            f.write(",".join([repr(k * h)] + [repr(float(row[j])) for j in cols]) + "\n")


def fmusim_wall(inputs, stop, h, out, *extra):
    """Wall time (s) of one fmusim run to ``stop`` s with communication step ``h`` s."""
    cmd = [str(FMUSIM), "--interface-type", "cs", "--stop-time", repr(stop), "--output-interval", repr(h)]
    if inputs is not None:
        cmd += ["--input-file", str(inputs)]
    t0 = time.perf_counter()
    subprocess.run([*cmd, *extra, "--output-file", str(out), str(FMU)], env=PLAIN, check=True, capture_output=True)
    return time.perf_counter() - t0


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--duration", type=float, default=1.0, help="simulated time of the long runs (s)")
    p.add_argument("--repeat", type=int, default=3, help="runs of each kind; the fastest counts (shared machine)")
    p.add_argument("--step", type=float, default=1e-4, help="communication step (s)")
    args = p.parse_args()
    h = args.step
    if not (h > 0 and args.duration >= 20 * h):
        p.error(f"--step {h!r}: must be positive and at most a twentieth of --duration ({args.duration!r} s)")
    if not FMU.exists() or FMU.stat().st_mtime < max(q.stat().st_mtime for q in build_fmu.sources()):
        subprocess.run([sys.executable, str(ROOT / "build_fmu.py")], check=True)

    model = cc.load_model()
    n = int(round(args.duration / h))
    short = n // 5
    table = np.hstack(scenario_motion(model)(h * np.arange(n + 1)))  # the master's samples at t = k h
    eng_s, fmpy_s, sim_long, sim_short, drive_long, drive_short, cold, warm = [], [], [], [], [], [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        write_fmusim_inputs(tmp / "inputs.csv", table, h)
        fmu_driver.run(tmp, "run", FMU, inputs=table[:2], h=h, outputs=["casing.B.Fz"])  # warm the caches
        for k in range(args.repeat):
            eng_s.append(engine_run(model, table[:n], h) / (n - 2))
            res = fmu_driver.run(tmp, "run", FMU, inputs=table[:n], h=h, outputs=list(OUTPUTS))
            assert np.all(res["status"] == 0), res["log"]
            fmpy_s.append(float(res["run_s"]) / (n - 1))
            warm.append(float(res["first_step_s"]))
            if FMUSIM.exists():
                sim_long.append(fmusim_wall(tmp / "inputs.csv", n * h, h, tmp / "long.csv"))
                sim_short.append(fmusim_wall(tmp / "inputs.csv", short * h, h, tmp / "short.csv"))
                drive = ("--start-value", "scenario.drive", "true")
                drive_long.append(fmusim_wall(None, n * h, h, tmp / "dlong.csv", *drive))
                drive_short.append(fmusim_wall(None, short * h, h, tmp / "dshort.csv", *drive))
            env = {key: v for key, v in os.environ.items() if key != "NUMBA_CACHE_DIR"}
            env["XDG_CACHE_HOME"] = str(tmp / f"empty-cache-{k}")
            res_cold = fmu_driver.run(tmp, "run", FMU, inputs=table[:2], h=h, outputs=["casing.B.Fz"], env=env)
            cold.append(float(res_cold["first_step_s"]))
    engine = min(eng_s)
    print(f"communication_step_s: {h:g}")
    print(f"engine_us_per_step: {engine * 1e6:.1f}")
    print(f"fmpy_us_per_step: {min(fmpy_s) * 1e6:.1f}")
    print(f"fmu_overhead_fmpy: {min(fmpy_s) / engine:.3f}")
    if sim_long:
        per_step = min(a - b for a, b in zip(sim_long, sim_short)) / (n - short)
        print(f"fmusim_us_per_step: {per_step * 1e6:.1f}")
        print(f"fmu_overhead_fmusim: {per_step / engine:.3f}")
        print(f"rtf_fmusim: {h / per_step:.3f}")
        print(f"rtf_fmusim_whole_run: {n * h / min(sim_long):.3f}")
        per_step = min(a - b for a, b in zip(drive_long, drive_short)) / (n - short)
        print(f"fmusim_drive_us_per_step: {per_step * 1e6:.1f}")
        print(f"fmu_overhead_fmusim_drive: {per_step / engine:.3f}")
        print(f"rtf_fmusim_drive: {h / per_step:.3f}")
        print(f"rtf_fmusim_drive_whole_run: {n * h / min(drive_long):.3f}")
    print(f"rtf_engine: {h / engine:.3f}")
    print(f"instantiate_cold_s: {min(cold):.2f}")
    print(f"instantiate_warm_s: {min(warm):.2f}")
    print(f"mean_active_contacts: {res['out'][:, OUTPUTS.index('contact.active')].mean():.2f}")


if __name__ == "__main__":
    main()
