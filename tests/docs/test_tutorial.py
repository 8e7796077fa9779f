"""The tutorial in the package's docstring and the schema's examples run as written (doctest)."""

import doctest

import cablecasing_core
from cablecasing_core.model import schema


def test_the_package_tutorial_runs_as_written():
    result = doctest.testmod(cablecasing_core, raise_on_error=False, verbose=False)
    assert result.attempted >= 15 and result.failed == 0


def test_the_schema_examples_run_as_written():
    result = doctest.testmod(schema, raise_on_error=False, verbose=False)
    assert result.attempted >= 3 and result.failed == 0
