"""The report as a team lead reads it (review S): what it states about its own runs matches the
runs (the skip and why, the record's length, df and lines in octave 1, the seeds in the figures'
titles, the energy ledger, where the contact is), what made it (the git commit and dirty flag, the
libraries, the command line), its links relative to its folder, and a report is a set of files: an
interrupted run leaves an earlier report whole, and no page beside another run's files."""

import hashlib
import json
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core import report
from cablecasing_core.report import figures, page

pytestmark = pytest.mark.slow  # (a 0.2 s report of 2 seeds: about 20 s)

ROOT = Path(__file__).resolve().parents[2]
ARGV = ["report", "--duration", "0.2", "--skip", "0.06", "--seeds", "2", "--study-samples", "0", "--no-progress"]


def _titles(fig):
    """Every title of a figure: the suptitle and each axes' three."""
    out = [fig._suptitle.get_text()] if fig._suptitle is not None else []
    for ax in fig.axes:
        out += [ax.get_title(loc) for loc in ("left", "center", "right")]
    return " ".join(" ".join(t.split()) for t in out if t)


@pytest.fixture(scope="module")
def made(tmp_path_factory):
    """One report of the built-in specimen by the command line, in process: its folder, the argv,
    and each figure's titles (and the PSD's x range and legend) as drawn, before it is saved (and
    under ``"<stderr>"`` what the command printed there)."""
    import contextlib
    import io

    import cablecasing_core.nvh.plots as nvh_plots
    import cablecasing_core.plotting as plotting
    from cablecasing_core.cli import main

    out = tmp_path_factory.mktemp("report") / "rep"
    argv = [*ARGV, "--out", str(out)]
    seen = {}
    originals = {m: m.save_figure for m in (plotting, nvh_plots)}

    def keep(module):
        def save(fig, path):
            ax = fig.axes[0]
            seen[Path(path).name] = {
                "titles": _titles(fig),
                "xlim": ax.get_xlim(),
                "legend": [t.get_text() for t in ax.get_legend().get_texts()] if ax.get_legend() else [],
            }
            return originals[module](fig, path)

        return save

    mp = pytest.MonkeyPatch()
    for module in originals:
        mp.setattr(module, "save_figure", keep(module))
    err = io.StringIO()
    try:
        with contextlib.redirect_stderr(err):
            assert main(argv) == 0
    finally:
        mp.undo()
    seen["<stderr>"] = err.getvalue()
    return out, argv, seen


def test_the_report_states_the_settings_it_ran(made):
    """The skip, the record after it, its FFT resolution and octave 1's lines, as counted on the
    saved record (samples after the skip, records.after_skip), in runs.json and on the page; a skip
    given below the drive's start transient is flagged."""
    from cablecasing_core.records import after_skip
    from cablecasing_core.timedomain.simulation import SimulationResult

    out, _, _ = made
    runs = json.loads((out / "runs.json").read_text())
    html = (out / "report.html").read_text()
    rec = SimulationResult.load(out / "records" / "drive.npz")
    n = int(after_skip(rec.time, 0.06).sum())
    dt = rec.time[1] - rec.time[0]
    assert (runs["duration"], runs["skip"], runs["window"], runs["seeds"]) == (0.2, 0.06, "hann", [1, 2])
    assert n == 14000 and runs["record_after_skip"] == pytest.approx(n * dt, rel=1e-12)
    assert runs["df"] == pytest.approx(1 / (n * dt), rel=1e-12)
    assert runs["lines_oct1"] == pytest.approx(11.0 * n * dt, rel=1e-12)  # (11-22 Hz: 11 Hz / df)
    assert f"{n * dt:.4g} s after the skip: FFT lines every df = {1 / (n * dt):.3g} Hz" in html
    assert f"{11 * n * dt:.3g} lines in octave 1" in html and "too few" in html  # (1.54 < 4)
    assert "Every record's first 0.06 s are left out" in html and "start transient of the harmonic drive" in html
    assert "The skip given, 0.06 s, is shorter than the drive's start transient, 0.30 s" in html


def test_a_warning_is_said_once_per_report(made):
    """Review V, D12: the 0.14 s left of 0.2 s put 1.5 FFT lines in octave 1; each variant's ensemble
    checks its records and finds it, and the report says it once."""
    lines = [x for x in made[2]["<stderr>"].splitlines() if x.startswith("cablecasing: warning:")]
    assert len([x for x in lines if "fewer than 4 FFT lines" in x]) == 1, lines
    assert len(lines) == len(set(lines)), lines


def test_the_report_files_are_those_it_declares(made):
    """Every file of a report (runs.json's ``files``) is a name of report.REPORT_FILES, which
    check_report_folder checks before the runs; runs.json marks itself as a report's."""
    import fnmatch

    runs = json.loads((made[0] / "runs.json").read_text())
    assert runs["report"] is True
    undeclared = [f for f in runs["files"] if not any(fnmatch.fnmatchcase(f, p) for p in report.REPORT_FILES)]
    assert not undeclared


def test_the_figures_carry_their_settings(made):
    """Review S, 5-7: each figure's titles give the seed, the duration and the skip (the band figure
    the seeds and the window); the PSD spans Table 3's bands up to 5680 Hz and names the curve that
    is two outputs; the contact figures say what the contact time counts."""
    _, _, seen = made
    for name in ("simulation.png", "scalograms.png", "psd.png"):
        assert "seed 1, 0.2 s at dt = 1e-05 s, levels after 0.06 s" in seen[name]["titles"], name
    assert "gamma = 12" in seen["scalograms.png"]["titles"]
    band = seen["band_levels.png"]["titles"]
    assert "0.2 s runs at dt = 1e-05 s, after 0.06 s, Hann's window, seeds 1..2" in band
    psd = seen["psd.png"]
    assert "Hann's window" in psd["titles"] and "Table 3's bands 11-5680 Hz" in psd["titles"]
    assert psd["xlim"][1] == pytest.approx(5680.0)  # (it ended at 3000 Hz: octave 9 was cut off)
    # without the drive cable.B.Fz is 0 N: one curve named as both, not one hidden under the other
    assert len(psd["legend"]) == 3 and "(= net.B.Fz: cable.B.Fz is 0 N)" in psd["legend"][0]
    for name in ("routing_contact.png", "contact_histogram.png"):
        assert "counted from t = 0 over the whole run, the first 0.06 s included" in seen[name]["titles"], name


def test_the_report_names_the_code_libraries_and_command(made):
    """Review S, D3: the git commit and whether the tree differs from it, as git itself says; the
    libraries' versions, as the modules give them; the command line."""
    import matplotlib
    import numba
    import scipy

    out, argv, _ = made
    runs = json.loads((out / "runs.json").read_text())
    html = (out / "report.html").read_text()
    top = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--show-toplevel"], capture_output=True, text=True)
    code = runs["code"]
    if top.returncode == 0 and Path(top.stdout.strip()).resolve() == ROOT.resolve():
        head = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "HEAD"], capture_output=True, text=True)
        status = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain"], capture_output=True, text=True)
        changed = len(status.stdout.splitlines())
        assert code["source"] == "git" and code["commit"] == head.stdout.strip()
        assert code["dirty"] == (changed > 0)
        assert f"git commit {code['commit']}" in html
    else:
        assert code["source"] == "package" and "no git commit" in html
    libs = runs["libraries"]
    assert libs["Python"] == "{}.{}.{}".format(*sys.version_info[:3])
    for module in (np, scipy, numba, matplotlib):
        assert libs[module.__name__] == module.__version__
        assert f"{module.__name__} {module.__version__}" in html
    assert runs["command"] == "cablecasing " + shlex.join(argv)
    assert f"<code>{page._e(runs['command'])}</code>" in html


def test_code_state_outside_a_checkout_gives_the_version_and_says_why(tmp_path):
    from cablecasing_core.report.provenance import code_state, describe_code

    outside = code_state(tmp_path)  # (pytest's folder: no git work tree)
    assert outside["source"] == "package" and outside["version"] == cc.__version__
    assert describe_code(outside).startswith(f"cablecasing {cc.__version__} as installed (no git commit: ")
    if (ROOT / ".git").exists():  # (a folder inside a checkout is not the package's checkout)
        inner = code_state(ROOT / "docs")
        assert inner["source"] == "package" and "not at the top of" in inner["why"]


def test_every_link_is_relative_and_every_file_listed(made):
    """Review S, D4: the page's links and runs.json's paths are relative to the report's folder and
    lead to its files; runs.json lists every file of the report, and no staging folder is left."""
    out, _, _ = made
    html = (out / "report.html").read_text()
    runs = json.loads((out / "runs.json").read_text())
    links = re.findall(r"(?:href|src)='([^']+)'", html)
    assert links and all(not Path(a).is_absolute() and ":" not in a for a in links)
    assert all((out / a).is_file() for a in links), [a for a in links if not (out / a).is_file()]
    assert all((out / v["record"]).is_file() and not Path(v["record"]).is_absolute() for v in runs["variants"])
    on_disk = sorted(p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file())
    assert runs["files"] == on_disk
    assert not [p for p in out.iterdir() if p.name.startswith(report.STAGE_PREFIX)]


def test_the_energy_ledger_and_the_contact_are_those_of_the_records(made):
    """Review S, 10 and 7: the supports' work, the normal force's own work and the residual of the
    reference record with the drive as saved (its .npz read with numpy: (name, value) rows), with
    the normal work's share of the supports' work; the node of most contact is that of the mean
    contact time of the ensemble's saved members (bands_drive.csv)."""
    from cablecasing_core.studies.ensemble import load_ensemble

    out, _, _ = made
    html = (out / "report.html").read_text()
    with np.load(out / "records" / "drive.npz", allow_pickle=True) as z:
        saved = {str(k): float(v) for k, v in z["energies"]}
        arc = z["arc_length"]
    ledger = html[html.index("Energy ledger") :]

    def cell(label):
        row = re.search(rf"<tr><td>{re.escape(page._e(label))}</td>(.*?)</tr>", ledger)[1]
        return re.findall(r"<td[^>]*>(.*?)</td>", row)[1]  # (the second variant's: with the drive)

    w, normal = saved["support_work"], saved["contact_normal_dissipation"]
    assert cell("work of the supports") == page._g(w, 4)
    assert cell("of which the normal force's own work") == (
        f"{page._g(normal, 4)} ({100 * normal / w + 0.0:+.2f} % of the supports' work)"
    )
    assert cell("residual of the balance").startswith(page._g(saved["residual"], 4) + " (")
    assert normal < 0  # (the normal-plane contact on the 35-element mesh makes energy: docs/time_domain.md)
    ct = load_ensemble(out / "bands_drive.csv").contact_time
    most = arc[int(np.argmax(ct.mean(axis=0)))]
    assert f"The most contact is at s = {most:.3g} m" in html


def _snapshot(folder):
    return {
        p.relative_to(folder).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in folder.rglob("*")
        if p.is_file()
    }


def test_an_interrupted_report_leaves_the_earlier_one_whole(made, tmp_path, stubbed):
    """Review S, D2: a run interrupted after it has written some files (the modes, the parameters,
    the TRFAM of another casing modulus: other bytes) leaves every file of the earlier report as it
    was, and no staging folder."""
    out = tmp_path / "rep"
    shutil.copytree(made[0], out)
    before = _snapshot(out)

    def stop(*a, **k):
        raise KeyboardInterrupt

    stubbed.setattr(figures, "time_figure", stop)  # (after modes.csv, parameters.csv and the TRFAM's files)
    model = cc.load_model().with_overrides({"casing.E": 6e9})
    with pytest.raises(KeyboardInterrupt):
        report.write_report(out, model=model, duration=0.2, skip=0.06, seeds=2, study_samples=0, progress=False)
    assert _snapshot(out) == before
    assert not [p for p in out.iterdir() if p.name.startswith(report.STAGE_PREFIX)]


def test_an_interrupt_while_the_files_move_in_leaves_no_page(made, tmp_path, stubbed):
    """Interrupted while the finished run's files replace the earlier ones, the folder has no
    report.html or runs.json (removed first, written last): no page shows a mix of two runs."""
    import os

    out = tmp_path / "rep"
    shutil.copytree(made[0], out)
    replace, moved = os.replace, []

    def replace_then_stop(src, dst):
        if Path(dst).parent.resolve() == out.resolve():  # (a file moved in, not one written in the stage)
            moved.append(Path(dst).name)
            if len(moved) == 3:
                raise KeyboardInterrupt
        return replace(src, dst)

    stubbed.setattr(os, "replace", replace_then_stop)
    with pytest.raises(KeyboardInterrupt):
        report.write_report(out, model=cc.load_model(), duration=0.2, skip=0.06, seeds=2, study_samples=0)
    assert not (out / "report.html").exists() and not (out / "runs.json").exists()
    assert not [p for p in out.iterdir() if p.name.startswith(report.STAGE_PREFIX)]


def test_a_finished_run_replaces_the_earlier_report_and_removes_its_other_files(made, tmp_path, stubbed):
    """The files the earlier report listed and this run does not write (its records, ensembles,
    figures) are removed; what was in the folder besides the report stays; the page is the new one."""
    out = tmp_path / "rep"
    shutil.copytree(made[0], out)
    (out / "mine.txt").write_text("not the report's")
    report.write_report(out, model=cc.load_model(), duration=0.2, skip=0.06, seeds=2, study_samples=0, progress=False)
    assert (out / "report.html").read_text() == "<html>the new run</html>"
    assert (out / "mine.txt").read_text() == "not the report's"
    assert not (out / "records" / "drive.npz").exists() and not (out / "band_levels.png").exists()
    runs = json.loads((out / "runs.json").read_text())
    on_disk = sorted(p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file())
    assert runs["files"] == [f for f in on_disk if f != "mine.txt"]
