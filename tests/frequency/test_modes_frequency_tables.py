"""Natural frequencies with a frequency-dependent stiffness and mounts: a modulus table E(f) on a
body in isolators and clips (with and without a prestress), and isolators whose stiffness is a
table k_scale(f). Mode i solves f_i = the i-th frequency of (E(f_i) / E_ref K_E + K_G + the mounts'
k_scale(f_i) K6, M): checked against that fixed point iterated here from the assembled matrices,
and against the undamped TRFAM, whose resonances apply E(f) and k_scale(f) at each frequency."""

import copy

import numpy as np
import pytest
from scipy.linalg import eigh
from scipy.optimize import brentq

import cablecasing_core as cc
import cablecasing_core.frequency.modal as modal
from cablecasing_core.model.load import model_from_dict
from cablecasing_core.structure.assembly import assemble_body
from cablecasing_core.timedomain.body_storage import time_domain_system

# Both sides solve the same fixed point (to 1e-14 here, 1e-10 in modal.py, where the secant's last step
# leaves far less); they differ by the round-off of the dense eigensolvers, |d lambda_i| ~ eps lambda_max,
# i.e. d f_i / f_i ~ eps lambda_max / (2 lambda_i) ~ 1e-9 for the first modes of these 64-element casings.
RTOL = 1e-8


def installation(E=None, isolator_tables=True, tension=None):
    """examples/installation.toml (casing in two isolators and two clips), with the casing's modulus
    ``E`` (a table), without the isolators' k_scale tables unless ``isolator_tables``, and with the
    cable tension ``tension`` (N) and gravity when given."""
    d = copy.deepcopy(cc.load_model("examples/installation.toml").data)
    if not isolator_tables:
        for iso in d["casing"]["isolator"].values():
            iso.pop("table")
    if E is not None:
        d["casing"]["E"] = E
    if tension is not None:
        d["loads"] = {"cable_tension": tension, "gravity": [0.0, 0.0, -9.81]}
    return model_from_dict(d)


def fixed_point(model, body, count):
    """The first ``count`` frequencies (Hz), each the fixed point f = F_i(f), F_i(f) the i-th frequency
    of (E(f) / E_ref K_E + K_G + sum_m k_scale_m(f) K6_m, M) on the free DOFs from the assembled
    matrices (independent of modal.py's solve). The tables here rise with f, so F_i rises and the
    fixed point lies in [F_i(0), F_i(1e4 Hz)], where F_i(f) - f changes sign: Brent's method there to
    1e-14 of f (a plain iteration f <- F_i(f) took up to 100 dense solves a mode, and its step was no
    bound on its error)."""
    s = assemble_body(model, body)
    KE, KG, M = s.augmented(s.K_E), s.augmented(s.K_G), s.augmented(s.M)
    ff = np.ix_(s.free, s.free)
    zero = np.zeros((s.ndof, s.ndof))

    def K(f):
        k6 = [mt.K6 * (1.0 if mt.table is None else np.interp(f, mt.table[:, 0], mt.table[:, 1])) for mt in s.mounts]
        return (s.spec.modulus(f) / s.E * KE + KG + s.augmented(zero, k6))[ff]

    def F(f, i):
        return np.sqrt(eigh(K(f), M[ff], eigvals_only=True, subset_by_index=[i, i])[0]) / (2 * np.pi)

    out = []
    for i in range(count):
        lo, hi = F(0.0, i), F(1e4, i)
        out.append(lo if hi == lo else brentq(lambda f, i=i: F(f, i) - f, lo, hi, xtol=1e-12, rtol=1e-14))
    return np.array(out)


def undamped_peak(model, f_center, rel=1e-3, n=801):
    """The frequency (Hz) of the largest |TRFAM| from casing end A to end B (x, y and z summed),
    undamped, on a grid of n lines over f_center (1 +- rel); and the grid's step."""
    fz = np.linspace((1 - rel) * f_center, (1 + rel) * f_center, n)
    H = sum(np.abs(cc.trfam(model, f"casing.A.{d}", f"casing.B.{d}", fz, damping="none")) for d in "xyz")
    return fz[np.argmax(H)], fz[1] - fz[0]


TABLES = [[[10.0, 2e9], [1000.0, 1e10]], [[1.0, 1e9], [200.0, 1e10]]]  # Pa: 5x and 10x over the modes


@pytest.mark.parametrize("E", TABLES)
def test_modulus_table_with_mounts_solves_each_mode_at_its_own_modulus(E):
    """The mounts' springs do not scale with E: f_ref sqrt(E(f) / E_ref) (what natural_frequencies
    returned) was 0.5-2.5 % (first table) and 7-32 % (second) too high."""
    m = installation(E, isolator_tables=False)
    f = cc.natural_frequencies(m, "casing", 6)
    ref = fixed_point(m, "casing", 6)
    np.testing.assert_allclose(f, ref, rtol=RTOL)
    f_ref = cc.natural_frequencies(m.with_overrides({"casing.E": E[0][1]}), "casing", 6)
    scaled = np.array([f_ref[i] * np.sqrt(np.interp(f[i], *np.transpose(E)) / E[0][1]) for i in range(6)])
    assert np.all(scaled / f - 1 > 4e-3)  # (the old answer, at the mode's own modulus, is far off)


def test_undamped_trfam_resonates_at_the_natural_frequencies():
    """The undamped TRFAM (E(f) and the isolators' k_scale(f) at each line) peaks at the first
    frequency, with a modulus table and with isolator tables: within one line of a 2e-6 grid."""
    for m in (installation(TABLES[0], isolator_tables=False), installation()):
        f1 = cc.natural_frequencies(m, "casing", 1)[0]
        peak, step = undamped_peak(m, f1)
        assert abs(peak - f1) <= step


def test_isolator_tables_set_the_frequencies_at_their_own_stiffness():
    """examples/installation.toml: constant E, isolators stiffer with frequency (k_scale 1 at 0 Hz,
    1.15 at 100 Hz): each mode at the isolators' stiffness at its frequency, above the static
    stiffness's frequencies."""
    m = installation()
    f = cc.natural_frequencies(m, "casing", 6)
    np.testing.assert_allclose(f, fixed_point(m, "casing", 6), rtol=RTOL)
    static = cc.natural_frequencies(installation(isolator_tables=False), "casing", 6)
    assert np.all(f > static * (1 + 1e-3))


@pytest.mark.parametrize("isolator_tables", [False, True])
def test_prestressed_body_in_mounts_with_a_modulus_table_keeps_its_mounts(isolator_tables):
    """A 5 N tension with gravity and a mild E(f): the mounts' springs stay in K(f) (they dropped out,
    and every frequency was 0 Hz). Without isolator tables the fixed point is at 26.54 / 33.44 /
    36.92 / 76.88 Hz (constant E: 26.53 Hz), as measured."""
    m = installation([[10.0, 5e9], [1000.0, 5.5e9]], isolator_tables=isolator_tables, tension=5.0)
    f = cc.natural_frequencies(m, "casing", 6)
    assert np.all(f > 20.0)
    np.testing.assert_allclose(f, fixed_point(m, "casing", 6), rtol=RTOL)


@pytest.mark.parametrize("name", ["default", "installed", "examples/clipped_specimen.toml"])
def test_constant_stiffness_is_the_reference_eigenproblem_bit_for_bit(name):
    """A constant modulus and mounts without tables: no iteration, the reference eigenproblem's own
    frequencies (the same bits as before the frequency tables were followed)."""
    m = cc.load_model(None if name == "default" else name)
    for body in m.bodies:
        expected = modal.modal_basis(assemble_body(m, body)).frequencies_hz
        assert np.array_equal(cc.natural_frequencies(m, body), expected)


def test_time_domain_takes_the_modulus_at_the_first_natural_frequency():
    """The time domain assembles the body with E(f1): f1 the fixed point's, not the scaled one."""
    m = installation(TABLES[0], isolator_tables=False)
    f1 = fixed_point(m, "casing", 1)[0]
    s = time_domain_system(m, "casing")
    assert s.E == pytest.approx(float(m.bodies["casing"].modulus(f1)), rel=1e-10)


def test_a_frequency_that_does_not_converge_names_the_table(monkeypatch):
    monkeypatch.setattr(modal, "MAX_SECANT", 0)
    monkeypatch.setattr(modal, "MAX_BRENT", 1)
    with pytest.raises(cc.ModelError, match=r"casing\.E.*mode 1 of the casing.*casing\.isolator\.A\.table"):
        cc.natural_frequencies(installation(TABLES[0]), "casing", 1)
