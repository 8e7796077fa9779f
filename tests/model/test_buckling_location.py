"""Buckling.at is where the mode's displacement *normal to the centerline*
is largest, not its total displacement; on a deep curved cantilever the two differ."""

import numpy as np
import pytest
from scipy.linalg import eigh

import cablecasing_core as cc
from cablecasing_core.structure import buckling as bk
from cablecasing_core.structure.assembly import assemble_body

CASING = dict(E=5e9, rho=4850.0, d_outer=0.0095, d_inner=0.004, I=2.7261e-10)


def test_the_buckling_mode_s_position_is_its_largest_lateral_displacement_on_a_curved_cantilever():
    # A 270 degree arc (R = 0.2 m) clamped at A, free at B, held out of plane by six clips stiff only
    # along their lateral_1 axis: its lowest buckling mode is in plane and, the arc being nearly
    # inextensional, carries tangential displacement as large as its lateral one, largest at the tip.
    L = 0.2 * np.radians(270.0)
    clips = [{"at": float(a), "stiffness": [0.0, 1e6, 0.0]} for a in np.linspace(0.05, L - 0.05, 6)]
    model = cc.model_from_dict(
        {
            "geometry": {
                "segments": [{"bend": {"radius": 0.2, "angle_deg": 270.0, "toward": [0, 1, 0]}}],
                "n_elements": 40,
            },
            "casing": dict(CASING, supports={"A": "clamped", "B": "free"}, clip=clips),
        }
    )
    system = assemble_body(model, "casing", check_buckling=False)
    b = bk.buckling(system)
    # independent: the pencil (K_G1, K_E) on the free DOFs of the augmented system, its largest mu
    KE = system.K_blocks[0]
    KG = system.blocks(bk.unit_geometric_stiffness(system))[0]
    mu, phi = eigh(KG, KE)
    assert b.load == pytest.approx(1.0 / mu[-1], rel=1e-9)
    u = np.zeros(system.n_augmented)
    u[system.free] = phi[:, -1]
    d = u[: system.ndof].reshape(-1, 6)[:, :3]
    t = system.centerline.tangents
    axial = np.einsum("ij,ij->i", d, t)
    lateral = np.linalg.norm(d - axial[:, None] * t, axis=1)
    assert np.abs(d[:, 2]).max() <= 1e-9 * lateral.max()  # the mode is in plane (the clips hold z)
    assert np.abs(axial).max() > lateral.max()  # tangential motion is not negligible here
    s = system.centerline.s
    # exact node equality: both pick a node by argmax; the two candidates are > 0.3 m apart
    assert b.at == pytest.approx(s[np.argmax(lateral)], abs=1e-12)
    assert abs(s[np.argmax(lateral)] - s[np.argmax(np.linalg.norm(d, axis=1))]) > 0.1
