"""Review I (the public API's edges), the time domain's part: the statics take the time domain's
``contact`` check (D2) and name a wrong support (D3); the entry points name a non-model (D7); the
run's warnings are ModelWarnings (D9); a result loads from its upper-case suffix (D11); a run of
its own motion records its inputs (D14); a support force is the caller's copy, the energies plain
floats (D15)."""

import warnings

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.model.schema import CHANNELS
from cablecasing_core.timedomain import engine as engine_module


@pytest.fixture(scope="module")
def model():
    return cc.load_model()


@pytest.fixture(scope="module")
def clipped():
    return cc.load_model("examples/installation.toml")


@pytest.fixture(scope="module")
def clipped_static(clipped):
    return cc.static_state(clipped)


NOT_BOOL = r"^contact = .*: must be None \(the model's contact.enabled\), True or False"


@pytest.mark.parametrize("contact", ["no", "False", 0, 1.0, "yes"])
def test_the_statics_refuse_a_contact_that_is_not_none_true_or_false(model, contact):
    with pytest.raises(cc.ModelError, match=NOT_BOOL):
        cc.static_state(model, contact=contact)
    with pytest.raises(cc.ModelError, match=NOT_BOOL):
        cc.simulate(model, duration=1e-3, contact=contact)  # (the same words)


@pytest.mark.parametrize(
    "support", ["casing.C", "casingA", "casing.clip7", "casing.clipx", "casing.clip-1", "cable.clip0"]
)
def test_a_reaction_of_a_support_the_model_lacks_is_refused_naming_the_allowed(clipped_static, support):
    allowed = "'casing.A', 'casing.B', 'cable.A', 'cable.B', 'casing.clip0', 'casing.clip1'"
    with pytest.raises(cc.ModelError, match=rf"^support = '{support}': must be one of {allowed}$"):
        clipped_static.reaction(support)


def test_the_reactions_of_the_supports_and_clips_it_has_are_given(clipped_static):
    st = clipped_static
    assert st.support_names[-2:] == ("casing.clip0", "casing.clip1")
    np.testing.assert_array_equal(st.reaction("casing.clip1"), st.clip_reactions[1])
    r = st.reaction("casing.B")
    r[:] = 1e9  # (a copy)
    assert not np.array_equal(st.reaction("casing.B"), r)
    assert set(st.as_dict()["support_reactions_N"]) == set(st.support_names)


def test_the_statics_warnings_point_at_the_callers_line(model):
    cantilever = model.with_overrides(
        {"casing.supports.B": "free", "cable.supports.B": "free", "loads.gravity.z": -9.81}
    )
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        cc.static_state(cantilever, contact=False)
    moved = [w for w in said if "the static state moves it" in str(w.message)]
    assert moved and all(issubclass(w.category, cc.ModelWarning) for w in moved)
    assert {w.filename for w in moved} == {__file__}, [(w.filename, w.lineno) for w in moved]


@pytest.mark.parametrize("given", [lambda m: m.data, lambda m: "default", lambda m: m.to_dict()])
def test_the_time_domain_given_no_model_names_it(model, given):
    with pytest.raises(cc.ModelError, match=r"^model = .*: must be a cablecasing_core\.Model"):
        cc.simulate(given(model), duration=1e-3)
    with pytest.raises(cc.ModelError, match=r"^model = .*: must be a cablecasing_core\.Model"):
        cc.static_state(given(model))


def test_a_runs_warnings_are_model_warnings(model, monkeypatch):
    still = model.without_excitations(["cable_axial", "casing_random"])
    with pytest.warns(cc.ModelWarning, match="has no excitation"):
        cc.simulate(still, duration=1e-3)
    # the step loop's own (an unconverged Newton, a tolerance not met: test_contact.py,
    # test_event_tolerance.py), here said by a stand-in engine's report
    monkeypatch.setattr(engine_module.Engine, "solver_warnings", lambda self: ["the contact Newton did not converge"])
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        cc.simulate(model, duration=1e-3)
    (w,) = [w for w in said if "Newton" in str(w.message)]
    assert w.category is cc.SolverWarning and issubclass(w.category, cc.ModelWarning) and w.filename == __file__


@pytest.fixture(scope="module")
def run(model):
    return cc.simulate(model, duration=2e-3)


def test_a_result_saved_with_an_upper_case_suffix_loads(run, tmp_path):
    path = tmp_path / "X.NPZ"
    run.save(path)
    back = cc.SimulationResult.load(path)
    np.testing.assert_array_equal(back.support_forces, run.support_forces)
    assert back.energies == run.energies


def test_a_support_force_is_a_copy_and_the_energies_plain_floats(run, tmp_path):
    before = run.records().columns["casing.B.Fz"].copy()
    f = run.support_force("casing.B.Fz")
    f -= f.mean() + 1.0
    np.testing.assert_array_equal(run.records().columns["casing.B.Fz"], before)
    assert all(type(v) is float for v in run.energies.values()), run.energies
    assert "contact_normal_dissipation" in run.energies
    with pytest.raises(cc.ModelError, match=r"^output = 'casing.C.Fz': must be one of"):
        run.support_force("casing.C.Fz")


def test_a_run_of_its_own_motion_records_the_channels_it_moves(model):
    j = CHANNELS.index("casing.A.z")
    w, A = 2 * np.pi * 100.0, 1e-5

    def harmonic(t):
        t = np.asarray(t)
        u, v, a = (np.zeros((t.size, len(CHANNELS))) for _ in range(3))
        u[:, j], v[:, j], a[:, j] = A * np.sin(w * t), A * w * np.cos(w * t), -A * w * w * np.sin(w * t)
        return u, v, a

    res = cc.simulate(model, duration=5e-3, motion=harmonic)
    assert list(res.inputs) == ["casing.A.z", "casing.A.vz", "casing.A.az"]
    np.testing.assert_allclose(res.inputs["casing.A.az"], -A * w * w * np.sin(w * res.time), rtol=0, atol=1e-12)
    rec = res.records()
    assert rec.columns["casing.A.az"][0] == 0.0 and len(rec.columns["casing.A.az"]) == len(rec.time)
    still = cc.simulate(model, duration=1e-3, motion=cc.timedomain.scenario.zero_motion)
    assert still.inputs == {}
