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
