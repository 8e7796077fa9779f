"""A run's record as UFF 58 keeps what its .csv and .npz state beside the columns (review B 11): the
passband, the harmonic lines and the supports' fade-in, in the ID lines 3 and 5 of every function, so
``bands`` reads the .uff of a run as it reads the .csv (the default skip was 0.05 s against 0.06 s,
the 16 Hz band 6 % apart)."""

import numpy as np
import pytest
import pyuff

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.errors import ModelError, ModelWarning
from cablecasing_core.records import Records, read_records, write_records


@pytest.fixture(scope="module")
def run():
    """0.2 s of the built-in specimen (its 50 Hz drive, 0.01 s ramp): a default skip of 0.06 s (7 whole
    periods after it) where 0.05 s is the least."""
    return cc.simulate(cc.load_model(), duration=0.2)


def _table(text, path):
    """The band rows and the header lines of `bands` output, the file's name taken out."""
    return [line.replace(str(path), "FILE") for line in text.splitlines()]


@pytest.mark.parametrize("interval", [None, 1e-4])
def test_the_uff_of_a_run_reads_back_as_its_csv(run, tmp_path, capsys, interval):
    """Every step (passband = Nyquist) and decimated to 1e-4 s (passband 3500 Hz): the .uff states the
    same passband, lines and ramp as the .csv (both to 15 digits: equal), so the same default skip,
    and `bands` prints the same lines. The levels agree to their 6 printed digits: the .csv keeps 9
    digits of each sample, the .uff doubles (a relative 5e-9 per sample)."""
    paths = {s: tmp_path / f"run{s}" for s in (".csv", ".npz", ".uff")}
    for p in paths.values():
        run.save(p, output_interval=interval)
    recs = {s: read_records(p) for s, p in paths.items()}
    # (the .uff states it to the .csv's 15 digits: equal; the .npz keeps the run's double, 1e-16 apart)
    assert float(recs[".uff"].extra["passband_hz"]) == float(recs[".csv"].extra["passband_hz"])
    for s in (".npz", ".uff"):
        # (the property is the lower of that and the Nyquist frequency of the time axis: the run's doubles
        # in .npz and .uff, 15 digits in .csv)
        assert recs[s].passband_hz == pytest.approx(recs[".csv"].passband_hz, rel=1e-12)
        assert recs[s].lines_hz == recs[".csv"].lines_hz == (50.0,)
        assert recs[s].ramp_s == recs[".csv"].ramp_s == 0.01
        assert recs[s].default_skip() == recs[".csv"].default_skip() == 0.06
    assert recs[".uff"].extra["passband_hz"] == (3500.0 if interval else 50000.0)
    out = {}
    for s in (".csv", ".uff"):
        assert main(["bands", str(paths[s]), "--kind", "octave"]) == 0
        out[s] = _table(capsys.readouterr().out, paths[s])
    assert out[".uff"] == out[".csv"]
    assert any(line.startswith("# FILE: casing.B.Fz after 0.06 s") for line in out[".uff"])


def test_what_a_record_states_goes_into_id_lines_3_and_5(tmp_path):
    """The statements' form: ID line 5 ``cablecasing passband_hz=... ramp_s=...``, ID line 3
    ``cablecasing lines_hz=...`` (80 characters each, as pyuff reads them back); a record that states
    nothing writes "NONE" there, as before."""
    t = np.arange(200) * 1e-3
    rec = Records(t, {"casing.B.Fz": np.sin(t)}, {"casing.B.Fz": "N"}, "", {
        "passband_hz": np.array(350.0), "lines_hz": np.array([50.0, 100.25]), "ramp_s": np.array(0.01)})  # fmt: skip
    write_records(tmp_path / "r.uff", rec)
    s = pyuff.UFF(str(tmp_path / "r.uff")).read_sets(0)
    assert s["id5"] == "cablecasing passband_hz=350 ramp_s=0.01" and s["id3"] == "cablecasing lines_hz=50 100.25"
    assert s["id4"] == "cablecasing x0=0.0 dx=0.001"
    back = read_records(tmp_path / "r.uff")
    assert back.passband_hz == 350.0 and back.lines_hz == (50.0, 100.25) and back.ramp_s == 0.01
    write_records(tmp_path / "n.uff", Records(t, {"x": np.sin(t)}, {}, ""))
    s = pyuff.UFF(str(tmp_path / "n.uff")).read_sets(0)
    assert s["id3"] == s["id5"] == "NONE" and read_records(tmp_path / "n.uff").extra == {}


def _other_tool(path, id3="NONE", id5="NONE", n=2):
    """A UFF of ``n`` time functions as another tool writes it (pyuff, ASCII), with these ID lines."""
    t = np.arange(100) * 1e-3
    zeros = dict.fromkeys(
        [f"{a}_{b}_unit_exp" for a in ("abscissa", "ordinate", "orddenom", "z_axis") for b in ("len", "force", "temp")],
        0,
    )
    sets = [
        pyuff.prepare_58(
            binary=0, func_type=1, id1=f"x{k}", id3=id3 if k == 0 else "NONE", id5=id5, rsp_node=1, rsp_dir=k + 1,
            ref_node=0, ref_dir=0, data=np.sin(t), x=t, abscissa_spacing=1, abscissa_spec_data_type=17,
            abscissa_axis_units_lab="s", ordinate_spec_data_type=0, ordinate_axis_units_lab="",
            orddenom_spec_data_type=0, orddenom_axis_units_lab="", z_axis_spec_data_type=0, z_axis_axis_units_lab="",
            z_axis_value=0.0, **zeros,
        )
        for k in range(n)
    ]  # fmt: skip
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")
    return path


def test_a_file_of_other_tools_states_nothing_and_a_bad_statement_is_refused(tmp_path):
    """ID lines that do not start with 'cablecasing' (a date, a test name) state nothing; one that
    states a value badly is refused naming the file and the ID line, as a CSV's comment line; functions
    of one record that state differently are refused."""
    rec = read_records(_other_tool(tmp_path / "a.uff", id3="12-Mar-24 10:00", id5="lines_hz=50 shaker test", n=1))
    assert rec.extra == {} and rec.lines_hz == () and rec.default_skip() == 0.05
    for line5, name, what in (
        ("cablecasing passband_hz=-1", "passband_hz", "a positive number of Hz"),
        ("cablecasing ramp_s=soon", "ramp_s", "a number of s, 0 or more"),
    ):
        path = _other_tool(tmp_path / "b.uff", id5=line5, n=1)
        with pytest.raises(ModelError) as e:
            read_records(path)
        assert e.value.key == "file" and e.value.value == str(path)
        assert e.value.allowed.startswith(f"its ID line 5 states {name}, but not as {what}")
    path = _other_tool(tmp_path / "c.uff", id3="cablecasing lines_hz=50", n=2)
    with pytest.raises(ModelError, match=r"time function 1 \(x1\) states nothing in its ID lines 3 and 5, time "):
        read_records(path)


def test_lines_the_id_line_cannot_hold_are_left_out_with_a_warning(tmp_path):
    """59 characters hold the lines (after 'cablecasing lines_hz='): 8 lines of 10 characters do not fit;
    the file leaves them out with a ModelWarning and keeps the passband and ramp."""
    t = np.arange(200) * 1e-3
    lines = 50.0 + np.arange(8) * 1.23456789
    rec = Records(t, {"x": np.sin(t)}, {}, "", {"lines_hz": lines, "ramp_s": np.array(0.02)})
    with pytest.warns(ModelWarning, match=r"cannot hold the record's lines_hz \(too many harmonic lines\)"):
        write_records(tmp_path / "r.uff", rec)
    back = read_records(tmp_path / "r.uff")
    assert back.lines_hz == () and back.ramp_s == 0.02
