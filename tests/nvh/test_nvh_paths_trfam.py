"""The TRFAM's band values (``frequency.trfam.trfam_band_rms``, ``cablecasing trfam --bands``): the RMS
of |H| over each band, sqrt(integral of |H|^2 df / (f_high - f_low)), checked against integrals by
hand: closed forms (a linear |H|^2, a resonance's Lorentzian) and an adaptive quadrature of the
built-in casing's TRFAM."""

import numpy as np
import pytest
from scipy.integrate import quad

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.errors import ModelError
from cablecasing_core.frequency.trfam import FrequencyResponse, trfam_band_rms
from cablecasing_core.structure.assembly import assemble_body
from cablecasing_core.studies import Bands

GRID = 10.0 + 0.25 * np.arange(3961)  # Hz: the trfam command's default grid, 10-1000 Hz by 0.25 Hz


def test_a_linear_power_is_integrated_exactly_and_the_bands_beyond_the_grid_are_left_out():
    """|H|^2 = 2 + 0.01 f (kg^2, f in Hz): its mean over a band is 2 + 0.01 (f_low + f_high) / 2. Table 3's
    edges (11, 22, ... Hz) lie on the grid, where the rule is the trapezoidal one, exact for a
    linear integrand (to round-off, 1e-13). The grid ends at 1000 Hz: oct7 (710-1420 Hz) and above
    are left out; kept as nan with outside="nan", refused naming them with "error"."""
    b = trfam_band_rms(GRID, np.sqrt(2 + 0.01 * GRID) * np.exp(1j * GRID))  # (the phase does not count)
    assert b.labels == ("oct1", "oct2", "oct3", "oct4", "oct5", "oct6") and b.unit == "kg"
    np.testing.assert_allclose(b.rms**2, 2 + 0.01 * (b.lower + b.upper) / 2, rtol=1e-13)
    np.testing.assert_allclose(b.bins, (b.upper - b.lower) / 0.25, rtol=1e-12)  # (the grid's points per band)
    kept = trfam_band_rms(GRID, np.ones(GRID.size), "table3", outside="nan")
    assert len(kept.labels) == 9 and np.all(np.isnan(kept.rms[6:])) and np.allclose(kept.rms[:6], 1.0)
    with pytest.raises(ModelError, match=r"^freqs_hz = 10..1000 Hz: .* leaves out oct7 \(710-1420 Hz\), oct8"):
        trfam_band_rms(GRID, np.ones(GRID.size), outside="error")
    with pytest.raises(ModelError, match=r"^freqs_hz = 100..150 Hz: .*, every band asked for"):
        trfam_band_rms([100.0, 150.0], [1.0, 1.0])
    with pytest.raises(ModelError, match=r"^H = 3 values: must hold one value per frequency: 3961"):
        trfam_band_rms(GRID, [1.0, 2.0, 3.0])
    with pytest.raises(ModelError, match=r"^freqs_hz = .*: must be two or more frequencies in Hz in increasing"):
        trfam_band_rms(GRID[::-1], np.ones(GRID.size))


def test_a_resonance_on_a_grid_of_half_its_bandwidth_is_integrated_within_half_a_percent():
    """A resonance's |H|^2 = 1 / ((f - f0)^2 + gamma^2), half-power bandwidth b = 2 gamma, has the
    band integral (atan((f_high - f0)/gamma) - atan((f_low - f0)/gamma)) / gamma. On the grid that
    keeps the peak's height within 11 % (step b/2, what ``trfam`` warns beyond) the trapezoidal
    rule's error is about 2 exp(-2 pi) = 0.37 % of the mean square, wherever the peak falls between
    two points (0.39 % at worst over 20 offsets)."""
    gamma = 0.5
    step = gamma  # (b / 2)
    f = 40.0 + step * np.arange(41)
    worst = 0.0
    for offset in np.arange(20) / 20:
        f0 = 50.0 + offset * step
        b = trfam_band_rms(f, 1 / np.sqrt((f - f0) ** 2 + gamma**2), Bands([40.0], [60.0], ["x"]))
        exact = (np.arctan((60.0 - f0) / gamma) - np.arctan((40.0 - f0) / gamma)) / gamma / 20.0
        worst = max(worst, abs(b.rms[0] ** 2 / exact - 1))
    assert 0.003 < worst < 0.005


@pytest.mark.parametrize("damping", ["viscous", "structural"])
def test_the_casings_band_values_are_an_adaptive_quadrature_of_its_trfam(damping):
    """The built-in casing's TRFAM from A to B in z on the default grid (0.25 Hz; the narrowest peak
    0.94 Hz wide with the structural loss factor): each Table 3 band's value against scipy's
    adaptive quadrature of |TRFAM(f)|^2 (to 1e-10, breaking at the natural frequencies) within
    1e-3: measured 2.5e-4 (viscous) and 8e-4 (structural, its narrower peaks), the trapezoidal rule's
    error over resonances 4 to 8 grid steps wide."""
    model = cc.load_model()
    H = cc.trfam(model, "casing.A.z", "casing.B.z", GRID, damping=damping)
    b = trfam_band_rms(GRID, H)
    system = assemble_body(model, "casing")
    fr, j, q = FrequencyResponse(system), system.prescribed_index("A", 2), system.prescribed_index("B", 2)

    def power(f):  # |TRFAM|^2 at one frequency (cc.trfam's, its modal basis built once)
        return abs(fr.support_forces(np.array([f]), damping, rows=[q], cols=[j])[0, 0, 0] / (2 * np.pi * f) ** 2) ** 2

    modes = cc.natural_frequencies(model, "casing", 40)
    for lo, hi, rms in zip(b.lower, b.upper, b.rms):
        inside = [f for f in modes if lo < f < hi] or None
        value = quad(power, lo, hi, points=inside, limit=500, epsabs=0, epsrel=1e-10)[0]
        assert rms == pytest.approx(np.sqrt(value / (hi - lo)), rel=1e-3), (lo, hi)


def test_the_command_prints_the_band_values_the_function_gives(tmp_path, capsys):
    """``trfam --bands table3`` prints (or writes to --out) the table of trfam_band_rms on its grid,
    after the line saying it is of each body alone (no contact), a line saying what it is and one naming
    the bands its grid leaves out and what holds them;
    a .uff --out (an FRF's lines) is refused with --bands, and a grid that holds no band names
    --fmin/--fmax."""
    args = ["trfam", "--input", "casing.A.z", "--output", "casing.B.z", "--bands", "table3"]
    assert main(args) == 0
    scope, *out = capsys.readouterr().out.splitlines()
    assert scope.startswith("# each body alone on its supports and mounts: no contact")  # (the cable lies on the wall)
    assert out[0].startswith("# TRFAM casing.B.z / casing.A.z (viscous damping), kg: the RMS of |TRFAM| over each")
    assert out[1] == (
        "# the grid leaves out band(s) oct7, oct8, oct9, which reach beyond it: they need frequencies up to "
        "5680 Hz (--fmax)"
    )
    assert out[2] == "band,f_centre [Hz],f_low [Hz],f_high [Hz],rms [kg]"
    expected = trfam_band_rms(GRID, cc.trfam(cc.load_model(), "casing.A.z", "casing.B.z", GRID))
    assert [r.split(",")[0] for r in out[3:]] == list(expected.labels)
    np.testing.assert_allclose([float(r.split(",")[4]) for r in out[3:]], expected.rms, rtol=1e-5)  # (6 digits)
    assert main([*args, "--out", str(tmp_path / "b.csv")]) == 0
    assert (tmp_path / "b.csv").read_text().splitlines() == out[2:]
    assert main([*args, "--out", str(tmp_path / "b.uff")]) == 2
    assert "--out = " in capsys.readouterr().err and not (tmp_path / "b.uff").exists()
    assert main([*args, "--fmin", "100", "--fmax", "150"]) == 2
    assert "--fmin/--fmax = 100..150 Hz: must reach from a band's lower edge" in capsys.readouterr().err
