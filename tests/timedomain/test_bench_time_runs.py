"""``benchmarks/bench_time.py`` runs against the present API (its installed part called
``scenario_motion`` with an argument issue 25 had removed, and nothing ran it)."""

import subprocess
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_time.py"


@pytest.mark.slow
def test_bench_time_prints_the_installed_figures():
    cmd = [sys.executable, str(BENCH), "--duration", "0.02", "--repeat", "1", "--speed-only"]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    values = dict(line.split(": ", 1) for line in out.splitlines() if ": " in line)
    names = ("rtf_installed", "mean_active_contacts_installed", "static_state_s", "static_cli_wall_s")
    costs = ("installed_default_over_switch_cost", "installed_default_over_switch_plain_cost")
    for name in (*names, *costs, "installed_default_over_tolerance_cost"):
        assert name in values, name
    # the installed run starts from the static state's 12 closed contacts, and the fade-in of the
    # first 0.01 s opens none of them all at once: at least 10 nodes in contact on average
    assert float(values["mean_active_contacts_installed"]) >= 10
    assert int(values["contact_unconverged_steps_installed"]) == 0
