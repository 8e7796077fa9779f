"""A record is written only as ``read_records`` reads it back (records.check_record_values): a column
with NaN, an infinity or a magnitude above files.MAX_MAGNITUDE (1e100) is refused before anything
is written, naming the column and the time of its first such value; an earlier file stays."""

import importlib.util
import warnings

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.errors import ModelError
from cablecasing_core.files import MAX_MAGNITUDE
from cablecasing_core.records import Records, read_records, write_records

T = np.arange(1000) * 1e-4  # s
SUFFIXES = [".csv", ".npz"] + ([".uff"] if importlib.util.find_spec("pyuff") else [])


@pytest.mark.parametrize("suffix", SUFFIXES)
@pytest.mark.parametrize("bad, shown", [(np.nan, "nan"), (np.inf, "inf"), (-np.inf, "-inf"), (-1.5e100, "-1.5e+100")])
def test_a_value_a_file_cannot_give_back_is_refused_naming_the_column_and_its_time(tmp_path, suffix, bad, shown):
    """The first such value of casing.B.Fy at row 438 (t = 0.0437 s) is named; nothing is written,
    and a file written before under that name is left byte for byte."""
    path = tmp_path / f"run{suffix}"
    good = Records(T, {"casing.B.Fz": np.sin(T), "casing.B.Fy": np.cos(T)}, {"casing.B.Fz": "N", "casing.B.Fy": "N"})
    write_records(path, good)
    before = path.read_bytes()
    y = np.cos(T)
    y[437:] = bad
    with pytest.raises(ModelError) as err:
        write_records(path, Records(T, {"casing.B.Fz": np.sin(T), "casing.B.Fy": y}, good.units))
    assert err.value.key == "column" and err.value.value == "casing.B.Fy"
    assert f"holds {shown} at t = 0.0437 s (row 438 of 1000)" in str(err.value)
    assert f"nothing was written to {path}" in str(err.value)
    assert path.read_bytes() == before and [p.name for p in tmp_path.iterdir()] == [path.name]


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_what_is_written_reads_back_up_to_the_readers_limit(tmp_path, suffix):
    """The writer's limit is the reader's (files.MAX_MAGNITUDE): +-1e100 is written and read back,
    as are integer and boolean columns (read as numbers); a complex column is refused at the write,
    as the reader refuses it."""
    edge = np.where(T < 0.05, MAX_MAGNITUDE, -MAX_MAGNITUDE)
    rec = Records(T, {"big": edge, "count": np.arange(T.size), "flag": T > 0.05})
    write_records(tmp_path / f"r{suffix}", rec)
    back = read_records(tmp_path / f"r{suffix}")
    np.testing.assert_allclose(back.column("big"), edge, rtol=1e-8)  # (a CSV's 9 digits)
    np.testing.assert_array_equal(back.column("flag"), (T > 0.05).astype(float))
    with pytest.raises(ModelError, match=r"^column = 'z': holds values of type complex128: .* real numbers only"):
        write_records(tmp_path / f"c{suffix}", Records(T, {"z": T + 1j}))
    assert not (tmp_path / f"c{suffix}").exists()


def test_a_run_driven_beyond_what_it_holds_is_not_written_as_a_file_no_reader_takes(tmp_path):
    """A support motion of 1e110 m (t^3) gives finite forces of 1e103 N and more: the engine, which
    stops at NaN, runs it, and its file was written, then refused by every reader. Now its save
    names the column and the time of the first force beyond 1e100 N (its first step, 1e-5 s) and
    writes nothing."""

    def motion(t):
        t = np.atleast_1d(t)
        u, v, a = (np.zeros((t.size, 12)) for _ in range(3))
        u[:, 2], v[:, 2], a[:, 2] = 1e110 * t**3, 3e110 * t**2, 6e110 * t  # casing.A.z
        return u, v, a

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = cc.simulate(cc.load_model(), duration=2e-4, motion=motion, contact=False)
    assert np.all(np.isfinite(res.support_forces)) and np.max(np.abs(res.support_forces)) > MAX_MAGNITUDE
    for suffix in (".csv", ".npz"):
        with pytest.raises(ModelError, match=r"^column = 'casing.A.Fz': holds -1.\d+e\+103 at t = 1e-05 s \(row 2"):
            res.save(tmp_path / f"run{suffix}")
    assert not list(tmp_path.iterdir())
