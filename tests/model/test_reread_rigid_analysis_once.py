"""buckling analyses a body's rigid motions once when its supports leave one free: the free motion
in words and as a basis of the free DOFs come from the same 6 x 6 analysis, and the load is that
of the bending on the rest (the symmetric Euler load of a column on end springs, as
test_undriven_free_motion states it: 56.204 N)."""

import numpy as np
import pytest
from scipy.optimize import brentq

import cablecasing_core as cc
from cablecasing_core.structure import support_check
from cablecasing_core.structure.assembly import assemble_body
from cablecasing_core.structure.buckling import buckling

L, EI, K_ROT = 0.85, 5e9 * 2.7261e-10, 20.0  # m, N.m2, N.m/rad: the casing of Table 2 (paper_bodies), its end isolators


def test_a_free_motion_is_analysed_once(monkeypatch, paper_bodies):
    iso = {"stiffness": [4e5, 1e5, 1e5], "rotational_stiffness": [0.0, K_ROT, K_ROT]}  # (free to twist)
    model = cc.model_from_dict(
        {
            "geometry": {"n_elements": 40, "curve": "polyline", "points": [[0, 0, 0], [L, 0, 0]]},
            "casing": dict(
                paper_bodies["casing"], supports={"A": "isolator", "B": "isolator"}, isolator={"A": iso, "B": iso}
            ),
            "cable": dict(paper_bodies["cable"], supports={"A": "clamped", "B": "clamped"}),
            "scenario": {"duration": 0.01, "dt": 1e-5},
        }
    )
    system = assemble_body(model, "casing")
    calls = []
    analysis = support_check._analysis
    monkeypatch.setattr(support_check, "_analysis", lambda *a: calls.append(1) or analysis(*a))
    b = buckling(system)
    assert len(calls) == 1
    assert b.undriven is not None and b.mechanism is None

    def f(lam):  # the symmetric mode's moment condition at the ends (x from mid-span)
        return EI * lam * np.cos(lam * L / 2) + K_ROT * np.sin(lam * L / 2)

    lam = brentq(f, np.pi / L * (1 + 1e-12), 2 * np.pi / L * (1 - 1e-12), xtol=1e-15)
    assert b.load == pytest.approx(EI * lam**2, rel=1e-5)  # (40 elements: the FE's 2e-6; 1e-5 a margin)
