"""The demo (make demo: examples/demo.py) and ``cablecasing report``: every figure and table from one
set of runs (the RMS table recomputed from the saved record the figures used, the ensembles' first
member equal to that record's run), the FMU equal to the core driven by the same sampled record,
and nothing written outside --out."""

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytestmark = pytest.mark.slow  # builds the FMU and runs the demo

ROOT = Path(__file__).resolve().parents[2]


def _run(args, cwd, **kw):
    return subprocess.run(
        [sys.executable, *args], check=True, cwd=cwd, timeout=1800, capture_output=True, text=True, **kw
    )


@pytest.mark.parametrize(
    "args, said",
    [
        (["--seeds", "1"], "--seeds = 1: must be an integer >= 2"),
        (["--duration", "-1"], "--duration = -1.0: must be a positive number"),
        (["--out", "{file}"], "is an existing file, not a folder"),
        (["--scheduler", "dask"], "argument --scheduler: invalid choice: 'dask' (choose from"),
    ],
)
def test_the_demo_refuses_bad_settings_before_it_builds_anything(tmp_path, args, said):
    """It built and ran the FMU, then stopped with a traceback."""
    (tmp_path / "afile").write_text("")
    args = [a.format(file=tmp_path / "afile") for a in args]
    out = [] if "--out" in args else ["--out", str(tmp_path / "results")]
    r = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "demo.py"), *out, *args], capture_output=True, text=True
    )
    assert r.returncode == 2 and said in r.stderr and "Traceback" not in r.stderr, r.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile"]


def test_the_demo_builds_the_fmu_under_the_lock_the_tests_fmu_takes(monkeypatch, tmp_path):
    """Review AX4: the demo rebuilt dist/CableCasing.fmu without the lock the ``fmu`` fixture takes,
    so under pytest-xdist another worker's build could replace it between the demo's build and its
    checksum (the test above compares the two). Its build (here a stand-in that fails, so that the
    demo stops there) runs while the lock is held: a second open description of the lock file cannot
    take it; and the demo lets it go when it stops."""
    import fcntl
    import importlib.util

    spec = importlib.util.spec_from_file_location("demo_under_test", ROOT / "examples" / "demo.py")
    demo = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(demo)
    lock_file = ROOT / "dist" / ".CableCasing.fmu.lock"
    held = []

    def build(cmd, **kw):
        with open(lock_file) as other:
            try:
                fcntl.flock(other, fcntl.LOCK_EX | fcntl.LOCK_NB)
                held.append(False)
            except BlockingIOError:
                held.append(True)
        return subprocess.CompletedProcess(cmd, 3)

    monkeypatch.setattr(demo.subprocess, "run", build)
    assert demo._run(None, tmp_path / "results") == 3 and held == [True]
    with open(lock_file) as other:
        fcntl.flock(other, fcntl.LOCK_EX)  # (released: this returns, once any other worker's build is done)
    assert not (tmp_path / "results").exists()


def test_the_demo_report_is_one_set_of_runs_and_the_fmu_is_the_core(tmp_path):
    from cablecasing_core.records import after_skip
    from cablecasing_core.timedomain.simulation import SimulationResult

    out = tmp_path / "results"
    _run(
        [
            str(ROOT / "examples" / "demo.py"),
            "--out",
            str(out),
            "--duration",
            "0.15",
            "--skip",
            "0.05",  # (the default, the drive's start transient of 0.30 s, needs 0.4015 s)
            "--seeds",
            "3",
            "--study-samples",
            "32",
        ],
        ROOT,
    )
    html = (out / "report.html").read_text()
    imgs = re.findall(r"<img src='([^']+)'", html)
    want = {
        "trfam_xyz.png",
        "simulation.png",
        "scalograms.png",
        "routing_contact.png",
        "contact_histogram.png",
        "band_levels.png",
        "psd.png",
        "apparent_mass.png",
        "study/correlations.png",
    }
    assert want <= set(imgs)
    # a 32-run study (4 base points) is too small for Sobol indices: the page says so instead
    assert "study/sobol.png" in imgs or "Sobol indices of these 4 base points are not shown" in html
    for name in imgs:
        data = (out / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000, name
    # the RMS table is the saved record's: recomputed from records/<variant>.npz after skip, the
    # mean, the RMS with it (total) and without it (dynamic: the standard deviation)
    runs = json.loads((out / "runs.json").read_text())
    assert runs["duration"] == 0.15 and runs["seeds"] == [1, 2, 3] and runs["version"] and runs["date"]
    lines = (out / "rms.csv").read_text().splitlines()
    assert lines[0] == "variant,record,output,mean [N],rms total [N],rms dynamic [N]"
    rows = [line.split(",") for line in lines[1:]]
    for v in runs["variants"]:
        rec = SimulationResult.load(out / v["record"])
        keep = after_skip(rec.time, runs["skip"])
        for _, _, name, *values in (r for r in rows if r[0] == v["key"]):
            x = rec.support_force(name)[keep]
            expected = [float(np.mean(x)), float(np.sqrt(np.mean(x**2))), float(np.std(x))]
            assert [float(y) for y in values] == expected  # (written with repr: exact)
            assert all(f"{y:.6g}" in html for y in expected)
        assert v["ensemble_first_member_vs_record"] == 0.0  # the ensemble's seed 1 is this record's run
    assert "without the cable drive" in html and "with the cable drive" in html and "Table 3" in html
    assert "casing.E" in html and "Pa" in html  # the parameter table, with units from the schema
    # the FMU (fmpy, the scenario's record sampled every 1e-4 s) against the core driven alike
    dev = runs["fmu"]["largest deviation, relative to the output's largest value"]
    assert float(dev.split()[0]) < 1e-8, dev  # fmu_outputs.csv has 9 digits: 5e-9 of the largest value
    assert (out / "fmu_outputs.csv").stat().st_size > 100
    # what made it (review S, D3, D4): the FMU by its checksum, its outputs by a path relative to the report
    import hashlib

    assert runs["fmu"]["FMU outputs"] == "fmu_outputs.csv" and "<a href='fmu_outputs.csv'>" in html
    fmu = ROOT / "dist" / "CableCasing.fmu"
    assert runs["fmu"]["FMU SHA-256"] == hashlib.sha256(fmu.read_bytes()).hexdigest()
    assert runs["command"].startswith("python examples/demo.py --out ") and runs["code"]["version"]
    assert "fmu_outputs.csv" in runs["files"] and not [p for p in out.iterdir() if p.name.startswith(".report-run-")]


def _tree(root):
    """(path, size, mtime) of every file under the source tree, but the caches and the venv."""
    skip = {".git", ".venv", "__pycache__", ".pytest_cache", ".ruff_cache"}
    out = set()
    for dirpath, dirs, files in os.walk(root):
        dirs[:] = [d for d in dirs if d not in skip]
        for f in files:
            st = os.stat(os.path.join(dirpath, f))
            out.add((os.path.join(dirpath, f), st.st_size, st.st_mtime_ns))
    return out


def test_report_writes_only_under_out(tmp_path, build_fmu):
    """The report writes nothing in the source tree but under --out. The tree is compared before and after under
    the lock on dist/CableCasing.fmu (build_fmu.default_fmu_lock), so that another pytest-xdist worker's build of
    the session FMU (the fmu fixture, the demo) cannot change dist/ in between."""
    with build_fmu.default_fmu_lock():
        _report_writes_only_under_out(tmp_path)


def _report_writes_only_under_out(tmp_path):
    before = _tree(ROOT)
    work = tmp_path / "work"
    work.mkdir()
    _run(
        [
            "-m",
            "cablecasing_core.cli",
            "report",
            "--out",
            "rep",
            "--duration",
            "0.15",
            "--skip",
            "0.05",
            "--seeds",
            "2",
            "--study-samples",
            "0",
            "--no-progress",
        ],
        work,
        env={**os.environ, "PYTHONDONTWRITEBYTECODE": "1"},
    )
    assert _tree(ROOT) == before
    assert [p.name for p in work.iterdir()] == ["rep"] and (work / "rep" / "report.html").exists()
    # the page says what its records hold: the H1 comes from the record without the cable drive,
    # which has no contact, so its coherence drops are not the contact's (the note said they were),
    # nor its random error's (review C, 3): the resolution's bias
    from cablecasing_core.timedomain.simulation import SimulationResult

    nodrive = SimulationResult.load(work / "rep" / "records" / "nodrive.npz")
    html = (work / "rep" / "report.html").read_text()
    assert "without and with the cable drive" in html
    if not nodrive.contact_time.any():
        assert "The record has no contact, so the system is linear" in html
        assert "the coherence drops are the resolution's bias, not random error" in html
        assert "the contact makes the transmission non-linear" not in html and "record has contact" not in html


def test_the_report_of_a_model_without_cable_drive_names_its_one_record_and_its_clips_units():
    """A model whose scenario has no cable drive (examples/installation.toml) has one record, the
    model's scenario, filed under that name (it was filed as drive.npz); its clips' keys are rows
    with their units (one row `casing.clip` without a unit before), and so are its segments'."""
    import cablecasing_core as cc
    from cablecasing_core.report.page import parameter_rows
    from cablecasing_core.report.runs import variants

    model = cc.load_model(str(ROOT / "examples" / "installation.toml"))
    (only,) = variants(model, Path("out"), 1)
    assert (only.key, only.title, only.record.name) == ("scenario", "the model's scenario", "scenario.npz")
    rows = {key: (value, unit) for key, value, unit, _ in parameter_rows(model, 0.15)}
    assert rows["casing.clip[0].stiffness"] == ("[20000.0, 50000.0, 50000.0]", "N/m")
    assert rows["casing.clip[1].damping"][1] == "N.s/m" and "casing.clip" not in rows
    # the route's segments as the file gives them (m, degrees; they had no unit)
    assert rows["geometry.segments[0].straight"] == ("0.15", "m")
    assert rows["geometry.segments[1].bend.radius"] == ("0.15", "m")
    assert rows["geometry.segments[1].bend.angle_deg"] == ("60.0", "deg")
