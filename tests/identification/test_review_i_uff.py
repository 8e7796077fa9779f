"""Review I, D10: saving to .uff leaks no file handle (pyuff's binary writer left one open per
column: a ResourceWarning each, an error under ``-W error``), and the file written by hand is byte
for byte what pyuff writes."""

import gc
import re
import warnings

import numpy as np
import pyuff

from cablecasing_core import uff
from cablecasing_core.identification.uff_io import Record, read_uff, write_uff
from cablecasing_core.records import Records, read_records, write_records

T = np.arange(200) * 1e-4


def _functions():
    return [
        Record("time", T, np.sin(400 * T), "casing.B.Fz", 2, 3, unit="N", data_type=9, stated={"passband_hz": "3500"}),
        Record("time", T**1.5 + T, np.cos(300 * T), "uneven µ", 1, 1),  # (an uneven abscissa, a non-ASCII name)
        Record("frf", 1 + np.arange(200) * 0.5, np.exp(1j * T), "H", 1, 3),
        Record("frf", 1 + T + T**2, np.exp(2j * T), "H uneven"),
    ]


def test_saving_a_record_of_38_columns_leaves_no_file_open(tmp_path):
    rec = Records(T, {f"c{k}": np.sin((k + 1) * 100 * T) for k in range(38)})
    gc.collect()  # (what earlier tests in this process left is collected, and warned of, before the window)
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        write_records(tmp_path / "run.uff", rec)
        gc.collect()  # (a handle left open is closed, and warned of, when collected)
    assert [str(w.message) for w in said if issubclass(w.category, ResourceWarning)] == []
    back = read_records(tmp_path / "run.uff")
    assert back.names == rec.names
    for name in rec.names:
        np.testing.assert_array_equal(back.column(name), rec.column(name))


def test_the_file_written_by_hand_is_what_pyuff_writes(tmp_path):
    functions = _functions()
    write_uff(tmp_path / "mine.uff", functions)
    sets = [uff._dataset(r, True) for r in functions]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResourceWarning)  # (pyuff's own handles)
        pyuff.UFF(str(tmp_path / "pyuff.uff")).write_sets(sets, mode="add")
        gc.collect()
    # byte for byte but for each 58b ID line's byte count, which pyuff writes as 8 x the points (review AY1)
    mine, theirs = (tmp_path / "mine.uff").read_bytes(), (tmp_path / "pyuff.uff").read_bytes()
    pattern = re.compile(rb"^(    58b.{25})(.{12})", re.M)
    counts = [int(m.group(2)) for m in pattern.finditer(mine)]
    assert counts == [8 * r.x.size * ((1 if r.kind == "time" else 2) + (k % 2)) for k, r in enumerate(functions)]
    assert pattern.sub(rb"\1" + b"x" * 12, mine) == pattern.sub(rb"\1" + b"x" * 12, theirs)
    back = read_uff(tmp_path / "mine.uff")
    assert [r.name for r in back] == [r.name for r in functions]
    for r, b in zip(functions, back):
        np.testing.assert_array_equal(b.data, r.data)
    np.testing.assert_array_equal(back[1].x, functions[1].x)  # (uneven: point by point, exact)
    assert back[0].stated == {"passband_hz": "3500"}


def test_the_ascii_form_leaves_no_file_open_either(tmp_path):
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        write_uff(tmp_path / "a.uff", _functions()[:1], binary=False)
        gc.collect()
    assert not [w for w in said if issubclass(w.category, ResourceWarning)]
    np.testing.assert_allclose(read_uff(tmp_path / "a.uff")[0].data, np.sin(400 * T), rtol=1e-10)
