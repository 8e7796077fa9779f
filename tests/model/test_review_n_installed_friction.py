"""Review N, N1: an installed model written from docs/mounted_example.md's recipe (examples/installation.toml
with `[loads]`) gets Coulomb's regularised friction law, as the built-in `installed` specimen has: with
the default switch law a cable on the wall recomputed 81 % of its steps and its levels do not converge
with the time step. The recipe's lines are taken from the doc as a reader copies them."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import tomllib

import cablecasing_core as cc

ROOT = Path(__file__).resolve().parents[2]


def test_the_installation_docs_mounted_model_has_the_regularized_law(tmp_path):
    doc = (ROOT / "docs" / "mounted_example.md").read_text()
    appended = re.search(r"printf '(.*?)' \| cat examples/installation\.toml - > mounted\.toml", doc).group(1)
    path = tmp_path / "mounted.toml"
    path.write_text((ROOT / "examples" / "installation.toml").read_text() + appended.replace("\\n", "\n"))
    model = cc.load_model(path)
    assert model.data["loads"]["cable_tension"] == 2.0
    assert model.data["contact"]["friction_law"] == "regularized"
    assert cc.load_model("installed").data["contact"]["friction_law"] == "regularized"


def test_the_model_file_docs_loads_example_makes_an_installed_model_with_the_regularized_law():
    """docs/model_file.md "Loads and rest shape": its TOML block added to the built-in specimen."""
    doc = (ROOT / "docs" / "model_file.md").read_text()
    section = doc[doc.index("## Loads and rest shape") :]
    start = section.index("```toml") + len("```toml")
    block = tomllib.loads(section[start : section.index("```", start)])
    data = cc.load_model().to_dict()
    for table, keys in block.items():
        data.setdefault(table, {}).update(keys)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (the specimen's own prestress notes: not what is tested)
        model = cc.model_from_dict(data)
    assert model.data["loads"]["cable_tension"] == 10.0 and model.data["contact"]["friction_law"] == "regularized"
