"""The benchmarks print ``name: value`` lines that a parser splitting at the first ``: `` reads: a name
without spaces, a value that is not empty, comments on lines of their own starting with ``#``
(review AN, A5: ``limits.py`` put a comment in the value, ``contact_regimes.py`` a name with spaces
per seed, ``default_step_parts.py`` a ``nan`` for a short run without contact). Three of them at
their shortest, each in a process of its own."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"
NAME = re.compile(r"[A-Za-z0-9_.<>/+-]+")


def lines_of(script, *args):
    cmd = [sys.executable, str(BENCH / script), *args]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=600, check=True)
    return done.stdout.splitlines()


@pytest.mark.slow
@pytest.mark.parametrize(
    ("script", "args", "names"),
    [
        # (10 and 12 elements: the eigenproblem and the 20 steps in a second each)
        ("limits.py", ["--modes", "10", "--simulate", "12"], ["modes_10_elements_s", "simulate_12_elements_peak_GB"]),
        # (one 0.05 s record: two chunks of the cost model)
        (
            "contact_regimes.py",
            ["--seeds", "1", "--duration", "0.05", "--workers", "1"],
            ["rms5_seed1_contacts_by_tenth", "rms5_seed1_us_per_step", "rms5_seed1_regime", "cost_model"],
        ),
        # (two rounds of 0.01 s after the 2 ms warm-up: no contact has closed yet)
        ("default_step_parts.py", ["--rounds", "2"], ["us_per_step_full", "contacts_per_step"]),
    ],
)
def test_every_line_is_a_name_and_a_value_or_a_comment(script, args, names):
    lines = lines_of(script, *args)
    values = {}
    for line in lines:
        if line.startswith("#"):
            continue
        name, sep, value = line.partition(": ")
        assert sep and NAME.fullmatch(name) and value.strip() and value.strip() != "nan", line
        values[name] = value
    for name in names:
        assert name in values, (name, lines)
    if script == "default_step_parts.py" and float(values["contacts_per_step"]) == 0:
        assert "contact_work_us_per_contact" not in values  # (no contact: a '#' line says why, no nan)
        assert any(line.startswith("# no contact closed") for line in lines), lines
