"""Review AY: identifying from other tools' UFF files. AY1, the byte count of the package's own 58b header; AY6,
pyuff's own binary writer. The files' bytes are parsed here by the 58b definition (pyuff's datasets/dataset_58.py:
ID line ``(I6,1A1,I6,I6,I12,I12,I6,I6,I12,I12)``, field 6 the number of bytes following the 11 ASCII lines, the end
line ``    -1`` right after them), not by the package."""

import gc
import os
import warnings

import numpy as np
import pytest
import pyuff

from cablecasing_core.errors import ModelError, ModelWarning
from cablecasing_core.identification import (
    loss_factor_circle,
    read_frf,
    read_frf_kind,
    read_time_record,
    write_uff_frf,
)
from cablecasing_core.records import read_records
from cablecasing_core.uff import Record, frf_fields, read_uff, write_uff

F0 = 1.0 + 0.25 * np.arange(301)  # Hz, even
H = (1 + 2j) / (100.0 - F0**2 + 1j * F0)  # a complex FRF, any values
F_UNEVEN = 1.0 + np.cumsum(np.linspace(0.1, 0.4, 301))  # Hz, uneven: stored point by point


def _datasets_58b(raw):
    """Each 58b dataset of ``raw`` as (its header's byte count, the bytes between its 11 ASCII lines and its end
    line): the definition's two numbers to compare."""
    out, at = [], 0
    while (at := raw.find(b"    58b", at)) >= 0:
        id_line = raw[at : raw.index(b"\n", at)]
        declared = int(id_line[31:43])  # (field 6: I6 + A1 + I6 + I6 + I12 are the 31 characters before it)
        start = at
        for _ in range(12):  # (the ID line and the 11 ASCII lines after it)
            start = raw.index(b"\n", start) + 1
        end = raw.index(b"    -1\n", start + declared - 1 if declared else start)
        out.append((declared, end - start))
        at = end
    return out


def _pyuff_sets(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResourceWarning)
        sets = pyuff.UFF(str(path)).read_sets()
        gc.collect()
    return sets if isinstance(sets, list) else [sets]


def test_the_58b_byte_count_is_that_of_the_bytes_written(tmp_path):
    """AY1: a complex FRF of n points holds n x 2 x 8 bytes (x 3 with an uneven abscissa), a real time record
    n x 8; the header said n x 8 for all (pyuff 2.5's count), half or a third of the bytes there."""
    t = np.arange(1001) * 1e-3
    records = [
        Record("frf", F0, H, "FRF", 2, 2, **frf_fields("apparent_mass")),
        Record("frf", F_UNEVEN, H, "FRF uneven", 2, 3, **frf_fields("acceleration")),
        Record("time", t, np.sin(2 * np.pi * 50 * t), "Response", 1, 3),
    ]
    p = tmp_path / "three.uff"
    write_uff(p, records)
    found = _datasets_58b(p.read_bytes())
    assert found == [(301 * 2 * 8, 301 * 2 * 8), (301 * 3 * 8, 301 * 3 * 8), (1001 * 8, 1001 * 8)]
    # pyuff reads the file back exactly (it counts the values from the point count, not from the byte count)
    sets = _pyuff_sets(p)
    assert [s["num_pts"] for s in sets] == [301, 301, 1001]
    np.testing.assert_array_equal(sets[0]["data"], H)
    np.testing.assert_array_equal(sets[0]["x"], F0)
    np.testing.assert_array_equal(sets[1]["data"], H)
    np.testing.assert_array_equal(sets[1]["x"], F_UNEVEN)
    np.testing.assert_array_equal(sets[2]["data"], records[2].data)
    # and so does the package
    back = read_uff(p)
    for r, b in zip(records, back):
        np.testing.assert_array_equal(b.data, r.data)
    np.testing.assert_array_equal(back[1].x, F_UNEVEN)


def test_files_with_pyuffs_byte_count_are_still_read(tmp_path):
    """AY1: the package's files before the fix, and pyuff's, give n x 8 for a complex FRF: read as before."""
    p = tmp_path / "frf.uff"
    write_uff(p, [Record("frf", F0, H, "FRF", **frf_fields("acceleration"))])
    raw = p.read_bytes()
    id_line = raw.index(b"    58b")
    old = raw[: id_line + 31] + f"{301 * 8:12d}".encode() + raw[id_line + 43 :]
    q = tmp_path / "old.uff"
    q.write_bytes(old)
    assert _datasets_58b(old) == [(301 * 8, 301 * 2 * 8)]
    np.testing.assert_array_equal(read_uff(q)[0].data, H)
    np.testing.assert_array_equal(_pyuff_sets(q)[0]["data"], H)


def _pyuff_58b(n, complex_):
    """pyuff's own dataset dict of a complex FRF or a real time record of ``n`` points, binary, every field given."""
    x = 1.0 + 0.5 * np.arange(n)
    data = (1 + 2j) / (100 - x**2 + 1j) if complex_ else np.sin(x)
    d = pyuff.prepare_58(
        binary=1,
        id1="FRF" if complex_ else "T",
        id2="a",
        id3="a",
        id4="a",
        id5="a",
        func_type=4 if complex_ else 1,
        ver_num=0,
        load_case_id=0,
        rsp_ent_name="NONE",
        ref_ent_name="NONE",
        rsp_node=1,
        rsp_dir=3,
        ref_node=1,
        ref_dir=3,
        ord_data_type=6 if complex_ else 4,
        num_pts=n,
        abscissa_spacing=1,
        abscissa_min=x[0],
        abscissa_inc=0.5,
        abscissa_spec_data_type=18 if complex_ else 17,
        abscissa_axis_units_lab="Hz" if complex_ else "s",
        ordinate_spec_data_type=12,
        ordinate_axis_units_lab="m/s2",
        orddenom_spec_data_type=13 if complex_ else 0,
        orddenom_axis_units_lab="N" if complex_ else "NONE",
        data=data,
        x=x,
    )
    return d, x, data


@pytest.mark.parametrize("complex_", [True, False], ids=["complex FRF", "real time"])
def test_pyuffs_binary_writer_in_add_mode_writes_whole_files_and_overwrite_seven_bytes(tmp_path, complex_):
    """AY6, what docs/identification.md says of pyuff 2.5.8's binary writer: ``mode="add"`` on a new file writes a
    whole 58b (pyuff and the package read it exactly), ``mode="overwrite"`` a 7-byte file for real and complex
    data alike (its ``_write58`` closes the file after the header and opens it again in "w" mode for the values,
    truncating the header, and again for the end line, truncating the values: the end line is left)."""
    d, x, data = _pyuff_58b(100, complex_)
    add, over = tmp_path / "add.uff", tmp_path / "over.uff"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResourceWarning)
        pyuff.UFF(str(add)).write_sets([d], mode="add")
        pyuff.UFF(str(over)).write_sets([_pyuff_58b(100, complex_)[0]], mode="overwrite")
        gc.collect()
    assert os.path.getsize(over) == 7
    ((declared, held),) = _datasets_58b(add.read_bytes())
    assert held == 100 * 8 * (2 if complex_ else 1) and declared == 100 * 8  # (pyuff's count, AY1)
    np.testing.assert_array_equal(_pyuff_sets(add)[0]["data"], data)
    np.testing.assert_array_equal(read_uff(add)[0].data, data)


# ------------------------------------------------------------------ AY2: a non-finite value on the 0 Hz line alone

F_N = np.array([22.39861, 62.75950, 90.69011])  # Hz, the review's modes
ETA = np.array([0.02, 0.03, 0.05])
F_DC = 0.05 * np.arange(3001)  # Hz, from 0 Hz (an analyser's export)


def _accelerance(synth):
    """An exact accelerance of structural modes (m/s2/N): each mode an exact circle, so the fits give ETA."""
    return -((2 * np.pi * F_DC) ** 2) * synth.receptance(F_DC, F_N, eta=ETA, A=np.array([1.0, -0.6, 0.35]))


def _with_dc(path, value):
    """The package's binary 58b FRF at ``path`` with its first (0 Hz) value replaced by ``value``, as another
    tool writes it (the package's writer refuses a value that is not finite): a copy next to it."""
    raw = path.read_bytes()
    start = raw.index(b"    58b")
    order = "<" if int(raw[start + 7 : start + 13]) == 1 else ">"  # (field 3: 1 little endian, 2 big)
    for _ in range(12):
        start = raw.index(b"\n", start) + 1
    q = path.with_name(f"dc_{path.name}")
    q.write_bytes(raw[:start] + np.array([value.real, value.imag], order + "f8").tobytes() + raw[start + 16 :])
    return q


def _csv_with_dc(path, f, H, re_dc, im_dc, kind):
    """An FRF CSV as a third-party tool writes it, its 0 Hz line ``re_dc,im_dc`` as text (``nan``, ``inf``)."""
    lines = [f"# kind = {kind}", "frequency_hz,re_H,im_H", f"0,{re_dc},{im_dc}"]
    lines += [f"{a!r},{b.real!r},{b.imag!r}" for a, b in zip(f[1:].tolist(), H[1:].tolist())]
    path.write_text("\n".join(lines) + "\n")
    return path


def _loss_factor(identify_cli, capsys, path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)  # (lines per bandwidth: an exact FRF has no leakage)
        code = identify_cli(["identify", "loss-factor", str(path), "--count", "3"])
    out = capsys.readouterr()
    assert code == 0, out.err
    table = [line.split() for line in out.out.splitlines() if line[:4].strip().isdigit()]
    return out.out, np.array([[float(v) for v in row[1:3]] for row in table])


@pytest.mark.parametrize(
    "dc", [complex(np.nan, 0.0), complex(np.inf, np.nan), complex(-np.inf, 0.0), complex(0.0, np.inf)]
)
def test_a_non_finite_value_on_the_0_hz_line_is_left_out_with_the_line(identify_cli, capsys, tmp_path, synth, dc):
    """AY2: an accelerance whose 0 Hz line is nan (an H1 with no force at DC) or inf (another tool's 1/(F/a)) was
    refused, UFF and CSV; it is left out like the line itself, the '#' line says so, and the fit is that of the
    same FRF with a 0 at 0 Hz: f_r and eta of the exact modes (printed to 4 and 5 decimals)."""
    H = _accelerance(synth)
    clean = tmp_path / "clean.uff"
    write_uff_frf(clean, F_DC, H, kind="acceleration")
    reference, fits = _loss_factor(identify_cli, capsys, clean)
    np.testing.assert_allclose(fits[:, 0], F_N, atol=1e-4)  # (exact circles: f_r to its 4 printed decimals)
    np.testing.assert_allclose(fits[:, 1], ETA, atol=1e-5)  # (eta to its 5 printed decimals)
    csv = _csv_with_dc(tmp_path / "dc.csv", F_DC, H, dc.real, dc.imag, "acceleration")
    for p in (_with_dc(clean, dc), csv):
        with warnings.catch_warnings():  # (nor numpy's: 1j * inf on the 0 Hz line, review BA4)
            warnings.simplefilter("error", RuntimeWarning)
            f, H_read, kind = read_frf_kind(p)
        assert kind == "acceleration" and f[0] == 0.0 and not np.isfinite(H_read[0])  # (returned as read)
        np.testing.assert_array_equal(H_read[1:], H[1:])
        out, got = _loss_factor(identify_cli, capsys, p)
        assert "# the 0 Hz line is left out (no resonance uses it)" in out
        np.testing.assert_array_equal(got, fits)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ModelWarning)
            np.testing.assert_array_equal(
                [r.eta for r in loss_factor_circle(f, H_read, count=3, kind="acceleration")],
                [r.eta for r in loss_factor_circle(F_DC, H, count=3, kind="acceleration")],
            )


def test_an_apparent_mass_infinite_at_0_hz_is_read(tmp_path, synth):
    """AY2: an apparent mass F/a computed as 1/(a/F) from 0 Hz is inf + nan i there (by definition infinite)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        am = 1.0 / _accelerance(synth)
    assert not np.isfinite(am[0])
    p = tmp_path / "am0.uff"
    write_uff_frf(p, F_DC, np.where(np.isfinite(am), am, 0), kind="apparent_mass")  # (its writer refuses an inf)
    for q in (_with_dc(p, am[0]), _csv_with_dc(tmp_path / "am.csv", F_DC, am, "inf", "nan", "apparent_mass")):
        f, H_read, kind = read_frf_kind(q)
        assert kind == "apparent_mass" and f.size == 3001 and not np.isfinite(H_read[0])
        np.testing.assert_array_equal(H_read[1:], am[1:])


def test_a_non_finite_value_elsewhere_is_refused_with_advice_that_can_be_followed(tmp_path, synth):
    """AY2: a nan at the first line of an FRF that starts above 0 Hz, or at 55 Hz beside a nan 0 Hz line, is still
    refused, naming its point, and the lines that could be kept are whole lines of the function: 'cut the function
    before it' at point 1 left nothing."""
    H = _accelerance(synth)[1:]
    f = F_DC[1:]
    p = tmp_path / "from_005.uff"
    write_uff_frf(p, f, H, kind="acceleration")
    with pytest.raises(ModelError) as e:
        read_frf(_with_dc(p, complex(np.nan, np.nan)))  # (its first line, 0.05 Hz)
    text = e.value.allowed
    assert "at 0.05 Hz (point 1 of 3000)" in text and "only a 0 Hz line" in text, text
    assert "before it" not in text and "the lines after it (points 2 to 3000)" in text, text
    # a nan at 0 Hz and at 55 Hz: the 55 Hz one is named, the lines on either side of it
    H0 = _accelerance(synth)
    H0[F_DC == 55.0] = np.nan
    csv = _csv_with_dc(tmp_path / "two.csv", F_DC, H0, "nan", "nan", "acceleration")
    with pytest.raises(ModelError) as e:
        read_frf(csv)
    assert "line 1103, column 2 is not a finite number" in e.value.allowed, e.value.allowed  # (2 + 1100 + 1)
    assert "only the 0 Hz line, which the fits leave out, may hold another value" in e.value.allowed
    q = tmp_path / "two.uff"
    write_uff_frf(q, F_DC, np.where(F_DC == 55.0, 0, H0), kind="acceleration")
    raw = bytearray(_with_dc(q, complex(np.nan, 0)).read_bytes())
    at = raw.index(np.array([H0[1].real, H0[1].imag]).tobytes()) + 16 * 1099  # (line 1101, 55 Hz)
    raw[at : at + 16] = np.array([np.nan, np.nan]).tobytes()
    q.write_bytes(bytes(raw))
    with pytest.raises(ModelError) as e:
        read_frf(q)
    text = e.value.allowed
    assert "at 55 Hz (point 1101 of 3001):" in text, text  # (the 0 Hz line's nan not counted as another)
    assert "points 1 to 1100" in text and "points 1102 to 3001" in text, text


def test_the_0_hz_exception_is_an_frfs_alone(tmp_path, identify_cli, capsys):
    """AY2: a time record's CSV whose first sample (t = 0) is nan, and a table mode,f_hz with a nan, are refused as
    before: only an FRF's reader leaves a 0 Hz line out."""
    from cablecasing_core.records import read_records

    p = tmp_path / "t.csv"
    p.write_text("time_s,x\n0,nan\n0.001,1\n0.002,2\n0.003,1\n")
    with pytest.raises(ModelError, match="line 2, column 2 is not a finite number of magnitude at most 1e100$"):
        read_records(p)
    q = tmp_path / "modes.csv"
    q.write_text("f_hz,mode\n0,nan\n22.4,1\n")
    model = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "straight_casing.toml")
    assert identify_cli(["identify", "modulus", str(q), "--model", model]) == 2
    err = capsys.readouterr().err
    assert "line 2, column 2 is not a finite number of magnitude at most 1e100\n" in err, err


# ------------------------------------------------------------------ AY4: one bad time function of a file


T3 = np.arange(3000) * 1e-3  # s, 1 kHz


def _two_functions(tmp_path, force, response, name="two.uff"):
    """A force and a response record in one UFF file (``force``, ``response``: (time, values)), as an analyser
    exports them; a value that is not finite put in afterwards (the package's writer refuses one)."""
    p = tmp_path / name
    write_uff(
        p,
        [
            Record("time", force[0], np.nan_to_num(force[1]), "Force", 3, 3, unit="N", data_type=13),
            Record("time", response[0], response[1], "Response", 1, 3, unit="m/s2", data_type=12),
        ],
    )
    bad = np.flatnonzero(~np.isfinite(force[1]))
    if bad.size:  # (the first dataset's values: after its 11 ASCII lines, 8 bytes each, the machine's order)
        raw = bytearray(p.read_bytes())
        start = raw.index(b"    58b")
        for _ in range(12):
            start = raw.index(b"\n", start) + 1
        for k in bad:
            raw[start + 8 * k : start + 8 * k + 8] = np.array([force[1][k]]).tobytes()
        p.write_bytes(bytes(raw))
    return p


def test_a_nan_in_another_channel_names_it_and_says_why_the_file_is_refused(tmp_path):
    """AY4: a nan in Force at 2.5 s refused `--channel Response` saying only "cut the function before it". The
    file is still refused as a whole (its functions are one record), and the message now says so, that the
    channel asked for is not concerned, and which whole parts could be exported."""
    force = np.zeros(T3.size)
    force[1], force[2500] = 1.0, np.nan
    p = _two_functions(tmp_path, (T3, force), (T3, np.sin(2 * np.pi * 20 * T3)))
    with pytest.raises(ModelError) as e:
        read_time_record(p, "Response")
    assert e.value.value == f"{p} (Force)"
    text = e.value.allowed
    assert "at 2.5 s (point 2501 of 3000)" in text, text
    assert "the channel asked for, Response, is not concerned, but" in text and "refused as a whole" in text, text
    assert "points 1 to 2500" in text and "points 2502 to 3000" in text and "without Force" in text, text
    with pytest.raises(ModelError) as e:  # (Force itself, or no channel: not said to be unconcerned)
        read_time_record(p, "Force")
    assert "not concerned" not in e.value.allowed and "refused as a whole" in e.value.allowed
    with pytest.raises(ModelError) as e:
        read_records(p)
    assert "not concerned" not in e.value.allowed


def test_time_axes_of_another_length_are_named_with_their_samples_start_and_step(tmp_path):
    """AY4: "has another time axis than the first" gave neither axis nor what is allowed."""
    a = np.sin(2 * np.pi * 20 * T3)
    p = _two_functions(tmp_path, (T3, a), (T3[:2990], a[:2990]))
    with pytest.raises(ModelError) as e:
        read_time_record(p, "Force")
    text = e.value.allowed
    assert (
        "time function 1 (Response) has another time axis than the first (Force): 2990 samples from 0 s every "
        "0.001 s, against 3000 samples from 0 s every 0.001 s" in text
    ), text
    assert "the same start, step and number of samples" in text, text
    assert "the channel asked for, Force, is not concerned" in text and "cut to the shorter" in text, text


def test_a_nan_at_a_records_first_sample_is_not_told_to_cut_before_it(tmp_path):
    """AY4/AY2: the advice is one that can be followed: at point 1 the record from the next sample."""
    x = np.sin(2 * np.pi * 20 * T3)
    x[0] = np.nan
    p = tmp_path / "one.uff"
    write_uff(p, [Record("time", T3, np.nan_to_num(x), "Response", 1, 3, unit="m/s2", data_type=12)])
    raw = bytearray(p.read_bytes())
    start = raw.index(b"    58b")
    for _ in range(12):
        start = raw.index(b"\n", start) + 1
    raw[start : start + 8] = np.array([np.nan]).tobytes()
    p.write_bytes(bytes(raw))
    with pytest.raises(ModelError) as e:
        read_time_record(p)
    text = e.value.allowed
    assert "(point 1 of 3000)" in text and "up to" not in text and "the record from 0.001 s (points 2 to 3000)" in text
    assert "refused as a whole" not in text, text  # (one function: nothing else to refuse)


def _uff_with_nan_at(tmp_path, points):
    """A one-function UFF time record on T3 whose samples at ``points`` (0-based) are NaN (written as
    finite and set to NaN in the file's bytes, as an overloaded channel's export)."""
    x = np.sin(2 * np.pi * 20 * T3)
    p = tmp_path / "nan.uff"
    write_uff(p, [Record("time", T3, x, "Response", 1, 3, unit="m/s2", data_type=12)])
    raw = bytearray(p.read_bytes())
    start = raw.index(b"    58b")
    for _ in range(12):
        start = raw.index(b"\n", start) + 1
    for k in points:  # (data type 12 binary: 8 bytes per sample, the abscissa even)
        raw[start + 8 * k : start + 8 * k + 8] = np.array([np.nan]).tobytes()
    p.write_bytes(bytes(raw))
    return p


def test_the_runs_named_around_a_nan_are_the_samples_on_each_side(tmp_path):
    """Review BF2: NaN at samples 101-103 of 3000 (0-based 100-102, 1 ms apart): the record up to
    the last good sample, 0.099 s (points 1 to 100), or from the first good one after, 0.103 s
    (points 104 to 3000): the times are those of the kept samples themselves."""
    with pytest.raises(ModelError) as e:
        read_time_record(_uff_with_nan_at(tmp_path, [100, 101, 102]))
    text = e.value.allowed
    assert "the record up to 0.099 s (points 1 to 100) or the record from 0.103 s (points 104 to 3000)" in text, text


def test_runs_to_keep_names_the_points_on_each_side_of_the_bad_ones():
    """files.runs_to_keep on a mask of 10 points, from its definition: the run before the first bad
    point and the one after the last, 1-based, none where the bad points reach an end."""
    from cablecasing_core.files import runs_to_keep

    def runs(bad_at):
        mask = np.zeros(10, bool)
        mask[bad_at] = True
        return runs_to_keep(mask, lambda k: f"before {k}", lambda j: f"after {j}")

    assert runs([3]) == ["before 3 (points 1 to 3)", "after 4 (points 5 to 10)"]
    assert runs([2, 3, 4, 5]) == ["before 2 (points 1 to 2)", "after 6 (points 7 to 10)"]
    assert runs([0]) == ["after 1 (points 2 to 10)"]
    assert runs([9]) == ["before 9 (points 1 to 9)"]
    assert runs([8]) == ["before 8 (points 1 to 8)", "after 9 (points 10 to 10)"]
    assert runs([0, 9]) == []
