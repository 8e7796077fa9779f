"""The demo (make demo: examples/demo.py) and its report: every figure the report references exists and is
a PNG, every CSV is written."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow  # builds the FMU and runs the demo

ROOT = Path(__file__).resolve().parents[2]


def test_report_renders_with_every_figure(tmp_path):
    out = tmp_path / "results"
    subprocess.run(
        [sys.executable, str(ROOT / "examples" / "demo.py"), "--out", str(out), "--duration", "0.15"],
        check=True,
        cwd=ROOT,
        timeout=1200,
    )
    html = (out / "report.html").read_text()
    imgs = re.findall(r'<img src="([^"]+)"', html)
    assert {"trfam_xyz.png", "simulation.png", "octave_bands.png"} <= set(imgs)
    for name in imgs:
        data = (out / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000, name
    for csv in ("fmu_outputs.csv", "simulation.csv", "octave_bands.csv", "trfam_x.csv"):
        assert (out / csv).stat().st_size > 100, csv
