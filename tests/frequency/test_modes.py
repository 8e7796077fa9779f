"""Natural frequencies and static deflections against closed forms (benchmarks.md)."""

import numpy as np
import pytest
from scipy.linalg import eigh

from cablecasing_core import modes, natural_frequencies
from cablecasing_core.structure.assembly import assemble_body

L = 1.0
D = 0.01  # m, solid circular section
A, I = np.pi * D**2 / 4, np.pi * D**4 / 64
J = 2 * I
E, RHO, NU = 2.1e11, 7850.0, 0.3  # steel, the material of conftest's beam_model
G = E / (2 * (1 + NU))
F_BEND = np.sqrt(E * I / (RHO * A)) / (2 * np.pi * L**2)


def dominant_family(shape):
    """'axial', 'lateral' or 'torsion' for a mode of a straight beam along x (by DOF share)."""
    u = shape.reshape(-1, 6)
    share = {"axial": np.sum(u[:, 0] ** 2), "lateral": np.sum(u[:, 1:3] ** 2), "torsion": np.sum(u[:, 3] ** 2)}
    return max(share, key=share.get)


def family_frequencies(model, family):
    f, shapes = modes(model, "cable")
    sel = [fi for fi, s in zip(f, shapes.T) if dominant_family(s) == family]
    return np.array(sel)


@pytest.mark.parametrize(
    "supports,betaL",
    [
        (("clamped", "free"), [1.875104, 4.694091, 7.854757, 10.995541, 14.137168]),
        (("clamped", "clamped"), [4.730041, 7.853205, 10.995608, 14.137165, 17.278760]),
    ],
)
def test_straight_bending_first_five_modes(supports, betaL, straight):
    assert straight().bodies["cable"].E == E and straight().bodies["cable"].rho == RHO
    f = family_frequencies(straight(L, 40, supports=supports), "lateral")
    # each bending frequency appears twice (two planes, equal I)
    np.testing.assert_allclose(f[0::2][:5], f[1::2][:5], rtol=1e-7)  # eigh accuracy ~ eps*lam_max/lam_1
    exact = np.array(betaL) ** 2 * F_BEND
    # the bound: 0.5% for the first five modes with 40 elements
    np.testing.assert_allclose(f[0::2][:5], exact, rtol=5e-3)
    assert np.all(f[0::2][:5] >= exact * (1 - 1e-7)), "consistent-mass Hermite elements converge from above"


def test_bending_converges_from_above(straight):
    exact = 4.694091**2 * F_BEND
    errs = [family_frequencies(straight(L, n), "lateral")[2] / exact - 1 for n in (5, 10, 20)]
    assert all(e > 0 for e in errs)
    # Hermite cubic: frequency error ~ h^4; halving h cuts it by ~16 (at least 8 allowed for pre-asymptotic)
    assert errs[0] / errs[1] > 8 and errs[1] / errs[2] > 8


@pytest.mark.parametrize(
    "family,c,supports",
    [
        ("axial", np.sqrt(E / RHO), ("clamped", "free")),
        ("axial", np.sqrt(E / RHO), ("clamped", "clamped")),
        ("torsion", np.sqrt(G / RHO), ("clamped", "free")),
        ("torsion", np.sqrt(G / RHO), ("clamped", "clamped")),
    ],
)
def test_rods(family, c, supports, straight):
    n = np.arange(1, 4)
    exact = (2 * n - 1) * c / (4 * L) if supports[1] == "free" else n * c / (2 * L)
    errs = []
    for ne in (20, 40):
        f = family_frequencies(straight(L, ne, supports=supports), family)[:3]
        errs.append(f / exact - 1)
    # linear consistent-mass rod: error ~ (k h)^2 / 24 from above, below 0.3% at 40 elements here
    assert np.all(errs[1] > 0) and np.all(errs[1] < 3e-3)
    np.testing.assert_allclose(errs[0] / errs[1], 4.0, rtol=0.05)  # second-order convergence


def _ring_system(R, n, arc_points, beam_model):
    """Free ring: a closed polyline with node n tied to node 0 (same DOFs)."""
    pts = arc_points(R, 2 * np.pi, n)
    model = beam_model(pts, n, d=D, supports=("free", "free"))
    sysm = assemble_body(model, "cable")
    K, M = sysm.K.toarray(), sysm.M.toarray()
    ndof = K.shape[0]
    Tm = np.zeros((ndof, ndof - 6))
    Tm[: ndof - 6, : ndof - 6] = np.eye(ndof - 6)
    Tm[ndof - 6 :, :6] = np.eye(6)
    return Tm.T @ K @ Tm, Tm.T @ M @ Tm


def test_free_ring_in_and_out_of_plane(arc_points, beam_model):
    R = 0.2
    Kr, Mr = _ring_system(R, 120, arc_points, beam_model)
    lam, phi = eigh(Kr, Mr)
    f = np.sqrt(np.clip(lam, 0, None)) / (2 * np.pi)
    u = phi.reshape(-1, 6, phi.shape[1])
    out_share = (np.sum(u[:, 2] ** 2, axis=0)) / np.sum(u[:, :3] ** 2, axis=(0, 1))
    elastic = f > 1.0
    f_in = np.sort(f[elastic & (out_share < 0.5)])
    f_out = np.sort(f[elastic & (out_share >= 0.5)])
    m = RHO * A
    w0 = np.sqrt(E * I / (m * R**4))
    k = np.arange(2, 5)
    exact_in = w0 * k * (k**2 - 1) / np.sqrt(k**2 + 1) / (2 * np.pi)
    # Out of plane: minimising bending + torsion energy over the twist amplitude (Love; Rao,
    # Mechanical Vibrations) gives omega^2 = w0^2 n^2 (n^2-1)^2 / (n^2 + EI/GJ). The reference sheet
    # (benchmarks.md) writes n^2 + 1 + EI/GJ; that extra 1 does not follow from the energies and the
    # FE model (whose static curved-cantilever deflection matches Castigliano) agrees with this form.
    exact_out = w0 * k * (k**2 - 1) / np.sqrt(k**2 + E * I / (G * J)) / (2 * np.pi)
    # modes come in pairs (cos/sin); 120 straight elements: chord and inextensibility errors ~0.5%
    np.testing.assert_allclose(f_in[0:6:2], exact_in, rtol=1e-2)
    np.testing.assert_allclose(f_out[0:6:2], exact_out, rtol=1e-2)


def test_arc_out_of_plane_simply_supported(arc_points, beam_model):
    """Arc with w = 0, twist = 0 and free bending rotation at both ends: ring formula with k = i pi / theta."""
    R, theta, n = 0.3, np.pi / 2, 80
    model = beam_model(arc_points(R, theta, n), n, d=D, supports=("free", "free"))
    sysm = assemble_body(model, "cable")
    K, M = sysm.K.toarray(), sysm.M.toarray()
    fixed = []
    for node in (0, n):
        fixed.append(6 * node + 2)  # w (global z = out of plane)
    # twist = rotation about the tangent: constrain via a penalty-free change of basis
    keep = np.setdiff1d(np.arange(K.shape[0]), fixed)
    T = np.eye(K.shape[0])[:, keep]
    C = []
    exact_t = (np.array([1.0, 0, 0]), np.array([np.cos(theta), np.sin(theta), 0]))  # arc tangents
    for node, t in zip((0, n), exact_t):
        row = np.zeros(K.shape[0])
        row[6 * node + 3 : 6 * node + 6] = t
        C.append(row[keep])
    # null space of the twist constraints
    from scipy.linalg import null_space

    Nn = null_space(np.array(C))
    T = T @ Nn
    lam, phi = eigh(T.T @ K @ T, T.T @ M @ T)
    full = T @ phi
    u = full.reshape(-1, 6, full.shape[1])
    out_share = np.sum(u[:, 2] ** 2, axis=0) / np.sum(u[:, :3] ** 2, axis=(0, 1))
    f = np.sqrt(np.clip(lam, 0, None)) / (2 * np.pi)
    f_out = np.sort(f[(out_share > 0.5) & (f > 1.0)])[:3]
    i = np.arange(1, 4)
    kk = i * np.pi / theta
    w0 = np.sqrt(E * I / (RHO * A * R**4))
    exact = w0 * kk * (kk**2 - 1) / np.sqrt(kk**2 + E * I / (G * J)) / (2 * np.pi)  # see the ring test
    np.testing.assert_allclose(f_out, exact, rtol=1e-2)  # 80 chords on a quarter circle: <1% geometric error


def _static_tip(model, force):
    sysm = assemble_body(model, "cable")
    Kff = sysm.K_blocks[0]
    f = np.zeros(sysm.ndof)
    tip = 6 * sysm.support_nodes["B"]
    f[tip : tip + 3] = force
    u = np.zeros(sysm.ndof)
    u[sysm.free] = np.linalg.solve(Kff, f[sysm.free])
    return u[tip : tip + 3]


def test_static_cantilever_tip_deflection(straight):
    P = 10.0
    u = _static_tip(straight(L, 10), [0, P, 0])
    np.testing.assert_allclose(u[1], P * L**3 / (3 * E * I), rtol=1e-10)  # Hermite is exact for end loads


def test_static_curved_cantilever_castigliano(arc_points, beam_model):
    """Quarter circle clamped at A, out-of-plane tip force P: delta = P R^3 [pi/(4EI) + (3pi/4 - 2)/(GJ)]."""
    R, P, n = 0.3, 5.0, 200
    u = _static_tip(beam_model(arc_points(R, np.pi / 2, n), n, d=D), [0, 0, P])
    exact = P * R**3 * (np.pi / (4 * E * I) + (3 * np.pi / 4 - 2) / (G * J))
    np.testing.assert_allclose(u[2], exact, rtol=1e-3)  # chord approximation error ~ (h/R)^2 = 6e-5


def test_frequency_dependent_modulus_shifts_sqrt(straight):
    base = straight(L, 20, supports=("clamped", "clamped"))
    f0 = natural_frequencies(base, "cable", 6)
    table = [[0.0, E], [2000.0, 2 * E]]
    ft = natural_frequencies(base.with_overrides({"cable.E": table}), "cable", 6)
    Ef = E * (1 + np.asarray(ft) / 2000.0)
    np.testing.assert_allclose(ft, f0 * np.sqrt(Ef / E), rtol=1e-9)
