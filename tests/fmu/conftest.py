"""The FMU's test driver as a fixture: tests/fmu/fmu_driver.py runs each scenario in a fresh
process (it is a script; the test process only prepares inputs and reads the results)."""

import importlib.util
from pathlib import Path

import pytest


@pytest.fixture(scope="session")
def fmu_driver():
    """The module tests/fmu/fmu_driver.py (``run``, ``INPUTS``), loaded from its file."""
    spec = importlib.util.spec_from_file_location("fmu_driver", Path(__file__).with_name("fmu_driver.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
