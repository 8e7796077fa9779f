"""The sizes behind the limits of model/limits.py (docs/model_file.md, "Limits"): the time and peak
memory of the frequency domain's dense eigenproblem and of a short time-domain run against the
number of elements, each in a fresh process (peak memory is per process).

Prints ``name: value`` lines: ``modes_<n>_elements_s`` (one body's modes), ``simulate_<n>_elements_s``
(20 steps of two bodies, with the engine's set-up), each with ``..._peak_GB``, or
``<what>_<n>_elements: refused`` followed by the refusal on a ``#`` line.

Run: .venv/bin/python benchmarks/limits.py   (about 2 minutes, and at its largest sizes several GB
of memory per process; docs/performance.md's command)
"""

import subprocess
import sys

from _options import checked, integer, parser

CHILD = r"""
import resource, sys, time
import cablecasing_core as cc
n, what = int(sys.argv[1]), sys.argv[2]
m = cc.load_model().with_overrides({"geometry.n_elements": n})
t0 = time.perf_counter()
if what == "modes":
    cc.natural_frequencies(m, "casing", 5)
else:
    cc.simulate(m, duration=2e-4)
print(time.perf_counter() - t0, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6)
"""


def main(argv=None):
    p = parser(__doc__)
    # 600 elements lies beyond the frequency domain's limit (MAX_DENSE_ELEMENTS = 500): its line shows the
    # refusal, which costs nothing, where a run would have taken a minute
    p.add_argument(
        "--modes",
        type=int,
        nargs="+",
        default=[100, 200, 400, 500, 600],
        metavar="N",
        help="elements of the dense eigenproblems timed (default: 100 200 400 500 600; 600 shows the refusal)",
    )
    p.add_argument(
        "--simulate",
        type=int,
        nargs="+",
        default=[35, 200, 500, 1000],
        metavar="N",
        help="elements of the 20-step runs timed (default: 35 200 500 1000)",
    )
    args = p.parse_args(argv)
    with checked(p):
        for option, sizes in (("--modes", args.modes), ("--simulate", args.simulate)):
            for n in sizes:
                integer(option, n, 1)
    print(
        "# modes_<n>_elements_s: one body's modes; "
        "simulate_<n>_elements_s: 20 steps of two bodies, with the engine's set-up"
    )
    for what, sizes in (("modes", args.modes), ("simulate", args.simulate)):
        for n in sizes:
            out = subprocess.run([sys.executable, "-c", CHILD, str(n), what], capture_output=True, text=True)
            if out.returncode:
                last = (out.stderr.strip().splitlines() or ["(no message)"])[-1]
                if "ModelError" not in last:
                    raise SystemExit(f"{what} at {n} elements failed: {out.stderr}")
                print(f"{what}_{n}_elements: refused")
                print(f"# {last}")
                continue
            seconds, gb = map(float, out.stdout.split())
            print(f"{what}_{n}_elements_s: {seconds:.3g}")
            print(f"{what}_{n}_elements_peak_GB: {gb:.3g}")


if __name__ == "__main__":
    main()
