"""The start transient of the built-in specimen's 50 Hz cable drive in its band levels (docs/nvh.md,
"The start transient of a harmonic drive"; the check of the report's skip, ``report.start_transient``).

Each seed runs the built-in specimen's own scenario (random base excitation at casing.A.z, the
50 Hz axial drive of the cable, contact; dt = 1e-5 s, 35 elements) from rest, longer than the
report's records, and its casing.B.Fz is cut into windows (the samples a < t <= b, t the end of each
step). The Table 3 band RMS of each window (``studies.octave_rms``: Hann's window, the mean removed,
as the report's levels) is compared with that of a late window of the same seed, r = L / L_late - 1,
and r is averaged over the seeds: mean ± 2 SE (paired: the same seed's record in both), in %.

* ``long``: seeds 401-416 (``--long-seeds``), 2 s runs; windows 0.06-1.0, 0.25-1.0, 0.06-0.5 (the
  report's old window, 0.5 s records after 0.06 s), 0.25-0.75 s against 1.0-2.0 s, and 1.25-1.75 s,
  a 0.5 s window long after the start (inside the late one: what a window's length alone changes);
* ``short``: seeds 301-312 (``--short-seeds``), 1.75 s runs; the 0.25 s windows 0-0.25, 0.25-0.5,
  0.5-0.75, 0.75-1.0 s against 1.0-1.75 s (bands of a 0.25 s window hold few FFT lines, 2.75 in
  octave 1: the comparison is of like with like, the late window's levels through the same window
  length would scatter alike; the long part measures the report's windows themselves).

Printed as ``name: value`` lines: ``<part>_<window>_oct<k>: mean ± 2SE %`` with ``*`` where |mean|
> 2 SE, and ``<part>_<window>_beyond_2se: oct...`` naming those bands. ``--no-drive`` runs the same
without the cable drive (the linear control: no contact, no start transient of the drive).
Run: .venv/bin/python benchmarks/start_transient.py [--parts long short] [--no-drive] (53 s of
simulated time: 1.6-2.8 min on one core of the shared 2-core machine, depending on its load).
"""

import warnings

import numpy as np
from _options import checked, parser, seeds

import cablecasing_core as cc
from cablecasing_core.errors import ModelError
from cablecasing_core.studies import octave_rms
from cablecasing_core.timedomain.simulation import simulate

OUTPUT = "casing.B.Fz"
PARTS = {
    "long": (2.0, [(0.06, 1.0), (0.25, 1.0), (0.06, 0.5), (0.25, 0.75), (1.25, 1.75)], (1.0, 2.0)),
    "short": (1.75, [(0.0, 0.25), (0.25, 0.5), (0.5, 0.75), (0.75, 1.0)], (1.0, 1.75)),
}

p = parser(__doc__)
p.add_argument("--parts", nargs="+", choices=list(PARTS), default=list(PARTS), help="the parts to run")
p.add_argument(
    "--long-seeds", type=int, nargs=2, default=(401, 416), metavar=("FIRST", "LAST"), help="seeds of the long part"
)
p.add_argument(
    "--short-seeds", type=int, nargs=2, default=(301, 312), metavar=("FIRST", "LAST"), help="seeds of the short part"
)
p.add_argument("--no-drive", action="store_true", help="the specimen without its cable drive (the control)")
args = p.parse_args()
with checked(p):
    for option, (first, last) in (("--long-seeds", args.long_seeds), ("--short-seeds", args.short_seeds)):
        seeds(option, [first, last])
        if not first < last:  # (the mean's standard error needs two seeds)
            raise ModelError(option, [first, last], "must be FIRST LAST with FIRST < LAST: two seeds at least")

model = cc.load_model()
if args.no_drive:
    from cablecasing_core.report.runs import without_cable_drive

    model = without_cable_drive(model)
random = [n for n, e in model.scenario["excitation"].items() if e["kind"] == "random"]


def levels(x, t, a, b):
    """Table 3 band RMS (N) of the samples a < t <= b (s) of x, through Hann's window."""
    keep = (t > a + 1e-9) & (t <= b + 1e-9)
    fs = 1.0 / (t[1] - t[0])
    return octave_rms(x[keep], fs, "table3", name=OUTPUT, warn_few_lines=False).rms


print(f"model: {model.source}; output: {OUTPUT}; dt: {model.scenario['dt']:g} s")
for part in args.parts:
    duration, windows, late = PARTS[part]
    first, last = args.long_seeds if part == "long" else args.short_seeds
    seeds = range(first, last + 1)
    r = []  # seeds x windows x bands
    for s in seeds:
        m = model.with_overrides({f"scenario.excitation.{n}.seed": s for n in random})
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # (the run's advice on the mesh: not this script's subject)
            res = simulate(m, duration=duration, progress=False)
        x, t = res.support_force(OUTPUT), res.time
        ref = levels(x, t, *late)
        r.append([levels(x, t, a, b) / ref - 1.0 for a, b in windows])
    r = 100.0 * np.array(r)
    mean, se2 = r.mean(axis=0), 2.0 * r.std(axis=0, ddof=1) / np.sqrt(len(seeds))
    print(f"{part}_seeds: {first}-{last} ({len(seeds)}), runs of {duration:g} s, against {late[0]:g}-{late[1]:g} s")
    for k, (a, b) in enumerate(windows):
        name = f"{part}_{a:.2f}-{b:.2f}"
        beyond = []
        for j in range(r.shape[2]):
            star = "*" if abs(mean[k, j]) > se2[k, j] else ""
            if star:
                beyond.append(f"oct{j + 1}")
            print(f"{name}_oct{j + 1}: {mean[k, j]:+.1f} ± {se2[k, j]:.1f} %{star}")
        print(f"{name}_beyond_2se: {' '.join(beyond) or 'none'}")
