"""The model-file layer against the defects a review found (docs/model_file.md): ``--set`` and
``with_overrides`` take keys of the schema, not tables, and a key once; ``to_toml`` leaves the
derived keys out; mounts that hold nothing and drives they cannot pass are refused; a second moment
of area outside its section's bounds, an impulse after the run and a ramp longer than it warn; the
regularized law's stick velocity and a route's ``curve`` are checked when the model is loaded; the
messages name the key the user typed."""

import copy
import math
import warnings

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core import ModelError, load_model, model_from_dict
from cablecasing_core.cli import main
from cablecasing_core.cli.assignments import with_assignments
from cablecasing_core.errors import ModelWarning
from cablecasing_core.identification import parameters_toml
from cablecasing_core.model.schema import lookup
from cablecasing_core.timedomain.scenario import scenario_motion


def raw(name=None):
    """The built-in specimen's checked data, as a dictionary to change."""
    return copy.deepcopy(load_model(name).data)


def model_warnings(build):
    """The texts of the ModelWarnings ``build()`` issues (its ModelErrors pass)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        build()
    return [str(w.message) for w in caught if issubclass(w.category, ModelWarning)]


# ------------------------------------------------------------------ 1, 2: --set takes keys, once
@pytest.mark.parametrize(
    "text, table", [("contact={friction=0.3}", "contact"), ("loads={}", "loads"), ("scenario={}", "scenario")]
)
def test_a_set_of_a_table_is_refused_naming_it(text, table, capsys):
    """Given whole, the table replaced every key it left out by its default (the installed
    specimen's friction_law went back to switch, loads={} dropped gravity and tension)."""
    assert main(["simulate", "installed", "--duration", "1e-4", "--no-progress", "--set", text]) == 2
    err = capsys.readouterr().err
    assert f"--set {table}: is a table, not a key: set its keys one by one (e.g. {table}." in err, err


def test_with_overrides_refuses_a_table_and_keeps_the_keys_a_dotted_change_leaves_out():
    m = load_model("installed")
    for key, value in (
        ("contact", {"friction": 0.3}),
        ("scenario.excitation.casing_random", {}),
        ("casing.isolator", {}),
    ):
        with pytest.raises(ModelError, match="is a table, not a key") as err:
            m.with_overrides({key: value})
        assert err.value.key == key
    changed = m.with_overrides({"contact.friction": 0.3})
    assert changed.contact["friction"] == 0.3
    assert changed.contact["friction_law"] == m.contact["friction_law"] == "regularized"


def test_an_isolator_is_added_by_its_dotted_keys():
    """A table cannot be set whole, so its keys add it (as TOML's dotted keys do)."""
    m = load_model().with_overrides({"casing.supports.A": "isolator", "casing.isolator.A.stiffness": 1e5})
    assert m.data["casing"]["isolator"]["A"]["stiffness"] == [1e5, 1e5, 1e5]


def test_a_set_key_given_twice_is_refused_with_both_values():
    for texts in (["contact.friction=99", "contact.friction=0.3"], ["contact.friction=0.3", "contact.friction=99"]):
        with pytest.raises(ModelError) as err:
            with_assignments(load_model(), "--set", texts)
        assert err.value.key == "--set contact.friction"
        assert "given twice" in str(err.value) and "99" in str(err.value) and "0.3" in str(err.value)


# ------------------------------------------------------------------ 3: to_toml and derived keys
def test_a_written_model_follows_a_change_of_the_seed_its_excitation_derives_from(tmp_path):
    """casing_random gives no seed: it takes scenario.seed, in the built-in model and in the file
    to_toml writes of it (which before pinned seed = 1, so seeds 1 and 2 gave one record)."""
    m = load_model()
    p = tmp_path / "rt.toml"
    p.write_text(m.to_toml())
    written = load_model(p)
    assert written.derived == m.derived == {"scenario.excitation.casing_random.seed"}
    records = []
    for model in (m, written):
        one, two = (model.with_overrides({"scenario.seed": s}) for s in (1, 2))
        assert two.scenario["excitation"]["casing_random"]["seed"] == 2
        t = np.array([0.05, 0.1])
        u1, u2 = (scenario_motion(x, dt=1e-5)(t)[0] for x in (one, two))
        assert not np.array_equal(u1, u2)  # another seed: another record
        records.append(u2)
    np.testing.assert_array_equal(records[0], records[1])  # (the same record, exactly: same seed and band)


# ------------------------------------------------------------------ 4: mounts that hold nothing
def _isolated(stiffness, target="casing.A.z", **keys):
    d = raw()
    d["casing"]["supports"] = {"A": "isolator", "B": "clamped"}
    d["casing"]["isolator"] = {"A": {"stiffness": stiffness, **keys}}
    d["scenario"]["excitation"]["casing_random"]["target"] = target
    return d


def test_an_isolator_or_clip_of_no_stiffness_in_any_direction_is_refused_naming_it():
    with pytest.raises(ModelError) as err:
        model_from_dict(_isolated(0.0, damping=10.0))  # (damping holds no static load either)
    assert err.value.key == "casing.isolator.A.stiffness" and "holds nothing" in str(err.value)
    # a torsion spring holds a rotation (driven at the clamped end B: end A's spring passes no translation)
    model_from_dict(_isolated(0.0, target="casing.B.z", rotational_stiffness=[1.0, 0.0, 0.0]))
    d = raw()
    d["casing"]["clip"] = [{"at": 0.4, "stiffness": 0.0}]
    with pytest.raises(ModelError) as err:
        model_from_dict(d)
    assert err.value.key == "casing.clip[0].stiffness" and "holds nothing" in str(err.value)


def test_a_drive_along_a_direction_the_isolator_does_not_pass_is_refused():
    """casing.A.axial on an isolator of lateral stiffness only: the spring transmits nothing along
    the tangent, and every output of that drive would be zero."""
    with pytest.raises(ModelError) as err:
        model_from_dict(_isolated([0.0, 1e5, 1e5], target="casing.A.axial"))
    assert err.value.key == "scenario.excitation.casing_random.target"
    assert "neither stiffness nor damping" in str(err.value)
    model_from_dict(_isolated([0.0, 1e5, 1e5], target="casing.A.z"))  # (lateral: passed)
    model_from_dict(_isolated([0.0, 1e5, 1e5], target="casing.A.axial", damping=[10.0, 0.0, 0.0]))  # a damper passes


# ------------------------------------------------------------------ 5: I against its section
def _with_I(body, factor):
    """The specimen with ``body``.I = factor times the solid circle of its outer diameter."""
    d = raw()
    outer = d[body]["d_outer"] if body == "casing" else d[body]["d"]
    d[body]["I"] = factor * math.pi * outer**4 / 64
    return d


@pytest.mark.parametrize("body", ["casing", "cable"])
def test_a_second_moment_of_area_outside_its_sections_bounds_warns(body):
    """Above the solid circle pi d^4 / 64 (no homogeneous section inside d is stiffer) or below 1e-3
    of the tube's (the wire's) section; 1.01 and 0.9e-3 are a per cent beyond each bound (far above
    the round-off of pi d^4 / 64)."""
    key = f"{body}.I"
    assert any(key in w and "solid circle" in w for w in model_warnings(lambda: model_from_dict(_with_I(body, 1.01))))
    assert not any(key in w for w in model_warnings(lambda: model_from_dict(_with_I(body, 1.0))))
    d = raw()
    if body == "casing":
        tube = math.pi * (d["casing"]["d_outer"] ** 4 - d["casing"]["d_inner"] ** 4) / 64
    else:
        tube = math.pi * d["cable"]["d"] ** 4 / 64
    for factor, warned in ((0.99e-3, True), (1.01e-3, False)):
        d[body]["I"] = factor * tube
        said = model_warnings(lambda: model_from_dict(d))
        assert any(key in w and "below 0.001" in w for w in said) == warned, said
    for I, words in ((1.0, "2.5e+09 times" if body == "casing" else "times"), (1e-30, "below 0.001")):
        d[body]["I"] = I
        assert any(key in w and words in w for w in model_warnings(lambda: model_from_dict(d)))


@pytest.mark.parametrize("name", ["default", "installed"])
def test_the_specimens_I_is_silent(name):
    """casing.I = 2.7261e-10 m4 lies between 3.9e-13 (1e-3 of the tube) and 4.0e-10 (the solid circle)."""
    assert load_model(name).data["casing"]["I"] == 2.7261e-10
    said = model_warnings(lambda: model_from_dict(raw(name)))
    assert not any(".I " in w for w in said), said


# ------------------------------------------------------------------ 6: drives outside the run
def _impulse(start, duration=0.01, ramp=0.0):
    d = raw()
    d["scenario"].update(duration=duration, ramp=ramp)
    d["scenario"]["excitation"] = {
        "knock": {"target": "casing.A.z", "kind": "impulse", "amplitude": 1e-3, "start": start, "width": 1e-3}
    }
    return d


def test_an_impulse_after_the_run_and_a_ramp_longer_than_it_warn():
    for start, warned in ((0.01, True), (5.0, True), (0.005, False)):
        said = model_warnings(lambda start=start: model_from_dict(_impulse(start)))
        assert any("scenario.excitation.knock.start" in w for w in said) == warned, (start, said)
    for ramp, warned in ((10.0, True), (0.01, False)):
        said = model_warnings(lambda ramp=ramp: model_from_dict(_impulse(0.0, ramp=ramp)))
        assert any("scenario.ramp" in w and "longer than scenario.duration" in w for w in said) == warned, said
    # the share it reaches: the half-cosine's 0.5 (1 - cos(pi T / ramp)), 2.47e-6 at 0.01 s of 10 s
    said = model_warnings(lambda: model_from_dict(_impulse(0.0, ramp=10.0)))
    assert any(f"{0.5 * (1 - math.cos(math.pi * 0.001)):.3g}" in w for w in said), said


# ------------------------------------------------------------------ 7, 8: combinations at load
def test_the_regularized_law_without_a_stick_velocity_is_refused_when_loaded():
    d = raw()
    d["contact"].update(friction_law="regularized", stick_velocity=0.0)
    with pytest.raises(ModelError) as err:
        model_from_dict(d)
    assert err.value.key == "contact.stick_velocity" and "regularized" in str(err.value)
    assert 'contact.friction_law = "regularized"' in lookup("contact.stick_velocity").allowed
    with pytest.raises(ModelError):
        load_model().with_overrides({"contact.stick_velocity": 0.0, "contact.friction_law": "regularized"})


def test_a_curve_with_a_route_of_segments_is_refused():
    d = raw()
    d["geometry"] = {"segments": [{"straight": 0.85}], "curve": "polyline"}
    with pytest.raises(ModelError) as err:
        model_from_dict(d)
    assert err.value.key == "geometry.curve" and "route given by points" in str(err.value)
    d["geometry"].pop("curve")
    m = model_from_dict(d)
    assert "curve" not in m.geometry  # (the default belongs to points: to_toml does not write it)
    assert model_from_dict(cc.model.load.tomllib.loads(m.to_toml())).data == m.data


# ------------------------------------------------------------------ 9, 10: messages
def test_missing_tables_and_keys_are_named_as_required():
    d = raw()
    del d["scenario"]["excitation"]["cable_axial"]["kind"]
    with pytest.raises(ModelError) as err:
        model_from_dict(d)
    assert str(err.value).startswith("scenario.excitation.cable_axial.kind: is required: one of 'random'")
    d = raw()
    d["casing"]["supports"]["A"] = "isolator"
    with pytest.raises(ModelError) as err:
        model_from_dict(d)
    assert str(err.value) == (
        "casing.isolator.A: the table [casing.isolator.A] with its stiffness (casing.isolator.A.stiffness, N/m) "
        "is required when casing.supports.A = 'isolator'"
    )


@pytest.mark.parametrize(
    "text, start",
    [
        (
            "geometry.segments=[{straight=0.85}]",
            "--set geometry.segments = [{straight=0.85}]: cannot be set on a "
            "model whose route is given by geometry.points",
        ),
        ("loads.gravity.z=abc", "--set loads.gravity.z = abc: must be a number"),  # (as typed)
        ("casing.Ex=1", "--set casing.Ex: unknown key; allowed keys are E, I, alpha"),
        ("foo.bar=1", "--set foo.bar: unknown key; allowed keys are cable, casing, contact"),
        ("casing.clip[0].at=0.3", "--set casing.clip[0].at: is a key of a clip"),
    ],
)
def test_a_set_is_refused_under_the_key_typed(text, start):
    with pytest.raises(ModelError) as err:
        with_assignments(load_model(), "--set", [text])
    assert str(err.value).startswith(start), str(err.value)
    assert "geometry.points must go" in str(err.value) or not text.startswith("geometry")


def test_an_unknown_section_of_a_file_is_named_as_written():
    d = raw()
    d["solver"] = {"dt": 1e-5}
    with pytest.raises(ModelError) as err:
        model_from_dict(d)
    assert str(err.value).startswith("solver: unknown key; allowed keys are cable, casing")


def test_a_key_given_twice_in_a_file_is_named_without_its_value(tmp_path):
    text = load_model().to_toml().replace("nu = 0.3\n", "nu = 0.3\nnu = 0.25\n", 1)
    p = tmp_path / "dup.toml"
    p.write_text(text)
    line = text.splitlines().index("nu = 0.25") + 1
    with pytest.raises(ModelError) as err:
        load_model(p)
    assert f"casing.nu is given twice (the second time on line {line})" in str(err.value)
    assert "0.25" not in str(err.value)  # (a file's values are not quoted)


# ------------------------------------------------------------------ 11: parameters_toml's reasons
@pytest.mark.parametrize(
    "kw, words",
    [
        ({"alpha": 2e9}, "must be a number in [0, 1e+09] in 1/s"),
        ({"beta": 5.0}, "must be a number in [0, 1] of seconds"),
        ({"beta": float("nan")}, "must be a finite number in [0, 1] of seconds"),
        ({"alpha": -1.0}, "refit with nonnegative=True"),
    ],
)
def test_parameters_toml_gives_the_schemas_reason(kw, words):
    with pytest.raises(ModelError) as err:
        parameters_toml("casing", **kw)
    assert words in str(err.value)
    assert ("refit" in str(err.value)) == (kw.get("alpha", 0.0) < 0)


# ------------------------------------------------------------------ 12: the target's note
def test_the_targets_note_says_what_the_loader_accepts():
    """An isolator support and an excited clip are driven (model_from_dict above), not only clamps."""
    note = lookup("scenario.excitation.x.target").note
    assert "isolator" in note and "clip" in note


def test_ensemble_refuses_a_set_or_against_key_given_twice_before_any_run(tmp_path, capsys):
    """ensemble built its changes with dict(), so the last value won and the first (a friction of
    -5) was never checked; it is refused as simulate refuses it, before any run is made."""
    for flag in ("--set", "--against"):
        argv = ["ensemble", "--seeds", "2", "--duration", "0.1", "--skip", "0", "--scheduler", "serial"]
        argv += [flag, "contact.friction=-5", flag, "contact.friction=0.1", "--out", str(tmp_path / "e.csv")]
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert f"{flag} contact.friction" in err and "is given twice (-5 and 0.1)" in err
        assert not (tmp_path / "e.csv").exists()


def test_keys_prints_the_rows_of_the_key_table(capsys):
    """docs/model_file.md says `cablecasing keys` prints the key table; it printed the sentinels
    REQUIRED and OPTIONAL as defaults and left out the plausible ranges. Each printed row now has
    the table's default and allowed cells (without the table's Markdown quoting)."""
    from cablecasing_core.model.schema import markdown_table

    assert main(["keys"]) == 0
    printed = {r.split("\t")[0]: r.split("\t") for r in capsys.readouterr().out.splitlines()}
    table = {}
    for row in markdown_table().splitlines()[2:]:
        cells = [c.strip() for c in row.strip("|").split(" | ")]
        table[cells[0].strip("`")] = cells
    assert printed.keys() == table.keys()
    for key, cells in table.items():
        assert printed[key][2] == cells[2].strip("`") and printed[key][4] == cells[4].replace("\\|", "|"), key
    assert "REQUIRED" not in str(printed) and "a warning outside" in printed["casing.E"][4]


def test_without_excitations_keeps_the_rest_and_what_follows_scenario_seed():
    """The report's run without the cable drive and the FMU's undriven supports remove excitations
    by one route: the rest of the model is the one a file without them loads, and a derived seed of
    an excitation kept still follows scenario.seed (so --set scenario.seed=2 on its TOML moves it)."""
    m = load_model("default")
    bare = m.without_excitations(["cable_axial"])
    assert list(bare.scenario["excitation"]) == ["casing_random"]
    data = copy.deepcopy(m.data)
    del data["scenario"]["excitation"]["cable_axial"]
    assert bare.data == model_from_dict(data).data
    assert bare.derived == m.derived == {"scenario.excitation.casing_random.seed"}
    # derived keys of a removed excitation leave with it
    assert m.without_excitations(["casing_random"]).derived == frozenset()
    assert "seed = " not in bare.to_toml().split("[scenario.excitation.casing_random]")[1].split("[")[0]


def test_without_excitations_refuses_a_name_the_model_does_not_have():
    with pytest.raises(ModelError, match=r"scenario.excitation = 'shaker': must name an excitation of the model"):
        load_model("default").without_excitations(["shaker"])


def test_a_number_from_a_reduction_of_an_array_subclass_is_a_number():
    """fmpy's results are an ndarray subclass, whose np.mean is a 0-d array of that subclass, not a
    float: `fs = 1 / np.mean(np.diff(r["time"]))` was refused as 'fs = 1000.0: must be a positive
    number'. A 0-d array of numbers is its number; one of bools, or a 1-element vector, is not."""
    from cablecasing_core.model.validators import number

    class Result(np.ndarray):
        pass

    fs = 1.0 / np.mean(np.diff(np.arange(0.0, 0.01, 1e-3).view(Result)))
    assert type(fs) is Result and fs.shape == ()
    assert number("fs", fs, gt=0, unit="Hz") == pytest.approx(1000.0, rel=1e-12)
    for bad in (np.array(True), np.array([1000.0])):
        with pytest.raises(ModelError, match="fs = .*must be a positive number"):
            number("fs", bad, gt=0, unit="Hz")
    from cablecasing_core.model.validators import integer

    assert integer("count", np.sum(np.arange(3).view(Result)), 1) == 3
    with pytest.raises(ModelError, match="count = 1.5: must be an integer"):
        integer("count", np.mean(np.arange(1.0, 3.0).view(Result)), 1)
