"""``benchmarks/contact_between_nodes.py`` (docs/time_domain.md, "The mesh") runs against the present
API: one specimen, one mesh, a short record."""

import subprocess
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "contact_between_nodes.py"


def test_the_contact_between_nodes_prints_its_figures():
    cmd = [sys.executable, str(BENCH), "--specimen", "installed", "--elements", "35", "--duration", "0.06"]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    values = dict(line.split(": ", 1) for line in out.splitlines() if ": " in line)
    assert int(values["installed_35_samples"]) == 21  # (0.05 to 0.06 s every 5e-4 s, both ends)
    # the installed cable lies on the wall: its nodes are in contact at every sample
    assert float(values["installed_35_nodes_in_contact"]) > 5
    assert float(values["installed_35_node_penetration_m"].split()[0]) > 0


def test_the_middles_are_the_cubic_hermite_middles_of_the_elements(monkeypatch):
    """The points the script measures are the elements' middles: for any nodal displacements u and
    rotations theta, the middle of a straight Hermite beam of length L and unit tangent t moves by
    (u_a + u_b) / 2 + L / 8 (theta_a - theta_b) x t (the cubic shape functions at 1/2: 1/2, L/8,
    1/2, -L/8 transverse, linear along t), written here independently of the kernels; its rest
    point is the chord's middle. To rounding (1e-12 of the displacements)."""
    import importlib.util

    import numpy as np

    import cablecasing_core as cc
    from cablecasing_core.timedomain.engine import Engine

    monkeypatch.syspath_prepend(str(BENCH.parent))  # (its own imports: _options, as when run as a script)
    spec = importlib.util.spec_from_file_location("contact_between_nodes", BENCH)
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    cable = Engine(cc.load_model("installed")).bodies["cable"].system
    Xm, Tm, Hm = bench.middles(cable)
    X, L = cable.centerline.nodes, cable.centerline.lengths
    np.testing.assert_allclose(Xm, 0.5 * (X[:-1] + X[1:]), rtol=0, atol=1e-15)
    U = np.random.default_rng(3).standard_normal(6 * len(X)) * 1e-3
    for e in range(len(L)):
        ua, ta, ub, tb = (U[6 * e + k : 6 * e + k + 3] for k in (0, 3, 6, 9))
        mid = 0.5 * (ua + ub) + L[e] / 8 * np.cross(ta - tb, Tm[e])
        np.testing.assert_allclose(Hm[e, :3] @ U[6 * e : 6 * e + 12], mid, rtol=0, atol=1e-15)
