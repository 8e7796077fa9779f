"""Isolators and clips in the frequency domain against closed forms: the rigid-body modes of a
stiff casing on two isolators (bounce sqrt(2k/M), rocking sqrt(6k/M)), the TRFAM through one
isolator (k + i omega c, or its complex stiffness table), a mass on an isolator, and a beam with a
mid-span clip (from pinned-pinned with a spring to clamped-pinned half spans as the clip stiffens)."""

import copy

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core import model_from_dict, natural_frequencies, trfam

STEEL = dict(E=2.1e11, nu=0.3, rho=7850.0, alpha=0.0, beta=0.0, loss_factor=0.0)


def casing_model(L, n, d, supports, isolators=None, clips=None, E=2.1e11, rho=7850.0):
    """A straight casing along x (solid-ish tube: d_outer = d, d_inner = d / 10), SI units."""
    casing = dict(STEEL, E=E, rho=rho, d_outer=d, d_inner=d / 10, supports=dict(zip("AB", supports)))
    if isolators:
        casing["isolator"] = isolators
    if clips:
        casing["clip"] = clips
    return model_from_dict(
        {"geometry": {"points": [[0, 0, 0], [L, 0, 0]], "n_elements": n, "curve": "polyline"}, "casing": casing}
    )


def test_rigid_casing_on_two_isolators_bounces_and_rocks_as_the_closed_form():
    L, d, rho = 0.5, 0.03, 7850.0
    k_ax, k_lat, k_t = 3.0e3, 1.0e3, 2.0  # N/m, N/m, N.m/rad (torsion only)
    iso = {"stiffness": [k_ax, k_lat, k_lat], "rotational_stiffness": [k_t, 0.0, 0.0]}
    # rigid-ish: E 100 times steel's puts the first free-free bending mode at ~5.5 kHz; 4 elements keep the
    # largest eigenvalue, and so the round-off of the smallest (~eps lambda_max / lambda), small
    m = casing_model(L, 4, d, ("isolator", "isolator"), {"A": iso, "B": iso}, rho=rho, E=2.1e13)
    A = np.pi / 4 * (d**2 - (d / 10) ** 2)
    M = rho * A * L  # kg
    Jx = rho * np.pi / 32 * (d**4 - (d / 10) ** 4) * L  # kg m2, polar mass moment about the axis
    two_pi = 2 * np.pi
    expected = sorted(
        [
            np.sqrt(2 * k_lat / M) / two_pi,  # bounce y, z
            np.sqrt(2 * k_lat / M) / two_pi,
            np.sqrt(6 * k_lat / M) / two_pi,  # rocking: 2 k (L/2)^2 / (M L^2 / 12)
            np.sqrt(6 * k_lat / M) / two_pi,
            np.sqrt(2 * k_ax / M) / two_pi,  # axial
            np.sqrt(2 * k_t / Jx) / two_pi,  # torsion
        ]
    )
    f = natural_frequencies(m, "casing", 7)
    # the rigid modes are at 4-18 Hz: the casing's bending shifts them by ~(10 Hz / 5.5 kHz)^2 ~ 3e-6, the
    # round-off of the eigensolver (eps lambda_max / lambda) is ~1e-6
    assert f[6] > 5000.0
    np.testing.assert_allclose(f[:6], expected, rtol=5e-6)


def test_trfam_through_one_isolator_is_its_dynamic_stiffness():
    """A short stiff, light casing clamped at B on an isolator at A: the force at B is the
    isolator's, (k + i omega c) u_A, to within the casing's compliance (|k~| / K_casing < 1e-4) and
    the inertia of its 0.4 g (|k~| / K_casing omega^2 m / k < 1e-5 at 300 Hz)."""
    k, c = 1.0e3, 2.0  # N/m, N.s/m laterally (z)
    iso = {"stiffness": [1e9, k, k], "damping": [0.0, c, c], "rotational_stiffness": 1e9}
    m = casing_model(0.2, 8, 0.05, ("isolator", "clamped"), {"A": iso}, rho=1.0)
    f = np.array([5.0, 20.0, 80.0, 300.0])
    w = 2 * np.pi * f
    H = trfam(m, "casing.A.z", "casing.B.z", f, damping="viscous")
    # the support at B holds the casing against the isolator's force: f_B = -(k + i w c) u_A, H = f_B / (-w^2 u_A)
    np.testing.assert_allclose(H, (k + 1j * w * c) / w**2, rtol=2e-4)
    # with a complex stiffness table: k k_scale(f) (1 + i eta(f)), interpolated linearly (the table stands for
    # stiffness and damping in the frequency domain; c is the time domain's)
    table = [[0.0, 1.0, 0.1], [100.0, 2.0, 0.3], [1000.0, 3.0, 0.3]]
    m2 = casing_model(0.2, 8, 0.05, ("isolator", "clamped"), {"A": dict(iso, table=table)}, rho=1.0)
    scale = np.interp(f, [0, 100, 1000], [1, 2, 3])
    eta = np.interp(f, [0, 100, 1000], [0.1, 0.3, 0.3])
    H2 = trfam(m2, "casing.A.z", "casing.B.z", f, damping="structural")
    np.testing.assert_allclose(H2, k * scale * (1 + 1j * eta) / w**2, rtol=2e-4)
    # undamped: the table's scale only
    H0 = trfam(m2, "casing.A.z", "casing.B.z", f, damping="none")
    np.testing.assert_allclose(H0, k * scale / w**2, rtol=2e-4)


def test_mass_on_an_isolator_driving_point_apparent_mass():
    """A stiff free casing on one axial isolator: a mass M on a spring k~ = k + i w c, whose base's
    driving-point apparent mass is k~ M / (k~ - w^2 M). The casing (E 100 times steel's) yields
    axially by k / (EA / L) ~ 6e-7, magnified near the 32 Hz resonance by its Q (~33): < 1e-4."""
    k, c = 2.0e4, 3.0
    iso = {"stiffness": [k, 1e9, 1e9], "damping": [c, 0.0, 0.0], "rotational_stiffness": 1e9}
    L, d, rho = 0.2, 0.02, 7850.0
    m = casing_model(L, 8, d, ("isolator", "free"), {"A": iso}, rho=rho, E=2.1e13)
    M = rho * np.pi / 4 * (d**2 - (d / 10) ** 2) * L
    f = np.linspace(5.0, 200.0, 40)
    w = 2 * np.pi * f
    kt = k + 1j * w * c
    H = trfam(m, "casing.A.x", "casing.A.x", f)
    np.testing.assert_allclose(H, kt * M / (kt - w**2 * M), rtol=1e-4)


def test_a_very_stiff_isolator_is_a_clamp():
    iso = {"stiffness": 1e13, "rotational_stiffness": 1e11}
    clamped = casing_model(0.6, 24, 0.01, ("clamped", "clamped"))
    isolated = casing_model(0.6, 24, 0.01, ("isolator", "clamped"), {"A": iso})
    # (a 1e13 N/m isolator yields by the tube's EA/L = 2.7e7 N/m over it, 3e-6, and less across: the
    # frequencies move by half that)
    np.testing.assert_allclose(
        natural_frequencies(isolated, "casing", 6), natural_frequencies(clamped, "casing", 6), rtol=1e-5
    )
    f = np.array([30.0, 300.0, 900.0])
    for port in ("casing.A.y", "casing.A.x"):
        a = trfam(clamped, port, port.replace("A", "B"), f)
        b = trfam(isolated, port, port.replace("A", "B"), f)
        # (as the frequencies: the tube's EA/L = 2.7e7 N/m is 3e-6 of the isolator's 1e13 N/m)
        np.testing.assert_allclose(b, a, rtol=1e-5)


@pytest.mark.parametrize("table", [False, True])
@pytest.mark.parametrize("k, k_rot", [(1e14, 1e12), (1e8, 1e12)])
def test_isolators_as_stiff_as_the_schema_allows_are_clamps_on_the_built_in_casing(k, k_rot, table):
    """The built-in casing (its thin section: the end node's torsional rotary inertia is small) on two
    isolators of the largest rotational stiffness the schema allows: its first six frequencies are
    the clamped casing's. A dense solve of (K, M) gets each eigenvalue to ~eps lambda_max, here
    k_rot over that inertia ~1e20 rad^2/s^2, and took the first modes 27 % off; the inverted pencil
    gets them to ~eps lambda_i / (2 pi 1 Hz)^2. The rest is the translational springs' compliance
    (1e8 N/m against the casing's end stiffness: ~2e-5), so 1e-4 and 1e-8. With a frequency table
    (a scale of 1 to 1.001 over 0-1000 Hz: the iteration of each mode's own frequency) as without."""
    clamped = cc.load_model()
    d = copy.deepcopy(clamped.data)
    d["casing"]["supports"] = {"A": "isolator", "B": "isolator"}
    d["casing"]["isolator"] = {s: {"stiffness": k, "rotational_stiffness": k_rot} for s in "AB"}
    if table:
        for iso in d["casing"]["isolator"].values():
            iso["table"] = [[0.0, 1.0, 0.0], [1000.0, 1.001, 0.0]]
    f, ref = (natural_frequencies(m, "casing", 6) for m in (cc.model_from_dict(d), clamped))
    np.testing.assert_allclose(f, ref, rtol=1e-4 if k < 1e10 else 1e-8)


def _spring_supported_beam_frequencies(L, EI, mass_per_length, k, count):
    """Bending frequencies (Hz) of a pinned-pinned beam with a lateral spring k (N/m) at mid-span,
    by the transfer-matrix closed form: symmetric modes solve the half span (pinned at 0, at mid-span
    zero slope and shear V = k w / 2); antisymmetric modes are the pinned-pinned ones of the half
    span, which the spring does not see (w = 0 at mid-span)."""
    from scipy.optimize import brentq

    a = L / 2
    beta4 = lambda f: (2 * np.pi * f) ** 2 * mass_per_length / EI  # noqa: E731

    def sym(f):
        b = beta4(f) ** 0.25
        # w = A sin(bx) + B sinh(bx) (pinned at x = 0); w'(a) = 0 and, the spring's force k w(a) shared by
        # the two halves, EI w'''(a) = k w(a) / 2 (shear V = -EI w''' jumps by k w at the spring)
        M = np.array(
            [
                [b * np.cos(b * a), b * np.cosh(b * a)],
                [
                    -EI * b**3 * np.cos(b * a) - 0.5 * k * np.sin(b * a),
                    EI * b**3 * np.cosh(b * a) - 0.5 * k * np.sinh(b * a),
                ],
            ]
        )
        return np.linalg.det(M) / np.cosh(b * a) ** 2

    grid = np.linspace(1.0, 1000.0, 4000)
    vals = np.array([sym(x) for x in grid])
    roots = [brentq(sym, grid[i], grid[i + 1]) for i in np.nonzero(np.sign(vals[:-1]) != np.sign(vals[1:]))[0]]
    anti = [(j * np.pi / a) ** 2 * np.sqrt(EI / mass_per_length) / (2 * np.pi) for j in range(1, 10)]
    return np.sort(np.concatenate([roots, anti]))[:count]


@pytest.mark.parametrize("k", [1.0e3, 3.0e4, 1.0e6])
def test_mid_span_clip_on_a_pinned_beam_matches_the_closed_form(k):
    """A clip (lateral spring k in both lateral axes) at mid-span of a pinned-pinned beam; pins are
    made by isolators that hold translations only (stiff, no rotational stiffness)."""
    L, d, n = 1.0, 0.01, 80
    pin = {"stiffness": [1e12, 1e12, 1e12]}
    clip = {"at": 0.5, "stiffness": [0.0, k, k]}
    m = casing_model(L, n, d, ("isolator", "isolator"), {"A": pin, "B": pin}, clips=[clip])
    do, di = d, d / 10
    EI = 2.1e11 * np.pi / 64 * (do**4 - di**4)
    mpl = 7850.0 * np.pi / 4 * (do**2 - di**2)
    expected = _spring_supported_beam_frequencies(L, EI, mpl, k, 4)
    f = natural_frequencies(m, "casing", 30)
    # each bending frequency appears twice (y and z); the pins leave the torsion free (0 Hz); 80 elements
    # converge the 4th bending frequency to ~1e-5
    f = f[f > 1.0]
    bending = np.sort(f[f < expected[-1] * 1.05])[::2][:4]
    np.testing.assert_allclose(bending, expected, rtol=2e-4)


def test_stiffening_clip_tends_to_a_clamped_mid_span_pinned_beam():
    """As the clip's lateral and rotational stiffness grow, the clamped-clamped beam with a clip at
    mid-span becomes two clamped-clamped half spans; with only the lateral stiffness it becomes two
    clamped-pinned half spans, first frequency (3.9266 / a)^2 sqrt(EI / m) / 2 pi (a = L / 2)."""
    L, d, n = 1.0, 0.01, 80
    do, di = d, d / 10
    EI = 2.1e11 * np.pi / 64 * (do**4 - di**4)
    mpl = 7850.0 * np.pi / 4 * (do**2 - di**2)
    a = L / 2
    f_cp = (3.926602 / a) ** 2 * np.sqrt(EI / mpl) / (2 * np.pi)
    f_cc_half = (4.730041 / a) ** 2 * np.sqrt(EI / mpl) / (2 * np.pi)
    first = []
    for k in (1e2, 1e4, 1e6, 1e9):
        m = casing_model(L, n, d, ("clamped", "clamped"), clips=[{"at": 0.5, "stiffness": [0.0, k, k]}])
        first.append(natural_frequencies(m, "casing", 1)[0])
    # stiffer clip, higher first (symmetric) frequency, up to the antisymmetric mode's, which the clip does not
    # see (w = 0 at mid-span) and which is the clamped-pinned half span's
    assert np.all(np.diff(first) > -1e-9 * f_cp) and first[0] < 0.5 * f_cp
    # a 1e9 N/m clip: the half span's lateral stiffness is ~1e5 N/m, so the clip yields by ~1e-4
    assert first[-1] == pytest.approx(f_cp, rel=1e-3)
    m = casing_model(
        L, n, d, ("clamped", "clamped"), clips=[{"at": 0.5, "stiffness": 1e10, "rotational_stiffness": 1e8}]
    )
    # (the clip yields by ~2e-5 of the half span's 192 EI / a^3 and ~1e-5 of its 4 EI / a: 1e-3 as above)
    assert natural_frequencies(m, "casing", 1)[0] == pytest.approx(f_cc_half, rel=1e-3)
