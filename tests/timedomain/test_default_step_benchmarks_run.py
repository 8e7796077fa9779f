"""``benchmarks/default_time_step.py`` and ``benchmarks/default_step_parts.py`` run against the
present API and print their figures (what docs/performance.md cites; no timing is asserted)."""

import subprocess
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[2] / "benchmarks"


def _run(script, *args):
    cmd = [sys.executable, str(BENCHMARKS / script), *args]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return {k: v for k, v in (line.split(": ", 1) for line in out.splitlines() if ": " in line)}


@pytest.mark.slow
def test_default_time_step_prints_every_step():
    values = _run("default_time_step.py", "--duration", "0.06", "--dt", "1e-5,2e-5")
    for dt in ("1e-05", "2e-05"):
        for name in ("rtf_coupled", "us_per_step", "contacts_per_step", "contact_newton_iterations_per_step"):
            assert f"{name}_dt{dt}" in values, (name, dt)
        # the scenario's impacts start within its first 0.06 s: contacts close, and each closed
        # contact takes at least one Newton iteration in its step
        contacts = float(values[f"contacts_per_step_dt{dt}"])
        assert contacts > 0
        assert float(values[f"contact_newton_iterations_per_step_dt{dt}"]) > 0


@pytest.mark.slow
def test_default_step_parts_keeps_every_node_off_the_wall_in_its_far_part():
    # the script exits non-zero if the all_far engine (gap = 1 m) closed any contact
    values = _run("default_step_parts.py", "--rounds", "6")
    for name in ("contact_free", "all_far", "full"):
        assert float(values[f"us_per_step_{name}"]) > 0
    assert float(values["contacts_per_step"]) > 0
    assert values["contact_work_us_per_contact"] != "nan"
