"""`cablecasing --version` (review AL L6: there was none, `the following arguments are required`):
the installed distribution's version, the folder the package runs from and the Python; a copy that
is not the installed one, or not installed at all (a checkout on PYTHONPATH), says so with the
version its pyproject.toml states. The distribution's metadata is stood in for, so that each case
is checked whatever this test environment installed."""

import importlib.metadata
import json
import platform
from pathlib import Path

import pytest

import cablecasing_core
from cablecasing_core.cli import main

try:
    import tomllib
except ModuleNotFoundError:  # (Python 3.10)
    import tomli as tomllib

PACKAGE = Path(cablecasing_core.__file__).resolve().parent
PYTHON = f"Python {platform.python_version()}"


class _Dist:
    """An installed distribution's metadata: ``version``; ``direct_url.json`` (pip's record of an
    install from a folder: ``editable`` for ``pip install -e``); its files under ``site``."""

    def __init__(self, version, direct_url=None, site=None):
        self.version, self._direct, self._site = version, direct_url, site

    def read_text(self, name):
        return json.dumps(self._direct) if name == "direct_url.json" and self._direct else None

    def locate_file(self, path):
        return Path(self._site) / path


def _version(capsys, monkeypatch, dist):
    def distribution(name):
        assert name == "cablecasing"
        if dist is None:
            raise importlib.metadata.PackageNotFoundError(name)
        return dist

    monkeypatch.setattr(importlib.metadata, "distribution", distribution)
    with pytest.raises(SystemExit) as stop:
        main(["--version"])
    out = capsys.readouterr().out
    assert stop.value.code == 0 and out.count("\n") == 1, out  # (one line, whatever the path's length)
    return out.strip()


def _checkout_version():
    """The version that the checkout of the tested package states (its pyproject.toml), or None."""
    pyproject = PACKAGE.parent / "pyproject.toml"
    return tomllib.loads(pyproject.read_text())["project"]["version"] if pyproject.exists() else None


def test_an_editable_install_of_this_checkout_prints_its_version(capsys, monkeypatch):
    dist = _Dist("9.8.7", {"url": PACKAGE.parent.as_uri(), "dir_info": {"editable": True}})
    assert _version(capsys, monkeypatch, dist) == f"cablecasing 9.8.7 (cablecasing_core from {PACKAGE}; {PYTHON})"


def test_a_regular_install_prints_its_version(capsys, monkeypatch):
    """(a wheel's files: the package found where the metadata says its files lie)"""
    dist = _Dist("9.8.7", {"url": "file:///somewhere/cablecasing", "dir_info": {}}, site=PACKAGE.parent)
    assert _version(capsys, monkeypatch, dist) == f"cablecasing 9.8.7 (cablecasing_core from {PACKAGE}; {PYTHON})"


@pytest.mark.parametrize("editable", [True, False])
def test_a_copy_that_is_not_the_installed_one_says_so(capsys, monkeypatch, tmp_path, editable):
    (tmp_path / "cablecasing_core").mkdir()
    (tmp_path / "cablecasing_core" / "__init__.py").write_text("")
    if editable:
        dist = _Dist("9.8.7", {"url": tmp_path.as_uri(), "dir_info": {"editable": True}})
    else:
        dist = _Dist("9.8.7", None, site=tmp_path)
    text = _version(capsys, monkeypatch, dist)
    stated = f"; its checkout's pyproject.toml states version {_checkout_version()}" if _checkout_version() else ""
    assert text == (
        f"cablecasing: this cablecasing_core, from {PACKAGE}, is not the installed one (cablecasing 9.8.7, from "
        f"{tmp_path.resolve() / 'cablecasing_core'}){stated}; {PYTHON}"
    )


def test_a_copy_that_is_not_installed_says_so_and_the_version_its_checkout_states(capsys, monkeypatch):
    text = _version(capsys, monkeypatch, None)
    stated = f"; its checkout's pyproject.toml states version {_checkout_version()}" if _checkout_version() else ""
    assert text == (
        f"cablecasing: not installed (no package metadata): cablecasing_core runs from {PACKAGE}{stated}; {PYTHON}; "
        "pip install . in the checkout installs it"
    )


def test_the_real_metadata_s_version_is_printed(capsys):
    """Without stand-ins: the version of the distribution this environment installed."""
    with pytest.raises(SystemExit):
        main(["--version"])
    out = capsys.readouterr().out
    try:
        version = importlib.metadata.version("cablecasing")
    except importlib.metadata.PackageNotFoundError:
        assert "not installed" in out
    else:
        assert f"cablecasing {version}" in out and str(PACKAGE) in out
