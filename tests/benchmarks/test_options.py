"""The benchmarks' command lines (benchmarks/_options.py): every script's ``--help`` says what it
measures, that it prints ``name: value`` lines and how it is run, and runs nothing; a typo and a bad
value end the script before any run with one line naming the option as typed and exit status 2
(a bad value used to run for minutes and end in a traceback naming an internal key, or print
nonsense with status 0). The cases run in one process (``benchmark_command_lines``), each as its
command line would; one runs as a command line of its own."""

import ast
import subprocess
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"
SCRIPTS = sorted(p.name for p in BENCH.glob("*.py") if not p.name.startswith("_"))


def refusal(result, script):
    """The refusal of argparse, or what was wrong instead: status 2, nothing on stdout (nothing
    ran), no traceback, and one line ``script: error: ...`` (after the usage), returned without
    that prefix."""
    code, stdout, stderr = result
    if code != 2 or stdout or "Traceback" in stderr:
        return f"status {code}, stdout {stdout[-300:]!r}, stderr {stderr[-600:]!r}"
    errors = [line for line in stderr.splitlines() if ": error: " in line]
    if len(errors) != 1 or stderr.splitlines()[-1] != errors[0] or not errors[0].startswith(f"{script}: error: "):
        return f"not one line '{script}: error: ...': {stderr[-600:]!r}"
    return errors[0][len(f"{script}: error: ") :]


def test_every_benchmark_is_found():
    assert len(SCRIPTS) >= 28 and "bench_time.py" in SCRIPTS  # (the folder was found)


def test_help_says_what_the_benchmark_measures_and_prints_and_runs_nothing(benchmark_command_lines):
    wrong = {}
    for script, (code, stdout, stderr) in zip(SCRIPTS, benchmark_command_lines([(s, ["--help"]) for s in SCRIPTS])):
        doc = ast.get_docstring(ast.parse((BENCH / script).read_text(encoding="utf-8")), clean=False)
        if code != 0:
            wrong[script] = f"status {code}: {stderr[-600:]}"
        elif doc.strip().splitlines()[0] not in stdout:  # what it measures: the docstring's first line
            wrong[script] = "the docstring's first line is not in --help"
        elif "name: value" not in stdout:  # what it prints
            wrong[script] = "--help does not say it prints name: value lines"
        elif f"benchmarks/{script}" not in stdout:  # how the docs run it
            wrong[script] = "--help shows no command"
    assert not wrong, wrong


def test_a_typo_is_refused(benchmark_command_lines):
    results = benchmark_command_lines([(s, ["--no-such-option"]) for s in SCRIPTS])
    lines = {s: refusal(r, s) for s, r in zip(SCRIPTS, results)}
    # (ab_kernels.py names its two trees first: they are missing too)
    wrong = {s: x for s, x in lines.items() if "--no-such-option" not in x and "required: a, b" not in x}
    assert not wrong, wrong


BAD = [
    ("ab_kernels.py", [".", ".", "--duration", "0"], "--duration = 0.0: must be a number >= 0.01"),
    ("ab_kernels.py", ["/nonexistent", "."], "a = '/nonexistent': must be a folder holding"),
    ("band_window.py", [], "nothing to measure: give --bias, --time-step or --ratio"),
    ("band_window.py", ["--bias", "--seeds", "-1"], "--seeds = -1: must be a whole number"),
    ("band_window.py", ["--ratio", "casing.E=2e9:1e10", "--seeds", "1"], "--seeds = [1]: must name at least 2"),
    ("band_window.py", ["--ratio", "casing.E"], "--ratio = 'casing.E': must be KEY=LO:HI"),
    ("bench_fmu.py", ["--repeat", "0"], "--repeat = 0: must be an integer >= 1"),
    ("bench_fmu.py", ["--hosts", "/nonexistent"], "--hosts = '/nonexistent': must be a folder holding fmusim"),
    ("bench_fmu_pool.py", ["--seeds", "1"], "--seeds = 1: must be an integer >= 2"),
    ("bench_mounts.py", ["--duration", "0"], "--duration = 0.0: must be a positive number of seconds"),
    ("bench_record.py", ["--repeat", "0"], "--repeat = 0: must be an integer >= 1"),
    ("bench_study.py", ["--samples", "2"], "--samples = 2: must be an integer >= 8"),
    ("bench_study.py", ["--kwargs", "[1]"], "--kwargs = '[1]': must be a JSON object"),
    ("bench_time.py", ["--duration", "-1", "--speed-only"], "--duration = -1.0: must be a positive number"),
    ("bench_time.py", ["--duration", "nan"], "--duration = nan: must be a positive number"),
    ("bench_time.py", ["--repeat", "0"], "--repeat = 0: must be an integer >= 1"),
    ("bench_time.py", ["--speed-only", "--ensemble", "2"], "--ensemble = 2 with --speed-only"),
    ("bench_time.py", ["--ensemble", "1"], "--ensemble = 1: must be an integer >= 2"),
    ("bench_time.py", ["--ensemble", "2", "--ensemble-save", "levels"], "--ensemble-save = 'levels': must be a name"),
    ("bench_time.py", ["--ensemble", "2", "--ensemble-save", "/nonexistent/l.npz"], "--ensemble-save = '/nonex"),
    ("bench_time.py", ["--ensemble-save", "levels.npz"], "--ensemble-save = 'levels.npz': needs --ensemble"),
    ("bench_time.py", ["--model", "nope.toml"], "--model = 'nope.toml': must be a readable TOML file"),
    ("chaos.py", ["--plot", "/nonexistent/x.png"], "--plot = '/nonexistent/x.png': must be a file in an existing"),
    ("chaos.py", ["--plot", "separation.txt"], "--plot = 'separation.txt': must be a name ending in .png"),
    ("chaos.py", ["--set", "contact.damping=-1"], "--set = ['contact.damping=-1']: contact.damping = -1.0"),
    ("condensed_contact_bound.py", ["--repeat", "0"], "--repeat = 0: must be an integer >= 1"),
    ("contact_between_nodes.py", ["--elements", "0"], "--elements = 0: must be a whole number"),
    ("contact_episodes.py", ["--duration", "0.02"], "--duration 0.02: must be at least 0.1 s"),
    ("contact_points.py", ["--variants", "70/3"], "--variants = '70/3': must be N/S"),
    ("contact_points.py", ["--seeds", "1"], "--seeds = 1: must be an integer >= 2"),
    ("contact_regimes.py", ["--seeds", "0"], "--seeds = 0: must be an integer >= 1"),
    ("default_step_parts.py", ["--rounds", "0"], "--rounds = 0: must be an integer >= 1"),
    ("default_time_step.py", ["--dt", "3e-5", "--duration", "0.02"], "--dt = 3e-05: must divide --chunk = 0.02 s"),
    ("driven_support_error.py", ["--frequencies", "-100"], "--frequencies = -100.0: must be a number in (0,"),
    ("event_tolerance.py", ["--model", "nope"], "--model = 'nope': must be a readable TOML file"),
    ("event_tolerance.py", ["--early", "0"], "--early = 0.0: must be a whole number of 1e-05 s steps, at least one"),
    ("event_tolerance.py", ["--early", "1.5e-5"], "--early = 1.5e-05: must be a whole number of 1e-05 s steps (it"),
    ("friction_laws.py", ["--duration", "-1"], "--duration -1.0, --chunk 0.01: need duration >= chunk > 0"),
    ("installed_mechanisms.py", ["--only", "nosuch"], "argument --only: invalid choice: 'nosuch'"),
    ("installed_mechanisms.py", ["--seeds", "0"], "--seeds = 0: must be an integer >= 1"),
    ("installed_time_step.py", ["--dts", "1e-5:0"], "--dts = '1e-5:0': SUBSTEPS is contact.event_substeps"),
    ("installed_time_step.py", ["--model", "nope.toml"], "--model = 'nope.toml': must be a readable TOML file"),
    ("limits.py", ["--modes", "0"], "--modes = 0: must be an integer >= 1"),
    ("mesh_refinement.py", ["--seeds", "x"], "--seeds = x: must be N or SPEC=N"),
    ("mesh_refinement.py", ["--json", "/nonexistent/m.json"], "--json = '/nonexistent/m.json': must be a file in"),
    ("rattle.py", ["--plot", "/nonexistent/x.png"], "--plot = '/nonexistent/x.png': must be a file in an existing"),
    ("start_transient.py", ["--short-seeds", "5", "3"], "--short-seeds = [5, 3]: must be FIRST LAST"),
    ("start_transient.py", ["--parts", "short", "--short-seeds", "301", "301"], "--short-seeds = [301, 301]"),
    ("stick_slip_switches.py", ["--dts", "1e-5:0"], "--dts = '1e-5:0': SUBSTEPS is contact.event_substeps"),
]


def test_the_bad_values_are_refused_before_any_run(benchmark_command_lines):
    results = benchmark_command_lines([(s, a) for s, a, _ in BAD])
    wrong = {}
    for (script, args, message), result in zip(BAD, results):
        line = refusal(result, script)
        if not line.startswith(message):
            wrong[f"{script} {' '.join(args)}"] = line
    assert not wrong, wrong


def test_a_bad_value_on_the_command_line_itself():
    """The same refusal from ``python benchmarks/bench_time.py --duration -1`` in a process of its own
    (the review's case: 11 s of runs, then a traceback naming ``h``)."""
    cmd = [sys.executable, str(BENCH / "bench_time.py"), "--duration", "-1", "--speed-only", "--repeat", "1"]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    line = refusal((done.returncode, done.stdout, done.stderr), "bench_time.py")
    assert line == "--duration = -1.0: must be a positive number of seconds", line
