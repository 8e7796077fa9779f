"""``cablecasing static``: the static state of a model on the command line (in-process)."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.timedomain.static_state import static_state


def test_static_json_of_the_installed_specimen(capsys, tmp_path):
    png = tmp_path / "static.png"
    assert main(["static", "installed", "--json", "--plot", str(png)]) == 0
    out = json.loads(capsys.readouterr().out)
    st = static_state(cc.load_model("installed"))
    assert set(out) == {
        "contact_force_N",
        "support_reactions_N",
        "balance_N",
        "buckling",
        "contact_nodes",
        "max_penetration_m",
        "largest_displacement_m",
    }
    for body, (d, at) in out["largest_displacement_m"].items():  # (the node that moves most, and its arc length)
        u = np.linalg.norm(st.U[body].reshape(-1, 6)[:, :3], axis=1)
        assert d == np.max(u) and at == st.arc_length[np.argmax(u)]
    np.testing.assert_array_equal(out["contact_force_N"], st.contact_force)  # same solve, same numbers
    assert set(out["support_reactions_N"]) == {"casing.A", "casing.B", "cable.A", "cable.B"}
    for name, r in out["support_reactions_N"].items():
        np.testing.assert_array_equal(r, st.reaction(name))
    assert out["contact_nodes"] == st.contact_nodes >= 10
    assert out["max_penetration_m"] == st.max_penetration > 0
    assert png.stat().st_size > 10_000


def test_static_table_and_errors(capsys):
    assert main(["static", "installed"]) == 0
    text = capsys.readouterr().out
    assert "cable nodes in contact" in text and "casing.A" in text and "pre-stretch force" in text
    assert main(["static"]) == 0  # the paper's specimen: nothing loads it
    text = capsys.readouterr().out
    assert "0 cable nodes in contact" in text
    # no cable node touches: said in one line, not a table's header without rows (review AN, B3)
    assert "  contact force of the casing on each cable node: none (no cable node in contact)\n" in text
    assert "penetration (m)" not in text
    straight = Path(__file__).resolve().parents[2] / "examples" / "straight_casing.toml"  # (a casing alone)
    assert main(["static", str(straight)]) == 0
    text = capsys.readouterr().out
    assert text.splitlines()[0].endswith(": gravity [0.0, 0.0, 0.0] m/s2 (no cable)")
    assert "cable" not in "\n".join(text.splitlines()[1:]), text  # (no tension, rest shape, contact)
    assert main(["static", "no_such_model.toml"]) == 2
    assert "MODEL = 'no_such_model.toml': must be a readable TOML file" in capsys.readouterr().err


@pytest.mark.slow
def test_static_runs_as_a_command():
    """The installed console script, in a fresh process, prints the JSON (its speed is measured by
    benchmarks/bench_time.py: static_cli_wall_s)."""
    exe = [sys.executable, "-m", "cablecasing_core.cli", "static", "installed", "--json"]
    out = json.loads(subprocess.run(exe, check=True, capture_output=True, text=True).stdout)
    assert out["contact_nodes"] >= 10


def test_the_static_command_loads_no_figures_statistics_or_studies():
    """docs/performance.md: the static command loads neither matplotlib nor scipy.stats, and the CLI
    imports a sub-command's modules only when it runs (the studies once came in with a constant the
    ensemble command's option check read). In a fresh process, as a user starts it."""
    code = (
        "import contextlib, io, sys\n"
        "from cablecasing_core.cli import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        "    assert main(['static', 'installed', '--json']) == 0\n"
        "print(sorted(m for m in ('matplotlib', 'scipy.stats', 'cablecasing_core.studies') if m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]", out
