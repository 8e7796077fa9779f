"""docs/architecture.md names every file of the package, the FMU's sources, the benchmarks and the
examples (its table is "one line per file": a file added without its line is a file no reader
finds)."""

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_the_architecture_table_names_every_file():
    text = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    files = [
        p
        for folder in ("cablecasing_core", "benchmarks", "examples", "fmu_src")
        for p in sorted((ROOT / folder).rglob("*"))
        if p.is_file() and "__pycache__" not in p.parts and not p.name.startswith(".")
    ]
    assert len(files) > 100  # (the folders were found)
    missing = [str(p.relative_to(ROOT)) for p in files if p.name not in text]
    assert not missing, f"docs/architecture.md does not name: {missing}"
