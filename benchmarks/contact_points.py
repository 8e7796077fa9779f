"""Is it the contact's points or the bodies' mesh that moves the band levels with the mesh?

A diagnostic for docs/time_domain.md, "The cable between its nodes". The contact sees the cable's
nodes only, so refining the mesh does two things at once: it resolves the bodies better and it
adds points of contact. This script separates them: a mesh of n elements whose contact acts at
every ``stride``-th cable node only (the others carry no share of the law, the kept ones ``stride``
times theirs, so the wall per unit length is the same), with the contact law per unit length at the
paper's wall (``contact.law_length`` = the cable's length / 35). n = 70 with stride 2 has the
contact points of 35 elements on the bodies of 70; n = 140 with stride 4 those of 35, stride 2
those of 70. It replaces ``engine.contact_shares`` in its worker processes for that (the static
state and the engine both take the shares from it); nothing else changes.

Per variant ``N/S`` (``--variants``, default 35/1 70/1 70/2 140/1 140/2 140/4) it runs the band
members of ``benchmarks/mesh_refinement.py`` (the specimen's scenario, 1 s, its own Δt, Table 3
band levels of casing.B.Fz after the skip) on seeds 1..``--seeds`` and prints ``name: value``
lines: the mean levels per variant (``levels_N_N/S``, N), and each variant's relative difference
from every other variant with the same contact points and from every other with the same mesh
(``rel_diff_N/S_vs_M/T_same_points``, ``..._same_mesh``: % ± 2 SE per band, paired over the seeds).
On the installed specimen octaves 3-9 are the drive's response (CV <= 0.2 %),
so 2 seeds resolve them; the built-in specimen's levels need ~128.

Run (2026-12-06, 2 workers):
  .venv/bin/python benchmarks/contact_points.py --specimen installed --seeds 2
  .venv/bin/python benchmarks/contact_points.py --specimen default --seeds 64
"""

import time
from multiprocessing import get_context

import numpy as np
from _options import checked, integer, parser
from mesh_refinement import DEFAULT_SKIP, member, paper_law_length

from cablecasing_core.errors import ModelError
from cablecasing_core.timedomain import engine
from cablecasing_core.timedomain.engine import contact_shares

STRIDE = 1  # (set in each worker by run)


def _strided_shares(model, element_lengths):
    """engine.contact_shares with the contact kept at every STRIDE-th cable node only (STRIDE
    times its share there, zero elsewhere)."""
    s = contact_shares(model, element_lengths)
    keep = np.zeros_like(s)
    keep[::STRIDE] = STRIDE
    return s * keep


def run(job):
    """(spec, n, stride, seed, skip, law_length) -> (n, stride, seed, levels)."""
    global STRIDE
    spec, n, stride, seed, skip, law_length = job
    engine.contact_shares = _strided_shares  # (the engine and the static state call it through the module)
    if n % stride:
        raise SystemExit(f"--variants {n}/{stride}: the stride must divide the mesh (both ends keep the contact)")
    STRIDE = stride
    rec = member((spec, spec, n, seed, 1.0, skip, None, law_length, "boxcar"))  # (its own source; the table's window)
    return n, stride, seed, np.array(rec["levels_N"]), rec["wall_s"]


def main():
    ap = parser(__doc__)
    ap.add_argument("--specimen", default="installed", choices=["default", "installed"], help="the specimen")
    ap.add_argument(
        "--variants",
        nargs="+",
        default=["35/1", "70/1", "70/2", "140/1", "140/2", "140/4"],
        metavar="N/S",
        help="meshes N with the contact at every S-th cable node (S divides N)",
    )
    ap.add_argument("--seeds", type=int, default=2, help="seeds 1..N of the casing's random excitation")
    ap.add_argument("--workers", type=int, default=2, help="processes")
    args = ap.parse_args()
    variants = []
    with checked(ap):
        integer("--seeds", args.seeds, 2)  # (a standard error needs two seeds)
        integer("--workers", args.workers, 1)
        for v in args.variants:
            n, _, k = v.partition("/")
            if not (n.isdigit() and k.isdigit() and int(n) >= 1 and int(k) >= 1 and int(n) % int(k) == 0):
                raise ModelError("--variants", v, "must be N/S, two whole numbers >= 1, S dividing N (e.g. 70/2)")
            variants.append((int(n), int(k)))
    spec = args.specimen
    law_length = paper_law_length(spec)
    jobs = [(spec, n, k, s, DEFAULT_SKIP[spec], law_length) for s in range(1, args.seeds + 1) for n, k in variants]
    jobs.sort(key=lambda j: -j[1])  # the costlier first
    print(f"date: {time.strftime('%Y-%m-%d %H:%M')}")
    print(f"law_length_m: {law_length:.6f}")
    t0 = time.perf_counter()
    with get_context("spawn").Pool(args.workers) as pool:
        got = pool.map(run, jobs, chunksize=1)
    print(f"wall_min: {(time.perf_counter() - t0) / 60:.1f}")
    L = {(n, k): {} for n, k in variants}
    walls = {(n, k): [] for n, k in variants}
    for n, k, s, lv, w in got:
        L[n, k][s] = lv
        walls[n, k].append(w)
    seeds = sorted(L[variants[0]])
    for v in variants:
        print(f"levels_N_{v[0]}/{v[1]}: " + " ".join(f"{x:.4g}" for x in np.mean([L[v][s] for s in seeds], axis=0)))
        print(f"wall_s_per_member_{v[0]}/{v[1]}: {np.median(walls[v]):.1f}")
    for a in variants:
        for b in variants:
            points_a, points_b = a[0] // a[1], b[0] // b[1]
            if a == b or not (points_a == points_b and a[0] < b[0] or a[0] == b[0] and points_a < points_b):
                continue
            A = np.array([L[a][s] for s in seeds])
            B = np.array([L[b][s] for s in seeds])
            r = A.mean(0) / B.mean(0) - 1
            d = A - B * (A.mean(0) / B.mean(0))  # (the ratio's paired deviations, delta method)
            se = d.std(0, ddof=1) / np.sqrt(len(seeds)) / B.mean(0)
            what = "same_points" if points_a == points_b else "same_mesh"
            print(
                f"rel_diff_{a[0]}/{a[1]}_vs_{b[0]}/{b[1]}_{what}: "
                + " ".join(f"{100 * x:+.1f}±{200 * e:.1f}" for x, e in zip(r, se))
            )


if __name__ == "__main__":
    main()
