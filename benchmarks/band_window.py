"""The window of the band levels: the rectangular window against Hann's, on the specimens' records.

``studies.octave_rms`` sums an FFT's bins over each band. Through the rectangular window the record
is taken as one period of a periodic signal: the jump between its last and first sample, and the
strong octaves 4-6 of casing.B.Fz, leak into the weak top octaves with the window's 1/m^2 tail of
power, a bias that falls as 1 / the record's length. Hann's window (power-normalised) has a 1/m^6
tail. This script measures both on records of the specimens, as ``name: value`` lines:

``--bias``: per seed one long run (``--long`` s after 0.06 s, default 16 s), cut into records of
0.44 s, 1 s, 4 s and the whole; each record's band levels with both windows; printed, the mean
level per band and record length relative to Hann's over the whole record (the estimate a long
record converges to), and the standard error over the records; and the ratio of the two windows'
levels on the same records (``boxcar_over_hann_*``, paired), the rectangular window's bias.

``--ratio KEY=LO:HI``: the paired ratio of the ensemble means (HI / LO, 1 s records of ``--spec``
after 0.06 s, seeds ``--seeds``) through both windows from the same runs, with |r| / SE: what a
one-at-a-time ensemble of docs/studies.md reads through each.

``--time-step``: the installed specimen's band levels after 0.06 s of 1 s at ``--dts`` against
``--ref-dt`` (6.25e-7 s: within 8e-4 of 3.125e-7 s in every band, docs/time_domain.md), seeds
``--seeds``, with both windows: the time step's error does not depend on the window.

    .venv/bin/python benchmarks/band_window.py --bias --spec default --seeds 1 2 --long 16
    .venv/bin/python benchmarks/band_window.py --time-step --seeds 1 2
    .venv/bin/python benchmarks/band_window.py --ratio contact.friction=0.05:0.2 casing.E=2e9:1e10 --seeds $(seq 16)
    .venv/bin/python benchmarks/band_window.py --ratio geometry.n_elements=35:140 --seeds $(seq 32)
    .venv/bin/python benchmarks/band_window.py --ratio scenario.dt=2.5e-6:1e-5 --seeds $(seq 64)
"""

from __future__ import annotations

import datetime
import time

import numpy as np
from _options import checked, model, parser, seconds, seeds, time_step

import cablecasing_core as cc
from cablecasing_core.errors import ModelError
from cablecasing_core.model.load import toml_value
from cablecasing_core.records import after_skip
from cablecasing_core.studies import octave_rms

SEED_KEY = "scenario.excitation.casing_random.seed"
WINDOWS = ("boxcar", "hann")

p = parser(__doc__)
p.add_argument("--bias", action="store_true", help="the windows' bias against a long record")
p.add_argument("--time-step", action="store_true", help="the installed specimen's time-step error by window")
p.add_argument("--spec", default="default", help="specimen of --bias and --ratio (default, installed, a model file)")
p.add_argument("--seeds", type=int, nargs="+", default=[1, 2], help="seeds of the casing's random excitation")
p.add_argument("--long", type=float, default=16.0, help="s of each --bias run after its 0.06 s")
p.add_argument("--dts", type=float, nargs="+", default=[1e-5, 1 / 30000], help="time steps of --time-step (s)")
p.add_argument("--ref-dt", type=float, default=6.25e-7, help="the reference time step of --time-step (s)")
p.add_argument(
    "--ratio",
    nargs="+",
    default=[],
    metavar="KEY=LO:HI",
    help="paired ratios of the mean levels (HI / LO) of --spec over --seeds (1 s, after 0.06 s) through both windows",
)
args = p.parse_args()
if not (args.bias or args.time_step or args.ratio):
    p.error("nothing to measure: give --bias, --time-step or --ratio KEY=LO:HI (or more than one)")
ratios = []
with checked(p):
    seeds("--seeds", args.seeds)
    seconds("--long", args.long)
    for dt in [*args.dts, args.ref_dt]:
        time_step("--dts" if dt in args.dts else "--ref-dt", dt)
    spec = model("--spec", args.spec) if args.bias or args.ratio else None
    for text in args.ratio:
        key, _, bounds = text.partition("=")
        values = bounds.split(":")
        if not key or len(values) != 2:
            raise ModelError("--ratio", text, "must be KEY=LO:HI, e.g. contact.friction=0.05:0.2")
        lo, hi = (toml_value(v) for v in values)  # (as --set reads a value: 140 an integer)
        for v in (lo, hi):  # (the model takes both values: checked before the runs)
            try:
                spec.with_overrides({key: v})
            except ModelError as exc:
                raise ModelError("--ratio", text, str(exc)) from None
        ratios.append((key, lo, hi))
    if args.ratio and len(args.seeds) < 2:
        raise ModelError("--seeds", args.seeds, "must name at least 2 seeds with --ratio (its standard error)")
if args.bias and args.long < 4.0:
    p.error(f"--long = {args.long:g}: must be at least 4 s with --bias (the records are cut into 0.44, 1 and 4 s)")
print(f"date: {datetime.datetime.now():%Y-%m-%d %H:%M}")


def levels(F, fs, window):
    return octave_rms(F, fs, window=window).rms


if args.bias:
    start = time.perf_counter()
    fs = 1.0 / spec.scenario["dt"]
    cuts = (0.44, 1.0, 4.0, args.long)
    got = {}
    for seed in args.seeds:
        run = cc.simulate(spec.with_overrides({SEED_KEY: seed}), duration=args.long + 0.06)
        F = run.support_force("casing.B.Fz")[after_skip(run.time, 0.06)]
        for T in cuts:
            n = int(round(T * fs))
            for w in WINDOWS:
                for c in range(len(F) // n):
                    got.setdefault((T, w), []).append(levels(F[c * n : (c + 1) * n], fs, w))
    ref = np.mean(got[(args.long, "hann")], axis=0)
    print(f"bias_spec: {args.spec}; seeds {args.seeds}; {args.long:g} s each after 0.06 s")
    print("# bias_reference_levels_N: Hann's window over the whole record")
    print("bias_reference_levels_N: " + " ".join(f"{x:.4g}" for x in ref))
    for (T, w), v in sorted(got.items()):
        rel = np.array(v) / ref - 1
        se = rel.std(axis=0, ddof=1) / np.sqrt(len(rel)) if len(rel) > 1 else np.full(rel.shape[1], np.nan)
        print(f"bias_{w}_{T:g}s: " + " ".join(f"{x:+.3f}" for x in rel.mean(axis=0)))
        print(f"bias_{w}_{T:g}s_se: " + " ".join(f"{x:.3f}" for x in se))
        print(f"bias_{w}_{T:g}s_records: {len(rel)}")
    for T in cuts:  # the two windows on the same records: the rectangular one's bias, paired
        ratio = np.array(got[(T, "boxcar")]) / np.array(got[(T, "hann")]) - 1
        se = ratio.std(axis=0, ddof=1) / np.sqrt(len(ratio)) if len(ratio) > 1 else np.full(ratio.shape[1], np.nan)
        print(f"boxcar_over_hann_{T:g}s: " + " ".join(f"{x:+.3f}" for x in ratio.mean(axis=0)))
        print(f"boxcar_over_hann_{T:g}s_se: " + " ".join(f"{x:.3f}" for x in se))
        print(f"boxcar_over_hann_{T:g}s_records: {len(ratio)}")
    print(f"bias_wall_s: {time.perf_counter() - start:.0f}")

if args.time_step:
    start = time.perf_counter()
    installed = cc.load_model("installed")
    for seed in args.seeds:
        m = installed.with_overrides({SEED_KEY: seed})
        lv = {}
        for dt in [args.ref_dt, *args.dts]:
            run = cc.simulate(m, duration=1.0, dt=dt)
            F = run.support_force("casing.B.Fz")[after_skip(run.time, 0.06)]
            lv[dt] = {w: levels(F, 1.0 / dt, w) for w in WINDOWS}
        for dt in args.dts:
            for w in WINDOWS:
                rel = lv[dt][w] / lv[args.ref_dt][w] - 1
                print(
                    f"time_step_err_{w}_dt{dt:.4g}_seed{seed}: max {np.abs(rel).max():.4f}; "
                    + " ".join(f"{x:+.4f}" for x in rel)
                )
        print(f"time_step_levels_ref_seed{seed}_boxcar_N: " + " ".join(f"{x:.4g}" for x in lv[args.ref_dt]["boxcar"]))
        print(f"time_step_levels_ref_seed{seed}_hann_N: " + " ".join(f"{x:.4g}" for x in lv[args.ref_dt]["hann"]))
    print(f"time_step_wall_s: {time.perf_counter() - start:.0f}")

for key, lo, hi in ratios:
    start = time.perf_counter()
    lv = {(w, v): [] for w in WINDOWS for v in (lo, hi)}
    for seed in args.seeds:
        for v in (lo, hi):
            run = cc.simulate(spec.with_overrides({SEED_KEY: seed, key: v}), duration=1.0)
            F = run.support_force("casing.B.Fz")[after_skip(run.time, 0.06)]
            for w in WINDOWS:
                lv[(w, v)].append(levels(F, 1.0 / (run.time[1] - run.time[0]), w))
    for w in WINDOWS:
        a, b = np.array(lv[(w, hi)]), np.array(lv[(w, lo)])
        r = a.mean(axis=0) / b.mean(axis=0)
        # (the ratio's SE by the delta method over paired seeds)
        d = a / a.mean(axis=0) - b / b.mean(axis=0)
        se = r * d.std(axis=0, ddof=1) / np.sqrt(len(d))
        print(f"ratio_{key}_{w}: " + " ".join(f"x{x:.2f}" for x in r))
        print(f"ratio_{key}_{w}_over_se: " + " ".join(f"{(x - 1) / e:+.1f}" for x, e in zip(r, se)))
    print(f"ratio_{key}_wall_s: {time.perf_counter() - start:.0f}")
