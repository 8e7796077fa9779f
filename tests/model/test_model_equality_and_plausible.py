"""Model equality is the data's, not the label's (review AC D2), and a negative value outside its
plausible range is said to be so in magnitude (review AC D3)."""

import os

import pytest

import cablecasing_core as cc
from cablecasing_core.errors import ModelWarning


def test_the_same_model_file_by_two_paths_is_one_model(tmp_path, monkeypatch):
    """Loaded by a relative and an absolute path, one file gives equal models with equal hashes (a
    cache keyed on models finds it); a label (source) does not count; another folder, against which
    relative files would resolve, does."""
    path = tmp_path / "m.toml"
    path.write_text(cc.load_model().to_toml())
    monkeypatch.chdir(tmp_path)
    rel, absolute = cc.load_model("m.toml"), cc.load_model(os.fspath(path))
    assert rel.source != absolute.source and rel == absolute and hash(rel) == hash(absolute)
    data = cc.load_model().to_dict()
    assert cc.model_from_dict(data, source="a") == cc.model_from_dict(data, source="b")
    other = tmp_path / "sub"
    other.mkdir()
    (other / "m.toml").write_text(path.read_text())
    assert cc.load_model(os.fspath(other / "m.toml")) != absolute


def test_a_negative_value_is_implausible_in_magnitude():
    """The plausible range of an amplitude holds |value|: -0.06 m warns "0 to 0.05 m in magnitude";
    a positive one keeps the plain wording."""
    model = cc.load_model()
    for value, said in ((-0.06, "0 to 0.05 m in magnitude"), (0.06, "0 to 0.05 m:")):
        with pytest.warns(ModelWarning, match=rf"outside the plausible {said}"):
            model.with_overrides({"scenario.excitation.cable_axial.amplitude": value})
