"""Review I, spectra and band levels: PSD.mean_square refuses NaN or
reversed limits (D6), the library names its arguments and the command line its options (D8), psd
warns ModelWarning (D9) and refuses a fractional nperseg (D12), and band levels default to the
unit's reference as the PSD's do (D13). The records' part is in test_review_i_records.py."""

import warnings

import numpy as np
import pytest

from cablecasing_core.cli import main
from cablecasing_core.errors import ModelError, ModelWarning
from cablecasing_core.nvh import psd, reference
from cablecasing_core.records import Records
from cablecasing_core.studies import octave_rms

FS = 1e4
T = np.arange(0, 1, 1 / FS)
A = np.random.default_rng(1).standard_normal(T.size)


# ---------------------------------------------------------------- D6: the limits of mean_square


def test_mean_square_and_covered_refuse_nan_or_reversed_limits():
    p = psd(np.random.default_rng(0).standard_normal(20000), FS, unit="N", f_min=20)
    for f_low, f_high, key in [(np.nan, 200, "f_low"), (100, np.nan, "f_high"), (-1, 200, "f_low")]:
        for method in (p.mean_square, p.covered):
            with pytest.raises(ModelError, match=f"^{key} = "):
                method(f_low, f_high)
    for method in (p.mean_square, p.covered):
        with pytest.raises(ModelError, match=r"^f_low/f_high = \(300.0, 200.0\): need f_low < f_high"):
            method(300, 200)
    assert p.mean_square(100, 200) + p.mean_square(200, 300) == pytest.approx(p.mean_square(100, 300))
    assert p.mean_square(6000, np.inf) == 0.0  # (above fs/2: no line lies there)


# ---------------------------------------------------------------- D8: arguments, and options on the command line


def test_the_library_names_its_arguments(tmp_path):
    rec = Records(T, {"casing.B.Fz": A})
    with pytest.raises(ModelError, match=r"^name = 'casing.B.Fy': must be a column of the record: casing.B.Fz"):
        rec.column("casing.B.Fy")
    with pytest.raises(ModelError, match=r"^ref = None: must be given for a quantity in 'furlong'"):
        psd(A, FS, unit="furlong").level_db()  # (a unit without a reference; without a unit it is 1, review X D3)
    with pytest.raises(ModelError, match=r"^ref = -1: must be"):
        reference("N", -1)
    with pytest.raises(ModelError) as err:
        octave_rms(A[:100], FS, "third", beyond_nyquist="drop")
    assert "(octave_bands(kind, f_min=500))" in str(err.value) and "--fmin" not in str(err.value)


def _write(path, x, name="casing.B.Fz [N]"):
    t = T[: len(x)]
    np.savetxt(path, np.column_stack([t, x]), delimiter=",", header=f"time [s],{name}", comments="", fmt="%.17g")
    return path


def test_the_command_line_names_its_options(tmp_path, capsys):
    path = _write(tmp_path / "r.csv", A)
    assert main(["bands", str(path), "--column", "casing.B.Fy"]) == 2
    assert "--column = 'casing.B.Fy': must be a column of" in capsys.readouterr().err
    assert main(["bands", str(path), "--ref", "-1"]) == 2
    assert "--ref = -1.0: must be" in capsys.readouterr().err
    assert main(["spectrum", str(path), "--ref", "-1"]) == 2
    assert "--ref = -1.0: must be" in capsys.readouterr().err
    # the advice to leave out the bands a short record cannot resolve names --fmin, warned or refused
    short = _write(tmp_path / "s.csv", A[:2500])  # (0.25 s; 0.19 s after the default skip)
    assert main(["bands", str(short), "--kind", "third", "--fmin", "40"]) == 0
    err = capsys.readouterr().err
    assert "warning: " in err and "or leave out the bands below 100Hz (--fmin 100)" in err
    assert main(["bands", str(short), "--kind", "third"]) == 2
    err = capsys.readouterr().err
    assert "is too short for band 10Hz" in err and "or leave out the bands below 25Hz (--fmin 25)" in err
    assert "octave_bands" not in err


# ---------------------------------------------------------------- D9, D12: psd's warnings and nperseg


def test_psd_warns_model_warnings():
    with warnings.catch_warnings():
        warnings.filterwarnings("error", category=ModelWarning)
        with pytest.raises(ModelWarning, match="the PSD measures from"):
            psd(A[:1000], FS)  # (capped to a quarter of the record: its lines start above 1 Hz)
        with pytest.raises(ModelWarning, match="averages only 1 segment"):
            psd(A[:1000], FS, nperseg=1000)


@pytest.mark.parametrize("nperseg", [100.5, 128.0, "128", True, 4, 20000])
def test_psd_refuses_an_nperseg_that_is_not_a_whole_number_of_samples_in_range(nperseg):
    with pytest.raises(ModelError, match=r"^nperseg = .*: must be an integer"):
        psd(A, FS, nperseg=nperseg)
    assert psd(A, FS, nperseg=np.int64(128)).nperseg == 128


# ---------------------------------------------------------------- D13: one reference for bands and PSD


def test_band_levels_take_the_units_reference_as_the_psd_levels_do():
    b = octave_rms(A, FS, "octave", beyond_nyquist="drop", unit="m/s2")
    assert b.unit == "m/s2" and b.reference() == 1e-6
    np.testing.assert_allclose(b.level_db(), 20 * np.log10(b.rms / 1e-6))
    np.testing.assert_allclose(b.level_db(1.0), b.level_db() - 120)
    # over the same band, the PSD's mean square and its level are against the same reference
    p = psd(A, FS, unit="m/s2")
    k = list(b.labels).index("1000Hz")
    ms = p.mean_square(b.lower[k], b.upper[k])
    # two estimates of one noise band (707 Hz over 1 s) differ by their scatter, ~1/sqrt(B T) = 0.16 dB each
    # (0.03 dB here, up to 0.27 dB over seeds 1-7); another reference would move it by 120 dB
    assert 10 * np.log10(ms / reference("m/s2") ** 2) == pytest.approx(b.level_db()[k], abs=0.3)
    # no unit: re 1 (as before); a unit without a reference needs ref
    plain = octave_rms(A, FS, "octave", beyond_nyquist="drop")
    assert plain.unit == "" and plain.reference() == 1.0
    np.testing.assert_allclose(plain.level_db(), 20 * np.log10(plain.rms))
    pa = octave_rms(A, FS, "octave", beyond_nyquist="drop", unit="Pa")
    with pytest.raises(ModelError, match=r"^ref = None: must be given for a quantity in 'Pa'"):
        pa.level_db()
    np.testing.assert_allclose(pa.level_db(2e-5), 20 * np.log10(pa.rms / 2e-5))
    with pytest.raises(ModelError, match="^unit = 3: must be a unit as text"):
        octave_rms(A, FS, unit=3)


def test_bands_states_the_reference_of_its_levels(tmp_path, capsys):
    path = _write(tmp_path / "a.csv", A, "casing.A.az [m/s2]")
    assert main(["bands", str(path), "--column", "casing.A.az", "--kind", "octave", "--fmax", "2000"]) == 0
    out = capsys.readouterr().out
    assert "level in dB re 1e-06 m/s2" in out and "level [dB re 1e-06 m/s2]" in out
    row = next(s for s in out.splitlines() if s.startswith("1000Hz,")).split(",")
    assert float(row[5]) == pytest.approx(20 * np.log10(float(row[4]) / 1e-6), abs=0.01)
