"""In-process A/B of two source trees of ``cablecasing_core`` (e.g. HEAD and a change).

On a shared VM whose speed drifts by 10-30 % over minutes, separate "fastest of N runs" figures
cannot resolve a few per cent. This loads both packages into one process (under the names ccA and
ccB), advances the default scenario with each
in alternating chunks of 0.01 s (the order alternates too), and prints the median and quartiles
of the per-chunk time ratio B/A, which the drift affects on both sides alike. Two identical trees
give 0.97-1.03, the resolution of the method; run both load orders. The numba cache of the two
trees is kept apart from their normal one (see NUMBA_CACHE_DIR below), so each run first
compiles both (~1.5 min).

Prints ``name: value`` lines: us_per_step_median_A, us_per_step_median_B (µs per step, the medians
of the chunks), ratio_B_over_A_median, ratio_B_over_A_quartiles (two numbers) and
ratio_B_over_A_total (B's whole time over A's).

Run:  git archive HEAD cablecasing_core | tar -x -C /tmp/A    (and the change into /tmp/B)
      .venv/bin/python benchmarks/ab_kernels.py /tmp/A /tmp/B [--duration 1.0] [--no-contact] [--no-record]
                                               [--model installed] [--dt 1e-5]
                                               [--step 1e-4]   (FMU-like calls: per-call costs)
"""

import atexit
import importlib
import importlib.util
import inspect
import os
import shutil
import sys
import tempfile

# numba's cache is keyed by source file, but a cached function remembers the module it was compiled
# in: kernels compiled here as ccA.kernels would be loaded by a later normal import of the same
# tree (or by a run with the trees in the other order) and fail there (No module named 'ccA'). So
# every run compiles into a cache directory of its own, removed at the end.
_CACHE = tempfile.mkdtemp(prefix="cablecasing-ab-numba-")
os.environ["NUMBA_CACHE_DIR"] = _CACHE
atexit.register(shutil.rmtree, _CACHE, True)

import numpy as np  # noqa: E402
from _alternating import alternate  # noqa: E402
from _options import checked, parser, seconds, time_step  # noqa: E402

from cablecasing_core.errors import ModelError  # noqa: E402
from cablecasing_core.model.validators import number  # noqa: E402


def load(root, name):
    """Import ``root/cablecasing_core`` as package ``name``."""
    spec = importlib.util.spec_from_file_location(
        name, f"{root}/cablecasing_core/__init__.py", submodule_search_locations=[f"{root}/cablecasing_core"]
    )
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    spec.loader.exec_module(mod)
    return mod


def fmu_like(support_motion, eng, motion, h):
    """advance(duration): what the FMU does per communication step h (s), without fmpy: the
    scenario sampled at the step's start, the support reconstruction, one Engine.advance, the
    outputs read."""
    rec = support_motion.SupportReconstruction(12)
    read = getattr(eng, "output_values", eng.outputs)

    def advance(duration):
        for _ in range(int(round(duration / h))):
            u, v, a = motion(np.array([eng.time]))
            m = rec.motion(eng.time, h, u[0], v[0], a[0])
            eng.advance(h, m)
            rec.accept(m)
            read()

    return advance


def module(name, new, old):
    """``name.new``, or ``name.old`` in a tree of the flat layout before issue 22 (so that a tree can
    be compared with one from before the renovation)."""
    try:
        return importlib.import_module(f"{name}.{new}")
    except ModuleNotFoundError:
        return importlib.import_module(f"{name}.{old}")


def main():
    p = parser(__doc__)
    p.add_argument("a", help="tree A: a folder holding cablecasing_core/")
    p.add_argument("b", help="tree B: a folder holding cablecasing_core/")
    p.add_argument("--duration", type=float, default=1.0, help="simulated time per tree (s)")
    p.add_argument("--dt", type=float, default=1e-5, help="time step of both trees (s)")
    p.add_argument("--no-contact", action="store_true", help="both engines without contact")
    p.add_argument("--no-record", action="store_true", help="both engines without their records")
    p.add_argument(
        "--model",
        default="default",
        help="built-in specimen of both trees: default or installed (the latter from its static state)",
    )
    p.add_argument(
        "--step",
        type=float,
        default=None,
        help="advance in calls of this many seconds as the FMU does (inputs sampled at the call's "
        "start, timedomain.support_motion.SupportReconstruction, outputs read after each call); default: one "
        "call per chunk",
    )
    args = p.parse_args()
    with checked(p):
        for option, root in (("a", args.a), ("b", args.b)):
            if not os.path.isfile(f"{root}/cablecasing_core/__init__.py"):
                raise ModelError(option, root, "must be a folder holding a tree's cablecasing_core/ (git archive)")
        number("--duration", args.duration, ge=0.01, unit="s")  # (at least one chunk)
        time_step("--dt", args.dt)
        if args.step is not None:
            seconds("--step", args.step)
        if args.model not in ("default", "installed"):
            raise ModelError("--model", args.model, "must be a built-in specimen: default or installed")
    dt, chunk = args.dt, 0.01
    runs = []
    for root, name in ((args.a, "ccA"), (args.b, "ccB")):
        cc = load(root, name)
        engine = module(name, "timedomain.engine", "engine")
        scenario = module(name, "timedomain.scenario", "scenario")
        # the tree's own specimen file (load_model(None) reads the installed package's)
        specimen = next(
            f
            for f in (
                f"{root}/cablecasing_core/model/specimens/{args.model}.toml",
                f"{root}/cablecasing_core/data/{args.model}_model.toml",
            )
            if os.path.exists(f)
        )
        model = cc.load_model(specimen)
        engine.Engine(model, dt=dt, ledger=False).advance(dt, scenario.scenario_motion(model))  # numba
        eng = engine.Engine(model, dt=dt, contact=not args.no_contact, ledger=False, record=not args.no_record)
        # (trees before issue 25 made the random record periodic over a duration they were given)
        periodic = "duration" in inspect.signature(scenario.scenario_motion).parameters
        motion = scenario.scenario_motion(model, dt=dt, **({"duration": args.duration} if periodic else {}))
        if args.step:
            motion = fmu_like(module(name, "timedomain.support_motion", "kinematics"), eng, motion, args.step)
        runs.append((eng, motion))
    calls = [
        (lambda mo=motion: mo(chunk)) if args.step else (lambda e=eng, mo=motion: e.advance(chunk, mo))
        for eng, motion in runs
    ]
    ta, tb = alternate(calls, int(round(args.duration / chunk))).T
    r = tb / ta
    per_step = lambda w: np.median(w) / chunk * dt * 1e6  # noqa: E731
    print(f"us_per_step_median_A: {per_step(ta):.2f}")
    print(f"us_per_step_median_B: {per_step(tb):.2f}")
    print(f"ratio_B_over_A_median: {np.median(r):.3f}")
    print(f"ratio_B_over_A_quartiles: {np.percentile(r, 25):.3f} {np.percentile(r, 75):.3f}")
    print(f"ratio_B_over_A_total: {tb.sum() / ta.sum():.3f}")


if __name__ == "__main__":
    main()
