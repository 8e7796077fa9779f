"""A clamped support's reaction includes the contact force that lands on
its end node's DOFs; the supports together carry exactly the bodies' (self-equilibrated) loads."""

import numpy as np

import cablecasing_core as cc
from cablecasing_core.timedomain.static_state import static_state


def test_a_straight_cable_springing_back_against_the_clamped_end_of_a_bent_casing_balances():
    # A cable stress-free straight, clamped at A and free at B, in a rigid 0.3 m-radius arc of 0.5 rad
    # clamped at both ends: without contact its tip would spring out by R (1 - cos 0.5) = 37 mm, far
    # beyond the 0.5 mm gap, so it presses on the wall next to the casing's clamped end B, whose
    # node takes a share of that contact through the last element's shape functions. No gravity:
    # the rest shape's load is self-equilibrated and the contact internal (the casing's share
    # H^T N n sums to N n), so the forces on the four supports add up to zero. Tolerance 1e-8 of
    # the contact force (Newton stops at 1e-10 of the loads).
    R, th = 0.3, 0.5
    a = np.linspace(0.0, th, 41)
    pts = [[R * np.sin(t), R * (1 - np.cos(t)), 0.0] for t in a]
    model = cc.model_from_dict(
        {
            "geometry": {"points": pts, "n_elements": 40, "curve": "polyline"},
            "casing": dict(E=5e14, rho=1.0, d_outer=0.0095, d_inner=0.004),
            "cable": dict(E=5.5e10, rho=7850.0, d=0.003, rest_shape="straight", supports={"A": "clamped", "B": "free"}),
            "contact": {"law": "linear", "stiffness": 1e7},
        }
    )
    st = static_state(model)
    scale = np.abs(st.contact_force).max()
    # the contact near the tip lands partly on the casing's clamped end node B (Hermite share)
    assert np.abs(st.generalized_contact["casing"][-6:-3]).max() > 1e-3 * scale
    R_all = st.reactions.reshape(4, 6)[:, :3].sum(0)  # forces the bodies exert on the supports
    np.testing.assert_allclose(R_all, 0.0, rtol=0, atol=1e-8 * scale)
    for body in ("cable", "casing"):
        np.testing.assert_allclose(st.balance[body]["residual"], 0.0, rtol=0, atol=1e-8 * scale)
