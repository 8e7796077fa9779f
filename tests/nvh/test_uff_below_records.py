"""The UFF 58 format (``cablecasing_core.uff``) lies below the records and the identification, which
import it, and imports neither; the records import nothing of the identification; every public name
of the format is still importable from ``identification.uff_io``; its data types are one table."""

import ast
import itertools
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "cablecasing_core"


def _imports(path: Path) -> set:
    """The package modules a file imports, at module level and inside functions (absolute names)."""
    package = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts[:-1])
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            base = package.split(".")[: len(package.split(".")) - node.level + 1] if node.level else []
            module = ".".join([*base, *([node.module] if node.module else [])])
            found.add(module)
            found.update(f"{module}.{a.name}" for a in node.names)  # (from . import x: x may be a module)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
    return {m for m in found if m.startswith("cablecasing_core")}


def test_uff_imports_neither_records_nor_identification_and_records_no_identification():
    uff = _imports(PACKAGE / "uff.py")
    records = _imports(PACKAGE / "records.py")
    assert "cablecasing_core.uff" in records  # (the records' .uff files go through it)
    assert not [m for m in uff if m.startswith(("cablecasing_core.records", "cablecasing_core.identification"))]
    assert not [m for m in records if m.startswith("cablecasing_core.identification")]
    uff_io = _imports(PACKAGE / "identification" / "uff_io.py")
    assert {"cablecasing_core.uff", "cablecasing_core.records"} <= uff_io  # (the way down, not back)


THREE = ["cablecasing_core.uff", "cablecasing_core.records", "cablecasing_core.identification"]


@pytest.mark.parametrize("order", list(itertools.permutations(THREE)))
def test_the_three_import_in_any_order_in_a_fresh_interpreter(order):
    code = "import importlib\n" + "".join(f"importlib.import_module({m!r})\n" for m in order)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=PACKAGE.parent)
    assert done.returncode == 0, done.stderr


def test_the_format_s_names_are_importable_from_where_they_were():
    from cablecasing_core import files, uff, units
    from cablecasing_core.identification import uff_io

    for name in ("Record", "read_uff", "write_uff", "write_uff_time", "write_uff_frf", "frf_kind", "FRF_KIND_TYPES"):
        assert getattr(uff_io, name) is getattr(uff, name)
    for name in ("STATEMENTS", "function_names", "is_uff", "UFF_EXTENSIONS", "PYUFF_MISSING"):
        assert getattr(uff_io, name) is getattr(uff, name)
    for name in ("FREQUENCY_UNITS", "frequency_factor", "frequency_units_text"):
        assert getattr(uff_io, name) is getattr(units, name)
    assert files.TIME_UNITS is units.TIME_UNITS and files.time_factor is units.time_factor


def test_one_table_of_data_types_gives_the_records_and_the_frf_kinds_theirs():
    """UFF 58's specific data types (the format's definition): 8 displacement, 9 reaction force, 11
    velocity, 12 acceleration, 13 excitation force."""
    from cablecasing_core.identification.circlefit import FRF_KINDS
    from cablecasing_core.uff import FRF_KIND_TYPES, Record, data_type, frf_kind

    assert [data_type(u) for u in ("N", "N.m", "m", "m/s", "m/s2", "Pa", "")] == [9, 9, 8, 11, 12, 0, 0]
    assert set(FRF_KIND_TYPES) == set(FRF_KINDS)  # (every kind the circle fit takes can be written)
    assert FRF_KIND_TYPES == {
        "displacement": (8, 13, "m", "N"),
        "velocity": (11, 13, "m/s", "N"),
        "acceleration": (12, 13, "m/s2", "N"),
        "apparent_mass": (9, 12, "N", "m/s2"),
    }
    for kind, (num, den, *_) in FRF_KIND_TYPES.items():  # each read back as written
        assert frf_kind(Record("frf", [1.0, 2.0], [1j, 1j], data_type=num, denominator_type=den)) == kind
    # a reaction force in the denominator is a force too; F/x (dynamic stiffness) is taken as it is
    assert frf_kind(Record("frf", [1.0, 2.0], [1j, 1j], data_type=11, denominator_type=9)) == "velocity"
    assert frf_kind(Record("frf", [1.0, 2.0], [1j, 1j], data_type=13, denominator_type=8)) == "displacement"
