"""The hint of a missing optional package names the packages with pyproject.toml's version ranges and
the checkout's extra, never the distribution `cablecasing`, which is not on the package index (review
AL M5: `pip install 'cablecasing[study]'` found nothing there)."""

from pathlib import Path

import pytest

from cablecasing_core.extras import EXTRAS, install_hint

try:
    import tomllib
except ModuleNotFoundError:  # (Python 3.10)
    import tomli as tomllib

PYPROJECT = tomllib.loads((Path(__file__).resolve().parents[2] / "pyproject.toml").read_text())


def test_the_extras_table_is_pyproject_s():
    """extras.EXTRAS, which the messages read, holds pyproject.toml's extras (but `test`) as written there."""
    extras = PYPROJECT["project"]["optional-dependencies"]
    assert EXTRAS == {name: tuple(reqs) for name, reqs in extras.items() if name != "test"}


@pytest.mark.parametrize("extra", sorted(PYPROJECT["project"]["optional-dependencies"].keys() - {"test"}))
def test_a_hint_installs_each_package_by_its_requirement_and_the_extra_from_a_checkout(extra):
    reqs = PYPROJECT["project"]["optional-dependencies"][extra]
    checkout = f" (from a checkout: pip install '.[{extra}]')"
    assert install_hint(extra) == "pip install " + " ".join(f"'{r}'" for r in reqs) + checkout
    for r in reqs:  # (a package by the name a message gives it: SALib, dask[distributed], pyuff)
        name = r.split(">=")[0]
        assert install_hint(extra, [name]) == f"pip install '{r}'{checkout}"
        assert "cablecasing[" not in install_hint(extra, [name])
