"""UFF dataset 58 and CSV round trips; identified parameters as model-file TOML."""

import sys
import warnings

import numpy as np
import pytest

from cablecasing_core import load_model
from cablecasing_core.errors import ModelError, ModelWarning
from cablecasing_core.identification import (
    Record,
    loss_factor_circle,
    parameters_toml,
    read_csv_frf,
    read_csv_time,
    read_frf,
    read_time_record,
    read_uff,
    write_csv_frf,
    write_csv_time,
    write_uff,
    write_uff_frf,
    write_uff_time,
)

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def _frf():
    f = np.arange(0.5, 400.0, 0.5)
    w2 = (2 * np.pi * f) ** 2
    return f, 1.0 / ((2 * np.pi * 182.0) ** 2 * (1 + 0.046j) - w2) + 1e-7j


@pytest.mark.parametrize("binary", [True, False])
def test_uff_round_trip_frf_and_time(tmp_path, binary):
    f, H = _frf()
    fs = 4096.0
    x = np.sin(2 * np.pi * 115.8 * np.arange(3000) / fs) * np.exp(-np.arange(3000) / 900.0)
    p_frf, p_time = tmp_path / "frf.uff", tmp_path / "x.uff"
    write_uff_frf(p_frf, f, H, name="TRFAM casing", binary=binary, rsp_node=2, rsp_dir=3, ref_node=1, ref_dir=1)
    write_uff_time(p_time, x, fs, name="impulse response", binary=binary)
    (r,) = read_uff(p_frf)
    assert r.kind == "frf" and r.name == "TRFAM casing" and (r.rsp_node, r.rsp_dir, r.ref_node) == (2, 3, 1)
    # binary 58b stores doubles: exact; ASCII stores E20.11 (12 significant digits)
    tol = 0.0 if binary else 1e-11
    np.testing.assert_allclose(r.data, H, rtol=tol, atol=0)
    np.testing.assert_array_equal(r.x, f)  # exact even abscissa from the ID-line tag
    x2, fs2, name = read_time_record(p_time)
    np.testing.assert_allclose(x2, x, rtol=tol, atol=tol * np.abs(x).max())
    assert fs2 == fs and name == "impulse response"
    f3, H3 = read_frf(p_frf)
    np.testing.assert_allclose(H3, H, rtol=tol, atol=0)


def test_uff_several_functions_and_uneven_abscissa(tmp_path):
    f_uneven = np.geomspace(10.0, 400.0, 57)
    H = 1.0 / (1.0 + 1j * f_uneven)
    recs = [
        Record("time", np.arange(10) * 0.5e-3, np.arange(10.0), "t1"),
        Record("frf", f_uneven, H, "uneven"),
        Record("time", np.arange(10) * 0.5e-3, -np.arange(10.0), "t2"),
    ]
    p = tmp_path / "many.unv"
    write_uff(p, recs)
    back = read_uff(p)
    assert [r.kind for r in back] == ["time", "frf", "time"]
    np.testing.assert_array_equal(back[1].x, f_uneven)  # binary: abscissa stored point by point, exact
    np.testing.assert_array_equal(back[1].data, H)
    x, fs, name = read_time_record(p, channel=1)
    assert name == "t2" and fs == pytest.approx(2000.0, rel=1e-12)
    np.testing.assert_array_equal(x, -np.arange(10.0))


def test_csv_round_trip(tmp_path):
    f, H = _frf()
    p = tmp_path / "h.csv"
    write_csv_frf(p, f, H, name="kg")
    f2, H2 = read_frf(p)
    np.testing.assert_array_equal(f2, f)  # %.17g round-trips doubles exactly
    np.testing.assert_array_equal(H2, H)
    X = np.column_stack([np.linspace(0, 1, 50), np.cos(np.arange(50))])
    pt = tmp_path / "x.csv"
    write_csv_time(pt, X, 1000.0, names=["force_N", "acc_m_s2"])
    x, fs, name = read_csv_time(pt, "acc_m_s2")
    np.testing.assert_array_equal(x, X[:, 1])
    assert name == "acc_m_s2" and fs == pytest.approx(1000.0, rel=1e-12)
    # the trfam CLI's CSV layout is accepted
    pc = tmp_path / "trfam.csv"
    np.savetxt(
        pc,
        np.column_stack([f, H.real, H.imag, abs(H), np.degrees(np.angle(H))]),
        delimiter=",",
        header="frequency_hz,re_kg,im_kg,magnitude_kg,phase_deg",
        comments="",
    )
    np.testing.assert_allclose(read_csv_frf(pc)[1], H, rtol=1e-15)


def test_io_errors(tmp_path):
    with pytest.raises(ModelError) as e:
        read_time_record(tmp_path / "missing.csv")
    assert e.value.key == "file"
    p = tmp_path / "frf.uff"
    f, H = _frf()
    write_uff_frf(p, f, H)
    with pytest.raises(ModelError) as e:
        read_time_record(p)
    assert e.value.key == "file" and "no time record" in e.value.allowed
    bad = tmp_path / "bad.csv"
    bad.write_text("time_s,x\n0,1\n0.1,2\n0.3,3\n")
    with pytest.raises(ModelError) as e:
        read_time_record(bad)
    assert "evenly" in e.value.allowed
    good = tmp_path / "good.csv"
    good.write_text("time_s,x\n0,1\n0.1,2\n0.2,3\n")
    with pytest.raises(ModelError) as e:
        read_csv_time(good, "y")
    assert e.value.key == "channel"
    nofrf = tmp_path / "n.csv"
    nofrf.write_text("frequency_hz,mag\n1,2\n")
    with pytest.raises(ModelError) as e:
        read_frf(nofrf)
    assert e.value.key == "file"


def test_parameters_toml_is_accepted_by_the_model():
    f, _ = _frf()
    w2 = (2 * np.pi * f) ** 2
    H = sum(1.0 / ((2 * np.pi * fk) ** 2 * (1 + 1j * e) - w2) for fk, e in [(115.8, 0.0764), (182.0, 0.046)])
    circles = loss_factor_circle(f, H, [115.8, 182.0])
    E_table = [[200.0, 5.3e9], [100.0, 5.1e9]]  # unsorted on purpose: written sorted
    text = parameters_toml(
        "casing", alpha=47.97, beta=8.5e-6, loss_factor=circles, E=E_table, comment="identified from Table 1"
    )
    data = tomllib.loads(text)["casing"]
    assert data["E"] == [[100.0, 5.1e9], [200.0, 5.3e9]]
    # (an exact two-mode sum: the circle fits' neighbour correction converges to its tolerance, < 1e-6)
    np.testing.assert_allclose(np.array(data["loss_factor"])[:, 1], [0.0764, 0.046], rtol=1e-6)
    m = load_model().with_overrides({f"casing.{k}": v for k, v in data.items()})
    spec = m.bodies["casing"]
    assert spec.alpha == 47.97 and spec.beta == 8.5e-6
    assert spec.modulus(150.0) == pytest.approx(5.2e9, rel=1e-12)
    # scalar form, no section header (to paste under an existing [cable])
    lines = parameters_toml(alpha=1.0, loss_factor=0.02, E=2.1e11)
    assert tomllib.loads(lines) == {"alpha": 1.0, "loss_factor": 0.02, "E": 2.1e11}


def test_parameters_toml_rejects_what_the_model_rejects():
    with pytest.raises(ModelError) as e:
        parameters_toml("casing", beta=-1e-6)
    assert e.value.key == "beta" and "nonnegative" in e.value.allowed
    with pytest.raises(ModelError) as e:
        parameters_toml("casing", E=[[100.0, 5e9], [100.0, 6e9]])
    assert e.value.key == "E"
    with pytest.raises(ModelError) as e:
        parameters_toml("housing", alpha=1.0)
    assert e.value.key == "body"


def test_a_uff_function_of_one_value_is_refused_by_name(tmp_path):
    """pyuff cannot write one abscissa value (an internal error before)."""
    from cablecasing_core.identification import write_uff_frf

    with pytest.raises(ModelError, match=r"a UFF 58 FRF needs at least 2 abscissa values"):
        write_uff_frf(tmp_path / "one.uff", [10.0], [1.0 + 0.0j])
    assert not (tmp_path / "one.uff").exists()


# ------------------------------------------------------------------ writers refuse bad input (review t14/t15)


def _good_time():
    return np.sin(np.arange(64) * 0.3)


def _writer_cases():
    f, H = _frf()
    H_nan = H.copy()
    H_nan[10] = np.nan  # (pyuff wrote it as 0 and read it back as 0j)
    f_uneven = np.sort(np.r_[f[:400], f[400:] + 0.01 * np.arange(399)])
    x_nan = _good_time()
    x_nan[5] = np.inf
    rec = Record("time", np.arange(64) / 1000.0, _good_time(), "t")
    return [
        ("uff nan", lambda p: write_uff_frf(p, f, H_nan), "H"),
        ("uff fewer values", lambda p: write_uff_frf(p, f, H[:-5]), "H"),  # (was cut to 794 frequencies)
        ("uff more values", lambda p: write_uff_frf(p, f[:-5], H), "H"),  # (5 frequencies were made up)
        ("uff uneven mismatch", lambda p: write_uff_frf(p, f_uneven, H[:-5]), "H"),  # (pyuff's bare Exception)
        ("uff decreasing", lambda p: write_uff_frf(p, f[::-1], H[::-1]), "freqs_hz"),
        ("uff repeated", lambda p: write_uff_frf(p, np.r_[f[:5], f[4:-1]], H), "freqs_hz"),
        ("uff nan frequency", lambda p: write_uff_frf(p, np.r_[np.nan, f[1:]], H), "freqs_hz"),
        ("uff time complex", lambda p: write_uff_time(p, np.exp(1j * np.arange(100.0)), 1000.0), "x"),  # (real part)
        ("uff time inf", lambda p: write_uff_time(p, x_nan, 1000.0), "x"),
        ("uff time fs", lambda p: write_uff_time(p, _good_time(), 0.0), "fs"),
        (
            "uff record complex",
            lambda p: write_uff(p, [rec, Record("time", rec.x, rec.data * 1j, "c")]),
            "records[1].data",
        ),
        ("uff record decreasing", lambda p: write_uff(p, [Record("time", rec.x[::-1], rec.data)]), "records[0].x"),
        ("csv nan", lambda p: write_csv_frf(p, f, H_nan), "H"),
        ("csv mismatch", lambda p: write_csv_frf(p, f, H[:-5]), "H"),  # (numpy's ValueError)
        ("csv decreasing", lambda p: write_csv_frf(p, f[::-1], H[::-1]), "freqs_hz"),
        ("csv time inf", lambda p: write_csv_time(p, x_nan, 1000.0), "x"),
        ("csv time complex", lambda p: write_csv_time(p, _good_time() * 1j, 1000.0), "x"),
        ("csv time names", lambda p: write_csv_time(p, np.column_stack([x_nan, x_nan]), 1e3, names=["a"]), "x"),
        ("csv time names2", lambda p: write_csv_time(p, np.ones((5, 2)), 1e3, names=["a"]), "names"),
    ]


@pytest.mark.parametrize("case", _writer_cases(), ids=lambda c: c[0])
def test_writers_refuse_bad_input_and_keep_the_old_file(tmp_path, case):
    _, write, key = case
    f, H = _frf()
    p = tmp_path / "out.csv" if "csv" in case[0] else tmp_path / "out.uff"
    if p.suffix == ".csv":
        write_csv_frf(p, f, H)
    else:
        write_uff_frf(p, f, H)
    before = p.read_bytes()
    with pytest.raises(ModelError) as e:
        write(p)
    assert e.value.key == key
    # checked before anything is written: the good file byte for byte, and no temporary file left
    assert p.read_bytes() == before
    assert sorted(q.name for q in tmp_path.iterdir()) == [p.name]


def _pyuff_frf(path, x, unit, id4):
    import pyuff

    f, H = _frf()
    s = pyuff.prepare_58(
        binary=1, func_type=4, rsp_node=1, rsp_dir=3, ref_node=1, ref_dir=3, data=H, x=x, id1="H", id4=id4,
        abscissa_spacing=1, abscissa_spec_data_type=18, abscissa_axis_units_lab=unit, ordinate_spec_data_type=8,
        orddenom_spec_data_type=13, ordinate_axis_units_lab="m", orddenom_axis_units_lab="N", z_axis_spec_data_type=0,
    )  # fmt: skip
    pyuff.UFF(str(path)).write_sets([s], mode="add")


@pytest.mark.parametrize("unit, x_of_f", [("rad/s", lambda f: 2 * np.pi * f), ("Hz", lambda f: f + 100.0)])
def test_a_stale_id_line_tag_does_not_override_the_header(tmp_path, unit, x_of_f):
    """A file re-saved in rad/s or shifted by another tool that kept ID line 4's tag (review t30: it read
    2 pi too low, or 100.5 Hz as 0.5 Hz): the header's abscissa is used, with a warning."""
    f, _ = _frf()
    p = tmp_path / "stale.uff"
    _pyuff_frf(p, x_of_f(f), unit, "cablecasing x0=0.5 dx=0.5")
    with pytest.warns(ModelWarning, match="header's abscissa is used"):
        f_read, _ = read_frf(p)
    truth = x_of_f(f) / (2 * np.pi) if unit == "rad/s" else x_of_f(f)
    # the header stores start and step in E13.5: each within 5e-6 relative, the k-th point within 5e-6 (1 + k)
    np.testing.assert_allclose(f_read, truth, rtol=5e-6 * f.size)
    assert f_read[0] == pytest.approx(truth[0], rel=5e-6)


def test_a_tag_that_agrees_with_the_header_gives_the_exact_abscissa(tmp_path):
    # 0.123456789 and 0.0123456789 round in E13.5 by 2.5e-6 and 4.6e-6 of themselves: the tag agrees
    f = 0.123456789 + np.arange(50) * 0.0123456789
    p = tmp_path / "exact.uff"
    write_uff_frf(p, f, 1.0 / (1.0 + 1j * f))
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelWarning)
        f_read, _ = read_frf(p)
    # the tag's start and step, exact (the header's 0.123457 would be 2.5e-6 off)
    assert f_read[0] == f[0]
    np.testing.assert_array_equal(f_read, f[0] + np.arange(50) * (f[1] - f[0]))


def test_a_nan_in_a_read_frf_names_the_file_and_frequency(tmp_path):
    """An ASCII UFF from another tool with a literal NaN (review t17: reported as H = 'array with nan/inf')."""
    f, H = _frf()
    p = tmp_path / "a.uff"
    write_uff_frf(p, f, H, binary=False)
    lines = p.read_text().split("\n")
    k = 364  # the data start on line 13, two complex values (four numbers) per line
    lines[13 + k // 2] = f"{'NaN':>20}" + lines[13 + k // 2][20:]
    p.write_text("\n".join(lines))
    with pytest.raises(ModelError) as e:
        read_frf(p)
    assert e.value.key == "file" and str(p) in e.value.value
    assert f"at {f[k]:g} Hz (point {k + 1} of {f.size})" in e.value.allowed


def test_a_csv_time_in_ms_printed_with_few_digits_reads_as_the_same_time_in_s(tmp_path):
    """An analyser's time [ms] printed %.6g (review: its digits were taken as s, a quantum of 1e-2 s
    against a step of 4.9e-4 s, and the 2048 Hz record refused; the same time in s read fine)."""
    fs, t = 2048.0, np.arange(4096) / 2048.0
    x = np.sin(2 * np.pi * 115.8 * t) * np.exp(-t / 0.4)
    got = {}
    for head, scale in (("time [s]", 1.0), ("time [ms]", 1e3), ("time_ms", 1e3), ("time [sec]", 1.0)):
        p = tmp_path / f"{head.replace(' ', '')}.csv"
        np.savetxt(p, np.column_stack([scale * t, x]), delimiter=",", header=f"{head},acc", comments="", fmt="%.6g")
        got[head] = read_csv_time(p)[1]
    # %.6g of t and of 1e3 t keep the same digits (t = k/2048 and 1e3 t are exact in binary): the ms times
    # differ from the s times by the rounding of the product by 1e-3 (1e-16 relative), not by the printing
    assert got["time [ms]"] == pytest.approx(got["time [s]"], rel=1e-12)
    assert got["time_ms"] == pytest.approx(got["time [s]"], rel=1e-12)
    assert got["time [sec]"] == got["time [s]"]  # (sec is s: the same file but for the header)
    assert got["time [s]"] == pytest.approx(fs, rel=1e-7)  # least squares over 4096 times rounded to <= 5e-6 s


def test_a_csv_with_quoted_times_printed_with_few_digits_reads_as_unquoted(tmp_path):
    """A spreadsheet's export quotes every cell ("0.000488281"): the printed digits of a quoted time
    were not read, so a %.6g record (uneven in its last digit) was refused as unevenly sampled."""
    t = np.arange(2048) / 2048.0
    x = np.sin(2 * np.pi * 115.8 * t)
    rows = [f"{v:.6g},{w:.6g}" for v, w in zip(t, x)]
    plain, quoted = tmp_path / "plain.csv", tmp_path / "quoted.csv"
    plain.write_text("time [s],acc\n" + "\n".join(rows) + "\n")
    quoted.write_text('"time [s]","acc"\n' + "\n".join('"' + r.replace(",", '","') + '"' for r in rows) + "\n")
    # the same numbers either way: the same rate (2048 Hz to the least squares' 1e-7, as above)
    assert read_csv_time(quoted)[1] == read_csv_time(plain)[1] == pytest.approx(2048.0, rel=1e-7)


def test_a_csv_time_in_ms_off_its_grid_is_refused_with_the_departure_in_s(tmp_path):
    t = np.delete(np.arange(2048) / 2048.0, 1000)
    p = tmp_path / "gap.csv"
    np.savetxt(p, np.column_stack([1e3 * t, np.sin(t)]), delimiter=",", header="time [ms],acc", comments="", fmt="%.6g")
    with pytest.raises(ModelError, match=r"no sample missing") as e:
        read_csv_time(p)
    # half the printing's digit in s: times of 100 to 999 ms printed %.6g to 1e-3 ms, 5e-7 s (not 0.0005)
    assert "the rounding the file kept each time to (5e-07 s there" in str(e.value)
    assert "sample 1001 of 2047 (t = 0.48877 s) departs from that grid" in str(e.value)  # (the gap, in s)


@pytest.mark.parametrize(("unit", "scale"), [("sec", 1.0), ("Seconds", 1.0), ("msec", 1e3), ("usec", 1e6), ("us", 1e6)])
def test_a_uff_time_abscissa_in_a_unit_of_the_csv_time_table_is_converted_to_s(tmp_path, unit, scale):
    import pyuff

    t = np.arange(500) / 1000.0
    s = pyuff.prepare_58(
        binary=1, func_type=1, rsp_node=1, rsp_dir=3, ref_node=0, ref_dir=0, data=np.sin(2 * np.pi * 50 * t),
        x=scale * t, id1="acc", id4="NONE", abscissa_spacing=1, abscissa_spec_data_type=17,
        abscissa_axis_units_lab=unit, ordinate_spec_data_type=12, ordinate_axis_units_lab="m/s2",
        orddenom_spec_data_type=0, orddenom_axis_units_lab="NONE", z_axis_spec_data_type=0,
    )  # fmt: skip
    p = tmp_path / "t.uff"
    pyuff.UFF(str(p)).write_sets([s], mode="add")
    (r,) = read_uff(p)
    np.testing.assert_allclose(r.x, t, rtol=1e-12, atol=1e-15)  # (a step of 1e-3 s is exact in the header's E13.5)
    assert read_time_record(p)[1] == pytest.approx(1000.0, rel=1e-12)


def test_a_uff_time_abscissa_in_a_unit_not_of_time_is_refused(tmp_path):
    import pyuff

    t = np.arange(100) / 1000.0
    s = pyuff.prepare_58(
        binary=1, func_type=1, rsp_node=1, rsp_dir=3, ref_node=0, ref_dir=0, data=np.sin(t), x=t, id1="acc",
        id4="NONE", abscissa_spacing=1, abscissa_spec_data_type=17, abscissa_axis_units_lab="Hz",
        ordinate_spec_data_type=12, ordinate_axis_units_lab="m/s2", orddenom_spec_data_type=0,
        orddenom_axis_units_lab="NONE", z_axis_spec_data_type=0,
    )  # fmt: skip
    p = tmp_path / "t.uff"
    pyuff.UFF(str(p)).write_sets([s], mode="add")
    with pytest.raises(ModelError, match=r"abscissa unit 'Hz' is not one this reader converts; a time record.*'usec'"):
        read_uff(p)


def _two_modes(f):
    w2 = (2 * np.pi * f) ** 2
    return 1 / ((2 * np.pi * 100) ** 2 * (1 + 0.03j) - w2) + 1 / ((2 * np.pi * 230) ** 2 * (1 + 0.05j) - w2)


@pytest.mark.parametrize(
    "header,per_hz",
    [
        ("frequency [rad/s]", 2 * np.pi),
        ("frequency [kHz]", 1e-3),
        ("Frequency (Hz)", 1.0),
        ("frequency_rpm", 60.0),
        ("f_khz", 1e-3),
        ("freq", 1.0),
    ],
)
def test_a_csv_frf_frequency_column_is_read_in_its_unit(tmp_path, capsys, header, per_hz):
    """Review B 2: the frequency column's unit was ignored (rad/s read as Hz: resonances 2 pi too high,
    E 39.5 times too high; kHz 1000 times too low). It is converted as a UFF abscissa label is (one
    table, uff_io.FREQUENCY_UNITS). The written values are exact (%.17g), so the frequencies come back
    to the two roundings of the scaling (1e-14); the circle fit then finds the modes at 100 and 230 Hz
    with their loss factors (an exact modal sum: 1e-6)."""
    from cablecasing_core.cli import main

    f = np.arange(60.0, 300.0, 0.1)
    H = _two_modes(f)
    path = tmp_path / "frf.csv"
    np.savetxt(path, np.column_stack([f * per_hz, H.real, H.imag]), delimiter=",", fmt="%.17g",
               header=f"# kind = displacement\n{header},re_m_N,im_m_N", comments="")  # fmt: skip
    got, H2 = read_csv_frf(path)
    np.testing.assert_allclose(got, f, rtol=1e-14)
    np.testing.assert_array_equal(H2, H)
    assert main(["identify", "loss-factor", str(path), "--count", "2"]) == 0
    rows = [line.split() for line in capsys.readouterr().out.splitlines() if line[:4].strip().isdigit()]
    np.testing.assert_allclose([[float(r[1]), float(r[2])] for r in rows], [[100, 0.03], [230, 0.05]], rtol=1e-6)


def test_a_csv_frf_of_an_unknown_unit_or_without_the_frequency_first_is_refused(tmp_path, capsys):
    """An unknown unit is refused naming the file, the header and the units converted; a first column
    that is no frequency (the header puts it elsewhere) naming the column that is."""
    from cablecasing_core.cli import main

    f = np.arange(60.0, 300.0, 0.5)
    H = _two_modes(f)
    path = tmp_path / "frf.csv"
    np.savetxt(path, np.column_stack([f / 60, H.real, H.imag]), delimiter=",", header="frequency [min],re_H,im_H",
               comments="")  # fmt: skip
    with pytest.raises(ModelError) as e:
        read_csv_frf(path)
    assert e.value.key == "file" and e.value.value == str(path)
    assert e.value.allowed.startswith("the header of its frequency column, 'frequency [min]', gives the frequency in")
    assert "one of 'Hz', '1/s', 'cps', 'kHz', 'rad/s', 'rad/sec', 'rads/s', 'r/s', 'rpm', 'cpm', '1/min'" in (
        e.value.allowed
    )
    assert main(["identify", "loss-factor", str(path), "--count", "2"]) == 2
    assert f"error: file = '{path}': the header of its frequency column, 'frequency [min]'" in capsys.readouterr().err
    np.savetxt(path, np.column_stack([H.real, H.imag, f]), delimiter=",", header="re_H,im_H,frequency_hz", comments="")
    with pytest.raises(ModelError, match=r"its first column, headed 're_H', is not a frequency \(its column 3, "):
        read_csv_frf(path)
    np.savetxt(path, np.column_stack([f, H.real, H.imag]), delimiter=",", header="time_s,re_H,im_H", comments="")
    with pytest.raises(ModelError, match=r"its first column, headed 'time_s', is not a frequency: an FRF CSV"):
        read_csv_frf(path)


@pytest.mark.parametrize("kind", ["displacement", "velocity", "acceleration", "apparent_mass"])
def test_write_uff_frf_records_the_frf_s_kind(tmp_path, kind, capsys):
    """Review Q: write_uff_frf wrote the ordinate and denominator data types 0, so the package's own UFF FRF read
    back as kind None and `identify loss-factor` took it for apparent mass (default). With kind= the header
    holds UFF 58's types (8/11/12 over 13; 9 over 12, the trfam command's apparent mass), read back as that
    kind, and the CLI fits it as the header's kind: one structural mode converted by hand into that kind gives
    eta 0.046 to the solver's tolerance (1e-6)."""
    from cablecasing_core.cli import main
    from cablecasing_core.identification import read_frf_kind

    f, Hd = _frf()
    w = 2 * np.pi * f
    H = {"displacement": Hd, "velocity": 1j * w * Hd, "acceleration": -(w**2) * Hd, "apparent_mass": Hd / -(w**2)}
    path = tmp_path / f"{kind}.uff"
    write_uff_frf(path, f, H[kind], kind=kind)
    f2, H2, declared = read_frf_kind(path)
    assert declared == kind and np.array_equal(f2, f) and np.array_equal(H2, H[kind])
    assert main(["identify", "loss-factor", str(path), "--freqs", "182"]) == 0
    out = capsys.readouterr().out
    assert f"kind {kind} (from the header of the file)" in out
    eta = float(next(line.split()[2] for line in out.splitlines() if line.startswith("   1 ")))
    assert eta == pytest.approx(0.046, rel=1e-4)  # (printed to 5 decimals)
    with pytest.raises(ModelError, match=r"kind = 'mobility'"):
        write_uff_frf(tmp_path / "x.uff", f, H[kind], kind="mobility")
    assert not (tmp_path / "x.uff").exists()


def test_parameters_toml_writes_ten_significant_digits():
    """Review Q: the TOML printed 17-digit floats (loss_factor = [[100.22999999999767, 0.019999999999721747]]).
    Ten significant digits round by at most 5e-10 relative, far below any identified value's uncertainty
    (1e-6 at best for a circle fit of an exact FRF); 5e9 stays a float (5000000000.0, not a TOML integer); a
    table whose frequencies ten digits would make equal keeps every digit (sorted and distinct, as the model
    file requires)."""
    text = parameters_toml(loss_factor=[[100.22999999999767, 0.019999999999721747], [143.6999, 0.0150000000001]])
    assert text == "loss_factor = [[100.23, 0.02], [143.6999, 0.015]]\n"
    values = (("E", 4491874887.580095), ("beta", 2.026963540059203e-05), ("alpha", 5.6529524145416445), ("E", 5e9))
    for key, v in values:
        (read,) = tomllib.loads(parameters_toml(**{key: v})).values()
        assert isinstance(read, float) and read == pytest.approx(v, rel=5e-10)
    close = [[10.0, 5e9], [10.00000000001, 5.1e9]]
    assert np.array(tomllib.loads(parameters_toml(E=close))["E"]).tolist() == close
