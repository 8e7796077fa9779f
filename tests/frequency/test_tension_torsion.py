"""Torsion of a straight clamped-clamped shaft under axial tension P: the twist equation
(G J + P Ip / A) phi'' = rho Ip phi_tt (the Wagner term P Ip / A of the geometric stiffness,
element_beam.geometric_stiffness) has f_n = n / (2 L) sqrt((G J + P Ip / A) / (rho Ip)).

The elements' torsion is linear with a consistent mass: on N equal elements the fixed-fixed chain's
modes are exactly sin(n pi j / N), with omega_n^2 = 6 k / (m h^2) (1 - cos t) / (2 + cos t),
t = n pi / N, h = L / N, k = G J + P Ip / A, m = rho Ip (the discrete closed form), which tends to
the continuum from above as 1 + t^2 / 24."""

import numpy as np
import pytest

import cablecasing_core as cc

E, NU, RHO = 2.1e11, 0.3, 7850.0  # steel (Pa, -, kg/m3)
G = E / (2 * (1 + NU))
L, D = 1.0, 0.01  # m
A, IP = np.pi * D**2 / 4, np.pi * D**4 / 32  # m2, m4 (geometric polar moment: the rotary inertia)
N_MODES = 4


def shaft(beam_model, P, n=40, I=None):
    """The straight steel cable clamped at both ends, n elements, tension P (N); ``I`` (m4) an
    effective second moment (then J = 2 I, sections.py; the rotary inertia keeps the geometric Ip)."""
    material = {} if I is None else {"I": I}
    m = beam_model([[0, 0, 0], [L, 0, 0]], n, d=D, supports=("clamped", "clamped"), **material)
    return m.with_overrides({"loads.cable_tension": P})


def torsion_frequencies(model):
    """The first N_MODES torsional frequencies (Hz) from cc.modes: the modes whose kinetic shape is
    all twist (a straight circular shaft's twist decouples from bending and stretching)."""
    f, shapes = cc.modes(model, "cable")
    u = shapes.reshape(-1, 6, shapes.shape[1])
    share = np.sum(u[:, 3] ** 2, axis=0) / np.sum(u**2, axis=(0, 1))
    tors = f[share > 1 - 1e-9]
    assert len(tors) >= N_MODES
    return tors[:N_MODES]


def continuum(P, J):
    n = np.arange(1, N_MODES + 1)
    return n / (2 * L) * np.sqrt((G * J + P * IP / A) / (RHO * IP))


def discrete(P, J, N):
    t = np.arange(1, N_MODES + 1) * np.pi / N
    h = L / N
    k, m = G * J + P * IP / A, RHO * IP
    return np.sqrt(6 * k / (m * h * h) * (1 - np.cos(t)) / (2 + np.cos(t))) / (2 * np.pi)


# (effective I, P): the solid steel section (J = Ip; P Ip / A = 1.6e-3 G J at 1e4 N, a stress of
# 127 MPa) and a wire rope's soft effective I (J = 2e-12 m4: the Wagner term is 7.7 % of G J at 1 kN)
CASES = [(None, 1.0e4), (1.0e-12, 1.0e3)]


@pytest.mark.parametrize("I, P", CASES)
def test_tension_stiffens_torsion_by_the_wagner_term(beam_model, I, P):
    """f(P) / f(0) = sqrt(1 + P Ip / (A G J)) for every mode, on any mesh (the torsion stiffness is
    G J / L + P Ip / (A L) times the same bar matrix, so the ratio is exact up to rounding: 1e-10)."""
    J = IP if I is None else 2 * I
    f0 = torsion_frequencies(shaft(beam_model, 0.0, I=I))
    fP = torsion_frequencies(shaft(beam_model, P, I=I))
    np.testing.assert_allclose(fP / f0, np.sqrt(1 + P * IP / (A * G * J)), rtol=1e-10)


@pytest.mark.parametrize("I, P", CASES + [(None, 0.0)])
def test_torsional_frequencies_against_the_closed_form(beam_model, I, P):
    """Each mesh against the chain's discrete closed form (rounding only: 1e-10), and the continuum
    f_n = n / (2 L) sqrt((G J + P Ip / A) / (rho Ip)) approached from above at second order: the
    relative excess is t^2 / 24 (t = n pi / N) to within its next term (< 1 % of itself for t <= 0.32,
    measured 0.12 %), and halving h divides it by 4 (to 1 %). At P = 0 this is the rod's
    f_n = n / (2 L) sqrt(G / rho) (benchmarks.md, torsion fixed-fixed)."""
    J = IP if I is None else 2 * I
    exact = continuum(P, J)
    if P == 0.0 and I is None:
        np.testing.assert_allclose(exact, np.arange(1, N_MODES + 1) / (2 * L) * np.sqrt(G / RHO), rtol=1e-14)
    excess = []
    for N in (40, 80):
        f = torsion_frequencies(shaft(beam_model, P, n=N, I=I))
        np.testing.assert_allclose(f, discrete(P, J, N), rtol=1e-10)
        t = np.arange(1, N_MODES + 1) * np.pi / N
        np.testing.assert_allclose(f / exact - 1, t**2 / 24, rtol=0.01)
        excess.append(f / exact - 1)
    np.testing.assert_allclose(excess[0] / excess[1], 4.0, rtol=0.01)
