"""``benchmarks/contact_between_nodes.py`` (docs/time_domain.md, "The mesh") runs against the present
API: one specimen, one mesh, a short record."""

import subprocess
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "contact_between_nodes.py"


def test_the_contact_between_nodes_prints_its_figures():
    cmd = [sys.executable, str(BENCH), "--specimen", "installed", "--elements", "35", "--duration", "0.06"]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    values = dict(line.split(": ", 1) for line in out.splitlines() if ": " in line)
    assert int(values["installed_35_samples"]) == 21  # (0.05 to 0.06 s every 5e-4 s, both ends)
    # the installed cable lies on the wall: its nodes are in contact at every sample
    assert float(values["installed_35_nodes_in_contact"]) > 5
    assert float(values["installed_35_node_penetration_m"].split()[0]) > 0
