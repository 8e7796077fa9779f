"""Fixtures of the benchmarks' tests: their command lines run as ``python benchmarks/SCRIPT ...``
would run them, many in one process (the imports paid once: a check that comes before the runs
answers in milliseconds, the interpreter and numpy in a second)."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"

# Runs each case [script, args] as its command line would (sys.argv, the script as __main__, its
# folder on the path), its stdout and stderr caught; a case still running after 60 s (a check that
# did not come before the runs) is stopped by an alarm. Prints [status, stdout, stderr] per case.
DRIVER = r"""
import contextlib, io, json, runpy, signal, sys, traceback
bench, cases = sys.argv[1], json.loads(sys.stdin.read())
sys.path.insert(0, bench)
out = sys.stdout

class Ran(BaseException):
    pass

def alarm(signum, frame):
    raise Ran("still running after 60 s: the check did not come before the runs")

signal.signal(signal.SIGALRM, alarm)
results = []
for script, args in cases:
    stdout, stderr = io.StringIO(), io.StringIO()
    sys.argv = [f"{bench}/{script}", *args]
    code = 0
    signal.alarm(60)
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        try:
            runpy.run_path(sys.argv[0], run_name="__main__")
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        except BaseException:
            code = 1
            traceback.print_exc()
    signal.alarm(0)
    results.append([code, stdout.getvalue(), stderr.getvalue()])
out.write(json.dumps(results))
"""


@pytest.fixture(scope="session")
def benchmark_command_lines():
    """``run(cases)``: the (exit status, stdout, stderr) of each case ``(script, [args])`` of
    benchmarks/, in one process."""

    def run(cases):
        cmd = [sys.executable, "-c", DRIVER, str(BENCH)]
        done = subprocess.run(
            cmd, input=json.dumps([[s, list(a)] for s, a in cases]), capture_output=True, text=True, timeout=900
        )
        assert done.returncode == 0, done.stderr[-3000:]
        return [tuple(r) for r in json.loads(done.stdout)]

    return run
