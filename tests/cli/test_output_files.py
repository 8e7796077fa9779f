"""Output files (issue 26): an interrupt during the save leaves the previous file bitwise intact and
the message says it was kept; a full, unwritable or special target is refused before the run."""

import errno
import os

import numpy as np
import pytest

from cablecasing_core.cli import main


def _interrupt_after_a_part(monkeypatch, module, name):
    """``module.name`` (a numpy writer) writes a part of its file, then Ctrl-C arrives."""
    real = getattr(module, name)

    def writes_then_interrupted(file, *args, **kwargs):
        real(file, *args, **kwargs)
        if hasattr(file, "write"):  # a handle (Ensemble.save): the writer had come half way
            file.flush()
            file.truncate(max(file.tell() // 2, 1))
        else:
            with open(file, "r+b") as fh:
                fh.truncate(max(os.path.getsize(file) // 2, 1))
        raise KeyboardInterrupt

    monkeypatch.setattr(module, name, writes_then_interrupted)


@pytest.mark.parametrize("suffix,writer", [(".csv", "savetxt"), (".npz", "savez_compressed")])
def test_an_interrupt_during_the_save_of_simulate_leaves_the_old_file_bitwise(
    tmp_path, capsys, monkeypatch, suffix, writer
):
    out = tmp_path / f"r{suffix}"
    old = os.urandom(5000) + b"\nan earlier result\n"
    out.write_bytes(old)
    _interrupt_after_a_part(monkeypatch, np, writer)
    assert main(["simulate", "--duration", "0.001", "--no-progress", "--out", str(out)]) == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"cablecasing: interrupted: the run was stopped: the previous {out} kept as it was"]
    assert out.read_bytes() == old and sorted(p.name for p in tmp_path.iterdir()) == [out.name]


def _parts(tmp_path):
    from cablecasing_core.studies import Ensemble

    names = []
    for k, seeds in enumerate(((1, 2), (3, 4))):
        ens = Ensemble(
            np.array(seeds),
            "casing.B.Fz",
            ("oct1",),
            np.array([11.0]),
            np.array([22.0]),
            np.array([[0.1], [0.2]]) * (k + 1),
            {},
            np.zeros((2, 0)),
            {"duration": 1.0},
        )
        ens.save(tmp_path / f"p{k}.csv")
        names.append(str(tmp_path / f"p{k}.csv"))
    return names


def test_an_interrupt_during_the_save_of_pool_leaves_the_old_file_bitwise(tmp_path, capsys, monkeypatch):
    parts = _parts(tmp_path)
    out = tmp_path / "pooled.csv"
    old = b"an earlier pool\n" * 300
    out.write_bytes(old)
    _interrupt_after_a_part(monkeypatch, np, "savetxt")  # (Ensemble.save's rows)
    assert main(["pool", *parts, "--out", str(out)]) == 130
    assert capsys.readouterr().err.strip().endswith(f"stopped: the previous {out} kept as it was")
    assert out.read_bytes() == old and sorted(p.name for p in tmp_path.iterdir()) == ["p0.csv", "p1.csv", "pooled.csv"]


def test_an_interrupt_during_the_save_of_an_ensemble_leaves_the_old_file_bitwise(tmp_path, capsys, monkeypatch):
    from cablecasing_core.studies import ensemble_runs, load_ensemble

    member = load_ensemble(_parts(tmp_path)[0])
    monkeypatch.setattr(ensemble_runs, "seed_ensemble", lambda *a, **k: member)  # (the runs are not the point)
    out = tmp_path / "e.csv"
    old = b"an earlier ensemble\n" * 300
    out.write_bytes(old)
    _interrupt_after_a_part(monkeypatch, np, "savetxt")
    assert main(["ensemble", "--seeds", "2", "--out", str(out)]) == 130
    assert capsys.readouterr().err.strip().endswith(f"the ensemble was stopped: the previous {out} kept as it was")
    assert out.read_bytes() == old


def _no_run(monkeypatch):
    from cablecasing_core.timedomain import simulation

    monkeypatch.setattr(simulation.Engine, "advance", lambda *a, **k: pytest.fail("the run started"))


@pytest.mark.parametrize(
    "target,message",
    [
        ("/proc/x.csv", "cannot be written: no file can be created in /proc"),
        ("link", "is a device or another special file (/dev/full), not a regular file"),
        ("folder", "is a folder"),
        ("missing/r.csv", "must be a file in an existing folder"),
    ],
)
def test_an_unwritable_target_is_refused_before_the_run(tmp_path, capsys, monkeypatch, target, message):
    _no_run(monkeypatch)
    if target == "link":
        target = tmp_path / "full.csv"
        target.symlink_to("/dev/full")
    elif target == "folder":
        target = tmp_path / "r.csv"
        target.mkdir()
    elif not target.startswith("/"):
        target = tmp_path / target
    assert main(["simulate", "--duration", "0.001", "--no-progress", "--out", str(target)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"cablecasing: error: --out = '{target}': ") and message in err[0], err


def test_a_full_disk_is_refused_before_the_run(tmp_path, capsys, monkeypatch):
    # (a full file system, as the probe sees it: its byte cannot be synced; ENOSPC is what a full disk gives)
    from cablecasing_core import files

    def full(fd):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    _no_run(monkeypatch)
    monkeypatch.setattr(files.os, "fsync", full)
    assert main(["bands", "whatever.csv", "--out", str(tmp_path / "b.csv")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        f"cablecasing: error: --out = '{tmp_path / 'b.csv'}': cannot be written: writing to {tmp_path} fails "
        "(No space left on device)"
    ]
    assert sorted(tmp_path.iterdir()) == []  # the probe is gone


def test_a_link_is_written_where_it_points(tmp_path, capsys):
    real = tmp_path / "real.csv"
    real.write_text("old\n")
    (tmp_path / "link.csv").symlink_to(real)
    assert main(["trfam", "--fmin", "10", "--fmax", "12", "--df", "1", "--out", str(tmp_path / "link.csv")]) == 0
    assert (tmp_path / "link.csv").is_symlink() and real.read_text().startswith("frequency_hz,")


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--out", "{long}.csv"], None),  # a name of 250 characters is written (its temporary name fit no more)
        (["--out", "{toolong}.csv"], "is not a usable file name (File name too long)"),  # (an internal error)
        (["--out", ".csv"], "--out = '.csv': must be a name ending in .csv or .npz or .uff"),  # (refused after the run)
    ],
)
def test_output_names_are_checked_before_the_run_and_a_long_one_is_written(
    tmp_path, capsys, monkeypatch, argv, message
):
    monkeypatch.chdir(tmp_path)
    argv = [a.format(long="x" * 246, toolong="x" * 300) for a in argv]
    if message is not None:
        _no_run(monkeypatch)
    code = main(["simulate", "--duration", "0.001", "--no-progress", *argv])
    err = capsys.readouterr().err
    if message is None:
        assert code == 0 and (tmp_path / argv[1]).is_file() and sorted(p.name for p in tmp_path.iterdir()) == [argv[1]]
    else:
        assert code == 2 and message in err and list(tmp_path.iterdir()) == [], err


def test_an_output_over_its_input_is_refused_and_upper_case_npz_and_a_byte_order_mark_are_read(tmp_path, capsys):
    """`spectrum in.csv --out in.csv` would replace the record by its PSD: refused. A record saved as
    `r.NPZ` is written whole (numpy appended .npz to the temporary name, and the save failed); a CSV
    and a model file that begin with a UTF-8 byte-order mark read as without it."""
    import cablecasing_core as cc
    from cablecasing_core.files import read_csv_table

    res = cc.simulate(cc.load_model(), duration=0.01)
    res.save(tmp_path / "r.NPZ")
    assert [p.name for p in tmp_path.iterdir()] == ["r.NPZ"]
    res.save(tmp_path / "in.csv")
    assert main(["spectrum", str(tmp_path / "in.csv"), "--out", str(tmp_path / "in.csv")]) == 2
    assert "must be another file than RECORD's" in capsys.readouterr().err
    (tmp_path / "bom.csv").write_bytes(b"\xef\xbb\xbfmode,f_hz\n1,10.0\n2,30.0\n")
    assert read_csv_table(tmp_path / "bom.csv", "file")[0] == ["mode", "f_hz"]
    (tmp_path / "m.toml").write_bytes(b"\xef\xbb\xbf" + cc.load_model().to_toml().encode())
    assert cc.load_model(str(tmp_path / "m.toml")).fingerprint() == cc.load_model().fingerprint()


def _without(modules, argv, cwd):
    """``cablecasing argv`` in a new interpreter where ``modules`` cannot be imported (an install
    without the extra that brings them): (status, stdout, stderr lines)."""
    import subprocess
    import sys

    hide = f"import sys\nfor m in {tuple(modules)!r}: sys.modules[m] = None\n"
    code = hide + "from cablecasing_core.cli import main\nsys.exit(main(sys.argv[1:]))"
    proc = subprocess.run([sys.executable, "-c", code, *argv], cwd=cwd, capture_output=True, text=True, timeout=120)
    return proc.returncode, proc.stdout, proc.stderr.strip().splitlines()


@pytest.mark.parametrize(
    "argv,instead",
    [
        (["simulate", "--duration", "0.3", "--no-progress", "--out", "x.uff"], "(or write .csv or .npz)"),
        (["trfam", "--out", "x.uff"], "(or write .csv)"),
    ],
    ids=["simulate", "trfam"],
)
def test_a_uff_output_without_pyuff_is_refused_before_the_run(tmp_path, argv, instead):
    """Without pyuff (the extra 'identify') `--out x.uff` is refused with the other output checks,
    naming --out and the extra, before the run (the whole run, then `file = 'UFF': ...`)."""
    code, out, err = _without(["pyuff"], argv, tmp_path)
    assert code == 2 and out == "", out
    assert err == [
        "cablecasing: error: --out = 'x.uff': writing UFF needs the optional package pyuff, which is not installed: "
        f"pip install 'pyuff>=2.4' (from a checkout: pip install '.[identify]') {instead}"
    ]
    assert list(tmp_path.iterdir()) == []


REPORT = ["report", "--duration", "0.5", "--seeds", "2", "--out", "r\u00e9p ort"]
NO_PYUFF = (
    "needs the optional package pyuff (for its trfam.uff), which is not installed: pip install 'pyuff>=2.4' "
    "(from a checkout: pip install '.[identify]')"
)


@pytest.mark.parametrize(
    "hidden,argv,message",
    [
        (["pyuff"], [*REPORT, "--study-samples", "0"], NO_PYUFF),
        (["pyuff"], REPORT, NO_PYUFF),
        (
            ["pyuff", "SALib"],
            REPORT,
            "needs the optional packages pyuff (for its trfam.uff) and SALib (for its study), which are not "
            "installed: pip install 'pyuff>=2.4' 'SALib>=1.5' (from a checkout: pip install '.[identify,study]')",
        ),
    ],
    ids=["no-study", "study", "both-missing"],
)
def test_a_report_without_pyuff_is_one_line_before_anything_is_made(tmp_path, hidden, argv, message):
    """The report writes trfam.uff through pyuff (the extra 'identify'): without it the report stopped
    after its first runs with `file = '.../trfam.uff': writing UFF needs ...`, leaving its --out folder
    behind; without SALib too, it named SALib first and pyuff only at the second try (review AL M4)."""
    code, out, err = _without(hidden, argv, tmp_path)
    assert (code, out, err) == (2, "", [f"cablecasing: error: report: {message}"])
    assert list(tmp_path.iterdir()) == []


def test_the_demo_without_pyuff_says_so_before_it_builds_the_fmu(tmp_path):
    """examples/demo.py (make demo) writes the report: its settings check refuses a missing pyuff
    before the FMU is built or the folder made."""
    import subprocess
    import sys
    from pathlib import Path

    demo = Path(__file__).resolve().parents[2] / "examples" / "demo.py"
    code = f"import runpy, sys\nsys.modules['pyuff'] = None\nsys.argv = {[str(demo), '--out', 'res']!r}\n"
    code += f"runpy.run_path({str(demo)!r}, run_name='__main__')"
    proc = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.strip().splitlines() == [f"demo.py: error: report: {NO_PYUFF}"]
    assert list(tmp_path.iterdir()) == []


def test_a_long_path_is_quoted_whole_in_the_message(tmp_path, capsys, monkeypatch):
    """A path is quoted whole, not cut to the 80 characters of other values: its end names the file
    (a folder 150 characters deep, as a project's results often are, lost the file's name before)."""
    _no_run(monkeypatch)
    deep = tmp_path / ("results_of_the_cable_routing_study_" * 4) / "missing"
    target = deep / "run_with_isolators.csv"
    assert len(str(target)) > 150
    assert main(["simulate", "--duration", "0.001", "--no-progress", "--out", str(target)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"cablecasing: error: --out = '{target}': "), err


def test_a_value_is_still_cut_unless_it_is_a_path():
    """Other values keep their 80-character excerpt, and a path's limit is PATH_EXCERPT (a huge string
    with a separator is still cut)."""
    from cablecasing_core.errors import EXCERPT, PATH_EXCERPT, excerpt

    word = "x" * 500
    assert len(excerpt(word)) <= EXCERPT and excerpt(word).endswith("(502 characters)")
    path = "/" + "d" * 300 + "/f.csv"
    assert excerpt(path) == repr(path)
    huge = "/" + "d" * 5000
    assert len(excerpt(huge)) <= PATH_EXCERPT and "characters)" in excerpt(huge)
