"""The model schema: one entry per key of the model file, what the loader fills in, the docs' table,
the one list of channels and outputs with their units."""

import subprocess
import sys
from pathlib import Path

import pytest

import cablecasing_core as cc
from cablecasing_core.model.schema import (
    CHANNELS,
    INTEGER_OUTPUTS,
    OPTIONAL,
    OUTPUTS,
    REQUIRED,
    SCHEMA,
    SUPPORT_OUTPUTS,
    lookup,
    output_spec,
)

ROOT = Path(__file__).resolve().parents[2]
# the SI units the FMU's UnitDefinitions know (build_fmu.UNITS), and "" for text and booleans
FMI_UNITS = {
    "",
    "1",
    "m",
    "m/s",
    "m/s2",
    "s",
    "1/s",
    "Hz",
    "rad",
    "N",
    "N.m",
    "J",
    "Pa",
    "kg/m3",
    "kg/s",
    "s/m",
    "N/m",
    "m4",
}


def leaves(node, prefix=""):
    """(dotted key, value) of every value of a nested table."""
    for k, v in node.items():
        if isinstance(v, dict):
            yield from leaves(v, f"{prefix}{k}.")
        else:
            yield f"{prefix}{k}", v


def test_every_key_of_the_specimen_is_in_the_schema_with_an_si_unit():
    model = cc.load_model()
    for key, value in leaves(model.data):
        spec = lookup(key)
        assert spec.key == key and spec.unit in FMI_UNITS, (key, spec.unit)
        if spec.kinds:  # an excitation's key: for its kind only
            assert model.scenario["excitation"][key.split(".")[2]]["kind"] in spec.kinds, key
        assert spec.check(value, key) == value  # the cleaned value is what its own check gives back
    for key in model.parameters():  # the FMU's parameters: numbers with a unit
        assert lookup(key).unit != "", key


def test_a_minimal_file_gets_every_default_of_the_schema():
    """Only the required keys given: every other key comes out with the schema's default (or, for a
    random excitation's seed, the scenario's seed)."""
    data = {
        "geometry": {"points": [[0.0, 0, 0], [1.0, 0, 0]]},
        "casing": {"E": 5e9, "rho": 4850.0, "d_outer": 0.0095, "d_inner": 0.004},
        "cable": {"E": 5.5e10, "rho": 7850.0, "d": 0.003},
        "scenario": {
            "seed": 7,
            "excitation": {
                "r": {"target": "casing.A.z", "kind": "random"},
                "h": {"target": "cable.A.x", "kind": "harmonic", "frequency": 50.0, "amplitude": 1e-4},
            },
        },
    }
    clean = cc.model_from_dict(data).data
    given = {
        "geometry.points",
        "casing.E",
        "casing.rho",
        "casing.d_outer",
        "casing.d_inner",
        "cable.E",
        "cable.rho",
        "cable.d",
        "scenario.seed",
    }
    for key, spec in SCHEMA.items():
        if key in given or spec.default in (REQUIRED, OPTIONAL) or key.startswith("scenario.excitation"):
            continue
        # keys of tables this file does not have: a route by segments, isolators, clips
        if key in ("geometry.start", "geometry.direction") or "<support>" in key or "[]" in key:
            continue
        table, name = key.rsplit(".", 1)
        node = clean
        for part in table.split("."):
            node = node[part]
        assert node[name] == spec.default and isinstance(node[name], type(spec.default)), (
            key
        )  # (a FrozenList is a list)
    r = clean["scenario"]["excitation"]["r"]
    assert r["rms"] == lookup("scenario.excitation.r.rms").default and r["band"] == [10.0, 1000.0]
    assert r["seed"] == 7  # default_from scenario.seed
    assert clean["scenario"]["excitation"]["h"]["phase"] == 0.0
    assert "I" not in clean["casing"]  # optional, no default


def test_lookup_names_what_it_does_not_know():
    with pytest.raises(cc.ModelError, match="casing.Ee"):
        lookup("casing.Ee")
    with pytest.raises(cc.ModelError, match="scenario.excitation.x.rmss"):
        lookup("scenario.excitation.x.rmss")
    spec = lookup("scenario.excitation.any_name.amplitude")
    assert spec.unit == "m" and set(spec.kinds) == {"harmonic", "impulse"}


def test_channels_and_outputs_with_their_units():
    assert CHANNELS[:3] == ("casing.A.x", "casing.A.y", "casing.A.z") and CHANNELS[-1] == "cable.B.z"
    assert len(CHANNELS) == 12 and len(SUPPORT_OUTPUTS) == 24 and OUTPUTS[:24] == SUPPORT_OUTPUTS
    for name in SUPPORT_OUTPUTS:
        unit, text = output_spec(name)
        assert unit == ("N" if name.split(".")[2].startswith("F") else "N.m")
        assert name.split(".")[0] in text and f"support {name.split('.')[1]}" in text
    assert [output_spec(n)[0] for n in OUTPUTS[24:]] == ["1", "m", "J"]
    # an integer output is a count: an output of every model, without a unit
    assert INTEGER_OUTPUTS and all(n in OUTPUTS and output_spec(n)[0] == "1" for n in INTEGER_OUTPUTS)
    with pytest.raises(cc.ModelError, match="casing.B.Gz"):
        output_spec("casing.B.Gz")


def test_the_docs_key_table_is_the_generated_one():
    r = subprocess.run([sys.executable, str(ROOT / "docs" / "make_key_table.py"), "--check"], cwd=ROOT)
    assert r.returncode == 0, "docs/model_file.md: run python docs/make_key_table.py"
