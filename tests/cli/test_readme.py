"""The README's examples of the command line and the Python API run as written (the FMU's needs a
built FMU: tests/fmu run it)."""

import re
import shlex
import warnings
from pathlib import Path

from cablecasing_core.cli import main

README = (Path(__file__).resolve().parents[2] / "README.md").read_text()


def _blocks(lang):
    return re.findall(rf"```{lang}\n(.*?)```", README, re.S)


def test_the_readme_states_the_two_commands():
    assert "make demo" in _blocks("sh")[0] and "make test" in _blocks("sh")[0]


def test_the_readme_says_how_to_install_with_every_extra():
    """`pip install .` and one line with every optional extra of pyproject.toml (but `test`), each
    extra named with what needs it."""
    try:
        import tomllib
    except ModuleNotFoundError:  # (Python 3.10)
        import tomli as tomllib

    pyproject = tomllib.loads((Path(__file__).resolve().parents[2] / "pyproject.toml").read_text())
    extras = set(pyproject["project"]["optional-dependencies"]) - {"test"}
    install = next(b for b in _blocks("sh") if "pip install" in b)
    assert re.search(r"^pip install \.\s", install, re.M)
    assert set(re.search(r"pip install '\.\[([a-z,]+)\]'", install).group(1).split(",")) == extras
    assert all(f"`{e}`:" in README for e in extras) and "make venv" in README
    # (in a section "Installing", which states the oldest Python that pyproject.toml's requires-python admits)
    section = README.split("\n## Installing\n")[1].split("\n## ")[0]
    assert install in section
    oldest = re.fullmatch(r">=\s*(3\.\d+)", pyproject["project"]["requires-python"]).group(1)
    assert f"Python {oldest} or newer" in " ".join(section.split())


def test_the_readme_command_line_example_runs_without_a_warning(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    block = next(b for b in _blocks("sh") if "cablecasing simulate" in b)
    lines = [s.split("#")[0] for s in block.splitlines() if s.strip()]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for line in lines:
            argv = shlex.split(line)
            assert argv[0] == "cablecasing"
            assert main(argv[1:] + (["--no-progress"] if argv[1] == "simulate" else [])) == 0, line
    out, err = capsys.readouterr()
    assert "warning" not in err and "RMS" in out and (tmp_path / "psd.png").exists()


def test_the_readme_python_example_runs_without_a_warning(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    code = _blocks("python")[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        exec(compile(code, "README.md", "exec"), {})
    assert "16Hz" in capsys.readouterr().out


def test_the_api_page_s_example_runs(tmp_path, monkeypatch, capsys):
    """docs/api.md's example runs as written (review AA M1: it called an undefined my_motion), and its
    own motion moves casing end A along z, as it says: the run's records have casing.A.az."""
    monkeypatch.chdir(tmp_path)
    page = (Path(__file__).resolve().parents[2] / "docs" / "api.md").read_text()
    code = re.findall(r"```python\n(.*?)```", page, re.S)[0]
    scope = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (its short runs warn of their few FFT lines, as the page says)
        exec(compile(code, "docs/api.md", "exec"), scope)
    rec = scope["own"].records()
    assert "casing.A.az" in rec.columns and abs(rec.column("casing.A.az")).max() > 0.0
    # its files have names of their own: a reader who ran README's 1 s `run.csv` first keeps it for
    # docs/nvh.md's apparent mass, which needs more than this 0.1 s run (review BC6)
    assert not (tmp_path / "run.csv").exists() and not (tmp_path / "run.npz").exists()
    assert (tmp_path / "api_run.csv").exists() and (tmp_path / "api_run.npz").exists()
    # the PSD's averages the comment states are those of the run it describes (review BC1)
    said = re.search(r"0\.1 s holds\s*#\s*(\d+) averages", page)
    assert said and int(said[1]) == scope["p"].n_averages, (said and said[1], scope["p"].n_averages)


def test_the_architecture_page_s_api_blocks_run(tmp_path, monkeypatch):
    """docs/architecture.md's two python blocks (the public API and the engine's contract) each run
    as written, on their own (reviews AG D3, AQ F3: they used freqs_hz, model, h, motion and state
    without defining them); what they leave is what they say: a 0.1 s run at the model's 1e-5 s read
    back from run.npz, and an engine that took h, then reset to t = 0."""
    monkeypatch.chdir(tmp_path)
    page = (Path(__file__).resolve().parents[2] / "docs" / "architecture.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", page, re.S)
    assert len(blocks) == 2
    scopes = []
    for code in blocks:
        scopes.append({})
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            exec(compile(code, "docs/architecture.md", "exec"), scopes[-1])
    rec = scopes[0]["rec"]
    assert abs(rec.time[-1] - 0.1) < 1e-12 and len(rec.time) == 10001  # (0 to 0.1 s every 1e-5 s, both ends)
    eng, state = scopes[1]["eng"], scopes[1]["state"]
    # (the state after advance(h), to round-off of the steps' sum; then reset to exactly 0)
    assert abs(float(state["time"][0]) - scopes[1]["h"]) < 1e-12 and eng.time == 0.0
