"""The augmented system of a body on mounts (its K_blocks, Eq. 13) holds
each mount as the two-node spring [[K6, -K6], [-K6, K6]]: a rigid translation of the body together
with its support nodes stretches nothing, and the support rows give the force through the mount."""

import numpy as np

import cablecasing_core as cc
from cablecasing_core.structure.assembly import assemble_body

CASING = dict(E=5e9, rho=4850.0, d_outer=0.0095, d_inner=0.004, I=2.7261e-10)


def _augmented_K(system):
    Kff, Kfp, Kpf, Kpp = system.K_blocks
    n = system.n_augmented
    K = np.zeros((n, n))
    f, p = system.free, system.prescribed
    K[np.ix_(f, f)], K[np.ix_(f, p)], K[np.ix_(p, f)], K[np.ix_(p, p)] = Kff, Kfp, Kpf, Kpp
    return K


def test_a_rigid_translation_of_a_mounted_body_and_its_supports_is_force_free():
    model = cc.model_from_dict(
        {
            "geometry": {"points": [[0.0, 0, 0], [0.5, 0.3, 0.1]], "n_elements": 12, "curve": "polyline"},
            "casing": dict(
                CASING,
                supports={"A": "isolator", "B": "clamped"},
                isolator={"A": {"stiffness": [4e5, 1e5, 2e5], "rotational_stiffness": [10.0, 20.0, 30.0]}},
                clip=[{"at": 0.3, "stiffness": 3e4}],
            ),
        }
    )
    system = assemble_body(model, "casing")
    K = _augmented_K(system)
    np.testing.assert_allclose(K, K.T, rtol=0, atol=1e-9 * np.abs(K).max())  # a spring system is symmetric
    for c in range(3):  # rigid translation of every node, the mounts' support nodes included
        u = np.zeros(system.n_augmented)
        u[c::6] = 1.0
        # K_E u of a rigid motion is zero to rounding: 1e-9 of the largest stiffness entry
        np.testing.assert_allclose(K @ u, 0.0, rtol=0, atol=1e-9 * np.abs(K).max())
    # support rows: a unit displacement of the isolator's support node alone pulls with K6 on it
    node, sup = system.mount_dofs(system.mount_of_support("A"))
    u = np.zeros(system.n_augmented)
    u[sup[0]] = 1.0
    np.testing.assert_allclose((K @ u)[sup], system.mounts[0].K6[:, 0], rtol=1e-12, atol=0)
    np.testing.assert_allclose((K @ u)[node], -system.mounts[0].K6[:, 0], rtol=1e-12, atol=0)
