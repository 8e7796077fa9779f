"""Review I, records: a Records whose columns do not match its time is
refused when made, naming the column and both lengths (D4); a CSV column's name with a comma or a
quote reads back, one a CSV header cannot give back is refused before writing (D5)."""

import numpy as np
import pytest

from cablecasing_core.errors import ModelError
from cablecasing_core.records import Records, read_records, write_records

FS = 1e4
T = np.arange(0, 1, 1 / FS)
A = np.random.default_rng(1).standard_normal(T.size)


# ---------------------------------------------------------------- D4: a record checked when made


def test_a_column_not_as_long_as_the_time_is_refused_naming_it_and_both_lengths(tmp_path):
    with pytest.raises(ModelError, match=r"^columns\['casing.A.az'\] = 100 samples: .* as long as the time: 10000"):
        Records(T, {"casing.A.az": A[:100]}, {"casing.A.az": "m/s2"})
    with pytest.raises(ModelError, match=r"^columns\['x'\] = an array of shape \(10000, 1\)"):
        Records(T, {"x": A[:, None]})
    with pytest.raises(ModelError, match=r"^time = .*: must be a 1-D array of real numbers"):
        Records(T[:, None], {"x": A})
    with pytest.raises(ModelError, match=r"^time = nan at sample 3: must hold finite numbers"):
        Records(np.where(np.arange(T.size) == 3, np.nan, T), {"x": A})
    with pytest.raises(ModelError, match=r"^columns = .*: must be a dict"):
        Records(T, [A])
    assert not (tmp_path / "r.csv").exists()


def test_lists_are_taken_as_arrays_and_the_callers_dict_is_left_alone():
    cols = {"casing.A.az": list(A)}
    rec = Records(list(T), cols)
    assert rec.fs == pytest.approx(FS) and isinstance(rec.time, np.ndarray)
    assert isinstance(rec.columns["casing.A.az"], np.ndarray) and isinstance(cols["casing.A.az"], list)
    # (a NaN in a column is a measurement's gap: kept, and refused by what cannot take it)
    assert np.isnan(Records(T, {"x": np.where(T > 0.5, np.nan, A)}).column("x")[-1])


def test_a_file_whose_columns_do_not_match_is_still_refused_naming_the_file(tmp_path):
    path = tmp_path / "bad.npz"
    np.savez(path, time=T, x=A, y=A[:10])  # (the loose form: the columns as long as the time are kept)
    assert read_records(path).names == ("x",)
    np.savez(path, time=np.where(T > 0.5, np.nan, T), x=A)
    with pytest.raises(ModelError, match=r"^file = .*bad.npz': sample 5002 is not a finite number"):
        read_records(path)


# ---------------------------------------------------------------- D5: CSV names that read back


def test_a_name_with_a_comma_or_a_quote_is_quoted_in_the_header_and_reads_back(tmp_path):
    F = 2 * A
    rec = Records(T, {"my force, N": F, 'say "x"': A, "acc": A}, {"my force, N": "N", "acc": "m/s2"})
    write_records(tmp_path / "odd.csv", rec)
    assert (tmp_path / "odd.csv").read_text().splitlines()[0] == 'time [s],"my force, N [N]","say ""x""",acc [m/s2]'
    back = read_records(tmp_path / "odd.csv")
    assert back.names == ("my force, N", 'say "x"', "acc")
    assert back.units == {"my force, N": "N", 'say "x"': "", "acc": "m/s2"}
    # (the CSV keeps 9 significant digits: 5e-9)
    np.testing.assert_allclose(back.column("my force, N"), F, rtol=1e-8)


@pytest.mark.parametrize(
    "name, why",
    [
        ("a\nb", "a line break"),
        ("a\rb", "a line break"),
        ("a\x0cb", "a line break"),  # (a form feed, U+2028: str.splitlines, the reader's, splits there too)
        ("a\u2028b", "a line break"),
        ("x [y]", "read as 'x' \\[y\\]"),
        (" padded", "read as 'padded'"),
        ("casing.B.Fz_N", "read as 'casing.B.Fz'"),
    ],
)
def test_a_name_a_csv_header_cannot_give_back_is_refused_before_writing(tmp_path, name, why):
    with pytest.raises(ModelError, match=f"^column = .*: holds .*{why}"):
        write_records(tmp_path / "r.csv", Records(T, {name: A}))
    assert not list(tmp_path.iterdir())
    write_records(tmp_path / "r.npz", Records(T, {name: A}))  # (.npz keeps any name)
    assert read_records(tmp_path / "r.npz").names == (name,)


def test_spectrum_out_of_a_column_named_with_a_comma_reads_back_as_its_columns(tmp_path, capsys):
    """`spectrum --out` of a column ``acc, sensor 3`` (a name a record's CSV holds, quoted): its
    table's header is quoted as the record's is, so it reads back as one column per field (it was
    joined with bare commas: 5 names over 3 columns, which the package's own reader refused)."""
    from cablecasing_core.cli import main
    from cablecasing_core.files import read_csv_table

    write_records(tmp_path / "r.csv", Records(T, {"acc, sensor 3": A}, {"acc, sensor 3": "m/s2"}))
    out = tmp_path / "s.csv"
    assert main(["spectrum", str(tmp_path / "r.csv"), "--column", "acc, sensor 3", "--out", str(out)]) == 0
    capsys.readouterr()
    names, data = read_csv_table(out)
    assert list(names) == [
        "frequency [Hz]",
        "acc, sensor 3 PSD [(m/s2)^2/Hz]",
        "acc, sensor 3 level [dB re (1e-06 m/s2)^2/Hz]",
    ]
    assert data.shape[1] == 3
