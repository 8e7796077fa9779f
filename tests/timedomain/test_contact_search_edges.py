"""The contact search and the static state on unusual routes (CHANGELOG, "Fixed: contact search and
static state on unusual routes"): a cable end node a hair outside the casing's end on a route that
comes back past its start (a 150 degree U-bend) has no contact, in the search, the time domain and
the static state; the static Newton with a stiff linear contact law converges (its tolerance is not
below the rounding of the contact forces), and when it fails it names why."""

import copy
import warnings

import numpy as np
import pytest

import cablecasing_core as cc
import cablecasing_core.timedomain.static_state as S
from cablecasing_core.errors import SimulationError
from cablecasing_core.structure.geometry import centerline_of
from cablecasing_core.timedomain import kernels as K

U_ROUTE = [
    {"straight": 0.12},
    {"bend": {"radius": 0.10, "angle_deg": 150.0, "toward": [0, 1, 0]}},
    {"straight": 0.30},
]


def u_route_specimen(target):
    """The built-in specimen (all supports clamped) on the U-route, its shaker on casing end A."""
    d = copy.deepcopy(cc.load_model().data)
    del d["geometry"]["points"]
    d["geometry"].pop("curve")  # (a points route's interpolation: a route of segments has none)
    d["geometry"].update({"n_elements": 40, "segments": U_ROUTE})
    d["scenario"]["excitation"]["casing_random"]["target"] = target
    return cc.model_from_dict(d)


def u_route_installed(excitation=None, gravity=-9.81):
    """examples/installation.toml on the U-route, casing end A on its axial isolator, B clamped."""
    d = copy.deepcopy(cc.load_model("examples/installation.toml").data)
    d["geometry"]["segments"] = U_ROUTE
    d["geometry"]["n_elements"] = 40
    d["casing"]["supports"] = {"A": "isolator", "B": "clamped"}
    del d["casing"]["isolator"]["B"]
    d["casing"].pop("clip")
    if excitation is None:
        d["loads"] = {"gravity": [0.0, 0.0, gravity], "cable_tension": 0.0}
    else:
        d["scenario"]["excitation"] = excitation
    return cc.model_from_dict(d)


@pytest.mark.parametrize("shift", [1e-6, 1e-4, -1e-6])
def test_a_node_beyond_the_casing_end_cuts_no_far_leg(shift):
    """The casing moved along its first tangent by ``shift`` (m) against cable node 0: outside the
    end (shift > 0) its normal plane cuts no element near it and the search finds none; the plane
    does cut the U's far leg, ~0.3 m away, which the search used to take as a 0.28 m penetration."""
    model = u_route_specimen("casing.A.x")
    cl = centerline_of(model)
    t = cl.tangents[0]
    Us = np.zeros(6 * len(cl.nodes))
    for j in range(len(cl.nodes)):
        Us[6 * j : 6 * j + 3] = shift * t
    x = cl.nodes[0]
    # the far leg is cut (the reason the old scan over the whole casing found it)
    far_cuts = []
    for e in range(cl.n_elements):
        a, b = cl.nodes[e] + shift * t, cl.nodes[e + 1] + shift * t
        xi = ((x - a) @ t) / ((b - a) @ t)
        if 0.0 <= xi <= 1.0:
            far_cuts.append(np.linalg.norm(a + xi * (b - a) - x))
    assert max(far_cuts) > 0.25
    e, xi, far, _, _, _ = K.search_node(*x, *t, cl.nodes, cl.frames, cl.lengths, Us, 0, model.radial_gap)
    if shift > 0:
        assert e == -1  # beyond the end: no contact
    else:
        # (Eq. (39)'s cut on the chord in closed form, as here: the rounding of positions ~1 m over the shift)
        assert (e, far) == (0, True) and xi == pytest.approx(-shift / cl.lengths[0], rel=1e-6)


@pytest.mark.parametrize("target", ["casing.A.x", "casing.A.y"])
def test_the_shaken_u_route_has_no_contact_at_its_end_node(target):
    """The paper's set-up (all clamped) on the U-route, the shaker at casing end A: node 0 stays
    within ~1e-6 m of its casing's end, inside the 0.5 mm gap (it used to raise 'cable node 0:
    penetration 0.2762 m exceeds the cable radius' at t ~ 0.01 s)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = cc.simulate(u_route_specimen(target), duration=0.02)
    pen, N = np.asarray(r.penetration), np.asarray(r.normal_force)
    assert not np.any(pen[:, 0]) and not np.any(N[:, 0])
    assert pen.max() == 0.0  # no contact anywhere: the cable hangs free in the gap (clamped, no gravity)


def test_an_isolated_casing_end_moving_past_the_cable_end_has_no_contact():
    """Casing end A on its axial isolator, pushed at 40 Hz by 0.2 mm past cable node 0."""
    exc = {"push": {"target": "casing.A.x", "kind": "harmonic", "frequency": 40.0, "amplitude": 2e-4}}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = cc.simulate(u_route_installed(excitation=exc), duration=0.02)
    assert np.asarray(r.penetration).max() == 0.0 and np.asarray(r.normal_force).max() == 0.0


@pytest.mark.parametrize("g", [-9.81, -0.5])
def test_static_state_on_the_u_route_converges_without_a_far_contact(g):
    """The static state under gravity (it failed at -9.81: a Newton trial step latched node 0's search
    onto the far leg, and the search kept it after the step was rejected). Every node is searched on
    its own element or a neighbour, the end nodes have no contact, and the weight goes into the
    supports: each body's force balance to 1e-9 of its weight (the solver's tolerance is 1e-10 of
    the largest load; the balance sums ~40 nodes' residuals)."""
    st = S.static_state(u_route_installed(gravity=g))
    nn = len(st.element)
    assert np.all(np.abs(st.element - np.clip(np.arange(nn), 0, nn - 2)) <= 1)
    assert st.normal_force[0] == 0.0 and st.normal_force[-1] == 0.0
    assert st.max_penetration < 1e-6
    for body, bal in st.balance.items():
        assert np.abs(bal["residual"]).max() <= 1e-9 * np.abs(st.weight[body]).max(), body


def test_no_trial_point_of_the_static_line_search_starts_from_another_guess(monkeypatch):
    """Every trial point of a line search is searched from the casing elements of the iterate it
    started from: the elements a rejected trial found are not kept (they used to be, and a trial
    that carried node 0 past the casing's end left its search on the far leg)."""
    evals, steps = [], []  # (z, elements at entry) of every evaluation; (z, elements) at every step
    evaluate, step = S._Evaluator.evaluate, S._Problem.step

    def spy_evaluate(self, z):
        evals.append((z.copy(), self.elem.copy()))
        return evaluate(self, z)

    def spy_step(self, x, R, fresh=None):
        steps.append((x[:-1].copy(), self.ev.elem.copy(), len(evals)))
        return step(self, x, R, fresh)

    monkeypatch.setattr(S._Evaluator, "evaluate", spy_evaluate)
    monkeypatch.setattr(S._Problem, "step", spy_step)
    S.static_state(u_route_installed(gravity=-9.81))
    trials = rejected = 0
    for (_, elem, a), (z_next, _, b) in zip(steps, steps[1:]):
        # the trials from this iterate: every evaluation up to the first at the next iterate
        for z, start in evals[a:b]:
            assert np.array_equal(start, elem)
            trials += 1
            if np.array_equal(z, z_next):
                break
            rejected += 1
    assert rejected > 0 and trials > rejected


LINEAR_BEND = {
    "geometry": {
        "n_elements": 22,
        "segments": [{"straight": 0.53}, {"bend": {"radius": 0.38, "angle_deg": 52.0, "toward": [0, 0, 1]}}],
    },
    "casing": {"E": 1.7e10, "nu": 0.26, "rho": 6150.0, "d_outer": 0.00619, "d_inner": 0.00383, "I": 1.154e-10,
               "alpha": 24.0, "beta": 4.2e-7},
    "cable": {"E": 6.16e9, "nu": 0.25, "rho": 5500.0, "d": 0.00187, "rest_shape": "straight", "alpha": 34.0,
              "beta": 1.2e-7},
    "contact": {"law": "linear", "stiffness": 1.0e7},
    "loads": {"gravity": [0.0, 0.0, -9.81], "cable_tension": 0.449},
    "scenario": {"duration": 0.01},
}  # fmt: skip


def linear_bend(k):
    d = copy.deepcopy(LINEAR_BEND)
    d["contact"]["stiffness"] = k
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (the step does not resolve a stiff contact: irrelevant at rest)
        return cc.model_from_dict(d)


@pytest.mark.parametrize("k", [1e6, 3e6, 1e7])
def test_static_state_with_a_stiff_linear_contact_converges(k):
    """A 0.53 m straight and a 52 degree bend, clamped, gravity and 0.45 N tension, the linear law:
    at 3e6 and 1e7 N/m Newton used to cycle at |R| ~ 1e-10 N, its tolerance 1.7e-11 N below the
    rounding of the contact forces (k times an ulp of the 0.83 m positions: 1.8e-9 N at 1e7 N/m).
    Converged: |R| at most 1e-8 of the load (the contact's rounding floor, 4 ulps x k x 0.83 m =
    7.4e-9 N at 1e7 N/m, is below 1e-8 of the 0.45 N tension), in one load step."""
    st = S.static_state(linear_bend(k))
    load = max(0.449, *(np.abs(w).max() for w in st.weight.values()))
    assert st.residual <= 1e-8 * load
    for bal in st.balance.values():
        assert np.abs(bal["residual"]).max() <= 1e-8 * load
    assert st.contact_nodes > 0 and st.max_penetration < 1e-6  # pressed into the bend's inside, stiffly
    assert st.load_steps == 1 and st.iterations <= S.MAX_ITERATIONS


def test_a_static_state_that_stalls_at_its_rounding_says_so(monkeypatch):
    """Without the contact's rounding floor (the tolerance as it was) the stiff linear contact
    stalls above its tolerance with the same contacts closed: the message names that, and no
    longer blames a soft contact."""
    monkeypatch.setattr(S, "CONTACT_ROUNDING_ULPS", 0.0)
    with pytest.raises(SimulationError) as err:
        S.static_state(linear_bend(1e7))
    msg = str(err.value)
    assert "stalled just above its tolerance" in msg and "rounding" in msg
    assert "too soft" not in msg


def test_the_failure_message_names_the_cause():
    """:func:`static_state._cause` from a failed Newton's evidence."""
    fail = {"tolerance": 1e-11, "switching": np.zeros(0, np.int64), "penetration": 1e-7}
    assert "stalled just above its tolerance" in S._cause(fail, 5e-11, 1e-3)
    assert "no equilibrium near the last one" in S._cause(fail, 1.0, 1e-3)
    cyc = dict(fail, switching=np.array([3, 4]))
    assert "cycles between sets of closed contacts (cable nodes 3, 4" in S._cause(cyc, 1.0, 1e-3)
    soft = dict(fail, penetration=2e-3)
    assert "too soft" in S._cause(soft, 1.0, 1e-3) and "exceeds the cable radius" in S._cause(soft, 1.0, 1e-3)
