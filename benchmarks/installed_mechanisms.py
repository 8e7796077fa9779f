"""Why the paper's conclusions hold or fail on each installation: the contact behind the band levels.

For each installation (the default specimen; the installed one; the installed one with the routing
as rest shape, i.e. tension and gravity only; the installed one without tension, i.e. the straight
rest shape and gravity only) at friction 0.05 and 0.2, one record of the default scenario per seed
(1 s, dt = 1e-5 s), and per record (``--vary KEY LOW HIGH`` sets another parameter's two values,
e.g. ``--vary casing.d_inner 0.0034 0.0046``; the tags then carry the value):

* contacts_per_step: cable nodes in contact per step (mean over the record after 0.06 s);
* stick_share: the share of those node-steps in stick (the rest slip);
* bends_share, transitions_share, first_bend_share, second_bend_share: the shares of the contact
  time in the bends (the runs of nodes whose routing curvature exceeds 0.3 of the maximum, as
  tests/studies/test_findings.py), within three elements outside them (where a bend begins and
  ends), and in each bend (the first is the tightest: smallest radius 0.128 m on the route,
  `cablecasing geometry`, and 0.136 m at the 35-element mesh's nodes, whose curvature these runs use);
* normal_force_first_bend_N, normal_force_second_bend_N, normal_force_straight_N: the mean total
  normal force per bend and off the bends (N, the static part included);
* dyn_normal_force_first_bend_N, ..._second_bend_N: the RMS of the normal force's fluctuation about
  its mean, summed in quadrature over the bend's nodes (N): the vibrating part of the contact;
* octave_rms_casing.B.Fz_N: the nine Table 3 band levels of casing.B.Fz (N, mean over the seeds);
* static_contact_nodes, static_force_first_bend_N, ..._second_bend_N (installed models): the static
  state's contact nodes and the magnitudes of its contact forces summed per bend, over the
  transitions and elsewhere (N).

Run: .venv/bin/python benchmarks/installed_mechanisms.py [--seeds 2] [--duration 1.0] [--only installed ...]
[--set KEY=VALUE] [--vary KEY LOW HIGH]
(prints name: value lines; about 20 s per record on the shared 2-core machine)
"""

import numpy as np
from _options import checked, integer, parser, seconds
from _record_length import require_band_record

import cablecasing_core as cc
from cablecasing_core.errors import ModelError
from cablecasing_core.nvh.bands import window_options
from cablecasing_core.records import after_skip
from cablecasing_core.studies import octave_rms
from cablecasing_core.timedomain.static_state import static_state

#: the rectangular window (no detrending) of this script's cached references and of the docs' tables
#: it made, before Hann's became the default of the band levels (benchmarks/band_window.py compares them)
RECT = window_options("boxcar")

INSTALLATIONS = {
    "default": ("default", {}),
    "installed": ("installed", {}),
    "tension_only": ("installed", {"cable.rest_shape": "routing"}),
    "straight_only": ("installed", {"loads.cable_tension": 0.0}),
}
SEED_KEY = "scenario.excitation.casing_random.seed"

p = parser(__doc__)
p.add_argument("--seeds", type=int, default=2, help="seeds 1..N of the casing's random excitation per record")
p.add_argument("--duration", type=float, default=1.0, help="s per record")
p.add_argument("--skip", type=float, default=0.06, help="s of each record left out (the fade-in, the transient)")
p.add_argument(
    "--only", nargs="*", default=list(INSTALLATIONS), choices=list(INSTALLATIONS), help="installations to run"
)
p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="another override for every run")
p.add_argument(
    "--vary",
    nargs=3,
    default=["contact.friction", "0.05", "0.2"],
    metavar=("KEY", "LOW", "HIGH"),
    help="the parameter varied and its two values",
)
args = p.parse_args()
EXTRA = {}
with checked(p):
    integer("--seeds", args.seeds, 1)
    seconds("--duration", args.duration)
    seconds("--skip", args.skip, zero_ok=True)
    for kv in args.set:
        k, eq, v = kv.partition("=")
        try:
            EXTRA[k] = float(v)
        except ValueError:
            raise ModelError("--set", kv, "must be KEY=NUMBER, e.g. casing.d_inner=0.004") from None
        if not eq:
            raise ModelError("--set", kv, "must be KEY=NUMBER, e.g. casing.d_inner=0.004")
    try:
        VALUES = (float(args.vary[1]), float(args.vary[2]))
    except ValueError:
        raise ModelError("--vary", " ".join(args.vary), "must be KEY LOW HIGH, two numbers") from None
    for name in args.only:  # (every model the runs make, made once before them: a key or value refused now)
        spec, over = INSTALLATIONS[name]
        for value in VALUES:
            try:
                cc.load_model(spec).with_overrides({**over, **EXTRA, args.vary[0]: value})
            except ModelError as exc:
                raise ModelError("--set/--vary", [*args.set, *args.vary], f"{name}: {exc}") from None
require_band_record(p, args.duration, args.skip)


def transitions(first, second, nodes, reach=3):
    """The nodes within ``reach`` elements outside either bend: where a bend begins and ends."""
    near = [np.arange(max(b.min() - reach, 0), min(b.max() + reach + 1, nodes)) for b in (first, second)]
    return np.setdiff1d(np.concatenate(near), np.concatenate([first, second]))


def bends(curvature):
    """The two bends' node indices (curvature above 0.3 of the maximum), first the tightest."""
    curved = np.flatnonzero(curvature > 0.3 * curvature.max())
    runs = np.split(curved, np.flatnonzero(np.diff(curved) > 1) + 1)
    return sorted(runs, key=lambda r: -curvature[r].max())


for name in args.only:
    spec, over = INSTALLATIONS[name]
    key = args.vary[0]
    for value in VALUES:
        rows, levels = [], []
        for seed in range(1, args.seeds + 1):
            m = cc.load_model(spec).with_overrides({**over, **EXTRA, key: value, SEED_KEY: seed})
            r = cc.simulate(m, duration=args.duration)
            keep = after_skip(r.time, args.skip)
            s = r.contact_state[keep]
            N = r.normal_force[keep]
            first, second = bends(r.curvature)
            arcs = np.concatenate([first, second])
            near = transitions(first, second, s.shape[1])
            straight = np.setdiff1d(np.arange(s.shape[1]), arcs)
            ct = np.count_nonzero(s, axis=0).astype(float)
            closed = max(np.count_nonzero(s), 1)
            dyn = N - N.mean(axis=0)
            F = r.support_force("casing.B.Fz")[keep]
            levels.append(octave_rms(F, 1.0 / (r.time[1] - r.time[0]), **RECT).rms)
            rows.append(
                [
                    np.count_nonzero(s, axis=1).mean(),
                    np.count_nonzero(s == 1) / closed,
                    ct[arcs].sum() / max(ct.sum(), 1),
                    ct[near].sum() / max(ct.sum(), 1),
                    ct[first].sum() / max(ct.sum(), 1),
                    ct[second].sum() / max(ct.sum(), 1),
                    N[:, first].mean(axis=0).sum(),
                    N[:, second].mean(axis=0).sum(),
                    N[:, straight].mean(axis=0).sum(),
                    np.sqrt((dyn[:, first] ** 2).mean(axis=0).sum()),
                    np.sqrt((dyn[:, second] ** 2).mean(axis=0).sum()),
                ]
            )
        v = np.mean(rows, axis=0)
        tag = f"{name}_{key.split('.')[-1]}{value:g}"
        names = (
            "contacts_per_step stick_share bends_share transitions_share first_bend_share second_bend_share "
            "normal_force_first_bend_N normal_force_second_bend_N normal_force_straight_N "
            "dyn_normal_force_first_bend_N dyn_normal_force_second_bend_N"
        ).split()
        for k, x in zip(names, v):
            print(f"{tag}_{k}: {x:.4g}")
        print(f"{tag}_octave_rms_casing.B.Fz_N: " + " ".join(f"{x:.4g}" for x in np.mean(levels, axis=0)))
        if spec != "default":  # the static state the record starts from (friction does not enter it)
            f = np.linalg.norm(static_state(m).contact_force, axis=1)
            print(f"{tag}_static_contact_nodes: {np.count_nonzero(f)} {np.flatnonzero(f).tolist()}")
            print(f"{tag}_static_force_first_bend_N: {f[first].sum():.4g} (nodes {first.tolist()})")
            print(f"{tag}_static_force_second_bend_N: {f[second].sum():.4g} (nodes {second.tolist()})")
            print(f"{tag}_static_force_transitions_N: {f[near].sum():.4g} (nodes {near.tolist()})")
            print(f"{tag}_static_force_straight_N: {f.sum() - f[first].sum() - f[second].sum() - f[near].sum():.4g}")
