"""Review I (the public API's edges), the model's part: a validated Model is read-only (D1), and a
wrong argument's type is a ModelError naming it (D7); complex frequencies are refused (D12); a
body's buckling load has a public entry point (D16)."""

import copy
import pickle

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.structure.assembly import assemble_body
from cablecasing_core.structure.buckling import buckling


@pytest.fixture(scope="module")
def model():
    return cc.load_model()


@pytest.mark.parametrize(
    "change",
    [
        lambda m: m.data["casing"].__setitem__("E", 10e9),
        lambda m: m.data["scenario"].update(dt=5e-5),
        lambda m: m.data["geometry"].pop("n_elements"),
        lambda m: m.data["geometry"]["points"].append([0.0, 0.0, 0.0]),
        lambda m: m.data["geometry"]["points"][0].__setitem__(0, 1.0),
        lambda m: m.data.__delitem__("contact"),
        lambda m: m.bodies.__setitem__("casing", None),
        lambda m: m.bodies["casing"].supports.__setitem__("A", "free"),
    ],
)
def test_a_validated_model_cannot_be_changed_behind_its_checks(model, change):
    before = model.fingerprint()
    with pytest.raises(TypeError, match=r"read-only.*with_overrides.*to_dict"):
        change(model)
    assert model.fingerprint() == before == cc.load_model().fingerprint()
    assert model.bodies["casing"].E == 5e9 and model.bodies["casing"].supports["A"] == "clamped"


def test_a_read_only_model_reads_as_before_and_its_copies_are_yours(model):
    data = model.data
    assert isinstance(data, dict) and isinstance(data["geometry"]["points"], list) and data == cc.load_model().data
    mine = model.to_dict()
    mine["casing"]["E"] = 6e9  # a plain copy: changes freely, and leaves the model as it was
    assert type(mine) is dict and type(mine["geometry"]["points"][0]) is list and model.data["casing"]["E"] == 5e9
    assert cc.model_from_dict(mine).bodies["casing"].E == 6e9
    deep = copy.deepcopy(model.data)  # (how many callers take their copy)
    deep["contact"]["friction"] = 0.9
    assert deep == {**mine, "contact": deep["contact"], "casing": model.to_dict()["casing"]}
    # the dict a model is built from is not aliased: changing it later does not change the model
    raw = model.to_dict()
    built = cc.model_from_dict(raw)
    raw["casing"]["E"] = 1.0
    assert built.bodies["casing"].E == 5e9
    assert model.with_overrides({"casing.E": 6e9}).bodies["casing"].E == 6e9
    assert cc.load_model(None).to_toml() == model.to_toml()


@pytest.mark.parametrize("name", ["default", "installed", "examples/installation.toml"])
def test_a_model_pickles_deep_copies_and_hashes(name):
    m = cc.load_model(name)
    for other in (pickle.loads(pickle.dumps(m)), copy.deepcopy(m), copy.copy(m)):
        assert other == m and hash(other) == hash(m) and other.fingerprint() == m.fingerprint()
        with pytest.raises(TypeError):
            other.data["contact"]["friction"] = 0.5
    assert {m: 1}[cc.load_model(name)] == 1  # equal models key one entry of a cache
    assert hash(m) != hash(m.with_overrides({"contact.friction": 0.11}))


def test_a_one_body_models_radial_gap_is_a_model_error(model):
    data = model.to_dict()
    del data["cable"]
    data["scenario"]["excitation"].pop("cable_axial")
    with pytest.raises(cc.ModelError, match=r"radial_gap = .*needs a \[cable\]"):
        _ = cc.model_from_dict(data).radial_gap
    assert model.radial_gap == pytest.approx(0.5 * (model.data["casing"]["d_inner"] - model.data["cable"]["d"]))


@pytest.mark.parametrize(
    "call",
    [
        lambda m: cc.natural_frequencies(m.data, "casing", count=3),
        lambda m: cc.natural_frequencies("default", "casing"),
        lambda m: cc.modes(m.to_dict(), "casing", count=3),
        lambda m: cc.trfam(m.data, "casing.A.z", "casing.B.z", [10.0]),
        lambda m: cc.trfam_matrix("default", "casing", "A", "B", [10.0]),
        lambda m: assemble_body(m.data, "casing"),
        lambda m: cc.body_buckling(None),
    ],
)
def test_an_entry_point_given_no_model_names_it(model, call):
    with pytest.raises(cc.ModelError, match=r"^model = .*must be a cablecasing_core\.Model, not (a dict|a str|None)"):
        call(model)


def test_other_wrong_arguments_are_named(model):
    with pytest.raises(cc.ModelError, match=r"^path = 3: must be a model file's path .*default, installed"):
        cc.load_model(3)
    with pytest.raises(cc.ModelError, match=r"^overrides = .*must be a mapping \(a dict\).* not a list"):
        model.with_overrides([("contact.friction", 0.1)])
    with pytest.raises(cc.ModelError, match=r"^names = 3: must be a name or a list of names"):
        model.without_excitations(3)
    with pytest.raises(cc.ModelError, match=r"^name = 'wire': must be one of 'casing', 'cable'"):
        assemble_body(model, "wire")
    with pytest.raises(cc.ModelError, match=r"^body = 'wire': must be one of 'casing', 'cable'"):
        cc.body_buckling(model, "wire")
    with pytest.raises(cc.ModelError, match=r"^system = <Model <built-in>>: .*cc\.body_buckling\(model, 'casing'\)"):
        buckling(model)


def test_one_excitation_name_is_one_name_not_its_letters(model):
    one = model.without_excitations("cable_axial")
    assert set(one.data["scenario"]["excitation"]) == {"casing_random"}
    assert one == model.without_excitations(["cable_axial"])


@pytest.mark.parametrize("freqs", [np.array([50 + 1j]), [50.0, 60 + 0j], np.array([50.0, 60.0], dtype=complex)])
def test_complex_frequencies_are_refused_not_cut_to_their_real_part(model, freqs):
    with pytest.raises(cc.ModelError, match=r"^freqs_hz = .*must be real frequencies in Hz"):
        cc.trfam(model, "casing.A.z", "casing.B.z", freqs)


def test_the_buckling_load_of_a_body_is_euler_s_and_the_static_commands(paper_bodies):
    """cc.body_buckling of each body of a straight 1 m pair clamped at both ends is Euler's
    4 pi^2 EI / L^2 (53.81 N for the casing, 8.633 N for the 3 mm cable) to 2e-5: the FE's h^4 error
    at 20 elements is 1.35e-5 (2.1e-4 at 10, 8.4e-7 at 40). On the installed specimen it is the load
    `cablecasing static` reports, structure.buckling.buckling of the assembled body, to the bit."""
    clamped = {"supports": {"A": "clamped", "B": "clamped"}}
    pair = cc.model_from_dict(
        {
            "geometry": {"n_elements": 20, "curve": "polyline", "points": [[0, 0, 0], [1.0, 0, 0]]},
            "casing": {**paper_bodies["casing"], **clamped},
            "cable": {**paper_bodies["cable"], **clamped},
        }
    )
    casing, cable = paper_bodies["casing"], paper_bodies["cable"]
    for body, EI in (("casing", casing["E"] * casing["I"]), ("cable", cable["E"] * np.pi * cable["d"] ** 4 / 64)):
        b = cc.body_buckling(pair, body)
        assert isinstance(b, cc.Buckling) and b.body == body
        assert b.load == pytest.approx(4 * np.pi**2 * EI, rel=2e-5), body
    installed = cc.load_model("installed")
    b = cc.body_buckling(installed)  # the casing, as `cablecasing static` assembles it
    assert b.body == "casing" and b.load > installed.loads["cable_tension"]  # (the specimen holds its tension)
    assert b.load == buckling(assemble_body(installed, "casing")).load
    assert cc.body_buckling(installed, "cable").load == buckling(assemble_body(installed, "cable")).load


def test_the_top_level_names_the_warnings_and_the_statics():
    assert issubclass(cc.SolverWarning, cc.ModelWarning) and issubclass(cc.ModelWarning, UserWarning)
    assert cc.PlausibilityWarning is cc.ModelWarning
    for name in ("ModelWarning", "SolverWarning", "static_state", "StaticState", "body_buckling", "Buckling"):
        assert name in cc.__all__ and getattr(cc, name) is not None


def test_the_radial_gap_is_computed_in_one_place(model, monkeypatch):
    """Eqs. 30-31's gap has one definition, ``model.model.radial_gap``: the property and the
    validation's warning of a gap below the roughness both read it (a gap function that says 1e-9 m
    makes the valid specimen warn, and the property give it), and it is (d_inner - d) / 2 of the
    model's diameters."""
    from cablecasing_core.model import model as model_module

    assert model_module.radial_gap(model.data) == 0.5 * (model.data["casing"]["d_inner"] - model.data["cable"]["d"])
    monkeypatch.setattr(model_module, "radial_gap", lambda data: 1e-9)
    with pytest.warns(cc.ModelWarning, match=r"radial gap .* = 1e-09 m is below"):
        again = cc.model_from_dict(model.to_dict())
    assert again.radial_gap == 1e-9
