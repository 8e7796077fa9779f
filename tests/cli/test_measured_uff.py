"""A measured UFF whose time functions share one id1 (an analyser's export names each "Response" and
tells them apart by node and direction) is read by every command that reads records: the functions
whose id1 repeats are named <id1>@<node><direction>; only functions that repeat those too are refused."""

import numpy as np
import pytest

from cablecasing_core.cli import main
from cablecasing_core.identification.uff_io import Record, write_uff
from cablecasing_core.records import read_records

FS = 4096.0


def _signal(f, seed):
    t = np.arange(16384) / FS
    return np.exp(-3 * t) * np.sin(2 * np.pi * f * t) + 1e-3 * np.random.default_rng(seed).standard_normal(t.size)


def _write(path, dofs):
    """A UFF of time functions "Response" at (node, direction) ``dofs``, one more named "Force"; each
    "Response" a decaying sine of its own frequency (100, 200, ... Hz)."""
    t = np.arange(16384) / FS
    funcs = [
        Record("time", t, _signal(100.0 * (k + 1), k), "Response", node, d, unit="m/s2", data_type=12)
        for k, (node, d) in enumerate(dofs)
    ]
    funcs.append(Record("time", t, _signal(700.0, 9), "Force", 1, 3, unit="N", data_type=9))
    write_uff(path, funcs)
    return path


def test_functions_of_one_id1_are_named_by_node_and_direction(tmp_path, capsys):
    path = _write(tmp_path / "m.uff", [(1, 3), (2, -3), (2, 5)])
    rec = read_records(path)
    assert list(rec.columns) == ["Response@1z", "Response@2-z", "Response@2ry", "Force"]
    assert rec.units["Response@2-z"] == "m/s2" and rec.units["Force"] == "N"
    assert np.array_equal(rec.columns["Response@2-z"], _signal(200.0, 1))  # (each its own function)
    capsys.readouterr()
    assert main(["bands", str(path), "--column", "Response@2-z", "--kind", "octave", "--skip", "0"]) == 0
    assert "# " + str(path) + ": Response@2-z after 0 s, octave bands" in capsys.readouterr().out
    assert main(["spectrum", str(path), "--column", "Response@1z", "--skip", "0", "--fmin", "50"]) == 0
    assert "# Response@1z: RMS" in capsys.readouterr().out
    # identify damping picks a function by the same name: the second one, at 200 Hz
    assert main(["identify", "damping", str(path), "--channel", "Response@2-z", "--freqs", "200"]) == 0
    row = capsys.readouterr().out.splitlines()[2].split()
    assert row[0] == "1" and abs(float(row[3]) - 200.0) < 1.0


def test_the_repeated_id1_alone_is_refused_naming_the_columns(tmp_path, capsys):
    path = _write(tmp_path / "m.uff", [(1, 3), (2, 3)])
    assert main(["bands", str(path), "--column", "Response"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        f"cablecasing: error: --column = 'Response': must be a column of {path}: Response@1z, Response@2z, Force"
    ]
    assert main(["identify", "damping", str(path), "--channel", "Response"]) == 2
    assert "--channel = 'Response': must be 0..2 or a name in the file: Response@1z, Response@2z, Force" in (
        capsys.readouterr().err
    )


def test_functions_of_one_id1_node_and_direction_are_refused(tmp_path, capsys):
    path = _write(tmp_path / "m.uff", [(1, 3), (1, 3)])
    with pytest.raises(Exception, match="time function 1 repeats the name of an earlier one, Response@1z"):
        read_records(path)
    assert main(["bands", str(path), "--column", "Force"]) == 2
    assert "names must be unique" in capsys.readouterr().err
