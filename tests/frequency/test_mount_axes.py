"""An isolator's stiffness acts in its local axes (axial = the centerline's
tangent) on a body that is not aligned with the global axes."""

import numpy as np

import cablecasing_core as cc
from cablecasing_core.structure.assembly import assemble_body

CASING = dict(E=5e9, rho=4850.0, d_outer=0.0095, d_inner=0.004, I=2.7261e-10)


def test_an_isolator_on_an_oblique_casing_is_stiff_along_its_tangent_and_soft_across_it():
    # A straight casing along (1, 2, 2)/3, clamped at B, on an isolator at A with axial stiffness
    # 4e5 N/m and lateral 1e3, 2e4 N/m, rotational 10, 20, 30 N.m/rad. In global axes the
    # translational block is R^T diag(k) R (R's rows: the local axes): its eigenpairs are the three
    # stiffnesses with the local axes as eigenvectors, so K t = k_a t for the tangent t exactly
    # (rounding only: 1e-9 of k_a), and the local stiffnesses come back as given.
    d = np.array([1.0, 2.0, 2.0]) / 3.0
    k, kr = [4e5, 1e3, 2e4], [10.0, 20.0, 30.0]
    model = cc.model_from_dict(
        {
            "geometry": {"points": [[0.0, 0, 0], list(0.9 * d)], "n_elements": 10, "curve": "polyline"},
            "casing": dict(
                CASING,
                supports={"A": "isolator", "B": "clamped"},
                isolator={"A": {"stiffness": k, "rotational_stiffness": kr}},
            ),
        }
    )
    (mount,) = assemble_body(model, "casing").mounts
    R = mount.axes
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(R[0], d, atol=1e-12)  # axial = tangent
    Kt, Kr = mount.K6[:3, :3], mount.K6[3:, 3:]
    for i in range(3):
        np.testing.assert_allclose(Kt @ R[i], k[i] * R[i], rtol=0, atol=1e-9 * max(k))
        np.testing.assert_allclose(Kr @ R[i], kr[i] * R[i], rtol=0, atol=1e-9 * max(kr))
    kt, krot = mount.local_stiffness()
    np.testing.assert_allclose(kt, k, rtol=1e-9)
    np.testing.assert_allclose(krot, kr, rtol=1e-9)
