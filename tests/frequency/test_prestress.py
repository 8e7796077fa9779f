"""Axial prestress in the frequency domain (issue 23): the beam-column geometric stiffness against
closed forms (string limit, pinned-pinned exact, the clamped-clamped frequency equation, Euler's
buckling load) and TRFAM of a prestressed body against an independent dense solve."""

import numpy as np
import pytest
from scipy.linalg import eigh
from scipy.optimize import brentq

import cablecasing_core as cc
from cablecasing_core.structure.assembly import assemble_body
from cablecasing_core.structure.buckling import buckling_load

STEEL = dict(E=2.1e11, rho=7850.0)


def tensioned(straight, T, L=1.0, n=40, d=0.01, supports=("clamped", "clamped")):
    return straight(L=L, n=n, d=d, supports=supports).with_overrides({"loads.cable_tension": T})


def bending_pairs(f):
    """The lateral frequencies of a straight circular beam come in equal pairs (two planes); the
    first of each pair (Hz)."""
    f = np.sort(f)
    keep = [f[0]]
    for x in f[1:]:
        if not np.isclose(x, keep[-1], rtol=1e-6):
            keep.append(x)
    return np.array(keep)


def test_string_limit_and_its_clamped_correction(straight):
    """A thin clamped wire under a large tension tends to the string, f_n -> n / (2 L) sqrt(T / m),
    with the clamped ends' first-order correction (1 + 2 / (k L)), k = sqrt(T / EI). At k L = 280
    with 160 elements (which resolve the clamps' boundary layers, 1 / k = 3.6 mm long, to 4e-5;
    checked against the exact frequency equation): within 5e-4 of the corrected string for n <= 2,
    the size of the neglected (4 + n^2 pi^2 / 2) / (k L)^2 <= 3.3e-4. And the excess over the string
    falls like 1 / (k L): ten times the tension, sqrt(10) = 3.16 times less (within 10 %)."""
    L, d = 1.0, 0.0005
    m = STEEL["rho"] * np.pi * d**2 / 4
    EI = STEEL["E"] * np.pi * d**4 / 64
    excess = []
    for T, check in ((50.0, True), (5.0, False)):
        kL = L * np.sqrt(T / EI)
        f = bending_pairs(cc.natural_frequencies(tensioned(straight, T, L, 160, d), "cable", 6))
        string = np.arange(1, 4) / (2 * L) * np.sqrt(T / m)
        if check:
            np.testing.assert_allclose(f[:2] / string[:2], 1 + 2 / kL, atol=5e-4)
            exact = [clamped_clamped_exact(EI, m, T, L, fi) for fi in f[:3]]
            np.testing.assert_allclose(f[:3], exact, rtol=1e-4)
        excess.append(f[0] / string[0] - 1)
    assert excess[1] / excess[0] == pytest.approx(np.sqrt(10.0), rel=0.1)


@pytest.mark.parametrize("T", [0.0, 1e3, 1e4])
def test_pinned_pinned_tensioned_beam_is_exact(straight, T):
    """omega_n = (n pi / L)^2 sqrt(EI / m) sqrt(1 + T L^2 / (n^2 pi^2 EI)) (benchmarks.md) for the
    assembled K_E + K_G and M with the ends pinned in one bending plane (v = 0 at both ends,
    rotations free; the model's supports are clamped or free, so the DOFs are chosen here).
    Tolerance 2e-5: 40 cubic elements converge as h^4, ~7e-6 for mode 4."""
    L, n, d = 1.0, 40, 0.01
    s = assemble_body(tensioned(straight, T, L, n, d), "cable")
    K, M = s.K.toarray(), s.M.toarray()
    keep = [6 * j + 1 for j in range(1, n)] + [6 * j + 5 for j in range(n + 1)]
    w = np.sqrt(eigh(K[np.ix_(keep, keep)], M[np.ix_(keep, keep)], eigvals_only=True)[:4])
    EI, m = STEEL["E"] * np.pi * d**4 / 64, STEEL["rho"] * np.pi * d**2 / 4
    k = np.arange(1, 5)
    exact = (k * np.pi / L) ** 2 * np.sqrt(EI / m) * np.sqrt(1 + T * L**2 / (k**2 * np.pi**2 * EI))
    np.testing.assert_allclose(w, exact, rtol=2e-5)


def clamped_clamped_exact(EI, m, T, L, f_guess):
    """Root near f_guess (Hz) of the clamped-clamped frequency equation of a beam under tension T:
    2 s1 s2 (1 - cosh(s1 L) cos(s2 L)) + (s1^2 - s2^2) sinh(s1 L) sin(s2 L) = 0, s1^2, s2^2 =
    sqrt(a^2 + m w^2 / EI) +- a, a = T / (2 EI) (from EI w'''' - T w'' - m w^2 w = 0). Scaled by
    cosh(s1 L) so that it stays of order one."""

    def F(f):
        w = 2 * np.pi * f
        a = T / (2 * EI)
        r = np.sqrt(a * a + m * w * w / EI)
        s1, s2 = np.sqrt(r + a), np.sqrt(r - a)
        ch = np.cosh(s1 * L)
        return (2 * s1 * s2 * (1 / ch - np.cos(s2 * L)) + (s1**2 - s2**2) * np.tanh(s1 * L) * np.sin(s2 * L)) / (
            s1 * s2
        )

    return brentq(F, 0.97 * f_guess, 1.03 * f_guess, xtol=1e-12)


def test_clamped_clamped_tensioned_beam_against_its_frequency_equation(straight):
    """A clamped-clamped beam with k L = 5 (bending and tension alike): the first four lateral
    frequencies against the roots of the exact frequency equation. Tolerance 2e-5 (h^4 error)."""
    L, n, d = 1.0, 40, 0.01
    EI, m = STEEL["E"] * np.pi * d**4 / 64, STEEL["rho"] * np.pi * d**2 / 4
    T = 25.0 * EI / L**2
    f = bending_pairs(cc.natural_frequencies(tensioned(straight, T, L, n, d), "cable", 10))[:4]
    exact = np.array([clamped_clamped_exact(EI, m, T, L, fi) for fi in f])
    np.testing.assert_allclose(f, exact, rtol=2e-5)
    f0 = bending_pairs(cc.natural_frequencies(straight(L=L, n=n, d=d, supports=("clamped", "clamped")), "cable", 10))
    assert np.all(f > f0[:4])  # tension stiffens


def straight_pair(T, L=1.0, n=40):
    """Casing and cable along a straight line, both clamped; the casing carries the compression T."""
    return cc.model_from_dict(
        {
            "geometry": {"points": [[0.0, 0, 0], [L, 0, 0]], "n_elements": n, "curve": "polyline"},
            "casing": dict(E=5e9, rho=4850.0, d_outer=0.0095, d_inner=0.004, I=2.7261e-10),
            "cable": dict(E=5.5e10, rho=7850.0, d=0.003),
            "loads": {"cable_tension": T},
        }
    )


def test_a_compressed_clamped_casing_softens_to_zero_at_euler_s_load():
    """The casing's buckling load is 4 pi^2 EI / L^2 (clamped-clamped; to 1e-5, the h^4 error of 40
    elements), its first frequency falls towards zero as the compression approaches it, close to
    sqrt(1 - P / P_cr) (exact for pinned ends, approximate for clamped ones: within 2 %), and a
    compression at the load is refused."""
    EI = 5e9 * 2.7261e-10
    P_cr = 4 * np.pi**2 * EI
    assert buckling_load(assemble_body(straight_pair(1.0), "casing")) == pytest.approx(P_cr, rel=1e-5)
    f0 = cc.natural_frequencies(straight_pair(0.0), "casing", 1)[0]
    ratios = []
    for r in (0.5, 0.9, 0.99, 0.999):
        f = cc.natural_frequencies(straight_pair(r * P_cr), "casing", 1)[0]
        ratios.append(f / f0)
        assert f / f0 == pytest.approx(np.sqrt(1 - r), rel=0.02)
    assert np.all(np.diff(ratios) < 0) and ratios[-1] < 0.035
    with pytest.raises(cc.ModelError) as err:
        cc.natural_frequencies(straight_pair(1.001 * P_cr), "casing", 1)
    assert err.value.key == "loads.cable_tension"


def dense_trfam(model, body, i_in, i_out, f, damping):
    """TRFAM (kg) by a dense solve of the partitioned Eq. (13) with D = kappa_E K_E + kappa_G K_G -
    mu M (written here from the definitions, independently of FrequencyResponse)."""
    s = assemble_body(model, body)
    KE, KG, M = (A.toarray() for A in (s.K_E, s.K_G, s.M))
    fr, p = s.free, s.prescribed
    spec = s.spec
    out = []
    for fk in f:
        w = 2 * np.pi * fk
        if damping == "structural":
            D = (1 + 1j * spec.loss_factor) * KE + KG - w * w * M
        else:  # viscous: C = alpha M + beta (K_E + K_G)
            D = (1 + 1j * w * spec.beta) * (KE + KG) - (w * w - 1j * w * spec.alpha) * M
        e = np.zeros(len(p))
        e[i_in] = 1.0
        x = -np.linalg.solve(D[np.ix_(fr, fr)], D[np.ix_(fr, p)] @ e)
        F = D[np.ix_(p, fr)] @ x + D[np.ix_(p, p)] @ e
        out.append(F[i_out] / (-w * w))
    return np.array(out)


@pytest.mark.parametrize("damping", ["structural", "viscous"])
def test_trfam_of_a_prestressed_casing_against_a_dense_solve(damping):
    """The installed specimen's casing (compressed by 10 N): TRFAM casing.A.z -> casing.B.z by the
    banded per-frequency solve against a dense solve of the same equations (rounding only)."""
    model = cc.load_model("installed")
    f = np.linspace(10.0, 400.0, 40)
    H = cc.trfam(model, "casing.A.z", "casing.B.z", f, damping=damping)
    s = assemble_body(model, "casing")
    ref = dense_trfam(model, "casing", s.prescribed_index("A", 2), s.prescribed_index("B", 2), f, damping)
    np.testing.assert_allclose(H, ref, rtol=1e-8, atol=1e-12 * np.abs(ref).max())


def test_the_direct_solve_tends_to_the_modal_sum_as_the_prestress_vanishes():
    """A prestress of 1e-9 N takes the direct path; it must give the unprestressed modal sum to
    within the relative size of K_G (1e-9 N against EI / L^2 ~ 2 N: below 1e-8)."""
    f = np.linspace(5.0, 600.0, 60)
    for damping in ("structural", "viscous", "none"):
        H0 = cc.trfam_matrix(cc.load_model(), "casing", "A", "B", f, damping=damping)
        tiny = cc.load_model().with_overrides({"loads.cable_tension": 1e-9})
        H1 = cc.trfam_matrix(tiny, "casing", "A", "B", f, damping=damping)
        np.testing.assert_allclose(H1, H0, rtol=1e-7, atol=1e-9 * np.abs(H0).max())


def test_frequency_dependent_modulus_with_prestress_is_self_consistent():
    """With E(f) each frequency of a prestressed body is the eigenfrequency of (E(f_i) / E_ref K_E +
    K_G, M) at its own f_i (to the iteration's 1e-12)."""
    table = [[0.0, 4e9], [100.0, 5e9], [1000.0, 8e9]]
    model = cc.load_model("installed").with_overrides({"casing.E": table})
    f = cc.natural_frequencies(model, "casing", 6)
    s = assemble_body(model, "casing")
    KE, KG, M = (s.blocks(A)[0] for A in (s.K_E, s.K_G, s.M))
    for i, fi in enumerate(f):
        sc = float(s.spec.modulus(fi)) / s.E
        lam = eigh(sc * KE + KG, M, eigvals_only=True)[i]
        assert np.sqrt(lam) / (2 * np.pi) == pytest.approx(fi, rel=1e-9)
