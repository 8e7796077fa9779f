"""What an engineer reads must be right (issue 34): spectra that state the range they integrate,
the output grid t = 0, Δ, ..., T with decimation filtered against aliasing, band names as IEC
61260-1 has them, and every defect the issue lists as its own regression test."""

import json
import re

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.nvh import psd
from cablecasing_core.nvh.bands import iec_nominal, octave_bands
from cablecasing_core.studies import octave_rms
from cablecasing_core.timedomain.simulation import decimate


def _write(path, t, x, name="casing.B.Fz [N]"):
    np.savetxt(path, np.column_stack([t, x]), delimiter=",", header=f"time [s],{name}", comments="", fmt="%.17g")
    return path


def _err(capsys):
    return capsys.readouterr().err


# ---------------------------------------------------------------- spectra that state their range


def test_a_sum_of_sines_below_inside_and_above_the_first_line_against_parseval():
    """The default resolution resolves f_min (the issue's default put the first line at 78 Hz, above
    a tone at 6 Hz that its RMS 'in 1-2000 Hz' then missed): a mean (0 Hz, below the first line),
    tones on lines 3, 25 and 47 (6, 50, 94 Hz) inside [2, 100] Hz and one at 200 Hz above; the RMS
    over [f_min, f_max] is Parseval's sum of the tones inside, to round-off (1e-9: tones on line
    centres, whose Hann main lobe, lines k-1..k+1, lies inside the range; nothing leaks beyond it)."""
    fs, f_min, f_max = 1024.0, 2.0, 100.0
    t = np.arange(2**16) / fs
    inside, above = [(1.0, 6.0), (0.7, 50.0), (0.3, 94.0)], [(5.0, 200.0)]
    x = 3.0 + sum(A * np.sin(2 * np.pi * f * t + 0.3) for A, f in inside + above)
    p = psd(x, fs, unit="N", name="casing.B.Fz", f_min=f_min)
    assert 2 * p.df <= f_min  # the lines measure from 2 df, at or below f_min
    assert p.mean_square(f_min, f_max) == pytest.approx(sum(A * A / 2 for A, _ in inside), rel=1e-9)
    # adjacent ranges add up to their union (edge lines split in proportion, as the bands split bins)
    assert p.mean_square(f_min, 31.0) + p.mean_square(31.0, f_max) == pytest.approx(p.mean_square(f_min, f_max))
    # a range that the lines do not cover says where they start
    assert p.covered(0.0, f_max) == (2 * p.df, f_max)


def test_the_default_resolution_warns_naming_the_first_line_when_the_record_cannot_resolve_fmin():
    x = np.sin(2 * np.pi * 300 * np.arange(2000) / 1e4)  # 0.2 s at 1e4 Hz: the record
    with pytest.warns(UserWarning, match=r"measures from 78.12 Hz \(2 lines, df = 39.06 Hz\), above f_min = 1 Hz"):
        p = psd(x, 1e4, name="casing.B.Fz")
    assert p.n_averages >= 7
    with pytest.warns(UserWarning, match=r"averages only 1 segment"):  # one average: said
        psd(x, 1e4, nperseg=2000, name="casing.B.Fz")


def test_spectrum_prints_the_rms_with_the_band_it_integrates_equal_to_the_bands_over_it(tmp_path, capsys):
    """Tones on the lines of both the Welch segments (4 Hz) and the whole record (1 Hz), two lines
    inside Table 3's octaves 1-7 (11-1420 Hz): the spectrum's RMS over 11-1420 Hz and the bands'
    total over the same range are Parseval's sum, to the 6 digits printed."""
    fs = 8192.0
    t = np.arange(8192) / fs
    tones = [(0.5, 32.0), (0.2, 200.0), (0.1, 800.0)]
    x = sum(A * np.sin(2 * np.pi * f * t) for A, f in tones)
    rec = _write(tmp_path / "r.csv", t, x)
    assert main(["spectrum", str(rec), "--skip", "0", "--fmin", "11", "--fmax", "1420"]) == 0
    out, err = capsys.readouterr()
    expect = np.sqrt(sum(A * A / 2 for A, _ in tones))
    line = next(s for s in out.splitlines() if s.startswith("# casing.B.Fz: RMS"))
    assert f"RMS {expect:.6g} N in 11-1420 Hz" in line
    assert "warning" not in err  # 1 s holds 7 averages of the 4 Hz lines, measuring from 8 Hz
    assert main(["bands", str(rec), "--skip", "0", "--fmax", "1000"]) == 0  # oct1..oct7, 11-1420 Hz
    out = capsys.readouterr().out
    assert f"11-1420 Hz: {expect:.6g} N" in out


@pytest.mark.parametrize(
    "rows, dt, fragment",
    [
        (20, 1e-5, "hold no spectral line"),  # the 20-row record: 'RMS 0 N', exit 0
        (200, 1e90, "hold no spectral line"),  # dt = 1e90 (fs = 1e-90): the same
    ],
)
def test_a_record_without_a_line_in_the_range_is_refused_naming_the_file_and_column(
    tmp_path, capsys, rows, dt, fragment
):
    t = dt * np.arange(rows)
    rec = _write(tmp_path / "r.csv", t, np.sin(np.arange(rows)))
    assert main(["spectrum", str(rec), "--skip", "0"]) == 2
    err = _err(capsys)
    assert fragment in err and str(rec) in err and "casing.B.Fz" in err and "fs =" not in err
    assert main(["bands", str(rec), "--skip", "0"]) == 2  # and bands: no empty table with exit 0
    err = _err(capsys)
    assert str(rec) in err and "casing.B.Fz" in err and "fs =" not in err and "x =" not in err
    assert main(["spectrum", str(rec)]) == 2  # the default --skip 0.05: more than 20 rows of 1e-5 s hold
    assert str(rec) in _err(capsys)


def test_a_constant_or_zero_signal_and_a_zero_reference_get_a_message_not_inf_or_nan(tmp_path, capsys):
    t = np.arange(4096) / 1e4
    for value in (0.0, 2.5):  # the issue: '9.765625,0,-inf' and 'oct1,11,22,0,-inf' with exit 0
        rec = _write(tmp_path / "c.csv", t, np.full(t.size, value))
        for cmd in ("spectrum", "bands"):
            assert main([cmd, str(rec), "--skip", "0"]) == 2
            err = _err(capsys)
            assert "is constant" in err and str(rec) in err and "casing.B.Fz" in err
    # a transfer function whose input (the reference) is zero: 'nan' rows with exit 0 before
    p = tmp_path / "z.csv"
    x = np.sin(2 * np.pi * 100 * t)
    np.savetxt(p, np.column_stack([t, 0 * t, x]), delimiter=",", header="time [s],casing.A.az,casing.B.Fz", comments="")
    assert main(["spectrum", str(p), "--kind", "apparent-mass", "--skip", "0"]) == 2
    err = _err(capsys)
    assert "--input = 'casing.A.az'" in err and "is constant" in err


def test_a_csv_cut_in_its_last_number_is_refused(tmp_path, capsys):
    t = np.arange(100) / 1e4
    text = "time [s],casing.B.Fz [N]\n" + "".join(f"{a!r},{0.01 * np.sin(a * 1e3)!r}\n" for a in t)
    p = tmp_path / "cut.csv"
    p.write_text(text + "0.5,-5.")  # the file: the write stopped inside '-5.0123...'
    assert main(["spectrum", str(p), "--skip", "0"]) == 2
    assert "looks cut" in _err(capsys)
    p.write_text(text + "0.01,-0.00512\n")  # the same line complete, with its line break: read
    assert main(["bands", str(p), "--skip", "0"]) != 0  # (too short for Table 3: but not 'cut')
    assert "looks cut" not in _err(capsys)


def test_messages_name_the_file_and_column_not_internals_and_integer_npz_is_read(tmp_path, capsys):
    t = np.arange(4096) / 1e4
    x = np.sin(2 * np.pi * 300 * t)
    p = tmp_path / "c.npz"
    np.savez(p, time=t, table=(x + 1j * x)[:, None], names=np.array(["casing.B.Fz"]), units=np.array(["N"]))
    assert main(["spectrum", str(p), "--skip", "0"]) == 2
    err = _err(capsys)
    assert "column casing.B.Fz holds complex numbers" in err and "complex array" not in err
    # an integer time column: read as an integer table is (the issue: refused in .npz only)
    q = tmp_path / "i.npz"
    np.savez(q, time=np.arange(4096), table=x[:, None], names=np.array(["casing.B.Fz"]), units=np.array(["N"]))
    assert main(["bands", str(q), "--skip", "0", "--kind", "octave", "--fmax", "0.2"]) == 2  # 1 s steps: far too slow
    assert "must be evenly sampled" not in _err(capsys)
    ints = tmp_path / "i.csv"
    ints.write_text("time [s],casing.B.Fz [N]\n" + "".join(f"{k},{k % 3}\n" for k in range(64)))
    from cablecasing_core.records import read_records

    assert read_records(q).fs == read_records(ints).fs == 1.0


# ---------------------------------------------------------------- the output grid


def test_the_grid_starts_at_zero_and_ends_at_T_for_the_core_and_the_cli(tmp_path):
    res = cc.simulate(cc.load_model(), duration=0.002)
    rec = res.records(1e-4)
    np.testing.assert_allclose(rec.time, 1e-4 * np.arange(21), rtol=0, atol=1e-15)
    assert rec.time[0] == 0 and rec.time[-1] == pytest.approx(0.002, abs=1e-15)
    fz = rec.columns["casing.B.Fz"]  # at rest at t = 0; filtered, the fade-in's start rings (~2 % here)
    assert abs(fz[0]) < 0.05 * np.sqrt(np.mean(fz**2))
    picked = res.records(1e-4, "pick")
    assert picked.columns["casing.B.Fz"][0] == 0.0
    np.testing.assert_array_equal(picked.columns["casing.B.Fz"][1:], res.support_force("casing.B.Fz")[9::10])
    # as an FMU's communication points: the outputs at t = k h, the first before any step
    from cablecasing_core.timedomain.simulation import simulate_sampled

    t_fmu, _ = simulate_sampled(cc.load_model(), 1e-4, 0.002)
    np.testing.assert_allclose(picked.time[1:], t_fmu, rtol=0, atol=1e-15)


def test_an_installed_records_first_row_is_its_static_state():
    from cablecasing_core.timedomain.engine import Engine

    model = cc.load_model("installed")
    res = cc.simulate(model, duration=2e-4)
    rec = res.records()
    static = Engine(model).output_values()
    for i, name in enumerate(cc.model.schema.SUPPORT_OUTPUTS):
        assert rec.columns[name][0] == static[i]
    assert rec.columns["contact.active"][0] == static[24] > 0


@pytest.mark.parametrize("m", [2, 3, 4, 5, 7, 10, 25, 100])
def test_decimation_is_80_db_down_everywhere_above_the_new_nyquist_for_any_factor(m):
    """Unit tones from the new Nyquist frequency fs/(2m) to 1.7 times it, densest near the band
    edge where a Kaiser design's first sidelobe sits: after decimating by m every one is below
    1e-4 (80 dB) away from the record's ends (the filter designed for 80 dB gave 78.7 dB at m = 2,
    just above the edge)."""
    fs = 1.0
    t = np.arange(400 * m) / fs
    interior = slice(60, -60)
    for r in (1.0005, 1.002, 1.005, 1.0085, 1.015, 1.03, 1.06, 1.1, 1.2, 1.35, 1.7):
        y = decimate(np.sin(2 * np.pi * r * fs / (2 * m) * t + 0.3), m)
        assert np.max(np.abs(y[interior])) < 1e-4, (m, r, 20 * np.log10(np.max(np.abs(y[interior]))))


def test_decimation_attenuates_a_tone_above_the_new_nyquist_as_the_filter_promises():
    """fs = 1e5 Hz decimated by 10: a 7 kHz tone (above the new Nyquist 5 kHz; picked, it aliases
    to 3 kHz at full amplitude) is at least 80 dB down; a 2.5 kHz tone (0.5 of the new Nyquist,
    inside the flat band to 0.7) keeps its amplitude within 0.01 dB. The ends (within the FIR's
    half length, 17 output samples) see the record's continuation and are left out."""
    fs, m = 1e5, 10
    t = np.arange(200001) / fs
    interior = slice(40, -40)
    high = np.sin(2 * np.pi * 7000 * t)
    y = decimate(high, m)
    assert y.size == 20001
    assert np.max(np.abs(y[interior])) < 1e-4  # 80 dB
    assert np.max(np.abs(high[::m][interior])) > 0.9  # (picked: the alias, full size)
    low = np.sin(2 * np.pi * 2500 * t)
    z = decimate(low, m)
    np.testing.assert_allclose(z[interior], low[::m][interior], atol=1.2e-3)  # 0.01 dB = 1.2e-3
    # a static preload (an installed model's) stays what it is to the last sample, ends included
    np.testing.assert_allclose(decimate(np.full(1001, 12.5), m), 12.5, rtol=1e-12)


def test_a_record_at_a_step_of_many_digits_reads_back_from_csv_with_its_step(tmp_path):
    """1 s at 1/30000 s (the installed specimen's real-time step) written to CSV and read back: the
    time column keeps its steps equal (15 digits at t <= 1 s leave ~1e-15 s, 3e-11 of a step), and
    a CSV of 9 digits (other tools, earlier versions: steps that differ by 3e-5 of themselves)
    still reads, its steps equal to what 9 digits keep (5e-9 of the largest time). A record that
    is not evenly sampled is still refused."""
    from cablecasing_core.records import Records, read_records, write_records

    dt = 1 / 30000
    t = dt * np.arange(30001)
    rec = Records(t, {"casing.B.Fz": np.sin(2 * np.pi * 50 * t)}, {"casing.B.Fz": "N"})
    write_records(tmp_path / "r.csv", rec)
    back = read_records(tmp_path / "r.csv")
    assert back.fs == pytest.approx(30000, rel=1e-9)
    np.testing.assert_allclose(back.time, t, rtol=0, atol=1e-14)
    table = np.loadtxt(tmp_path / "r.csv", delimiter=",", skiprows=1)
    header = (tmp_path / "r.csv").read_text().splitlines()[0]
    np.savetxt(tmp_path / "nine.csv", table, delimiter=",", header=header, comments="", fmt="%.9g")
    assert np.ptp(np.diff(np.loadtxt(tmp_path / "nine.csv", delimiter=",", skiprows=1)[:, 0])) > 1e-5 * dt
    assert read_records(tmp_path / "nine.csv").fs == pytest.approx(30000, rel=1e-6)
    table[15000, 0] += 0.01 * dt  # one sample 1 % of a step late
    np.savetxt(tmp_path / "uneven.csv", table, delimiter=",", header=header, comments="", fmt="%.17g")
    with pytest.raises(cc.ModelError, match="must be evenly sampled"):
        _ = read_records(tmp_path / "uneven.csv").fs


def test_a_run_that_ends_with_a_shorter_step_is_recorded_to_its_last_whole_step(tmp_path, capsys):
    """A duration that is not a whole number of steps (0.001 s at 3e-5 s: 33 steps and one of 1e-5
    s) ends the run with a shorter step, off the grid: the record leaves it out, evenly sampled to
    the last whole step, and ``simulate`` says so."""
    res = cc.simulate(cc.load_model(), duration=0.001, dt=3e-5)
    assert len(res.time) == 34 and res.whole_steps == 33
    rec = res.records()
    np.testing.assert_allclose(rec.time, 3e-5 * np.arange(34), rtol=0, atol=1e-15)
    assert rec.fs == pytest.approx(1 / 3e-5, rel=1e-9)
    np.testing.assert_array_equal(rec.columns["casing.B.Fz"][1:], res.support_force("casing.B.Fz")[:33])
    out = tmp_path / "r.csv"
    assert main(["simulate", "--duration", "0.001", "--dt", "3e-5", "--out", str(out)]) == 0
    said = capsys.readouterr().out
    assert "the record ends at the last whole step, t = 0.00099 s" in said, said
    assert main(["spectrum", str(out), "--skip", "0", "--fmin", "5000", "--fmax", "15000"]) == 0  # (it reads)
    # a run of one and a half steps: its dt is the run's, not the spacing of its two times
    short = cc.simulate(cc.load_model(), duration=1.5e-5)
    assert short.whole_steps == 1 and short.dt == 1e-5
    np.testing.assert_allclose(short.records().time, [0.0, 1e-5], rtol=0, atol=1e-18)
    with pytest.raises(cc.ModelError, match=r"^output_interval = 5e-06: must be a whole number of time steps"):
        short.records(output_interval=5e-6)


def test_output_interval_must_divide_the_duration_and_pick_is_an_option(tmp_path, capsys):
    out = tmp_path / "r.csv"
    assert main(["simulate", "--duration", "0.001", "--output-interval", "3e-4", "--out", str(out)]) == 2
    assert "must divide the duration" in _err(capsys)
    assert not out.exists()


# ---------------------------------------------------------------- band names of IEC 61260-1

#: IEC 61260-1:2014, Annex E (Table E.1): nominal mid-band frequencies (Hz), one-third octaves
#: 10 Hz .. 20 kHz; every third one (from 16 Hz) is an octave's.
IEC_THIRDS = (
    10, 12.5, 16, 20, 25, 31.5, 40, 50, 63, 80, 100, 125, 160, 200, 250, 315, 400, 500, 630, 800,
    1000, 1250, 1600, 2000, 2500, 3150, 4000, 5000, 6300, 8000, 10000, 12500, 16000, 20000,
)  # fmt: skip
IEC_OCTAVES = (16, 31.5, 63, 125, 250, 500, 1000, 2000, 4000, 8000, 16000)


def test_band_names_are_the_nominal_values_of_the_standard_and_the_exact_centres_stay():
    th, oc = octave_bands("third"), octave_bands("octave")
    assert th.labels == tuple(f"{f:g}Hz" for f in IEC_THIRDS)
    assert oc.labels == tuple(f"{f:g}Hz" for f in IEC_OCTAVES)
    assert th.nominal == tuple(float(f) for f in IEC_THIRDS)
    # the exact centres are base-10: 1000 G^(x/3), G = 10^0.3; each within 2 % of its name
    np.testing.assert_allclose(th.centre, 1000 * 10 ** (0.1 * np.arange(-20, 14)), rtol=1e-12)
    np.testing.assert_allclose(th.centre, IEC_THIRDS, rtol=0.02)
    assert iec_nominal([-1, 0, 1, -20], 3).tolist() == [800, 1000, 1250, 10]
    # Table 3 keeps the paper's names, and says which octave each stands in for
    t3 = octave_bands("table3")
    assert t3.labels[0] == "oct1" and t3.nominal == (16, 31.5, 63, 125, 250, 500, 1000, 2000, 4000)
    # selection by name: --fmin 16 keeps the 16 Hz octave (centre 15.85 Hz)
    assert octave_bands("octave", 16, 2000).labels == ("16Hz", "31.5Hz", "63Hz", "125Hz", "250Hz", "500Hz",
                                                       "1000Hz", "2000Hz")  # fmt: skip


def test_bands_of_a_short_record_name_the_duration_needed_and_fmin_leaves_them_out(tmp_path, capsys):
    t = np.arange(4000) / 2e4  # 0.2 s: the record ('x = 3000 samples (0.15 s)' after skip)
    rec = _write(tmp_path / "r.csv", t, np.sin(2 * np.pi * 300 * t) + 0.1 * np.sin(2 * np.pi * 60 * t))
    assert main(["bands", str(rec), "--kind", "third"]) == 2
    err = _err(capsys)  # (the 2999 samples after 0.05 s: the one at 0.05 s is left out, records.after_skip)
    assert "'0.1499 s': is too short for band 10Hz" in err and "at least 1 / 2.31 Hz = 0.433 s" in err
    assert "--fmin 31.5" in err and "samples" not in err and "x =" not in err
    assert main(["bands", str(rec), "--kind", "third", "--fmin", "31.5", "--out", str(tmp_path / "b.csv")]) == 0
    rows = (tmp_path / "b.csv").read_text().splitlines()
    assert rows[0].startswith("band,f_centre [Hz],f_low [Hz]") and rows[1].startswith("31.5Hz,31.6228,")


def test_a_repeated_column_is_refused(tmp_path, capsys):
    t = np.arange(4096) / 1e4
    rec = _write(tmp_path / "r.csv", t, np.sin(2 * np.pi * 300 * t))
    for cmd in ("spectrum", "bands"):
        assert main([cmd, str(rec), "--column", "casing.B.Fz", "--column", "casing.B.Fz"]) == 2
        assert "is given twice" in _err(capsys)


def test_band_plots_are_labelled_by_nominal_centre():
    from cablecasing_core.nvh.plots import band_ticks

    assert band_ticks(octave_bands("octave", 16, 125)) == ["16", "31.5", "63", "125"]
    assert band_ticks(octave_bands("table3"))[4] == "oct5\n250"


# ---------------------------------------------------------------- any output, in studies and summaries


@pytest.mark.slow
def test_study_output_is_recorded_in_the_header_meta_and_titles_and_the_lock_goes(tmp_path, capsys):
    out = tmp_path / "st"
    args = ["study", "--vary", "contact.friction=0.05:0.3", "--samples", "3", "--duration", "0.15"]
    args += ["--scheduler", "serial", "--out", str(out), "--output", "casing.A.Fx"]
    assert main(args) == 0
    text = capsys.readouterr().out
    assert "6 runs: 2 base points x 3" in text and "asked for" not in text  # --samples 3 runs 6, and why
    assert "band RMS of casing.A.Fx (N)" in text
    header = (out / "study.csv").read_text().splitlines()[0].split(",")
    assert "casing.A.Fx oct1 [N]" in header and "casing.A.Fx oct9 [N]" in header
    meta = json.loads((out / "study.csv.meta.json").read_text())
    assert meta["quantity"]["name"] == "casing.A.Fx" and meta["quantity"]["unit"] == "N"
    assert meta["evaluate_kwargs"]["output"] == "casing.A.Fx"
    assert not (out / "study.csv.lock").exists()  # the issue: left after a clean exit
    from cablecasing_core.studies import load_results

    assert load_results(out / "study.csv").quantity["name"] == "casing.A.Fx"


def test_study_refuses_an_unknown_output_and_names_a_vary_typo_by_option_and_key(tmp_path, capsys):
    out = tmp_path / "st"
    assert main(["study", "--output", "casing.B.Fzz", "--out", str(out)]) == 2
    assert "--output = 'casing.B.Fzz'" in (err := _err(capsys)) and "did you mean casing.B.Fz?" in err
    assert main(["study", "--vary", "contact.frcition=0.1:0.2", "--out", str(out)]) == 2
    err = _err(capsys)
    assert "--vary contact.frcition" in err and "did you mean contact.friction?" in err and "bounds." not in err
    assert not out.exists()


def test_simulate_summarises_every_support_isolator_and_clip_output_with_the_dynamic_rms(capsys):
    from pathlib import Path

    clipped = Path(__file__).resolve().parents[2] / "examples" / "clipped_specimen.toml"
    assert main(["simulate", str(clipped), "--duration", "0.002", "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "RMS dynamic" in out
    for name in ("casing.A.Fx", "casing.B.Mz", "cable.A.Fx", "cable.B.Mz", "casing.clip0.Fz", "casing.clip1.Mz"):
        assert f"  {name} " in out, name
    model = cc.load_model(clipped)
    res = cc.simulate(model, duration=0.002)
    x = res.support_force("casing.clip0.Fz")
    row = next(s for s in out.splitlines() if s.strip().startswith("casing.clip0.Fz"))
    # (printed to 4 significant digits: 1e-3 holds the rounding)
    assert row.split()[1] == "clip" and float(row.split()[-2]) == pytest.approx(np.std(x), rel=1e-3)


# ---------------------------------------------------------------- figures an engineer can read


@pytest.fixture
def figures(monkeypatch):
    """The figures drawn, kept open instead of written (``save_figure`` replaced)."""
    import matplotlib.pyplot as plt

    import cablecasing_core.plotting as plotting

    drawn = []
    monkeypatch.setattr(plotting, "save_figure", lambda fig, path: drawn.append(fig))
    import cablecasing_core.nvh.plots as nvh_plots

    monkeypatch.setattr(nvh_plots, "save_figure", lambda fig, path: drawn.append(fig))
    yield drawn
    for fig in drawn:
        plt.close(fig)


def test_scalograms_mark_the_drive_on_its_panel_only_and_state_differing_colour_scales(figures):
    from cablecasing_core.plotting import plot_scalograms

    f = np.geomspace(20, 2000, 40)
    t = np.linspace(0, 0.3, 50)
    panels = [(t, np.full((50, 40), 0.1), "without the drive"), (t, np.full((50, 40), 1.3), "with the drive")]
    harmonics = [50, 100, 150, 200, 250, 300, 350, 400]
    plot_scalograms(panels, f, "x.png", natural_hz=[88, 132], harmonics_hz=harmonics, harmonics_on=[1])
    a, b = figures[0].axes[:2]  # (the colour bars come after them)
    red = [ln for ln in a.get_lines() if ln.get_color() == "tab:red"]
    assert not red and not [x for x in a.texts if "Hz" in x.get_text()]  # nothing of the drive on (a)
    labels = [x for x in b.texts if x.get_text().endswith(" Hz")]
    assert 4 <= len(labels) <= len(harmonics)
    assert all(x.xy[0] > 0 for x in labels)  # inside the panel, not on its left edge
    assert "colour scale 0-0.1 N" in a.get_title(loc="left") and "13 x finer" in a.get_title(loc="left")


def test_the_psd_axis_spans_a_sensible_dynamic_range(figures):
    from cablecasing_core.nvh.plots import plot_psd

    fs = 8192.0
    x = np.sin(2 * np.pi * 100 * np.arange(2**15) / fs)  # a clean tone: lines down to ~1e-30 around it
    plot_psd([psd(x, fs, nperseg=1024, unit="N", name="casing.B.Fz")], "p.png")
    lo, hi = figures[0].axes[0].get_ylim()
    assert 10 * np.log10(hi / lo) <= 60 + 10 * np.log10(2) + 1e-9  # 60 dB below the peak (x2 headroom)


def test_a_flat_route_has_one_z_tick(figures):
    import matplotlib.pyplot as plt

    from cablecasing_core.plotting import _route_axes

    fig = plt.figure()
    figures.append(fig)
    ax = fig.add_subplot(projection="3d")
    s = np.linspace(0, 1, 30)
    P = np.column_stack([s, 0.3 * s**2, np.zeros_like(s)])
    ax.plot(*P.T)
    _route_axes(ax, P)
    assert list(ax.get_zticks()) == [0.0] and len(ax.get_xticks()) <= 6


def test_the_report_names_the_specimen_and_every_image_has_alt_text():
    from cablecasing_core.report.page import ALT, _with_alt, specimen_name

    assert "<built-in>" not in specimen_name("<built-in>") and "built-in specimen" in specimen_name("<built-in>")
    assert specimen_name("<built-in installed>") == "the built-in specimen 'installed'"
    assert specimen_name("/a/b/route.toml") == "route.toml"
    page = _with_alt("<img src='psd.png'><img src='other.png'>")
    assert f"alt='{ALT['psd.png']}'" in page and "alt='other.png'" in page


def test_the_demo_help_is_complete(capsys):
    import runpy
    from pathlib import Path

    demo = Path(__file__).resolve().parents[2] / "examples" / "demo.py"
    ns = runpy.run_path(str(demo))
    with pytest.raises(SystemExit):
        ns["main"](["--help"])
    out = capsys.readouterr().out
    assert "checked against the core driven by the same sampled record." in " ".join(out.split())


def test_many_band_names_are_turned_so_they_do_not_run_into_each_other(figures):
    from cablecasing_core.nvh.plots import plot_band_levels

    x = np.random.default_rng(1).standard_normal(20000)
    plot_band_levels([octave_rms(x, 1e4, octave_bands("third", 16, 4000))], "b.png")  # 25 bands
    ticks = figures[0].axes[0].get_xticklabels()
    assert ticks[-1].get_text() == "4000" and ticks[-1].get_rotation() == 90
    plot_band_levels([octave_rms(x, 1e4, "table3", beyond_nyquist="drop")], "c.png")  # 8 bands: upright
    assert figures[1].axes[0].get_xticklabels()[0].get_rotation() == 0


def test_spectrum_levels_each_column_against_its_own_unit_and_resolves_a_narrow_range(tmp_path, capsys):
    """A force (N) and an acceleration (m/s2) in one `spectrum`: each level column names its own
    reference (the acceleration's said 1 m/s2 while its values were re 1e-6 m/s2, 120 dB apart),
    the density's squared in brackets; and the default resolution puts lines in a narrow range
    (10-110 Hz of an 8 s record got 64 Hz lines, and was refused), so that the RMS of a 1 N tone at
    100 Hz over 88-177 Hz is the `bands` octave's (within 0.1 %: Hann leakage cut at the range's
    edges; it read 0.77 N, -2.2 dB, with 64 Hz lines)."""
    from cablecasing_core.records import Records, write_records

    fs = 8192.0
    t = np.arange(int(2.05 * fs)) / fs
    tone = np.sqrt(2) * np.sin(2 * np.pi * 100 * t) + 5.0
    acc = np.random.default_rng(0).normal(size=t.size)
    write_records(
        tmp_path / "r.npz",
        Records(t, {"casing.B.Fz": tone, "casing.A.az": acc}, {"casing.B.Fz": "N", "casing.A.az": "m/s2"}),
    )
    out = tmp_path / "s.csv"
    args = ["spectrum", str(tmp_path / "r.npz"), "--column", "casing.B.Fz", "--column", "casing.A.az", "--skip", "0"]
    assert main(args + ["--fmin", "5", "--fmax", "3000", "--out", str(out)]) == 0
    header = out.read_text().splitlines()[0].split(",")
    assert "casing.B.Fz level [dB re 1 N^2/Hz]" in header and "casing.A.az level [dB re (1e-06 m/s2)^2/Hz]" in header
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    j = header.index("casing.A.az PSD [(m/s2)^2/Hz]")
    np.testing.assert_allclose(
        table[:, header.index("casing.A.az level [dB re (1e-06 m/s2)^2/Hz]")], 10 * np.log10(table[:, j] / 1e-12)
    )
    capsys.readouterr()
    one = ["spectrum", str(tmp_path / "r.npz"), "--skip", "0"]
    assert main(one + ["--fmin", "100", "--fmax", "110"]) == 0
    capsys.readouterr()
    assert main(one + ["--fmin", "88", "--fmax", "177"]) == 0
    rms = float(re.search(r"RMS ([0-9.e-]+) N in 88-177 Hz", capsys.readouterr().out).group(1))
    assert rms == pytest.approx(1.0, rel=1e-3)
    assert (
        main(["bands", str(tmp_path / "r.npz"), "--skip", "0", "--kind", "octave", "--fmin", "125", "--fmax", "125"])
        == 0
    )
    assert "125Hz" in capsys.readouterr().out


def test_a_filtered_record_is_the_tone_at_the_grid_times():
    """A run's histories replaced by a 2 kHz tone (0.4 of the new Nyquist frequency 5 kHz at
    output_interval = 10 dt, inside the filter's flat band to 0.7): the filtered record on
    t = 0, 10 dt, ... is the tone at those times, amplitude and phase, to the filter's 0.01 dB
    ripple (1.2e-3 of the amplitude), away from the 40 output samples at each end where the edge
    continuation acts. A delay of one fine step (1e-5 s) is a phase error of 0.13 rad."""
    import dataclasses

    base = cc.simulate(cc.load_model(), duration=2e-4)
    dt, n = base.dt, 20000
    t = dt * np.arange(1, n + 1)
    tone = lambda s: np.sin(2 * np.pi * 2000.0 * s + 0.3)  # noqa: E731
    forces = np.zeros((n, base.support_forces.shape[1]))
    j = base.force_names.index("casing.B.Fz")
    forces[:, j] = tone(t)
    f0 = np.zeros(forces.shape[1])
    f0[j] = tone(0.0)
    k = base.contact_state.shape[1]
    res = dataclasses.replace(
        base,
        time=t,
        support_forces=forces,
        contact_state=np.zeros((n, k), np.int8),
        normal_force=np.zeros((n, k)),
        penetration=np.zeros((n, k)),
        inputs={},
        initial_forces=f0,
        initial_inputs={},
        solver={"dt": dt},
    )
    rec = res.records(10 * dt)
    assert rec.time.size == n // 10 + 1
    inner = slice(40, -40)
    np.testing.assert_allclose(rec.columns["casing.B.Fz"][inner], tone(rec.time)[inner], rtol=0, atol=1.2e-3)
