"""TRFAM (Eq. 12) against the exact solution of Eq. (1), reciprocity, peaks, damping models."""

import numpy as np
import pytest
from scipy.signal import find_peaks

from cablecasing_core import load_model, natural_frequencies, trfam, trfam_matrix

L, D = 1.0, 0.01  # m, solid circular section
A, I = np.pi * D**2 / 4, np.pi * D**4 / 64
E, RHO = 2.1e11, 7850.0  # steel, the material of conftest's beam_model
ETA = 0.02


def exact_transfer(f_hz, eta=ETA):
    """Clamped-clamped Euler-Bernoulli beam, complex modulus E(1+i eta): force on the beam at B
    (lateral) per unit acceleration of support A (kg), from the closed-form solution of Eq. (1)."""
    out = []
    EI = E * (1 + 1j * eta) * I
    for f in f_hz:
        w = 2 * np.pi * f
        b = (w**2 * RHO * A / EI) ** 0.25

        def rows(x, b=b):
            c, s, ch, sh = np.cos(b * x), np.sin(b * x), np.cosh(b * x), np.sinh(b * x)
            return (np.array([c, s, ch, sh]), b * np.array([-s, c, sh, ch]), b**3 * np.array([s, -c, sh, ch]))

        w0, d0, _ = rows(0.0)
        wL, dL, tL = rows(L)
        a = np.linalg.solve(np.array([w0, d0, wL, dL]), np.array([1.0, 0, 0, 0]))
        F_B = -EI * (tL @ a)  # force the support applies to the beam at B, along +y
        out.append(F_B / (-(w**2)))
    return np.array(out)


def fe_transfer(straight, n, f):
    m = straight(L, n, supports=("clamped", "clamped"), loss_factor=ETA)
    return trfam(m, "cable.A.y", "cable.B.y", f, damping="structural")


def test_trfam_matches_exact_beam_below_fifth_mode(straight):
    assert straight().bodies["cable"].E == E and straight().bodies["cable"].rho == RHO
    f5 = 17.278760**2 / (2 * np.pi * L**2) * np.sqrt(E * I / (RHO * A))
    f = np.linspace(2.0, f5 * 0.98, 1500)
    ex = exact_transfer(f)
    fe = fe_transfer(straight, 35, f)
    mag = np.abs(ex)
    mins, _ = find_peaks(-mag)
    keep = np.ones_like(f, dtype=bool)
    for i in mins:  # leave out +-2% around anti-resonances
        keep &= np.abs(f - f[i]) > 0.02 * f[i]
    rel = np.abs(fe - ex) / np.abs(ex)
    assert rel[keep].max() < 0.01  # the 1% bound at 35 elements


def test_trfam_converges_under_refinement(straight):
    f = np.linspace(5.0, 1000.0, 400)
    ex = exact_transfer(f)
    errs = [np.linalg.norm(fe_transfer(straight, n, f) - ex) / np.linalg.norm(ex) for n in (10, 20, 40)]
    assert errs[0] > errs[1] > errs[2]
    assert errs[2] < 0.01


def test_low_frequency_limit_is_static_stiffness(straight):
    # quasi-static: F_B = -12 EI / L^3 per unit displacement, so TRFAM -> 12 EI/(L^3 w^2)
    f = np.array([0.01])
    fe = trfam(straight(L, 10, supports=("clamped", "clamped")), "cable.A.y", "cable.B.y", f, damping="none")
    w = 2 * np.pi * f
    # (Hermite elements are exact in statics; the inertia at 0.01 Hz adds (f / f_1)^2, below 1e-6)
    np.testing.assert_allclose(fe.real, 12 * E * I / (L**3 * w**2), rtol=1e-6)


def test_reciprocity_on_curved_casing():
    m = load_model()
    f = np.linspace(10, 1000, 200)
    for damping in ("viscous", "structural"):
        H = trfam_matrix(m, "casing", "A", "B", f, damping)
        Ht = trfam_matrix(m, "casing", "B", "A", f, damping)
        # Maxwell-Betti: D(w) is symmetric, so F_B/x_A = (F_A/x_B)^T to round-off
        np.testing.assert_allclose(H, np.transpose(Ht, (0, 2, 1)), rtol=1e-8, atol=1e-12 * np.abs(H).max())


def test_trfam_and_its_matrix_share_eq_12s_last_step(monkeypatch):
    """The force over the acceleration (Eq. 12's last step) has one place, ``apparent_mass_of``:
    ``trfam`` is ``trfam_matrix``'s element (to 1e-12: the forces of one column and of three come
    from products of other shapes, which round differently), and a change of that step changes both."""
    from cablecasing_core.frequency import trfam as module

    m, f = load_model(), np.array([0.1, 37.0, 850.0])
    H = trfam_matrix(m, "casing", "A", "B", f, "viscous")
    np.testing.assert_allclose(trfam(m, "casing.A.y", "casing.B.z", f, "viscous"), H[:, 2, 1], rtol=1e-12)
    monkeypatch.setattr(module, "apparent_mass_of", lambda forces, f: 0 * forces + 7.0)
    assert np.all(trfam(m, "casing.A.y", "casing.B.z", f) == 7.0)
    assert np.all(trfam_matrix(m, "casing", "A", "B", f) == 7.0)


def test_peaks_at_natural_frequencies():
    m = load_model().with_overrides({"casing.alpha": 0.5, "casing.beta": 1e-7})
    fn = natural_frequencies(m, "casing", 40)
    f = np.arange(5.0, 600.0, 0.05)
    for d in "xyz":
        H = np.abs(trfam(m, f"casing.A.{d}", f"casing.B.{d}", f, "viscous"))
        peaks, _ = find_peaks(H, prominence=0.05 * H.max())
        assert len(peaks) >= 3
        for p in peaks:
            assert np.min(np.abs(fn - f[p])) < 0.1  # light damping: peak within two lines of f_n


def test_viscous_and_structural_give_same_peak_when_eta_is_2zeta(straight):
    base = straight(L, 35, supports=("clamped", "clamped"))
    f1 = natural_frequencies(base, "cable", 1)[0]
    zeta = 0.01
    visc = base.with_overrides({"cable.alpha": 2 * zeta * 2 * np.pi * f1})  # zeta_1 = alpha / (2 w1)
    struc = base.with_overrides({"cable.loss_factor": 2 * zeta})
    f = np.linspace(0.97 * f1, 1.03 * f1, 3001)
    hv = np.abs(trfam(visc, "cable.A.y", "cable.B.y", f, "viscous")).max()
    hs = np.abs(trfam(struc, "cable.A.y", "cable.B.y", f, "structural")).max()
    assert abs(hv / hs - 1) < 0.01


def test_frequency_dependent_modulus_moves_resonance_as_sqrt_E(straight):
    base = straight(L, 35, supports=("clamped", "clamped"), loss_factor=0.005)
    f1 = natural_frequencies(base, "cable", 1)[0]
    table = [[0.0, E], [100.0, 1.5 * E]]  # E(f) rises 50 % over 0..100 Hz, held above
    mod = base.with_overrides({"cable.E": table})
    f = np.linspace(0.8 * f1, 1.6 * f1, 20001)
    H = np.abs(trfam(mod, "cable.A.y", "cable.B.y", f, "structural"))
    fp = f[np.argmax(H)]
    # the resonance solves f = f1 sqrt(E(f)/E) on the table's linear ramp
    from scipy.optimize import brentq

    fr = brentq(lambda x: x - f1 * np.sqrt(np.interp(x, [0, 100], [1, 1.5])), f1, 2 * f1)
    assert abs(fp / fr - 1) < 2e-4  # within the 4e-5*f1 grid spacing plus peak skew from light damping


def test_trfam_rejects_bad_ports():
    m = load_model()
    from cablecasing_core import ModelError

    with pytest.raises(ModelError, match="output"):
        trfam(m, "casing.A.x", "cable.B.x", [10.0])
    with pytest.raises(ModelError, match="freqs_hz"):
        trfam(m, "casing.A.x", "casing.B.x", [0.0, 10.0])
    with pytest.raises(ModelError, match="damping"):
        trfam(m, "casing.A.x", "casing.B.x", [10.0], damping="coulomb")


def test_a_port_the_model_does_not_have_is_refused_with_the_ports_it_has_and_frequencies_are_checked():
    """A clip index beyond the model's clips (it got the generic pattern, which it fits) is refused
    with the ports of this model; non-numeric frequencies are a ModelError (a bare ValueError
    before), and more than MAX_FREQUENCIES are refused before any work, as the CLI refuses them."""
    from pathlib import Path

    from cablecasing_core import ModelError
    from cablecasing_core.model.limits import MAX_FREQUENCIES

    m = load_model(str(Path(__file__).resolve().parents[2] / "examples" / "installation.toml"))
    with pytest.raises(ModelError) as e:
        trfam(m, "casing.clip7.z", "casing.B.z", [10.0])
    assert str(e.value).endswith("casing.A, casing.B, cable.A, cable.B, casing.clip0, casing.clip1"), str(e.value)
    with pytest.raises(ModelError, match=r"freqs_hz = \['a'\]: must be one or more frequencies in Hz \(numbers\)"):
        trfam(m, "casing.A.z", "casing.B.z", ["a"])
    with pytest.raises(ModelError, match=rf"frequencies': must be at most {MAX_FREQUENCIES}"):
        trfam_matrix(m, "casing", "A", "B", np.ones(MAX_FREQUENCIES + 1))


def test_the_cli_grid_ends_at_fmax_and_needs_two_frequencies(tmp_path, capsys):
    """`trfam --fmin 10 --fmax 11 --df 0.6` computes 10 and 10.6 Hz, not 11.2 (beyond --fmax);
    a --df wider than the range is refused (it computed fmin alone, and a UFF of one frequency
    then failed inside pyuff)."""
    from cablecasing_core.cli import main

    out = tmp_path / "t.csv"
    assert main(["trfam", "--fmin", "10", "--fmax", "11", "--df", "0.6", "--out", str(out)]) == 0
    np.testing.assert_allclose(np.loadtxt(out, delimiter=",", skiprows=1)[:, 0], [10.0, 10.6])
    assert main(["trfam", "--fmin", "10", "--fmax", "11", "--df", "5", "--out", str(tmp_path / "one.uff")]) == 2
    assert "--df = 5.0: must be at most fmax - fmin = 1 Hz" in capsys.readouterr().err
    assert not (tmp_path / "one.uff").exists()


def test_trfam_matrix_names_the_argument_that_is_wrong():
    from cablecasing_core import ModelError

    m = load_model()
    for args, key in (
        (("hose", "A", "B"), "body"),
        (("casing", "C", "B"), "input_support"),
        (("casing", "A", "x"), "output_support"),
    ):
        with pytest.raises(ModelError) as e:
            trfam_matrix(m, *args, [10.0])
        assert e.value.key == key
