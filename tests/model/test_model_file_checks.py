"""Checks of a model file found by a review: a harmonic above the Nyquist frequency, excitation
names and the TOML that Model.to_toml() writes, a CSV excitation with extra columns, the largest
seeds."""

import copy
import warnings

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core import ModelError, load_model, model_from_dict
from cablecasing_core.model.load import tomllib
from cablecasing_core.model.model import _to_toml
from cablecasing_core.model.schema import MAX_SEED
from cablecasing_core.model.validators import Number
from cablecasing_core.timedomain.scenario import scenario_motion


def raw():
    return copy.deepcopy(load_model().data)


def harmonic_only(frequency=50.0, dt=1e-5):
    """The built-in specimen driven by its harmonic cable_axial alone (no random band, whose own
    Nyquist check would speak first), at ``frequency`` Hz with scenario.dt = ``dt`` s."""
    d = raw()
    del d["scenario"]["excitation"]["casing_random"]
    d["scenario"]["excitation"]["cable_axial"]["frequency"] = frequency
    d["scenario"]["dt"] = dt
    return d


# ------------------------------------------------------------- a harmonic above the Nyquist frequency
def test_a_harmonic_above_the_nyquist_frequency_is_refused_naming_its_alias():
    """99990 Hz at dt = 1e-5 s was taken and ran as its 10 Hz alias (a ledger residual of 2.6e6 J)."""
    with pytest.raises(ModelError) as exc:
        model_from_dict(harmonic_only(99990.0))
    err = exc.value
    assert err.key == "scenario.excitation.cable_axial.frequency" and err.value == 99990.0
    assert "must be below the Nyquist frequency" in str(err) and "50000 Hz" in str(err)
    assert "alias at 10 Hz" in str(err)


@pytest.mark.parametrize("frequency, ok", [(49999.0, True), (50000.0, False), (50001.0, False), (1e6, False)])
def test_the_harmonic_frequency_must_lie_below_one_over_two_dt(frequency, ok):
    if ok:
        assert model_from_dict(harmonic_only(frequency)).scenario["excitation"]["cable_axial"]["frequency"] == frequency
    else:
        with pytest.raises(ModelError, match="scenario.excitation.cable_axial.frequency"):
            model_from_dict(harmonic_only(frequency))


def test_an_override_of_the_step_or_the_frequency_is_checked_too():
    m = model_from_dict(harmonic_only(50.0))
    with pytest.raises(ModelError, match="scenario.excitation.cable_axial.frequency"), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (a step of 10 ms is implausible too)
        m.with_overrides({"scenario.dt": 0.01})  # Nyquist 50 Hz
    with pytest.raises(ModelError, match="scenario.excitation.cable_axial.frequency"):
        m.with_overrides({"scenario.excitation.cable_axial.frequency": 60000.0})


def test_a_runs_own_step_is_checked_against_the_harmonic_as_against_a_random_band():
    """simulate(dt=...) (the CLI's --dt, the FMU's solver.dt) makes the motion with its own step:
    the harmonic is checked there, as the random band is, before any step is taken."""
    m = model_from_dict(harmonic_only(50.0))
    scenario_motion(m, dt=0.0099)  # Nyquist 50.5 Hz: fine
    for run in (lambda: scenario_motion(m, dt=0.011), lambda: cc.simulate(m, duration=0.05, dt=0.011)):
        with pytest.raises(ModelError) as exc:
            run()
        assert exc.value.key == "dt" and exc.value.value == 0.011
        assert "scenario.excitation.cable_axial" in str(exc.value) and "50 Hz" in str(exc.value)
        assert "dt < 0.01 s" in str(exc.value)


# ---------------------------------------------------------------------------------- excitation names
@pytest.mark.parametrize("name", ["cable axial", "", "a.b", "kabel_ö", "a\nb", '"q"', "[x]"])
def test_an_excitation_name_that_is_no_bare_key_is_refused(name):
    d = raw()
    d["scenario"]["excitation"][name] = d["scenario"]["excitation"].pop("cable_axial")
    with pytest.raises(ModelError) as exc:
        model_from_dict(d)
    err = exc.value
    assert err.key == "scenario.excitation.<name>" and err.value == name
    assert "ASCII letters, digits, _ and -" in str(err) and "\n" not in str(err)


@pytest.mark.parametrize("name", ["cable_axial", "Cable-2", "9", "-"])
def test_a_bare_key_names_an_excitation(name):
    d = raw()
    d["scenario"]["excitation"][name] = d["scenario"]["excitation"].pop("cable_axial")
    m = model_from_dict(d)
    assert m.scenario["excitation"][name]["kind"] == "harmonic"
    assert tomllib.loads(m.to_toml()) == m.data


def test_a_file_with_a_quoted_excitation_name_is_refused(tmp_path):
    """The review's file: [scenario.excitation."cable axial"] loaded, and `cablecasing report`
    failed after all its runs on the model.toml it wrote (to_toml wrote the name unquoted)."""
    text = load_model().to_toml().replace("[scenario.excitation.cable_axial]", '[scenario.excitation."cable axial"]')
    p = tmp_path / "m.toml"
    p.write_text(text)
    with pytest.raises(ModelError, match="scenario.excitation.<name> = 'cable axial'"):
        load_model(p)


# ------------------------------------------------------------------------- the TOML to_toml() writes
AWKWARD = 'a "quoted" \\back\\slash\ttab\nline\r\x01\x1f\x7f \u00e9\u4e2d\U0001f600 \'\'\' """ # [x] = y'


def test_to_toml_quotes_every_key_that_is_no_bare_key_and_escapes_every_string():
    """The writer alone, on keys a model cannot have (the loader refuses them) and on strings with
    every character a TOML basic string cannot hold as it is."""
    data = {
        "geometry": {"curve": AWKWARD, "supports": {"A": AWKWARD, "B b": "x"}},
        "a b": {"": 1, "x.y": -2.5e-300, "ok-key_1": [True, False], AWKWARD: {"deep": {"c": "\x00"}}},
        "scenario": {"excitation": {"cable axial": {"kind": AWKWARD, "band": [1.0, 2.0]}, "": {"seed": MAX_SEED}}},
    }
    assert tomllib.loads(_to_toml(data)) == data


def _models(tmp_path):
    """Valid models that exercise the writer: both specimens, a route of segments with isolators and
    an excited clip, and a CSV excitation whose file name holds every awkward character a Linux file
    name can."""
    yield load_model()
    yield load_model("installed")
    d = raw()
    d["geometry"] = {
        "n_elements": 20,
        "segments": [
            {"straight": 0.2},
            {"bend": {"radius": 0.15, "angle_deg": 60.0, "toward": [0.0, 1.0, 0.0]}},
            {"straight": 0.3},
        ],
    }
    d["casing"]["supports"] = {"A": "isolator", "B": "clamped"}
    d["casing"]["isolator"] = {"A": {"stiffness": [4e5, 1e5, 1e5], "table": [[0.0, 1.0, 0.1], [100.0, 1.2, 0.2]]}}
    d["casing"]["clip"] = [{"at": 0.3, "stiffness": 2e4, "excitation": "tunnel"}]
    d["scenario"]["excitation"]["tunnel-z"] = {"target": "tunnel.z", "kind": "impulse", "amplitude": 1e-4}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        yield model_from_dict(d)
    name = AWKWARD.replace("\x00", "") + ".csv"  # (a file name holds every character but NUL and /)
    (tmp_path / name).write_text("time_s,u_m\n0.0,0.0\n0.001,1e-5\n0.002,0.0\n")
    d = raw()
    d["scenario"]["excitation"]["from-file"] = {"target": "casing.B.y", "kind": "csv", "file": name}
    yield model_from_dict(d, base_dir=str(tmp_path))


def test_every_valid_model_round_trips_through_to_toml(tmp_path):
    """tomllib reads back the very data, and load_model of the written file is the same model
    (before, a tab or a line break in a CSV file's path, or a name needing quotes, gave invalid TOML)."""
    for i, m in enumerate(_models(tmp_path)):
        text = m.to_toml()
        written = copy.deepcopy(m.data)
        for key in m.derived:  # (left out: derived again from their source when read back)
            *path, last = key.split(".")
            node = written
            for p in path:
                node = node[p]
            del node[last]
        assert tomllib.loads(text) == written
        p = tmp_path / f"written{i}.toml"
        p.write_text(text, encoding="utf-8")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            again = load_model(p)
        assert again.data == m.data and again.derived == m.derived
    assert again.scenario["excitation"]["from-file"]["file"].endswith(AWKWARD.replace("\x00", "") + ".csv")


# ---------------------------------------------------------------------- CSV excitation with more columns
def _csv_model(tmp_path, header, rows):
    (tmp_path / "table.csv").write_text(header + "\n" + "".join(rows))
    d = raw()
    d["scenario"]["excitation"] = {"e": {"target": "casing.A.z", "kind": "csv", "file": "table.csv"}}
    p = tmp_path / "m.toml"
    p.write_text(_to_toml(d))
    return p


def test_a_csv_excitation_with_a_third_column_is_refused_not_ignored(tmp_path):
    p = _csv_model(tmp_path, "time_s,u,v", ["0,0,0\n", "0.001,1e-5,0\n", "0.002,0,0\n"])
    with pytest.raises(ModelError) as exc:
        load_model(p)
    err = exc.value
    assert err.key == "scenario.excitation.e.file" and err.value == str(tmp_path / "table.csv")
    assert "must have two columns" in str(err) and "3 columns" in str(err)
    # a model built from a dictionary reads its file when its motion is made: refused there alike
    d = raw()
    d["scenario"]["excitation"] = {"e": {"target": "casing.A.z", "kind": "csv", "file": "table.csv"}}
    m = model_from_dict(d, base_dir=str(tmp_path))
    with pytest.raises(ModelError, match="3 columns"):
        scenario_motion(m)


def test_a_csv_excitation_of_two_columns_drives_its_support(tmp_path):
    p = _csv_model(tmp_path, "time_s,u_m", ["0,0\n", "0.001,1e-5\n", "0.002,0\n"])
    m = load_model(p)
    u = scenario_motion(m)(np.array([0.001]))[0]
    assert u[0, 2] == pytest.approx(1e-5 * 0.5 * (1 - np.cos(np.pi * 0.001 / m.scenario["ramp"])))


# --------------------------------------------------------------------------------------- the largest seeds
@pytest.mark.parametrize("seed", [MAX_SEED, MAX_SEED - 1, MAX_SEED - 511, 2**63 - 513, 2**53 + 1, 0])
def test_every_seed_up_to_max_seed_is_taken_and_drives_its_own_record(seed):
    """The 512 seeds from 2**63 - 512 to 2**63 - 1 were refused by a message saying they are allowed
    (float(seed) rounds them up to 2**63); numpy's default_rng takes them all."""
    m = load_model().with_overrides({"scenario.seed": seed})
    assert m.scenario["seed"] == seed and type(m.scenario["seed"]) is int
    assert m.scenario["excitation"]["casing_random"]["seed"] == seed
    t = np.linspace(0.05, 0.06, 5)
    a = scenario_motion(m)(t)[2][:, 2]
    other = load_model().with_overrides({"scenario.seed": seed - 1 if seed else 1})
    assert np.all(np.isfinite(a)) and not np.array_equal(a, scenario_motion(other)(t)[2][:, 2])
    assert tomllib.loads(m.to_toml())["scenario"]["seed"] == seed


@pytest.mark.parametrize("seed", [MAX_SEED + 1, 2**64, -1, np.uint64(2**63), 10**400])
def test_a_seed_beyond_max_seed_is_refused(seed):
    with pytest.raises(ModelError, match=r"scenario.seed = .*must be a whole number in \[0, 9223372036854775807\]"):
        load_model().with_overrides({"scenario.seed": seed})


def test_whole_numbers_are_compared_as_whole_numbers():
    rule = Number(ge=0, le=MAX_SEED, integer=True)
    assert rule("k", np.int64(MAX_SEED)) == MAX_SEED and type(rule("k", np.int64(MAX_SEED))) is int
    assert rule("k", np.uint64(MAX_SEED)) == MAX_SEED
    with pytest.raises(ModelError):
        rule("k", np.uint64(MAX_SEED + 1))
    small = Number(gt=2**60, lt=2**60 + 2, integer=True)  # (float() would make 2**60 + 1 equal to 2**60)
    assert small("k", 2**60 + 1) == 2**60 + 1
    with pytest.raises(ModelError):
        small("k", 2**60)


def test_a_model_file_that_is_no_regular_file_is_refused_without_reading_it(tmp_path):
    """A FIFO as model_file hung the reading (an FMU's initialisation with it): it is refused, as a
    folder and a device are, naming the path. (Should the check go, a writer thread opens and closes
    the FIFO after 2 s, so that the read ends and the test fails instead of hanging.)"""
    import os
    import threading

    fifo = tmp_path / "model.toml"
    os.mkfifo(fifo)

    def unblock():
        try:
            os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))  # (ENXIO when nobody reads: fine)
        except OSError:
            pass

    timer = threading.Timer(2.0, unblock)
    timer.start()
    try:
        for path in (fifo, tmp_path, "/dev/null"):
            with pytest.raises(ModelError, match="must be a TOML file, a regular file"):
                load_model(path)
    finally:
        timer.cancel()
