"""Fixtures shared by the test modules."""
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
FMU = ROOT / "dist" / "CableCasing.fmu"


@pytest.fixture(scope="session")
def fmu():
    """The FMU, built (in a separate process) if missing or older than any of its sources."""
    sys.path.insert(0, str(ROOT))
    try:
        import build_fmu
    finally:
        sys.path.remove(str(ROOT))
    newest = max(p.stat().st_mtime for p in build_fmu.sources())
    if not FMU.exists() or FMU.stat().st_mtime < newest:
        subprocess.run([sys.executable, str(ROOT / "build_fmu.py")], check=True, cwd=ROOT)
    return FMU
