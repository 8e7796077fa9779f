"""Throughput and scaling of the Monte-Carlo study (Section 4.4) on dask.distributed LocalClusters.

Runs the same study (``--samples`` runs of Saltelli's design over the paper's six parameters) on a
LocalCluster of 1 worker and of 2 workers (processes, 1 thread each) and prints ``name: value``:

    samples_per_minute_1worker, samples_per_minute_2workers,
    scaling_efficiency        = rate(2 workers) / (2 rate(1 worker)); goal > 0.85
    raw_scaling_efficiency    the same ratio for the bare evaluate in 1 and 2 plain processes
                              (multiprocessing, no dask): what the machine itself allows
    scaling_efficiency_vs_raw = scaling_efficiency / raw_scaling_efficiency (dask's own losses)
    seconds_per_sample (1 worker, s), cpu_count
    burn_evaluate_repeats     the repetitions per sample the 'burn' evaluate was calibrated to

The clock runs from the first submission to the last row written (cluster start-up and the workers'
first import are excluded: each worker imports the evaluate function before timing). Each rate is the
best of ``--repeat`` runs (default 2), since other load on the machine can only slow a run down.

Evaluate function (``--evaluate``):
  burn (default)  a fixed amount of CPU work per sample (``cpu_burn_evaluate``: octave RMS of a
                  cache-sized synthetic record, repeated), calibrated on a worker to about
                  ``--seconds`` s: a stand-in for the time-domain model.
  package.module:function   any evaluate(overrides, **kwargs) -> {band: rms}, e.g. the real
                  engine evaluation once it exists; extra keyword arguments as JSON via --kwargs.

Run: .venv/bin/python benchmarks/bench_study.py [--samples 24] [--seconds 0.5] [--evaluate burn]
(``--samples`` at least 8, four per worker of the 2-worker run: with fewer, the rates are those of
the first samples and the efficiency can exceed 1)
"""

import json
import os
import tempfile
import time
from multiprocessing import get_context

from _options import checked, integer, parser, seconds, seeds
from distributed import Client, LocalCluster

from cablecasing_core.errors import ModelError, renamed
from cablecasing_core.studies import PAPER_BOUNDS, resolve_evaluate, run_study, sobol_design
from cablecasing_core.studies._stand_ins import cpu_burn_evaluate
from cablecasing_core.studies.executor import LOCAL_CLUSTER_OPTIONS
from cablecasing_core.studies.sampling import base_points

BURN = "cablecasing_core.studies._stand_ins:cpu_burn_evaluate"


def _timed_burn(params, repeats):
    """Wall time (s) of one burn evaluation with ``repeats`` repetitions."""
    t0 = time.perf_counter()
    cpu_burn_evaluate(params, repeats=repeats)
    return time.perf_counter() - t0


def _plain_call(job):
    spec, kwargs, overrides = job
    return resolve_evaluate(spec)(overrides, **kwargs)


def _raw_rate(spec, kwargs, design, processes):
    """Samples per minute of the bare evaluate in a spawn pool of ``processes`` (no dask)."""
    jobs = [(spec, kwargs, dict(zip(PAPER_BOUNDS, row.tolist()))) for row in design]
    with get_context("spawn").Pool(processes) as pool:
        pool.map(_plain_call, jobs[:processes], chunksize=1)  # import and warm up
        t0 = time.perf_counter()
        pool.map(_plain_call, jobs, chunksize=1)
        return len(jobs) / (time.perf_counter() - t0) * 60.0


def main():
    p = parser(__doc__)
    p.add_argument("--evaluate", default="burn", help="'burn' or a dotted path package.module:function")
    p.add_argument("--kwargs", default="{}", help="JSON object of extra keyword arguments of evaluate")
    p.add_argument("--samples", type=int, default=24, help="samples per run (a multiple of 2 keeps both workers busy)")
    p.add_argument("--seconds", type=float, default=0.5, help="target CPU time per sample of the 'burn' evaluate (s)")
    p.add_argument("--seed", type=int, default=0, help="seed of the design")
    p.add_argument("--repeat", type=int, default=2, help="runs per configuration; the best rate is kept")
    p.add_argument("--no-raw", action="store_true", help="skip the plain-multiprocessing baseline")
    args = p.parse_args()
    with checked(p):
        integer("--samples", args.samples, 8)
        seconds("--seconds", args.seconds)
        seeds("--seed", args.seed)
        integer("--repeat", args.repeat, 1)
        try:
            kwargs = json.loads(args.kwargs)
        except ValueError:
            kwargs = None
        if not isinstance(kwargs, dict):
            raise ModelError("--kwargs", args.kwargs, "must be a JSON object, e.g. '{\"repeats\": 50}'")
        spec = BURN if args.evaluate == "burn" else args.evaluate
        with renamed({"evaluate": "--evaluate"}):
            resolve_evaluate(spec)  # fail early on a bad path
    centre = {k: 0.5 * (lo + hi) for k, (lo, hi) in PAPER_BOUNDS.items()}

    rates = {}
    with tempfile.TemporaryDirectory() as tmp:
        for workers in (1, 2):
            with (
                LocalCluster(n_workers=workers, **LOCAL_CLUSTER_OPTIONS) as cluster,
                Client(cluster) as client,
            ):
                client.run(resolve_evaluate, spec)  # import on every worker before timing
                if spec == BURN and "repeats" not in kwargs:  # calibrate on a worker
                    client.submit(cpu_burn_evaluate, centre, repeats=20, pure=False).result()
                    per_repeat = client.submit(_timed_burn, centre, 200, pure=False).result() / 200
                    kwargs["repeats"] = max(1, round(args.seconds / per_repeat))
                best = 0.0
                for rep in range(args.repeat):  # best of --repeat: host noise only slows
                    t0 = time.perf_counter()
                    res = run_study(
                        os.path.join(tmp, f"w{workers}-{rep}.csv"),
                        spec,
                        PAPER_BOUNDS,
                        args.samples,
                        args.seed,
                        evaluate_kwargs=kwargs,
                        scheduler=client,
                        progress=False,
                    )
                    best = max(best, len(res) / (time.perf_counter() - t0) * 60.0)
                    ok = int(res.ok.sum())
                    if ok != len(res):
                        print(f"# {len(res) - ok} samples failed: {res.error[~res.ok][0]}")
            rates[workers] = best
            if workers == 1:
                seconds_per_sample = 60.0 / best
    if spec == BURN:
        print(f"burn_evaluate_repeats: {kwargs['repeats']}")
    eff = rates[2] / (2 * rates[1])
    print(f"samples_per_minute_1worker: {rates[1]:.2f}")
    print(f"samples_per_minute_2workers: {rates[2]:.2f}")
    print(f"scaling_efficiency: {eff:.3f}")
    if not args.no_raw:
        design = sobol_design(PAPER_BOUNDS, base_points(PAPER_BOUNDS, args.samples), args.seed)
        raw = {n: max(_raw_rate(spec, kwargs, design, n) for _ in range(args.repeat)) for n in (1, 2)}
        raw_eff = raw[2] / (2 * raw[1])
        print(f"raw_scaling_efficiency: {raw_eff:.3f}")
        print(f"scaling_efficiency_vs_raw: {eff / raw_eff:.3f}")
    print(f"seconds_per_sample: {seconds_per_sample:.3f}")
    print(f"cpu_count: {os.cpu_count()}")


if __name__ == "__main__":  # dask's worker processes are spawned: guard the entry point
    main()
