"""Review AF: the command line driven from scripts and CI. An interrupt names the files this run has
written as written (not as kept or not written); spectrum's empty RMS range, bands' empty band
range, an ensemble's too coarse --dt and a missing sub-command are named by the options as typed;
study --out '' is refused; ensemble and study take --no-progress; a bad MPLBACKEND is refused before
the run and an output stream that cannot encode a path does not turn a run into an internal error;
docs/cli.md's exit statuses are those of the command line's docstring."""

import io
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import cablecasing_core
from cablecasing_core.cli import main

ROOT = Path(__file__).resolve().parents[2]
#: Where the cablecasing_core this test imports lies (a process of its own imports the same).
PACKAGE_ROOT = str(Path(cablecasing_core.__file__).resolve().parents[1])


def _record(path, duration=1.0, dt=1e-4):
    """A time record as 'simulate --out' writes one (time first, a column casing.B.Fz in N): white
    noise, seed 1, every band level non-zero."""
    t = np.arange(round(duration / dt) + 1) * dt
    x = np.random.default_rng(1).normal(size=t.size)
    np.savetxt(path, np.column_stack([t, x]), delimiter=",", header="time [s],casing.B.Fz [N]", comments="")
    return str(path)


def _interrupt(monkeypatch, module, name):
    """``module.name`` (the figure's writer) is interrupted (Ctrl-C) before it writes anything."""

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(module, name, interrupted)


# --- M1: the interrupt line says what this run has written, at the moment of the interrupt --------


@pytest.mark.parametrize("earlier", [True, False])
def test_an_interrupt_after_out_is_written_says_this_run_wrote_it(tmp_path, capsys, monkeypatch, earlier):
    from cablecasing_core import plotting

    out, png = tmp_path / "r.csv", tmp_path / "p.png"
    if earlier:
        out.write_text("an earlier record\n")
    _interrupt(monkeypatch, plotting, "plot_time_result")  # (after --out is written, before --plot)
    argv = ["simulate", "--duration", "0.001", "--no-progress", "--out", str(out), "--plot", str(png)]
    assert main(argv) == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"cablecasing: interrupted: the run was stopped: {out} written by this run; {png} not written"]
    assert out.read_text().startswith("time [s],")  # (this run's record, not the earlier file)
    assert not png.exists()


def test_the_interrupt_line_of_bands_names_written_kept_and_unwritten_files(tmp_path, capsys, monkeypatch):
    """One mechanism for every command: bands writes --out, then is stopped drawing --plot, whose
    earlier file is kept."""
    from cablecasing_core.nvh import plots

    rec = _record(tmp_path / "r.csv")
    out, png = tmp_path / "b.csv", tmp_path / "b.png"
    out.write_text("an earlier table\n")
    png.write_bytes(b"an earlier figure")
    _interrupt(monkeypatch, plots, "plot_band_levels")
    assert main(["bands", rec, "--out", str(out), "--plot", str(png)]) == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"cablecasing: interrupted: stopped: {out} written by this run; the previous {png} kept as it was"]
    assert out.read_text().startswith("band,") and png.read_bytes() == b"an earlier figure"


# --- M2: spectrum's RMS range left empty by --fmax or --resolution --------------------------------


@pytest.mark.parametrize(
    "argv,key",
    [
        (["--fmax", "60"], "--fmax = 60.0"),  # (the default resolution of a 0.2 s record: df = 39 Hz)
        (["--resolution", "1000"], "--resolution = 1000.0"),  # (df = 1250 Hz: 2 df above the default --fmax)
        (["--fmax", "100", "--resolution", "100"], "--resolution = 100.0"),
    ],
)
def test_spectrum_whose_lines_start_above_fmax_names_the_option_before_printing(tmp_path, capsys, argv, key):
    rec = _record(tmp_path / "r.csv", duration=0.2)
    assert main(["spectrum", rec, *argv]) == 2
    out, err = capsys.readouterr()
    assert out == ""  # (refused before the header line)
    line = err.strip().splitlines()[-1]
    assert line.startswith(f"cablecasing: error: {key}: leaves the PSD's RMS no range: its lines measure from 2 df = ")
    assert "f_low" not in err and "f_high" not in err
    # what it advises works: the finer --resolution it names, or a --fmax above 2 df
    two_df = float(re.search(r"2 df = ([0-9.]+) Hz", line).group(1))
    finer = re.search(r"--resolution ([0-9.]+) Hz or finer", line).group(1)
    fmax = argv[argv.index("--fmax") + 1] if "--fmax" in argv else "2000"
    resolution = ["--resolution", argv[argv.index("--resolution") + 1]] if "--resolution" in argv else []
    assert main(["spectrum", rec, "--fmax", fmax, "--resolution", finer]) == 0
    assert main(["spectrum", rec, "--fmax", f"{two_df * 1.01:g}", *resolution]) == 0  # (1 %: above its 4 digits)


# --- M3: study --out '' -----------------------------------------------------------------------------


def test_study_refuses_an_empty_out_as_report_does(tmp_path, capsys, monkeypatch):
    """An unset variable in a script, --out "$OUTDIR", must not write the study into the current folder."""
    monkeypatch.chdir(tmp_path)
    said = "--out = '': must name a folder (an empty path would write into the current folder)"
    for argv in (
        ["study", "--vary", "casing.E=2e9:1e10", "--samples", "3", "--duration", "0.5", "--scheduler", "serial"],
        ["report", "--duration", "0.5", "--seeds", "2", "--study-samples", "0"],
    ):
        assert main([*argv, "--out", ""]) == 2
        out, err = capsys.readouterr()
        assert err.strip().splitlines() == [f"cablecasing: error: {said}"] and out == ""
    assert list(tmp_path.iterdir()) == []


# --- L2: --no-progress of ensemble and study --------------------------------------------------------


@pytest.mark.parametrize("quiet", [True, False])
def test_ensemble_draws_no_bar_with_no_progress(capsys, quiet):
    """A CI log gets no progress bar with --no-progress (without it, the bar is there: what the check
    looks for is what tqdm draws)."""
    assert main(["ensemble", "--seeds", "2", "--duration", "0.5", *(["--no-progress"] if quiet else [])]) == 0
    assert ("run/s" in capsys.readouterr().err) is not quiet


@pytest.mark.slow
def test_study_draws_no_bar_with_no_progress(tmp_path, capsys):
    argv = ["study", "--vary", "casing.E=2e9:1e10", "--samples", "3", "--duration", "0.5", "--scheduler", "serial"]
    assert main([*argv, "--out", str(tmp_path / "st"), "--no-progress"]) == 0
    err = capsys.readouterr().err
    assert "sample/s" not in err and "study:" not in err  # (tqdm's rate and its desc)


def test_no_progress_is_described_alike_in_help_and_docs():
    """--no-progress of simulate, report, ensemble and study: in each one's --help and synopsis."""
    from cablecasing_core.cli import build_parser

    sub = build_parser()._subparsers._group_actions[0].choices
    synopsis = (ROOT / "docs" / "cli.md").read_text()
    for name in ("simulate", "report", "ensemble", "study"):
        help_text = " ".join(sub[name].format_help().split())
        assert "--no-progress no progress bar" in help_text and "on stderr)" in help_text, name
        line = re.search(rf"^cablecasing {name} .*?(?=^cablecasing |^```)", synopsis, re.M | re.S).group(0)
        assert "[--no-progress]" in line, name


# --- L4: bands and spectrum name their record as --help does --------------------------------------


@pytest.mark.parametrize("command", ["bands", "spectrum"])
def test_bands_and_spectrum_name_their_record_as_help_does(tmp_path, capsys, command):
    from cablecasing_core.cli import build_parser

    sub = build_parser()._subparsers._group_actions[0].choices
    usage = sub[command].format_usage().split()
    assert usage[-1] == "RECORD"  # (the positional, last in the usage line)
    missing = tmp_path / "nope.csv"
    assert main([command, str(missing)]) == 2
    assert capsys.readouterr().err.strip() == f"cablecasing: error: RECORD = '{missing}': does not exist"
    uneven = tmp_path / "u.csv"  # (an error the record's reader names only once it is read: Records.fs)
    uneven.write_text("time [s],casing.B.Fz [N]\n" + "".join(f"{t!r},{t}\n" for t in (0.0, 0.1, 0.3, 0.35)))
    assert main([command, str(uneven), "--skip", "0"]) == 2
    assert capsys.readouterr().err.strip().startswith(f"cablecasing: error: RECORD = '{uneven}': must be evenly")


# --- L5: errors name the option the user gave ---------------------------------------------------------


@pytest.mark.parametrize(
    "argv,message",
    [
        # (table3 from 0 Hz by default: --fmax alone leaves no band)
        (
            ["--fmax", "5"],
            "--fmax = 5.0: leaves no table3 band whose nominal frequency lies in 0..5 Hz (--fmin..--fmax)",
        ),
        (["--fmin", "8000"], "--fmin = 8000.0: leaves no table3 band whose nominal frequency lies in 8000..inf Hz"),
        (["--fmin", "100", "--fmax", "105"], "--fmin/--fmax = (100.0, 105.0): leaves no table3 band whose nominal"),
        (
            ["--kind", "octave", "--fmax", "5"],
            "--fmax = 5.0: must be at least --fmin, by default 10 Hz (give --fmin too)",
        ),
    ],
)
def test_bands_names_the_limit_that_leaves_no_band(tmp_path, capsys, argv, message):
    assert main(["bands", _record(tmp_path / "r.csv", duration=0.2), *argv]) == 2
    assert capsys.readouterr().err.strip().startswith(f"cablecasing: error: {message}")


def test_an_ensemble_whose_dt_is_too_coarse_names_dt_not_the_duration(capsys):
    """--dt 1 makes the skip one whole step of 1 s, longer than the duration; the step is what is wrong
    (0.5 / 5680 Hz, the top edge of Table 3's bands, is the largest step allowed)."""
    assert main(["ensemble", "--seeds", "2", "--duration", "0.5", "--dt", "1"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"cablecasing: error: --dt = 1.0: must be at most {0.5 / 5680:.4g} s so that every band lies")


@pytest.mark.parametrize(
    "argv,choices",
    [(["identify"], "{damping,loss-factor,modulus}"), ([], "{modes,trfam,keys,geometry,simulate,static,")],
)
def test_a_missing_sub_command_is_named_by_its_choices(capsys, argv, choices):
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert f"error: the following arguments are required: {choices}" in err and "_command" not in err


# --- L6: the environment: an unknown MPLBACKEND, a stdout that cannot spell a path --------------------


@pytest.mark.parametrize("argv", [["simulate", "--duration", "0.001", "--out", "x.csv", "--plot", "p.png"], ["bands"]])
def test_an_unknown_mplbackend_is_named_before_the_run(tmp_path, argv):
    """In a process of its own (matplotlib is imported in this one already): status 2 and one line naming
    MPLBACKEND, before the run (no --out written); also where a command imports matplotlib without --plot."""
    if argv == ["bands"]:
        argv = ["bands", _record(tmp_path / "r.csv", duration=0.2)]
    env = {
        **os.environ,
        "MPLBACKEND": "nonsense",
        "PYTHONPATH": os.pathsep.join([PACKAGE_ROOT, os.environ.get("PYTHONPATH", "")]),
    }
    run = subprocess.run(
        [sys.executable, "-m", "cablecasing_core", *argv], cwd=tmp_path, env=env, capture_output=True, text=True
    )
    assert run.returncode == 2, run.stderr
    assert run.stderr.strip().splitlines() == [
        "cablecasing: error: MPLBACKEND = 'nonsense': must name a backend matplotlib knows (e.g. Agg) or be unset: "
        "matplotlib, which draws the figures (with Agg, whatever it names), does not start with it"
    ]
    assert not (tmp_path / "x.csv").exists()


def test_a_path_stdout_cannot_encode_leaves_a_done_run_done(tmp_path, monkeypatch):
    """PYTHONIOENCODING=ascii and an output path in unicode: the file is written and the line that says so
    is escaped, status 0 (it was 'internal error: UnicodeEncodeError', status 1, after the file was written)."""
    raw = io.BytesIO()
    monkeypatch.setattr(sys, "stdout", io.TextIOWrapper(raw, encoding="ascii"))
    out = tmp_path / "\u00fcn\u00ef" / "x.csv"
    out.parent.mkdir()
    assert main(["simulate", "--duration", "0.001", "--no-progress", "--out", str(out)]) == 0
    sys.stdout.flush()
    assert out.read_text().startswith("time [s],")
    escaped = str(out).encode("ascii", "backslashreplace").decode("ascii")
    assert f"wrote {escaped}, t = 0 and every step" in raw.getvalue().decode("ascii")


# --- L8: one table of exit statuses, in step with the docstring and the code ---------------------------


def _numbers(text):
    """The whole numbers in ``text`` that stand alone (not in 'SIGTERM', '1.5' or 'L8')."""
    return {int(n) for n in re.findall(r"(?<![\w.])(\d+)(?![\w.])", text)}


def test_docs_cli_md_tabulates_the_exit_statuses_of_the_docstring_and_the_code():
    import ast
    import signal

    import cablecasing_core.cli as cli

    said = _numbers(cli.__doc__.split("Exit statuses:")[1].split("(docs/cli.md")[0])
    section = (ROOT / "docs" / "cli.md").read_text().split("### Exit status\n")[1].split("\n#")[0]
    rows = [line.split("|")[1] for line in section.splitlines() if re.match(r"\| \d", line)]
    table = set().union(*(_numbers(r) for r in rows))
    # the code: every `return <status>` of the command line's modules, and 128 + the signals that stop it
    # (main returns 128 + signum for SIGTERM and SIGHUP, _STOP_SIGNALS)
    returned = set()
    for module in Path(cli.__file__).parent.glob("*.py"):
        for node in ast.walk(ast.parse(module.read_text())):
            if isinstance(node, ast.Return) and isinstance(node.value, ast.Constant) and type(node.value.value) is int:
                returned.add(node.value.value)
    returned |= {128 + s for s in cli._STOP_SIGNALS}
    assert table == said == returned == {0, 1, 2, 3, 130, 128 + signal.SIGTERM, 128 + signal.SIGHUP}


def test_each_line_main_prints_on_its_way_out_is_in_its_status_s_row_of_the_table():
    """Every line that main()'s exception handlers print (its literal head, up to the first value
    filled in) stands in docs/cli.md's row of the status the handler returns after printing it: a new
    way out (review AL L1: a warning made an error by -W error, status 2) is tabulated with its line."""
    import ast
    import signal

    import cablecasing_core.cli as cli

    section = (ROOT / "docs" / "cli.md").read_text().split("### Exit status\n")[1].split("\n#")[0]
    rows = {}
    for line in section.splitlines():
        if re.match(r"\| \d", line):
            for status in _numbers(line.split("|")[1]):
                rows[status] = line
    main_def = next(
        n for n in ast.parse(Path(cli.__file__).read_text()).body if isinstance(n, ast.FunctionDef) and n.name == "main"
    )
    handlers = [h for t in ast.walk(main_def) if isinstance(t, ast.Try) for h in t.handlers]
    pairs = []
    for handler in handlers:
        events = []  # (line, "print", head) and (line, "return", statuses), in source order
        for node in ast.walk(handler):
            if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "print" and node.args:
                first = node.args[0]
                parts = first.values if isinstance(first, ast.JoinedStr) else [first]
                head = parts[0].value if isinstance(parts[0], ast.Constant) else ""
                if head.strip().startswith("cablecasing:"):
                    events.append((node.lineno, "print", head.lstrip()))
            elif isinstance(node, ast.Return) and isinstance(node.value, ast.Constant):
                events.append((node.lineno, "return", {node.value.value}))
            elif isinstance(node, ast.Return) and isinstance(node.value, ast.BinOp):  # 128 + signum
                events.append((node.lineno, "return", {128 + s for s in cli._STOP_SIGNALS}))
        events.sort(key=lambda e: e[0])
        for i, (_, kind, head) in enumerate(events):
            if kind == "print":
                statuses = next(e[2] for e in events[i + 1 :] if e[1] == "return")
                pairs += [(status, head) for status in statuses]
    assert len(pairs) >= 8  # (the handlers were found: 3, 2, 2, 1, 130, 143, 129, 1, 2, 2)
    assert (2, "cablecasing: error: (a warning made an error by -W error / PYTHONWARNINGS): ") in pairs
    assert 128 + signal.SIGTERM in {s for s, _ in pairs}
    missing = [(status, head) for status, head in pairs if head not in rows[status]]
    assert not missing, f"docs/cli.md's exit-status rows do not show these lines: {missing}"
