"""Review AY: a third-party record's unit labels in the transfer functions (AY3) and a record too short for any
skip (AY5)."""

import numpy as np
import pytest

from cablecasing_core import ModelError
from cablecasing_core.cli import main
from cablecasing_core.nvh import apparent_mass, transmissibility
from cablecasing_core.records import Records
from cablecasing_core.uff import Record, write_uff

FS = 1000.0
T = np.arange(4096) / FS
A = np.random.default_rng(7).normal(size=T.size)  # m/s2, white noise
M = 2.5  # kg: the recorded force of a rigid mass is -M a, so the apparent mass (-F/a, the TRFAM's sign) is M


@pytest.mark.parametrize("spelled", ["m/s^2", "m/s**2", "m/s²", "[m/s2]", " m/s 2"])
def test_the_apparent_mass_takes_an_acceleration_however_its_unit_is_spelled(spelled):
    """AY3: the UFF reader takes m/s^2, m/s**2 and m/s² for m/s2 (``units.unit_key``); the apparent mass compared the
    unit as a string and refused them. A rigid mass of 2.5 kg: H1 = 2.5 at every line (one linear map, no noise:
    to rounding, 1e-12)."""
    rec = Records(T, {"acc": A, "force": -M * A}, {"acc": spelled, "force": "N"})
    tr = apparent_mass(rec, input="acc", output="force", skip=0.0)
    np.testing.assert_allclose(tr.H, M, rtol=1e-12)
    assert tr.unit == "kg"
    tt = transmissibility(Records(T, {"a": A, "b": 3 * A}, {"a": spelled, "b": "m/s2"}), "a", "b", skip=0.0)
    np.testing.assert_allclose(tt.H, 3.0, rtol=1e-12)


@pytest.mark.parametrize("units", [("g", "N"), ("m/s2", "kN"), ("m/s", "N"), ("", "N"), ("M/S2", "N"), ("m/s2", "n")])
def test_other_units_are_still_refused(units):
    """AY3: an acceleration in g (the apparent mass would not be in kg), a force in kN, a velocity, no unit; case
    counts (M/S2 is megametres per square second, n no force unit)."""
    rec = Records(T, {"acc": A, "force": -M * A}, dict(zip(("acc", "force"), units)))
    with pytest.raises(ModelError, match=r"needs an acceleration in m/s2 \(m/s\^2, m/s\*\*2, m/s² alike\)"):
        apparent_mass(rec, input="acc", output="force", skip=0.0)
    with pytest.raises(ModelError, match="a transmissibility needs two signals of one unit"):
        transmissibility(Records(T, {"a": A, "b": A}, {"a": "m/s^2", "b": "m/s"}), "a", "b", skip=0.0)


def test_spectrum_apparent_mass_of_a_uff_labelled_m_s_caret_2(tmp_path, capsys):
    """AY3, the review's command: a force (N) and a response labelled m/s^2 (data type 12) written to UFF, as
    pyuff writes them; `spectrum --kind apparent-mass` refused them."""
    p = tmp_path / "noise_FA.uff"
    write_uff(
        p,
        [
            Record("time", T, -M * A, "Force", 3, 3, unit="N", data_type=13),
            Record("time", T, A, "Response", 1, 3, unit="m/s^2", data_type=12),
        ],
    )
    out = tmp_path / "am.csv"
    argv = ["spectrum", str(p), "--kind", "apparent-mass", "--input", "Response", "--column", "Force", "--skip", "0"]
    assert main([*argv, "--out", str(out)]) == 0, capsys.readouterr().err
    table = np.genfromtxt(out, delimiter=",", names=True)
    re_col = next(n for n in table.dtype.names if n.startswith("re_"))
    np.testing.assert_allclose(table[re_col], M, rtol=1e-12)  # (H1 of the rigid mass, to rounding)


@pytest.mark.parametrize("command", ["spectrum", "bands"])
@pytest.mark.parametrize("skip", [[], ["--skip", "0"]])
def test_a_record_too_short_for_any_skip_names_the_file_its_length_and_the_minimum(tmp_path, capsys, command, skip):
    """AY5: a record of 2 samples was told to give a shorter --skip, even at --skip 0."""
    p = tmp_path / "short.csv"
    p.write_text("time [s],Response [m/s2]\n0,0.1\n0.001,-0.2\n")
    assert main([command, str(p), "--column", "Response", *skip]) == 2
    err = capsys.readouterr().err
    assert f"RECORD = '{p} (Response)': holds 2 samples (0.001 s at dt = 0.001 s): at least 16 samples" in err, err
    assert "--skip =" not in err and "shorter" not in err, err


def test_a_skip_that_leaves_too_few_of_a_long_enough_record_is_still_named(tmp_path, capsys):
    """AY5: 20 samples hold 16 with --skip 0; --skip 0.01 leaves 10: that one is the option to change."""
    p = tmp_path / "twenty.csv"
    t = np.arange(20) / FS
    p.write_text(
        "time [s],Response [m/s2]\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(t.tolist(), np.sin(300 * t).tolist()))
    )
    assert main(["spectrum", str(p), "--column", "Response", "--skip", "0.01"]) == 2
    err = capsys.readouterr().err
    assert "--skip = 0.01: must leave at least 16 samples" in err, err


def test_a_transmissibility_keeps_the_case_of_a_prefix():
    """A prefix's case is its factor: forces in mN and MN differ by 1e9, so their ratio is not a transmissibility;
    N and N, kN and kN, m/s^2 and m/s2 are one unit each."""
    with pytest.raises(ModelError, match="case counts: mN is not MN"):
        transmissibility(Records(T, {"a": A, "b": A}, {"a": "mN", "b": "MN"}), "a", "b", skip=0.0)
    for a, b in (("N", "N"), ("kN", "[kN]"), ("m/s^2", "m/s2")):
        tt = transmissibility(Records(T, {"a": A, "b": 2 * A}, {"a": a, "b": b}), "a", "b", skip=0.0)
        np.testing.assert_allclose(tt.H, 2.0, rtol=1e-12)


def test_db_references_and_summed_columns_take_a_units_spellings_alike():
    """The one rule of unit spellings (units.unit_key) in the dB references (an acceleration in m/s^2 is
    referred to 1e-6 m/s2, ISO 1683, as one in m/s2) and in a summed column (m/s^2 + m/s2 is one unit);
    the case still counts (mN + MN is refused; no reference is known for M/S2)."""
    from cablecasing_core.nvh.spectra import reference

    assert reference("m/s^2") == reference("m/s2") == 1e-6 and reference("[N]") == 1.0
    with pytest.raises(ModelError, match="must be given for a quantity in 'M/S2'"):
        reference("M/S2")
    rec = Records(T, {"a": A, "b": 2 * A}, {"a": "m/s^2", "b": "m/s2"})
    np.testing.assert_allclose(rec.column("a+b"), 3 * A, rtol=1e-15)
    with pytest.raises(ModelError, match="adds columns of different units"):
        Records(T, {"a": A, "b": A}, {"a": "mN", "b": "MN"}).column("a+b")


def test_a_squared_velocity_is_no_acceleration():
    """Review BA1: the spelling rule took the brackets out of (m/s)^2, a squared velocity (nvh.spectra.squared's
    own spelling), and read it as m/s2: an apparent mass over it, the acceleration's dB reference and a sum with an
    acceleration were accepted. Only brackets around the whole label go ([m/s2], (N)); a ratio label's parts are
    read each in its own ((m/s^2)/N is an accelerance)."""
    from cablecasing_core.nvh.spectra import reference, squared
    from cablecasing_core.uff import frf_kind_of_labels
    from cablecasing_core.units import unit_key

    assert squared("m/s") == "(m/s)^2" and unit_key("(m/s)^2") != unit_key("m/s2")
    rec = Records(T, {"v2": A * A, "force": -M * A}, {"v2": "(m/s)^2", "force": "N"})
    with pytest.raises(ModelError, match="needs an acceleration in m/s2"):
        apparent_mass(rec, input="v2", output="force", skip=0.0)
    with pytest.raises(ModelError, match=r"must be given for a quantity in '\(m/s\)\^2'"):
        reference("(m/s)^2")
    with pytest.raises(ModelError, match="adds columns of different units"):
        Records(T, {"a": A, "b": A}, {"a": "(m/s)^2", "b": "m/s2"}).column("a+b")
    labels = [("(m/s^2)/N", ""), ("[g]/[N]", ""), ("N", "[m/s^2]"), ("(m/s)^2", "N")]
    kinds = [frf_kind_of_labels(Record("frf", T[:2], A[:2] + 0j, unit=u, denominator_unit=d)) for u, d in labels]
    assert kinds == ["acceleration", "acceleration", "apparent_mass", None]
