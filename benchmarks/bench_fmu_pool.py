"""Runs on several threads at once: the FMU on a master's thread pool, the core's ``simulate`` on
Python threads, and a seed ensemble on the studies' ``threads`` scheduler.

The FMU: instances of the default specimen (one per contact.friction,
different records), each driven at casing.A.z by a 300 Hz sine with a 1e-4 s communication step,
stepped one after the other and at once, a thread each, by the C host ``tests/fmu/pool_host.c`` in
the plain environment (the two orders alternate with the repetitions; the records of the two equal
bit for bit, or the host fails). Only the steps are timed: the instances are made before the clock
starts and freed after it stops.

Prints ``name: value`` lines:

* ``pool_instances``, ``cores_available``: the instances stepped at once, and the cores this
  process may run on (``os.sched_getaffinity``);
* ``pool_serial_us_per_step`` and ``pool_threads_us_per_step``: wall time per communication step
  of one instance (the run's wall time over its steps and instances), serial and threaded, the
  medians over the repetitions;
* ``pool_threads_over_serial``: the serial run's wall time over the threaded run's, the median of
  the repetitions' ratios (each ratio from two runs taken back to back): the speed-up a thread pool
  gets. All instances of a process share one Python interpreter; the step's compiled kernels run
  outside its lock, the Python of each call inside it, so the ratio stays below the instances'
  count even on as many free cores;
* ``simulate_threads_over_serial``: ``cablecasing_core.simulate`` of the default specimen (one per
  contact.friction, ``--duration`` each) on as many Python threads, against one after the other in
  the same process, the median of the repetitions' ratios (the orders alternating): the step loop
  runs outside the interpreter's lock, the Python of a run (its scenario's motion, chunk by chunk;
  its records) inside it;
* ``ensemble_serial_s``, ``ensemble_threads_s`` and ``ensemble_threads_over_serial``: a seed
  ensemble of the default specimen (``--seeds`` members of ``--duration``, ``seed_ensemble``) with
  ``scheduler="serial"`` and ``"threads"`` (one thread per core), the whole call as a user waits
  for it, the medians over the repetitions (alternating), and their ratio; with ``--dask`` also
  ``ensemble_local_s`` on a LocalCluster of one worker per core, started inside the call as the
  command line's ``--scheduler local`` does.

The machine's speed drifts: compare the ratio, not the absolute figures, across runs.

Run: .venv/bin/python benchmarks/bench_fmu_pool.py [--duration 0.5] [--reps 6] [--instances 2] [--fmu PATH]
(docs/performance.md: ``--duration 0.3 --reps 6``)
"""

import os
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

from _options import checked, integer, parser

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests" / "fmu"))
sys.path.insert(0, str(ROOT))

import fmu_driver  # noqa: E402

import build_fmu  # noqa: E402
import cablecasing_core as cc  # noqa: E402
from cablecasing_core.errors import ModelError  # noqa: E402
from cablecasing_core.model.validators import number  # noqa: E402

FMU = ROOT / "dist" / "CableCasing.fmu"
H = 1e-4  # communication step (s)
PLAIN = {"HOME": os.environ.get("HOME", "/root"), "PATH": "/usr/bin:/bin"}
PLAIN |= {k: v for k, v in os.environ.items() if k.startswith("OPENBLAS_")}  # (as tests/fmu/test_hosts.py)


def simulate_ratios(models, duration, reps):
    """The ratios serial / threaded wall time of ``cc.simulate(model, duration)`` for ``models``,
    one per repetition, the two orders alternating."""
    for m in models:
        cc.simulate(m, duration=0.01)  # (the kernels loaded, the caches warm)
    ratios = []
    for r in range(reps):
        took = {}
        for kind in ("serial", "threads") if r % 2 == 0 else ("threads", "serial"):
            t0 = time.perf_counter()
            if kind == "serial":
                for m in models:
                    cc.simulate(m, duration=duration)
            else:
                threads = [
                    threading.Thread(target=cc.simulate, args=(m,), kwargs={"duration": duration}) for m in models
                ]
                for t in threads:
                    t.start()
                for t in threads:
                    t.join()
            took[kind] = time.perf_counter() - t0
        ratios.append(took["serial"] / took["threads"])
    return ratios


def ensemble_times(model, seeds, duration, reps, dask):
    """Wall times (s) of ``seed_ensemble(model, seeds, duration)`` per scheduler, ``reps`` each, the
    schedulers' order turning with the repetitions."""
    from cablecasing_core.studies import seed_ensemble

    kinds = ["serial", "threads"] + (["local"] if dask else [])
    seed_ensemble(model, 2, duration=duration)  # (the kernels loaded)
    took = {k: [] for k in kinds}
    for r in range(reps):
        for kind in kinds[r % len(kinds) :] + kinds[: r % len(kinds)]:
            t0 = time.perf_counter()
            seed_ensemble(model, seeds, duration=duration, scheduler=kind, progress=False)
            took[kind].append(time.perf_counter() - t0)
    return took


def main():
    p = parser(__doc__)
    p.add_argument("--duration", type=float, default=0.5, help="simulated time of each instance's run (s)")
    p.add_argument("--reps", type=int, default=6, help="repetitions (serial and threaded each)")
    p.add_argument("--instances", type=int, default=2, help="instances stepped at once")
    p.add_argument("--fmu", type=Path, default=FMU, help="the FMU (default: dist/CableCasing.fmu, built if stale)")
    p.add_argument("--seeds", type=int, default=4, help="members of the seed ensemble")
    p.add_argument("--dask", action="store_true", help="also the ensemble on a local dask cluster")
    args = p.parse_args()
    with checked(p):
        number("--duration", args.duration, ge=10 * H, unit="s")  # (ten communication steps)
        integer("--reps", args.reps, 1)
        integer("--instances", args.instances, 1, 64)
        integer("--seeds", args.seeds, 2)  # (seed_ensemble's least)
        if args.fmu != FMU and not args.fmu.is_file():  # (the default one is built below when missing)
            raise ModelError("--fmu", str(args.fmu), "must be an FMU file")
    if args.fmu == FMU and (
        not FMU.exists() or FMU.stat().st_mtime < max(q.stat().st_mtime for q in build_fmu.sources())
    ):
        subprocess.run([sys.executable, str(ROOT / "build_fmu.py")], check=True)
    n = int(round(args.duration / H))
    frictions = [0.15 + 0.05 * i for i in range(args.instances)]
    with tempfile.TemporaryDirectory() as tmp:
        cmd = fmu_driver.pool_host_command(args.fmu, Path(tmp), n, H, args.reps, frictions)
        if cmd is None:
            sys.exit("needs a C compiler on Linux")
        proc = subprocess.run(cmd, capture_output=True, text=True, env=PLAIN, timeout=3600)
    if proc.returncode != 0:
        sys.exit(f"the pool host failed ({proc.returncode}): {proc.stdout[-2000:]}{proc.stderr[-2000:]}")
    runs = [tuple(map(float, line.split()[2::2])) for line in proc.stdout.splitlines() if line.startswith("time ")]
    steps = n * args.instances
    print(f"pool_instances: {args.instances}")
    print(f"cores_available: {len(os.sched_getaffinity(0))}")
    print(f"pool_serial_us_per_step: {statistics.median(s for s, _ in runs) / steps * 1e6:.1f}")
    print(f"pool_threads_us_per_step: {statistics.median(t for _, t in runs) / steps * 1e6:.1f}")
    print(f"pool_threads_over_serial: {statistics.median(s / t for s, t in runs):.3f}")
    base = cc.load_model()
    models = [base.with_overrides({"contact.friction": f}) for f in frictions]
    print(f"simulate_threads_over_serial: {statistics.median(simulate_ratios(models, args.duration, args.reps)):.3f}")
    took = ensemble_times(base, args.seeds, max(args.duration, 0.16), args.reps, args.dask)
    serial, threads = statistics.median(took["serial"]), statistics.median(took["threads"])
    print(f"ensemble_serial_s: {serial:.2f}")
    print(f"ensemble_threads_s: {threads:.2f}")
    print(f"ensemble_threads_over_serial: {serial / threads:.3f}")
    if args.dask:
        print(f"ensemble_local_s: {statistics.median(took['local']):.2f}")


if __name__ == "__main__":
    main()
