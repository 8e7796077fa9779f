"""docs/identification.md, section 7: the example commands run as written, on the inputs the
section says how to make from examples/straight_casing.toml, and give back what the model holds."""

import re
import shlex
from pathlib import Path

import numpy as np
import pytest

from cablecasing_core.cli import main
from cablecasing_core.model.load import tomllib  # (tomllib, or tomli before Python 3.11)

ROOT = Path(__file__).resolve().parents[2]


def _section_7_blocks():
    text = (ROOT / "docs" / "identification.md").read_text()
    section = text.split("## 7. Command line", 1)[1].split("\n## ", 1)[0]
    return [b.strip().splitlines() for b in re.findall(r"```\n(.*?)```", section, re.S)]


def _run(line, folder):
    """One line of a block: `cablecasing ...` through the CLI's main, a `printf '...' > file` written."""
    if line.startswith("printf "):
        fmt, target = re.fullmatch(r"printf '(.*)' > (\S+)", line).groups()
        (folder / target).write_text(fmt.replace("\\n", "\n"))
        return 0
    words = shlex.split(line)
    assert words[0] == "cablecasing", line
    return main([str(ROOT / w) if w.startswith("examples/") else w for w in words[1:]])


@pytest.mark.slow  # a 1.5 s run of the straight casing (~4 s) and three identifications
def test_the_identification_examples_run_as_written(tmp_path, monkeypatch, capsys):
    import pyuff  # noqa: F401  (required by the [test] extra: a missing one fails the test, not skips it)

    commands, recipes = _section_7_blocks()[:2]
    monkeypatch.chdir(tmp_path)
    for line in recipes + commands:
        assert _run(line, tmp_path) == 0, (line, capsys.readouterr().err)
    rayleigh = tomllib.loads((tmp_path / "rayleigh.toml").read_text())["casing"]
    assert rayleigh["alpha"] == pytest.approx(2.0, rel=0.01) and rayleigh["beta"] == pytest.approx(4.23e-5, rel=0.01)
    eta = np.array(tomllib.loads((tmp_path / "eta.toml").read_text())["casing"]["loss_factor"])
    np.testing.assert_allclose(eta[:, 0], [29.82, 58.47, 96.66], rtol=1e-3)
    np.testing.assert_allclose(eta[:, 1], 0.05, rtol=0.02)
    out = capsys.readouterr().out
    E = [float(x) for x in re.findall(r"^\s+\d+\s+\S+\s+\S+\s+(\S+)\s+\d+$", out, re.M)]
    assert len(E) == 4 and np.allclose(E, 1.1**2 * 5e9, rtol=2e-3), out
    for png in ("ridges.png", "circles.png", "E.png"):
        assert (tmp_path / png).stat().st_size > 0
