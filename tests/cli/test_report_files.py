"""Review V, D1-D3: the report never loses a report or a user's files. A folder where the report
writes a file, or a subfolder of --out on another file system, is refused before the runs; one
found after them, or a move that fails, keeps the earlier report (or as much as the move had not
replaced) and the finished run, and says where it is; a later report removes only the files an
earlier report listed as its own; the git status of the provenance leaves the report's folder out."""

import errno
import json
import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

import cablecasing_core as cc
from cablecasing_core import report
from cablecasing_core.cli import main
from cablecasing_core.files import WriteError
from cablecasing_core.report import figures
from cablecasing_core.report.provenance import code_state

SHORT = dict(duration=0.2, skip=0.06, seeds=2, study_samples=0, progress=False)
ARGV = ["report", "--duration", "0.2", "--skip", "0.06", "--seeds", "2", "--study-samples", "0", "--no-progress"]
#: A file system other than pytest's temporary folder's, for a subfolder linked there (None: none).
OTHER_FS = "/dev/shm"


@pytest.fixture
def quick(stubbed):
    """``stubbed`` with the TRFAM's figure stubbed too (it writes its file): a report in about a second."""
    stubbed.setattr(figures, "trfam_figure", lambda model, body, out: (out / "trfam_xyz.png").write_text("stub"))
    return stubbed


def _snapshot(folder):
    """{relative path: bytes} of every file under ``folder``, and the folders (b'<dir>')."""
    return {p.relative_to(folder).as_posix(): (p.read_bytes() if p.is_file() else b"<dir>") for p in folder.rglob("*")}


def _earlier(out, files=("report.html", "runs.json", "records/drive.npz", "psd.png"), marked=True):
    """An earlier report's files in ``out``: each holds 'earlier <name>'; its runs.json lists them."""
    for name in files:
        (out / name).parent.mkdir(parents=True, exist_ok=True)
        (out / name).write_text(f"earlier {name}")
    runs = {"files": sorted(files), "report": True} if marked else {"files": sorted(files)}
    (out / "runs.json").write_text(json.dumps(runs))


def _stages(out):
    return [p for p in out.iterdir() if p.name.startswith(report.STAGE_PREFIX)]


def _other_fs_folder(tmp_path):
    """A new folder on another file system than ``tmp_path``'s, or a skip."""
    if not os.path.isdir(OTHER_FS) or os.stat(OTHER_FS).st_dev == os.stat(tmp_path).st_dev:
        pytest.skip(f"no other file system at {OTHER_FS}")
    import tempfile

    return Path(tempfile.mkdtemp(prefix="cablecasing-test-", dir=OTHER_FS))


def test_a_folder_where_the_report_writes_a_file_is_refused_before_the_runs(tmp_path, monkeypatch, capsys):
    """psd.png/ a folder in --out: refused with status 2, naming --out and the file, before anything
    runs or is written (the earlier report as it was, no staging folder)."""
    out = tmp_path / "rep"
    _earlier(out)
    (out / "psd.png").unlink()
    (out / "psd.png").mkdir()
    (out / "psd.png" / "mine.txt").write_text("mine")
    before = _snapshot(out)
    monkeypatch.setattr(report, "_write", lambda *a, **k: pytest.fail("the report ran"))
    assert main([*ARGV, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"cablecasing: error: --out = {str(out)!r}: must be a folder into")
    assert f"{out / 'psd.png'} is a folder where the report writes a file" in err[0]
    assert _snapshot(out) == before and not _stages(out)


def test_a_records_folder_on_another_file_system_is_refused_before_the_runs(tmp_path, monkeypatch, capsys):
    """--out/records a link to another file system (a file cannot be renamed across): refused with
    status 2 before the runs (it was 'internal error ... a bug' after them, both reports lost)."""
    out = tmp_path / "rep"
    _earlier(out)
    elsewhere = _other_fs_folder(tmp_path)
    try:
        shutil.move(out / "records" / "drive.npz", elsewhere / "drive.npz")  # (a copy: another file system)
        (out / "records").rmdir()
        (out / "records").symlink_to(elsewhere)
        before = _snapshot(out)
        monkeypatch.setattr(report, "_write", lambda *a, **k: pytest.fail("the report ran"))
        assert main([*ARGV, "--out", str(out)]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith(f"cablecasing: error: --out = {str(out)!r}: must be a folder")
        assert f"{out / 'records'} lies on another file system ({elsewhere})" in err[0]
        assert _snapshot(out) == before and not _stages(out)
    finally:
        (elsewhere / "drive.npz").unlink(missing_ok=True)
        elsewhere.rmdir()


def test_a_link_to_another_file_system_found_at_the_move_keeps_both_reports(tmp_path):
    """The same link met by the move itself (staged_report without the check before the runs):
    nothing is removed or moved, the error names the file and the staging folder, which is kept
    and holds the whole run."""
    out = tmp_path / "rep"
    _earlier(out)
    elsewhere = _other_fs_folder(tmp_path)
    try:
        (out / "records" / "drive.npz").unlink()
        (out / "records").rmdir()
        (out / "records").symlink_to(elsewhere)
        before = _snapshot(out)
        with pytest.raises(WriteError) as raised, report.staged_report(out) as stage:
            for name in ("records/drive.npz", "psd.png", "runs.json", "report.html"):
                (stage / name).parent.mkdir(exist_ok=True)
                (stage / name).write_text(f"new {name}")
        assert raised.value.errno == errno.EXDEV and raised.value.filename == str(out / "records" / "drive.npz")
        assert "nothing was moved or removed" in raised.value.strerror and str(stage) in raised.value.strerror
        assert {k: v for k, v in _snapshot(out).items() if not k.startswith(report.STAGE_PREFIX)} == before
        assert _stages(out) == [stage] and (stage / "records" / "drive.npz").read_text() == "new records/drive.npz"
    finally:
        elsewhere.rmdir()


def test_a_folder_made_during_the_run_keeps_the_earlier_report_and_the_run(tmp_path, quick, capsys):
    """A folder that takes the place of a file of the report while it runs (simulation.png/, here
    made by the stub of its figure) is found before anything is moved: status 1, one line naming
    --out, the file and where the finished run is kept; the earlier report is whole."""
    out = tmp_path / "rep"
    _earlier(out)

    def figure_and_folder(variants, path, info=None):
        path.write_text("new simulation.png")
        (out / "simulation.png").mkdir()

    quick.setattr(figures, "time_figure", figure_and_folder)
    before = _snapshot(out)
    assert main([*ARGV, "--out", str(out)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    (stage,) = _stages(out)
    assert len(err) == 1 and err[0].startswith("cablecasing: error: --out = ") and ": could not be written (" in err[0]
    assert f"{out / 'simulation.png'} is a folder where the report writes a file" in err[0]
    assert "nothing was moved or removed" in err[0] and f"kept whole in {stage}" in err[0]
    after = {k: v for k, v in _snapshot(out).items() if not k.startswith(report.STAGE_PREFIX)}
    assert after == {**before, "simulation.png": b"<dir>"}
    assert (stage / "report.html").read_text() == "<html>the new run</html>"
    assert sorted(json.loads((stage / "runs.json").read_text())["files"]) == report._files_under(stage)


def test_a_move_that_fails_puts_the_run_back_into_its_folder(tmp_path, quick):
    """An error of the file system in the middle of the move (EXDEV on the third file here): the
    files moved so far go back into the staging folder, which is kept with the whole run; --out has
    no page (removed first), the error is a WriteError naming the file and the staging folder."""
    out = tmp_path / "rep"
    _earlier(out)
    replace, moved = os.replace, []

    def fail_third(src, dst):
        if Path(dst).parent.resolve() == out.resolve() and report.STAGE_PREFIX in str(src):
            moved.append(Path(dst).name)
            if len(moved) == 3:
                raise OSError(errno.EXDEV, "Invalid cross-device link", str(src), None, str(dst))
        return replace(src, dst)

    quick.setattr(os, "replace", fail_third)
    with pytest.raises(WriteError) as raised:
        report.write_report(out, model=cc.load_model(), **SHORT)
    (stage,) = _stages(out)
    assert raised.value.errno == errno.EXDEV and raised.value.filename == str(out / moved[2])
    assert f"kept whole in {stage}" in raised.value.strerror
    assert not (out / "report.html").exists() and not (out / "runs.json").exists()
    listed = json.loads((stage / "runs.json").read_text())["files"]
    assert report._files_under(stage) == sorted(listed)  # (the whole run, back in its folder)
    assert (out / "records" / "drive.npz").read_text() == "earlier records/drive.npz"  # (not yet replaced)


def test_a_report_leaves_a_users_study_in_its_folder(tmp_path, quick):
    """Review V, D3: --out holds a user's study (cablecasing study --out results/study) and no
    report: a report there leaves every file of it (it removed study.csv, hours of runs)."""
    out = tmp_path / "results"
    study = out / "study"
    study.mkdir(parents=True)
    mine = {n: f"the user's {n}" for n in ("study.csv", "study.csv.meta.json", "model.toml", "sobol.png")}
    for name, text in mine.items():
        (study / name).write_text(text)
    report.write_report(out, model=cc.load_model(), **SHORT)
    assert {p.name: p.read_text() for p in study.iterdir()} == mine
    assert json.loads((out / "runs.json").read_text())["report"] is True


def test_only_a_reports_runs_json_says_what_to_remove(tmp_path, quick):
    """A runs.json that is not a report's (a list of files of the user's own) removes nothing; a
    report's, marked or written before the mark (its files, variants, fingerprint and seeds), removes
    the files it lists that the new run does not write, and the study folder it leaves empty."""
    out = tmp_path / "a"
    out.mkdir()
    (out / "mine.csv").write_text("mine")
    (out / "runs.json").write_text(json.dumps({"files": ["mine.csv"]}))
    report.write_report(out, model=cc.load_model(), **SHORT)
    assert (out / "mine.csv").read_text() == "mine"

    for marked in (True, False):
        out = tmp_path / f"b{marked}"
        out.mkdir()
        _earlier(out, ("report.html", "runs.json", "band_levels.png", "study/study.csv", "study/sobol.png"), marked)
        if not marked:  # (a report's runs.json before the mark)
            runs = json.loads((out / "runs.json").read_text())
            (out / "runs.json").write_text(json.dumps({**runs, "variants": [], "fingerprint": "x", "seeds": [1, 2]}))
        (out / "mine.txt").write_text("mine")
        report.write_report(out, model=cc.load_model(), **SHORT)
        assert not (out / "band_levels.png").exists() and not (out / "study").exists(), marked
        assert (out / "mine.txt").read_text() == "mine"


def _git(repo, *args):
    subprocess.run(["git", "-C", str(repo), *args], check=True, capture_output=True)


@pytest.fixture
def repo(tmp_path):
    """A git work tree with one committed file (skipped without git)."""
    repo = tmp_path / "repo"
    repo.mkdir()
    try:
        _git(repo, "init", "-q")
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("no git")
    (repo / "code.py").write_text("x = 1\n")
    _git(repo, "add", "code.py")
    _git(repo, "-c", "user.email=t@t", "-c", "user.name=t", "commit", "-q", "-m", "one")
    return repo


def test_the_provenance_leaves_the_reports_own_folder_out(repo):
    """Review V, D2: a report's earlier output in --out inside the checkout (not git-ignored) and its
    staging folder do not make the tree dirty; any other change does, as git status lists it."""
    out = repo / "myrep"
    (out / "records").mkdir(parents=True)
    (out / "report.html").write_text("earlier")
    (out / "records" / "drive.npz").write_text("earlier")
    (out / f"{report.STAGE_PREFIX}abc").mkdir()
    (out / f"{report.STAGE_PREFIX}abc" / "psd.png").write_text("new")
    assert code_state(repo)["changed_paths"] == 1  # (git's own count: `?? myrep/`)
    clean = code_state(repo, exclude=out)
    assert clean["source"] == "git" and clean["dirty"] is False and clean["changed_paths"] == 0
    (repo / "code.py").write_text("x = 2\n")
    (repo / "new.py").write_text("")
    assert code_state(repo, exclude=out)["changed_paths"] == 2
    assert code_state(repo, exclude=repo.parent / "elsewhere")["changed_paths"] == 3


def test_a_report_at_the_top_of_the_checkout_leaves_out_only_its_own_files(repo):
    """--out the work tree's top: the report's files (report.REPORT_FILES, its staging folders) are
    left out of the status, the rest of the tree is the code."""
    (repo / "records").mkdir()
    (repo / "records" / "drive.npz").write_text("")
    for name in ("report.html", "runs.json", "bands_drive.csv", "psd.png"):
        (repo / name).write_text("")
    (repo / f"{report.STAGE_PREFIX}abc").mkdir()
    (repo / f"{report.STAGE_PREFIX}abc" / "x").write_text("")
    assert code_state(repo, exclude=repo)["dirty"] is False
    (repo / "notes.txt").write_text("")
    assert code_state(repo, exclude=repo)["changed_paths"] == 1


def test_the_report_gives_its_own_folder_to_the_provenance(tmp_path, quick):
    """write_report leaves --out out of the status, not its staging folder alone (which git would
    not list while it is empty of files the status shows: the first report said clean, the next
    dirty)."""
    from cablecasing_core.report import provenance

    given = []
    quick.setattr(provenance, "code_state", lambda root=None, exclude=None: given.append(exclude) or {})
    out = tmp_path / "rep"
    report.write_report(out, model=cc.load_model(), **SHORT)
    assert given == [out]


def test_a_report_on_threads_is_the_serial_report(tmp_path, drawn):
    """write_report(scheduler="threads"), the default, runs the ensembles and the study at once on
    threads: the page (but for the minute it states it was written at) and every table it writes
    equal the serial report's to the byte (the study's rows but for their order, as they completed,
    and their wall time). The figures are drawn but not written (``drawn``: half a report's time);
    the demo's test writes them."""
    import csv

    settings = dict(SHORT, seeds=3, study_samples=8)
    pages = {}
    for scheduler in ("serial", "threads"):
        out = tmp_path / scheduler
        report.write_report(out, model=cc.load_model(), scheduler=scheduler, command="cablecasing report", **settings)
        pages[scheduler] = out
    tables = sorted(p.relative_to(pages["serial"]) for p in pages["serial"].rglob("*.csv"))
    assert any(str(t).startswith("bands_") for t in tables) and Path("study/study.csv") in tables
    for name in tables:
        a, b = (pages[s] / name for s in ("serial", "threads"))
        if name == Path("study/study.csv"):
            # (rows in the order they completed: on threads not the index order)
            rows = [
                sorted(({k: v for k, v in r.items() if k != "elapsed_s"} for r in csv.DictReader(open(p))), key=str)
                for p in (a, b)
            ]
            assert rows[0] == rows[1] and len(rows[0]) >= 8
        else:
            assert a.read_bytes() == b.read_bytes(), name
    # the page: the same but for its date row, to the minute, which two reports may straddle
    html = [re.sub(r"<td>date</td><td>[^<]*</td>", "", (pages[s] / "report.html").read_text()) for s in pages]
    assert html[0] == html[1] and "<td>date</td>" in (pages["serial"] / "report.html").read_text()
    with pytest.raises(cc.ModelError, match="scheduler"):
        report.write_report(tmp_path / "x", model=cc.load_model(), scheduler="local", **settings)
