"""Every page or figure of docs/ that the project cites (README, the pages themselves, error messages
and docstrings of the code, examples, benchmarks, the FMU's sources, the tests that read a page)
exists under that name: a page renamed (the mounted-cable example, installation.md, became
mounted_example.md, review AL L3) leaves no reader at a missing file. CHANGELOG.md is history and
keeps the names pages had then."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CITED = re.compile(r"\bdocs/[A-Za-z0-9_.-]+(?:/[A-Za-z0-9_.-]+)*\.(?:md|png)\b")


def _citing_files():
    yield from (ROOT / name for name in ("README.md", "build_fmu.py", "Makefile", "pyproject.toml"))
    for folder in ("docs", "cablecasing_core", "examples", "benchmarks", "fmu_src", "tests"):
        for path in sorted((ROOT / folder).rglob("*")):
            if path.suffix in (".md", ".py", ".toml", ".c", ".txt") and "__pycache__" not in path.parts:
                yield path


def test_every_cited_page_of_docs_exists():
    cited = {}
    for path in _citing_files():
        for name in CITED.findall(path.read_text(encoding="utf-8", errors="replace")):
            cited.setdefault(name, path.relative_to(ROOT).as_posix())
    assert "docs/mounted_example.md" in cited and "docs/model_file.md" in cited  # (the files were read)
    missing = {name: where for name, where in cited.items() if not (ROOT / name).exists()}
    assert not missing, f"cited but missing (name: first file citing it): {missing}"
