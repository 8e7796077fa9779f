"""The kept-prestress warning (timedomain/static_state.py, ``check_kept_prestress``) on the cases of
review M: a tension with contact off in a bent route (D6), and a clamped casing against the same
casing on isolators of 1e12 N/m (D1); said once per process and model (an ensemble's seeds, a
command's several runs), the warnings filters still deciding. And the static state of a body whose
stiffness underflows in double precision, named."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.errors import ModelWarning
from cablecasing_core.structure.assembly import assemble_body
from cablecasing_core.timedomain.static_state import end_axial_forces

CASING = {
    "E": 5e9,
    "nu": 0.3,
    "rho": 4850.0,
    "alpha": 0.0,
    "beta": 0.0,
    "loss_factor": 0.05,
    "d_outer": 0.0095,
    "d_inner": 0.004,
    "I": 2.7261e-10,
}
CABLE = {"E": 5.5e10, "nu": 0.3, "rho": 7850.0, "d": 0.003, "alpha": 0.0, "beta": 0.0, "loss_factor": 0.02}
BODIES = (("casing", CASING), ("cable", CABLE))
BENT = [{"straight": 0.2}, {"bend": {"radius": 0.15, "angle_deg": 90, "toward": [0, 1, 0]}}, {"straight": 0.2}]


def _model(segments, n, T, gravity=(0.0, 0.0, 0.0), isolators=None):
    casing = dict(CASING, supports={"A": "clamped", "B": "clamped"})
    if isolators is not None:
        casing["supports"] = {"A": "isolator", "B": "isolator"}
        casing["isolator"] = {"A": isolators, "B": isolators}
    d = {
        "geometry": {"n_elements": n, "segments": segments},
        "casing": casing,
        "cable": dict(CABLE, supports={"A": "clamped", "B": "clamped"}),
        "loads": {"gravity": list(gravity), "cable_tension": T},
        "scenario": {"duration": 0.01, "dt": 1e-5},
    }
    return cc.model_from_dict(d)


def _static(model, contact):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        st = cc.static_state(model, contact=contact)
    return st, [str(w.message) for w in caught if issubclass(w.category, ModelWarning)]


@pytest.fixture(scope="module")
def bent():
    """0.2 m, a 90 deg bend of R = 0.15 m, 0.2 m; both bodies clamped; T = 10 N (review M, D6)."""
    return _model(BENT, 60, 10.0)


def test_without_contact_a_bent_route_loses_the_fixed_prestress_and_both_bodies_warn(bent):
    """A fixed prestress N0 in a curved rod is held by the load N0 (t_e - t_(e-1)) at its nodes; a
    chain of bars answers it with the axial force -N0 exactly, so the net axial force vanishes up to
    the bending stiffness's share, (r_g / R)^2 = I / (A R^2) = 2e-4 for the casing (less for the
    cable): |N| < 0.01 T at both ends of both bodies, and the reactions carry no more of T."""
    st, caught = _static(bent, contact=False)
    T = 10.0
    for body, N0 in (("cable", T), ("casing", -T)):
        N = end_axial_forces(assemble_body(bent, body), st.U[body])
        assert np.abs(N).max() < 0.01 * T, (body, N)
        assert np.linalg.norm(st.reaction(f"{body}.A")[:3]) < 0.01 * T
        (msg,) = [m for m in caught if m.startswith(f"{body}:")]
        assert f"{N[0]:.4g} N at end A" in msg and f"N0 = {N0:.4g} N" in msg
        assert "with contact off nothing holds it in its bends" in msg
        assert "isolators" not in msg  # (clamped: not a cause)


def test_with_contact_the_tension_is_kept_and_nothing_is_warned(bent):
    """With contact the tension pulls the cable against the inside of the bend: the cable's ends
    carry T to within the capstan-free clamps' shear (review M, (c): 0.2 %), so the reactions are
    about T and the warning stays silent."""
    st, caught = _static(bent, contact=True)
    assert not caught
    assert st.reaction("cable.A")[0] == pytest.approx(10.0, rel=0.01)


def test_the_cli_says_what_a_tension_without_contact_does(tmp_path, capsys):
    path = tmp_path / "bent.toml"
    path.write_text(
        "[geometry]\nn_elements = 30\nsegments = [{straight = 0.2}, {bend = {radius = 0.15, angle_deg = 90, "
        "toward = [0, 1, 0]}}, {straight = 0.2}]\n[loads]\ncable_tension = 10.0\n"
        + "".join(f"[{name}]\n" + "".join(f"{k} = {v!r}\n" for k, v in body.items()) for name, body in BODIES)
    )
    assert main(["static", str(path), "--no-contact"]) == 0
    out = capsys.readouterr().out
    line = next(ln for ln in out.splitlines() if "contact off" in ln)
    assert "relaxes where the route bends" in line and "+10 N (cable) and -10 N (casing)" in line
    forces = [float(x) for x in re.findall(r"(?:cable|casing) (\S+) and (\S+) N", line)[0]]
    assert np.abs(forces).max() < 0.1  # (1 % of T, as above)
    assert "is a fixed prestress (" not in line


ROUTE = [
    {"straight": 0.15},
    {"bend": {"radius": 0.15, "angle_deg": 60, "toward": [0, 1, 0]}},
    {"straight": 0.15},
    {"bend": {"radius": 0.2, "angle_deg": 60, "toward": [0, 0, 1]}},
    {"straight": 0.3},
]


def test_stiff_isolators_and_clamps_are_answered_alike_and_the_isolators_are_not_blamed():
    """Isolators of 1e12 N/m keep k/(k + 2EA/L) = 1 - 2e-6 of N0 (EA/L = 3.9e5 N/m here): the same
    static state as clamped ends (review M: 2e-10), so the same answer. With contact both are
    silent (ends that keep N0 are not checked with contact on, docs/installed.md); without it both
    warn alike, naming the bends and the weight along the axis, never the isolators."""
    stiff = {"stiffness": 1e12, "rotational_stiffness": 1e12}
    found = []
    for iso in (None, stiff):
        model = _model(ROUTE, 64, 2.0, gravity=(0.0, 0.0, -9.81), isolators=iso)
        assert not [m for m in _static(model, contact=True)[1] if m.startswith("casing:")]
        (msg,) = [m for m in _static(model, contact=False)[1] if m.startswith("casing:")]
        assert "isolators give way" not in msg
        assert "nothing holds it in its bends" in msg and "weight along its axis" in msg
        found.append(re.sub(r"-?\d\.\d+e-\d+", "", msg))
    assert found[0] == found[1]


def test_soft_isolators_are_named_with_the_share_they_keep():
    """A straight casing between isolators of k = 1e5 N/m keeps k/(k + 2EA/L) of -T (EA/L = 3.45e5
    N/m for 0.85 m): 0.127, i.e. -1.27 N of -10 N, to the 1e-3 of the closed form's rounding."""
    iso = {"stiffness": 1e5, "rotational_stiffness": 20.0}
    model = _model([{"straight": 0.85}], 40, 10.0, isolators=iso)
    st, caught = _static(model, contact=True)
    (msg,) = [m for m in caught if m.startswith("casing:")]
    assert "isolators give way" in msg
    EA_L = 5e9 * np.pi / 4 * (0.0095**2 - 0.004**2) / 0.85
    N = end_axial_forces(assemble_body(model, "casing"), st.U["casing"])
    assert N == pytest.approx(-10.0 * 1e5 / (1e5 + 2 * EA_L), rel=1e-3)


def _bent_file(tmp_path, extra=""):
    """The bent route of the CLI test above as a model file (T = 10 N), with contact off and a random
    excitation of casing.A.z for an ensemble."""
    path = tmp_path / "bent.toml"
    path.write_text(
        "[geometry]\nn_elements = 30\nsegments = [{straight = 0.2}, {bend = {radius = 0.15, angle_deg = 90, "
        "toward = [0, 1, 0]}}, {straight = 0.2}]\n[loads]\ncable_tension = 10.0\n[contact]\nenabled = false\n"
        + "".join(f"[{name}]\n" + "".join(f"{k} = {v!r}\n" for k, v in body.items()) for name, body in BODIES)
        + "[scenario]\nduration = 0.12\ndt = 1e-5\n[scenario.excitation.x]\nkind = 'random'\ntarget = 'casing.A.z'\n"
        "rms = 0.1\nband = [10, 2000]\n" + extra
    )
    return path


@pytest.fixture
def said_afresh(monkeypatch):
    """This process as if it had said no kept-prestress warning yet (they are said once per process)."""
    from cablecasing_core import errors

    monkeypatch.setattr(errors, "_SAID_ONCE", set())


@pytest.mark.slow  # (two ensembles of 3 runs of 0.12 s)
def test_an_ensemble_of_three_seeds_says_it_once(tmp_path, capsys, said_afresh):
    """Every seed's static state gives the same warning (a property of the model, not of the run),
    and 'ensemble --against' runs a second ensemble of the same model: each body's warning is said
    once in the whole command, not per seed nor per ensemble."""
    path = _bent_file(tmp_path)
    args = ["ensemble", str(path), "--seeds", "3", "--skip", "0.01", "--against", "contact.friction=0.2"]
    assert main(args) == 0
    err = capsys.readouterr().err
    for body in ("casing", "cable"):
        lines = [ln for ln in err.splitlines() if f"{body}: the static state leaves an axial force" in ln]
        assert len(lines) == 1, err
        assert lines[0].startswith("cablecasing: warning: seed 1: ")


def test_the_warning_is_said_once_per_process_and_the_filters_still_apply(bent, said_afresh):
    """Under the default action the second static state of the same model says nothing; a filter
    'always' (what pytest.warns and a study's recording set) or 'error' still gets it every time, and
    the category is a ModelWarning, filterable on its own."""
    from cablecasing_core.timedomain.static_state import KeptPrestressWarning

    def said(action):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter(action, KeptPrestressWarning)
            cc.static_state(bent, contact=False)
        return [str(w.message) for w in caught if issubclass(w.category, KeptPrestressWarning)]

    assert issubclass(KeptPrestressWarning, ModelWarning)
    first = said("default")
    assert sorted(m.split(":")[0] for m in first) == ["cable", "casing"]
    assert said("default") == []  # (said once in this process)
    assert said("always") == first  # (a recording filter gets it every time)
    for _ in range(2):
        with warnings.catch_warnings(), pytest.raises(KeptPrestressWarning):
            warnings.simplefilter("error", KeptPrestressWarning)
            cc.static_state(bent, contact=False)
    assert said("default") == []


def test_a_stiffness_too_small_for_double_precision_is_named(bent):
    """cable.E = 5e-324 Pa lies inside the schema's bounds (E > 0), but its stiffness matrix underflows:
    the static state under gravity had no solution and its solve raised LinAlgError (an internal
    error to the command line and the FMU); it names cable.E, its value and what to give."""
    model = bent.with_overrides({"cable.E": 5e-324, "loads.gravity": [0.0, 0.0, -9.81], "loads.cable_tension": 0.0})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        with pytest.raises(cc.ModelError, match=r"^cable\.E = 5e-324: makes the cable's stiffness matrix singular"):
            cc.static_state(model, contact=False)
