"""Where is the cable between its nodes? The contact law sees the cable nodes only (Eqs. 36-39: a
node's normal plane against the casing axis), so between two nodes the cable's axis (its Hermite
interpolation, as the casing's) may pass into the wall unseen. This script measures by how much,
against the mesh (docs/time_domain.md, "The mesh").

Per specimen (``--specimen``) and mesh (``--elements``) it runs the specimen's scenario for
``--duration`` s at its own time step and samples every ``--every`` s after 0.05 s. At each sample
it places a point at the middle of every cable element (the element's Hermite displacement and
rotation at xi = 1/2, ``kernels.hermite_matrix``) and measures that point's penetration into the
deformed casing with the static state's contact kernel (``kernels.static_contact``: the same
normal-plane search and gap as a node's, ``share`` 1), and prints ``name: value`` lines:
* ``<spec>_<n>_node_penetration_m``: the mean over the samples of the deepest node's penetration,
  and its largest value;
* ``<spec>_<n>_midpoint_penetration_m``: the same for the elements' middles;
* ``<spec>_<n>_midpoint_over_node``: the ratio of the two means;
* ``<spec>_<n>_nodes_in_contact`` and ``<spec>_<n>_midpoints_in_the_wall``: per sample, mean;
* ``<spec>_<n>_unseen_midpoints``: middles in the wall with both of their element's nodes out of
  contact, per sample, the share of samples with one, and the deepest (m);
* ``<spec>_<n>_wall_s``: the run's wall time.
The casing's axis is itself a Hermite beam on the same nodes, so the middles' penetration is the
model's own (not a comparison with the smooth route).

Run (2026-12-06, one core, 1.7 min of runs; docs/time_domain.md "The mesh" has its figures):
  .venv/bin/python benchmarks/contact_between_nodes.py
"""

import time

import numpy as np
from _options import checked, parser, seconds

import cablecasing_core as cc
from cablecasing_core.model.schema import lookup
from cablecasing_core.model.validators import number
from cablecasing_core.timedomain import kernels as K
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion

SETTLE = 0.05  # s: the samples before it are left out (the start of the scenario's motion)


def middles(cable):
    """(rest positions (m), unit tangents, 6 x 12 interpolation matrices at xi = 1/2) of the cable
    elements' middles: each element is a straight Hermite beam between its nodes."""
    X, R, L = cable.centerline.nodes, cable.centerline.frames, cable.centerline.lengths
    H = np.zeros((len(L), 6, 12))
    for e in range(len(L)):
        K.hermite_matrix(0.5, L[e], R[e], H[e])
    return 0.5 * (X[:-1] + X[1:]), (X[1:] - X[:-1]) / L[:, None], H


def measure(spec, n, duration, every):
    model = cc.load_model(spec).with_overrides({"geometry.n_elements": n})
    eng = Engine(model)
    motion = scenario_motion(model)
    Xm, Tm, Hm = middles(eng.bodies["cable"].system)
    ne = len(Xm)
    g, h, N, kn, xi = (np.zeros(ne) for _ in range(5))
    nrm, HH = np.zeros((ne, 3)), np.zeros((ne, 6, 12))
    fcc, fcs = np.zeros(6 * ne), np.zeros(len(eng.bodies["casing"].U))
    elem = np.minimum(np.arange(ne), len(eng.Ls) - 1).astype(np.int64)
    rows = []
    t0 = time.perf_counter()
    for k in range(int(round(duration / every))):
        eng.advance(every, motion)
        if (k + 1) * every < SETTLE:
            continue
        Uc = eng.bodies["cable"].U
        Um = np.einsum("eij,ej->ei", Hm, np.stack([Uc[6 * e : 6 * e + 12] for e in range(ne)])).ravel()
        K.static_contact(
            Xm, Tm, Um, eng.Xs, eng.Rs, eng.Ls, eng.bodies["casing"].U, elem, eng.gap, eng.law, eng.k_lin,
            eng.k_hertz, np.ones(ne), g, h, N, kn, nrm, xi, HH, fcc, fcs,
        )  # fmt: skip
        gn = eng.gn
        unseen = (g > 0) & (gn[:-1] <= 0) & (gn[1:] <= 0)
        rows.append(
            (gn.max(), g.max(), (gn > 0).sum(), (g > 0).sum(), unseen.sum(), g[unseen].max() if unseen.any() else 0.0)
        )
    wall = time.perf_counter() - t0
    r = np.array(rows)
    p = f"{spec}_{n}"
    print(f"{p}_samples: {len(r)}")
    print(f"{p}_node_penetration_m: {r[:, 0].mean():.3e} (largest {r[:, 0].max():.3e})")
    print(f"{p}_midpoint_penetration_m: {r[:, 1].mean():.3e} (largest {r[:, 1].max():.3e})")
    print(f"{p}_midpoint_over_node: {r[:, 1].mean() / r[:, 0].mean():.2f}")
    print(f"{p}_nodes_in_contact: {r[:, 2].mean():.2f}")
    print(f"{p}_midpoints_in_the_wall: {r[:, 3].mean():.2f}")
    print(
        f"{p}_unseen_midpoints: {r[:, 4].mean():.2f} per sample, in {100 * np.mean(r[:, 4] > 0):.0f} % of samples, "
        f"deepest {r[:, 5].max():.3e}"
    )
    print(f"{p}_wall_s: {wall:.1f}")


def main():
    ap = parser(__doc__)
    ap.add_argument(
        "--specimen", nargs="+", default=["default", "installed"], choices=["default", "installed"], help="specimens"
    )
    ap.add_argument("--elements", nargs="+", type=int, default=[35, 70, 140, 280], help="meshes (elements per body)")
    ap.add_argument("--duration", type=float, default=0.3, help="s simulated per run")
    ap.add_argument("--every", type=float, default=5e-4, help="s between samples")
    args = ap.parse_args()
    with checked(ap):
        number("--duration", args.duration, gt=SETTLE, unit="s")  # (samples are taken after SETTLE s)
        seconds("--every", args.every)
        for n in args.elements:
            lookup("geometry.n_elements").check(n, "--elements")
    print(f"date: {time.strftime('%Y-%m-%d %H:%M')}")
    for spec in args.specimen:
        for n in args.elements:
            measure(spec, n, args.duration, args.every)


if __name__ == "__main__":
    main()
