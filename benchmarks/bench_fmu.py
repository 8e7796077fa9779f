"""Speed of the FMU: the default scenario (35 + 35 elements, contact with friction, random
excitation at casing A z and the cable's 50 Hz axial excitation) through fmpy with a 1e-4 s
communication step, against the core's own engine on the same run.

Prints ``name: value`` lines:

* ``rtf_fmu``: simulated seconds per wall second through fmpy (fresh process, warm numba cache);
* ``rtf_core_same_run``: the core's ``Engine.advance`` over the same communication steps with the
  same input reconstruction (bit-identical outputs);
* ``fmu_overhead``: FMU wall time / core wall time of that same run (goal < 1.1);
* ``rtf_core_one_advance`` and ``fmu_overhead_vs_one_advance``: the core in a single
  ``Engine.advance`` call over the whole run with the scenario's own motion (no per-step calls);
* ``instantiate_s``: from loading the FMU (already unzipped) through fmi2Instantiate, the
  initialisation and the first step, numba cache warm (goal < 3 s);
* ``mean_active_contacts``: cable nodes in contact, averaged over the steps.

``--step`` sets the communication step (default 1e-4 s, ten Newmark steps per call); a longer one
spreads the fixed cost per call (fmpy, pythonfmu, the core's Python) over more steps.

Run: .venv/bin/python benchmarks/bench_fmu.py [--duration 0.2] [--step 1e-4]
"""

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT))

import fmu_driver  # noqa: E402

import build_fmu  # noqa: E402
import cablecasing_core as cc  # noqa: E402
from cablecasing_core.model.schema import CHANNELS, OUTPUTS  # noqa: E402
from cablecasing_core.timedomain.engine import Engine  # noqa: E402
from cablecasing_core.timedomain.scenario import scenario_motion  # noqa: E402
from cablecasing_core.timedomain.support_motion import SupportReconstruction  # noqa: E402

FMU = ROOT / "dist" / "CableCasing.fmu"
NCH = len(CHANNELS)


def core_same_run(model, table, h):
    """Wall time (s) of the core's Engine.advance over the same communication steps with the same
    reconstruction, outputs read after each step; and those outputs."""
    n = len(table)
    eng = Engine(model, ledger=False)
    rec = SupportReconstruction(NCH)
    ref = np.zeros((n, len(OUTPUTS)))

    def step(k):
        row = table[k]
        m = rec.motion(eng.time, h, row[:NCH], row[NCH : 2 * NCH], row[2 * NCH :])
        eng.advance(h, m)
        rec.accept(m)
        eng.output_values(ref[k])

    step(0)  # numba load, factorisation
    t0 = time.perf_counter()
    for k in range(1, n):
        step(k)
    return time.perf_counter() - t0, ref


def core_one_advance(model, n, h):
    """Wall time (s) of one Engine.advance over the run with the scenario's own motion."""
    eng = Engine(model, ledger=False)
    motion = scenario_motion(model)
    eng.advance(h, motion)
    t0 = time.perf_counter()
    eng.advance((n - 1) * h, motion)
    return time.perf_counter() - t0


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--duration", type=float, default=0.2, help="simulated time (s)")
    p.add_argument("--repeat", type=int, default=3, help="runs of each kind; the fastest counts (shared machine)")
    p.add_argument("--step", type=float, default=1e-4, help="communication step (s)")
    args = p.parse_args()
    H = args.step
    if not (H > 0 and args.duration >= 2 * H):
        p.error(f"--step {H!r}: must be positive and at most half of --duration ({args.duration!r} s)")
    if not FMU.exists() or FMU.stat().st_mtime < max(q.stat().st_mtime for q in build_fmu.sources()):
        subprocess.run([sys.executable, str(ROOT / "build_fmu.py")], check=True)

    model = cc.load_model()
    n = int(round(args.duration / H))
    table = np.hstack(scenario_motion(model)(H * np.arange(n)))  # the master's samples at t = k h
    fmu_s, first_s, same_s, one_s = [], [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        fmu_driver.run(tmp, "run", FMU, inputs=table[:2], h=H, outputs=["casing.B.Fz"])  # warm the cache
        for _ in range(args.repeat):  # alternate, so that load changes hit both
            res = fmu_driver.run(tmp, "run", FMU, inputs=table, h=H, outputs=list(OUTPUTS))
            assert np.all(res["status"] == 0), res["log"]
            fmu_s.append(float(res["run_s"]))
            first_s.append(float(res["first_step_s"]))
            wall, ref = core_same_run(model, table, H)
            same_s.append(wall)
            one_s.append(core_one_advance(model, n, H))
    sim = (n - 1) * H
    fmu, same, one = min(fmu_s), min(same_s), min(one_s)
    print(f"communication_step_s: {H:g}")
    print(f"rtf_fmu: {sim / fmu:.4f}")
    print(f"rtf_core_same_run: {sim / same:.4f}")
    print(f"fmu_overhead: {fmu / same:.3f}")
    print(f"rtf_core_one_advance: {sim / one:.4f}")
    print(f"fmu_overhead_vs_one_advance: {fmu / one:.3f}")
    print(f"instantiate_s: {min(first_s):.3f}")
    print(f"mean_active_contacts: {res['out'][:, OUTPUTS.index('contact.active')].mean():.2f}")
    print(f"fmu_equals_core_bitwise: {int(np.array_equal(ref, res['out']))}")


if __name__ == "__main__":
    main()
