"""The optional extras of the distribution ``cablecasing`` (pyproject.toml's
``[project.optional-dependencies]``, but ``test``) and how a message about a missing optional package
says to install it.

The distribution is installed from a source checkout; it is not on the Python Package Index, so a
hint ``pip install 'cablecasing[study]'`` would fail there (or install someone else's package of
that name). :func:`install_hint` names the packages themselves with their version ranges, which a
plain ``pip install`` gets from the index, and the checkout's extra. :data:`EXTRAS` holds the
extras as pyproject.toml states them (tests/cli/test_install_hints.py keeps the two equal; the
installed metadata is not read, for a copy run from its folder, such as the FMU's, has none).
"""

from __future__ import annotations

import re

#: The extras of pyproject.toml with their requirements, as written there (but ``test``).
EXTRAS = {
    "fmu": ("pythonfmu>=0.6.5", "fmpy>=0.3.20"),
    "identify": ("pywavelets>=1.5", "pyuff>=2.4"),
    "study": ("dask[distributed]>=2024.1", "SALib>=1.5"),
}


def _package(requirement: str) -> str:
    """The package a requirement names, with its own extras (``dask[distributed]`` of
    ``dask[distributed]>=2024.1``), lower case."""
    return re.split(r"[<>=!~;\s]", requirement, maxsplit=1)[0].lower()


def install_hint(extra, packages=None) -> str:
    """How to install ``packages`` (names as a requirement of the extra ``extra`` gives them, e.g.
    ``SALib``, ``dask[distributed]``; default: the whole extra): ``pip install 'SALib>=1.5'
    'dask[distributed]>=2024.1' (from a checkout: pip install '.[study]')``. ``extra`` may also be a
    dict ``{extra: packages or None}``, for packages of several extras in one command (``pip install
    'pyuff>=2.4' 'SALib>=1.5' (from a checkout: pip install '.[identify,study]')``). A name the extra
    does not list is a ``KeyError`` (a message naming a package that its extra lost)."""
    wants = extra if isinstance(extra, dict) else {extra: packages}
    named = []
    for name, pkgs in wants.items():
        reqs = EXTRAS[name]
        if pkgs is not None:
            by_name = {_package(r): r for r in reqs}
            reqs = [by_name[p.lower()] for p in pkgs]
        named += reqs
    checkout = ",".join(wants)
    return "pip install " + " ".join(f"'{r}'" for r in named) + f" (from a checkout: pip install '.[{checkout}]')"
