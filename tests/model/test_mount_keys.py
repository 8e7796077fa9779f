"""Bad input for the keys of isolators and clips: each error names the key, the value and what is
allowed (ModelError), and nothing is built."""

import copy

import pytest

from cablecasing_core import ModelError, load_model, model_from_dict
from cablecasing_core.model.schema import lookup


def with_casing(**changes):
    d = copy.deepcopy(load_model().data)
    d["casing"].update(changes)
    return d


ISO = {"stiffness": [2e5, 1e5, 1e5]}


@pytest.mark.parametrize(
    "changes, key, words",
    [
        ({"supports": {"A": "isolator", "B": "clamped"}}, "casing.isolator.A", "is required"),
        ({"supports": {"A": "elastic", "B": "clamped"}}, "casing.supports.A", "'isolator'"),
        ({"isolator": {"A": ISO}}, "casing.isolator.A", "casing.supports.A = 'clamped'"),
        ({"isolator": {"C": ISO}}, "casing.isolator.C", "allowed keys are A, B"),
        ({"supports": {"A": "isolator"}, "isolator": {"A": {}}}, "casing.isolator.A.stiffness", "is required"),
        (
            {"supports": {"A": "isolator"}, "isolator": {"A": {"stiffness": -1.0}}},
            "casing.isolator.A.stiffness",
            "a number in [0, 1e+14] in N/m",
        ),
        (  # a stiffer mount is a clamp to round-off; 1e30 N/m made the system singular
            {"supports": {"A": "isolator"}, "isolator": {"A": {"stiffness": 1e30}}},
            "casing.isolator.A.stiffness",
            "a number in [0, 1e+14] in N/m",
        ),
        (
            {"supports": {"A": "isolator"}, "isolator": {"A": dict(ISO, rotational_damping=1e9)}},
            "casing.isolator.A.rotational_damping",
            "a number in [0, 1e+08] in N.m.s/rad",
        ),
        (
            {"supports": {"A": "isolator"}, "isolator": {"A": {"stiffness": [1.0, 2.0]}}},
            "casing.isolator.A.stiffness",
            "three of them",
        ),
        (
            {"supports": {"A": "isolator"}, "isolator": {"A": {"stiffness": [1.0, "x", 2.0]}}},
            "casing.isolator.A.stiffness[1]",
            "N/m",
        ),
        (
            {"supports": {"A": "isolator"}, "isolator": {"A": dict(ISO, damping=-2.0)}},
            "casing.isolator.A.damping",
            "N.s/m",
        ),
        (
            {"supports": {"A": "isolator"}, "isolator": {"A": dict(ISO, rotational_stiffness=[1, 1, -1])}},
            "rotational_stiffness[2]",
            "N.m/rad",
        ),
        (
            {"supports": {"A": "isolator"}, "isolator": {"A": dict(ISO, rotational_damping=float("nan"))}},
            "rotational_damping",
            "finite",
        ),
        (
            {"supports": {"A": "isolator"}, "isolator": {"A": dict(ISO, stifness=1.0)}},
            "casing.isolator.A.stifness",
            "unknown key",
        ),
        (
            {"supports": {"A": "isolator"}, "isolator": {"A": dict(ISO, table=[[0, 1]])}},
            "casing.isolator.A.table[0]",
            "[f_Hz, k_scale, loss_factor]",
        ),
        (
            {"supports": {"A": "isolator"}, "isolator": {"A": dict(ISO, table=[[0, 0.0, 0.1]])}},
            "casing.isolator.A.table[0][1]",
            "positive",
        ),
        (
            {"supports": {"A": "isolator"}, "isolator": {"A": dict(ISO, table=[[0, 1, -0.1]])}},
            "casing.isolator.A.table[0][2]",
            "zero or a positive",
        ),
        (
            {"supports": {"A": "isolator"}, "isolator": {"A": dict(ISO, table=[[10, 1, 0], [5, 1, 0]])}},
            "casing.isolator.A.table",
            "increasing",
        ),
        ({"clip": {"at": 0.4}}, "casing.clip", "array of tables"),
        ({"clip": [{"stiffness": 1e4}]}, "casing.clip[0].at", "is required"),
        ({"clip": [{"at": 0.0, "stiffness": 1e4}]}, "casing.clip[0].at", "positive"),
        ({"clip": [{"at": 5.0, "stiffness": 1e4}]}, "casing.clip[0].at", "inside the route"),
        ({"clip": [{"at": 0.005, "stiffness": 1e4}]}, "casing.clip[0].at", "end node"),
        (
            {"clip": [{"at": 0.4, "stiffness": 1e4}, {"at": 0.395, "stiffness": 1e4}]},
            "casing.clip[1].at",
            "casing.clip[0] holds",
        ),
        (
            {"clip": [{"at": 0.4, "stiffness": 1e4, "excitation": "1dash"}]},
            "casing.clip[0].excitation",
            "starting with a letter",
        ),
        (
            {"clip": [{"at": 0.4, "stiffness": 1e4, "excitation": "dash.z"}]},
            "casing.clip[0].excitation",
            "letters, digits and _",
        ),
        (
            {
                "clip": [
                    {"at": 0.3, "stiffness": 1e4, "excitation": "d"},
                    {"at": 0.6, "stiffness": 1e4, "excitation": "d"},
                ]
            },
            "casing.clip[1].excitation",
            "unique",
        ),
        ({"clip": [{"at": 0.4, "stiffness": 1e4, "excitation": "cable"}]}, "casing.clip[0].excitation", "not a body"),
        ({"clip": [{"at": 0.4, "stiffness": 1e4, "where": 1}]}, "casing.clip[0].where", "unknown key"),
    ],
)
def test_bad_mount_keys_name_key_value_and_what_is_allowed(changes, key, words):
    # (a clip on an end node, two clips on one node: the refusals of the nearest-node convention,
    # geometry.nodes_at_clips = false; the default's own, spans too short: tests/model/test_clip_nodes.py)
    data = with_casing(**changes)
    data["geometry"]["nodes_at_clips"] = False
    with pytest.raises(ModelError) as e:
        model_from_dict(data)
    assert key in e.value.key, (e.value.key, str(e.value))
    assert words in str(e.value)


def test_the_cable_is_never_clipped():
    d = copy.deepcopy(load_model().data)
    d["cable"]["clip"] = [{"at": 0.4, "stiffness": 1e4}]
    with pytest.raises(ModelError, match="cable.clip.*never clipped"):
        model_from_dict(d)


def test_mount_keys_are_in_the_schema_with_units():
    assert lookup("casing.isolator.A.stiffness").unit == "N/m"
    assert lookup("cable.isolator.B.rotational_damping").unit == "N.m.s/rad"
    assert lookup("casing.clip[3].at").unit == "m"
    m = model_from_dict(with_casing(supports={"A": "isolator", "B": "clamped"}, isolator={"A": {"stiffness": 1e5}}))
    iso = m.data["casing"]["isolator"]["A"]
    assert iso["stiffness"] == [1e5] * 3 and iso["rotational_stiffness"] == [0.0] * 3 and "table" not in iso


def test_mount_components_are_parameters_a_study_can_vary():
    """A mount's three values are parameters by component (``...stiffness.lateral_1``, local axes),
    as loads.gravity's are: Model.parameters lists them, with_overrides sets one (validated)."""
    m = model_from_dict(
        with_casing(supports={"A": "isolator", "B": "clamped"}, isolator={"A": {"stiffness": [1e5, 2e5, 3e5]}})
    )
    p = m.parameters()
    assert p["casing.isolator.A.stiffness.lateral_1"] == 2e5 and p["casing.isolator.A.rotational_damping.axial"] == 0.0
    m2 = m.with_overrides({"casing.isolator.A.stiffness.lateral_1": 7e4})
    assert m2.data["casing"]["isolator"]["A"]["stiffness"] == [1e5, 7e4, 3e5]
    assert lookup("casing.isolator.A.stiffness.axial").unit == "N/m"
    with pytest.raises(
        ModelError, match=r"casing.isolator.A.stiffness.lateral_1 = -1.0: must be a number in \[0, 1e\+14\]"
    ):
        m.with_overrides({"casing.isolator.A.stiffness.lateral_1": -1.0})


def test_a_support_changed_from_an_isolator_leaves_its_table_behind():
    """with_overrides: casing.supports.B set to 'clamped' or 'free' drops [casing.isolator.B] (it
    belonged to the isolator the change replaced), the same model as one written without it; a key
    of that table set with it is the contradiction validation names, with the two ways out."""
    iso = with_casing(supports={"A": "clamped", "B": "isolator"}, isolator={"B": dict(ISO)})
    m = model_from_dict(iso)
    for kind in ("clamped", "free"):
        changed = m.with_overrides({"casing.supports.B": kind})
        assert "isolator" not in changed.data["casing"]
        assert changed.fingerprint() == model_from_dict(with_casing(supports={"A": "clamped", "B": kind})).fingerprint()
    assert m.with_overrides({"casing.supports.B": "isolator"}).data["casing"]["isolator"]["B"]["stiffness"] == [
        2e5,
        1e5,
        1e5,
    ]
    with pytest.raises(
        ModelError, match=r"casing.supports.B = 'clamped': leave the table out, or make casing.supports.B"
    ):
        m.with_overrides({"casing.supports.B": "clamped", "casing.isolator.B.stiffness.axial": 3e5})


def test_a_key_of_an_excitation_the_model_lacks_names_the_model_s_excitations():
    """An excitation needs its kind and target: a key of one the model does not have is refused
    naming the key and the model's excitations (it was refused naming a '.kind' that nobody set),
    unless the overrides make it, its kind among them."""
    m = load_model()
    with pytest.raises(
        ModelError,
        match=r"scenario.excitation.shaker.rms = 2.0: belongs to the excitation 'shaker', which this model does not "
        r"have \(its excitations: cable_axial, casing_random\)",
    ):
        m.with_overrides({"scenario.excitation.shaker.rms": 2.0})
    assert (
        m.with_overrides({"scenario.excitation.casing_random.rms": 2.0}).scenario["excitation"]["casing_random"]["rms"]
        == 2.0
    )
    made = {"target": "casing.B.z", "kind": "harmonic", "amplitude": 1e-5, "frequency": 75.0}
    new = m.with_overrides({f"scenario.excitation.second.{k}": v for k, v in made.items()})
    assert {k: new.scenario["excitation"]["second"][k] for k in made} == made  # (made key by key, kind among them)


def test_a_clip_far_from_a_node_warns_and_is_said_where_it_acts(tmp_path, capsys):
    """With geometry.nodes_at_clips = false a clip acts at its nearest node: on 4 elements of 0.25 m
    clips asked at 0.37 and 0.7 m act at 0.25 and 0.75 m, farther than CLIP_OFF_NODE (10 % of an
    element) from where they were asked: the model warns naming each, and `static` prints where they
    act (it printed 0.37 and 0.7 m beside the reactions of clips at 0.25 and 0.75 m). A clip within
    10 % of an element of its node (10 mm of 250 mm) does not warn."""
    import warnings

    from cablecasing_core.cli import main
    from cablecasing_core.errors import ModelWarning
    from cablecasing_core.structure.mount_element import clip_positions

    data = copy.deepcopy(load_model().data)
    data["geometry"] = {
        "points": [[0.0, 0, 0], [1.0, 0, 0]],
        "n_elements": 4,
        "curve": "polyline",
        "nodes_at_clips": False,
    }
    data.pop("cable")
    data["scenario"].pop("excitation")
    clip = {"stiffness": 1e6, "rotational_stiffness": 10.0}
    data["casing"].update(supports={"A": "free", "B": "free"}, clip=[dict(clip, at=0.37), dict(clip, at=0.7)])
    with pytest.warns(ModelWarning) as said:
        m = model_from_dict(data)
    texts = [str(w.message) for w in said]
    assert any("casing.clip[0].at = 0.37 m: a clip acts at a node, the nearest, at s = 0.25 m" in t for t in texts)
    assert any("casing.clip[1].at = 0.7 m: a clip acts at a node, the nearest, at s = 0.75 m" in t for t in texts)
    assert clip_positions(m) == pytest.approx([0.25, 0.75], abs=1e-12)
    path = tmp_path / "clips.toml"
    path.write_text(m.to_toml())
    assert main(["static", str(path)]) == 0
    out = capsys.readouterr().out
    assert "casing.clip0 s=0.25 " in out and "casing.clip1 s=0.75 " in out, out
    data["casing"]["clip"] = [dict(clip, at=0.26), dict(clip, at=0.74)]
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelWarning)
        assert clip_positions(model_from_dict(data)) == pytest.approx([0.25, 0.75], abs=1e-12)
