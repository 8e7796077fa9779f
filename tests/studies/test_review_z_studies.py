"""What an NVH engineer's review of the studies found (review Z): the --against table in bands
without response, a change interval below -100 %, a change that did nothing, edited ensemble
settings, and refusals that leave out the value or the option."""

import re

import numpy as np
import pytest
from scipy import stats

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.errors import ModelError
from cablecasing_core.studies import critical_correlation, load_ensemble, paired_difference, seed_ensemble


def _change_rows(out):
    """{band: the change table's fields} of an ensemble command's output."""
    text = out.split("band,mean_against,rel_diff,se,ci_low,ci_high,diff_over_se,p\n", 1)[1]
    return {line.split(",")[0]: line.split(",")[1:] for line in text.splitlines() if not line.startswith("#")}


def test_the_change_table_gives_no_ratio_where_nothing_responds(capsys):
    """Review Z D1: without the cable's drive the octaves above 1 kHz hold only Hann's window's
    leakage (the first table says "no response"), yet the change table printed ratios there
    (-70 % at -6.9 SE in one run). They read nan now, in exactly the bands with no response in
    either ensemble, and a line names them; the others keep their ratio."""
    argv = ["ensemble", "--kind", "octave", "--seeds", "2", "--duration", "0.3", "--scheduler", "serial",
            "--set", "scenario.excitation.cable_axial.amplitude=0", "--against", "casing.E=6e9"]  # fmt: skip
    assert main(argv) == 0
    out = capsys.readouterr().out
    said = re.search(r"# no response in ([^:]*):", out).group(1).split(", ")
    rows = _change_rows(out)
    gone = [band for band, f in rows.items() if f[1] == "nan"]
    assert said and set(said) <= set(gone), (said, gone)
    assert re.search(rf"# no change given in {re.escape(', '.join(gone))}: no response there", out)
    assert any(f[1] != "nan" for f in rows.values())


def test_a_change_that_makes_no_difference_is_said_not_nan(capsys):
    """Review Z D4: --against with the model's own value gives the same records; the table read
    "+0.0000 0.0000 ... +nan". diff_over_se reads +0.0 and a line says the levels are the same (the
    paired t test's p is nan: a_i - b_i = 0 in every member, its t statistic 0/0; review BE)."""
    friction = cc.load_model().data["contact"]["friction"]
    argv = ["ensemble", "--seeds", "2", "--duration", "0.2", "--scheduler", "serial",
            "--against", f"contact.friction={friction}"]  # fmt: skip
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert all(f[1] == "+0.0000" and f[-2:] == ["+0.0", "nan"] for f in _change_rows(out).values())
    assert "# the change made no difference in any member: the two ensembles' levels are the same to the bit" in out


def test_the_interval_of_a_relative_change_stops_at_minus_one():
    """Review Z D3: r - t se went below -1 (a negative mean level); it is cut at -1 as the levels'
    intervals are cut at 0, and the upper end is Student's (scipy.stats.t) unchanged."""
    a = np.array([[0.01], [1.0], [0.02]])
    b = np.ones((3, 1))
    d = paired_difference(a, b)
    lo, hi = d.ci(0.95)
    r = a.mean() / b.mean() - 1.0
    se = np.std(a[:, 0] - (1 + r) * b[:, 0], ddof=1) / np.sqrt(3) / b.mean()  # (the linearised SE)
    assert d.r[0] == pytest.approx(r) and d.se[0] == pytest.approx(se)
    assert r - stats.t.ppf(0.975, 2) * se < -1.0  # (the uncut interval would go below -1)
    assert lo[0] == -1.0 and hi[0] == pytest.approx(r + stats.t.ppf(0.975, 2) * se)


def test_edited_settings_of_an_ensemble_file_are_refused_by_name(tmp_path):
    """Review Z D2: a window that is no window stopped `pool` on an internal KeyError; a skip of -5
    s and a dt of "fast" were accepted. Each is refused, naming the settings key, its value and
    what is allowed."""
    ens = seed_ensemble(cc.load_model(), seeds=2, duration=0.15)
    path = tmp_path / "e.csv"
    ens.save(path)
    text = path.read_text()
    for key, new, said in (
        ("window", '"nonsense"', 'settings window = "nonsense": must be one of hann, boxcar'),
        ("skip", "-5", "settings skip = -5: must be a number of s >= 0"),
        ("dt", '"fast"', 'settings dt = "fast": must be a number of s > 0'),
    ):
        edited, n = re.subn(rf'"{key}": ("[^"]*"|[-+0-9.e]+)', f'"{key}": {new}', text, count=1)
        assert n == 1, key
        bad = tmp_path / "bad.csv"
        bad.write_text(edited)
        with pytest.raises(ModelError, match=re.escape(said)):
            load_ensemble(bad)


def test_refusals_name_the_value():
    """Review Z D5: a seed given twice was said as "'2 seeds'"; it is named. critical_correlation
    is Fisher's from n = 4 on (tanh 1.96 = 0.96), 1 only where it is not defined (n <= 3)."""
    with pytest.raises(ModelError, match=r"must hold each seed once: 1 is given twice"):
        seed_ensemble(cc.load_model(), seeds=[1, 1], duration=0.15)
    assert critical_correlation(4) == pytest.approx(np.tanh(1.96)) and critical_correlation(3) == 1.0


def test_a_resumed_study_names_the_bounds_and_the_edited_cell(tmp_path, capsys):
    """Review Z D5: resuming with other bounds said "bounds = {...}: must equal {...}" (the Python
    name, both dicts) where every other resume refusal names the option; a parameter edited by hand
    was "row of sample 2 does not match the design", without its line and column."""
    out = tmp_path / "st"
    argv = ["study", "--vary", "contact.friction=0.05:0.2", "--samples", "6", "--duration", "0.16",
            "--scheduler", "serial", "--out", str(out)]  # fmt: skip
    assert main(argv) == 0
    capsys.readouterr()
    wider = [a.replace("0.05:0.2", "0.05:0.3") for a in argv]
    assert main(wider) == 2
    err = capsys.readouterr().err
    assert "--vary contact.friction = 0.05:0.3: must be 0.05:0.2, the bounds the study in" in err, err
    # from a --vary-file, named as the file's key (review AB AB2), with bounds that differ in the 7th digit apart
    vf = tmp_path / "vary.toml"
    vf.write_text('"contact.friction" = [0.05, 0.2000001]\n')
    by_file = [a for a in argv if a not in ("--vary", "contact.friction=0.05:0.2")] + ["--vary-file", str(vf)]
    assert main(by_file) == 2
    err = capsys.readouterr().err
    assert f"--vary-file {vf}: contact.friction = 0.05:0.2000001: must be 0.05:0.2, the bounds" in err, err
    csv = out / "study.csv"
    lines = csv.read_text().splitlines(keepends=True)
    fields = lines[3].split(",")  # (line 4: sample 2)
    fields[2] = repr(float(fields[2]) + 0.01)
    lines[3] = ",".join(fields)
    csv.write_text("".join(lines))
    assert main(argv) == 2
    err = capsys.readouterr().err
    said = r"line 4, column 'contact.friction' holds .* where the design of this seed and bounds has"
    assert re.search(said, err), err


def test_a_change_that_silences_the_output_reads_minus_100_percent(capsys):
    """Review AB AB5: when every level of the second ensemble is 0 (the change silences the output),
    the table read nan in every band with "the window's leakage sets a level", though nothing leaks
    from nothing: it reads -1 (-100 %) and a line says the output is silenced."""
    from cablecasing_core.cli.study import _print_change
    from cablecasing_core.studies.ensemble import Ensemble

    seeds, labels = np.array([1, 2, 3]), ("o1", "o2", "o3")
    lo, hi = np.array([10.0, 20.0, 40.0]), np.array([20.0, 40.0, 80.0])
    levels = np.array([[1.0, 2.0, 3.0], [1.1, 2.1, 3.2], [0.9, 1.9, 2.8]])
    ens = Ensemble(seeds, "casing.B.Fz", labels, lo, hi, levels)
    other = Ensemble(seeds, "casing.B.Fz", labels, lo, hi, np.zeros((3, 3)))
    _print_change(ens, other, paired_difference(other, ens), "a change", 0.95)
    out = capsys.readouterr().out
    assert all(f[1] == "-1.0000" for f in _change_rows(out).values()), out
    assert "# the change silences casing.B.Fz: every level of every member is 0 N (-100 %)" in out
    assert "no change given" not in out
