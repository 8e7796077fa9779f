"""The structure as built (issue 35): the casing's buckling load with its real supports, isolators
and clips against closed forms, and the refusal, before any work, of a structure that cannot carry
its loads (zero-stiffness mounts, a free end under tension, a mechanism), alike on every mesh."""

from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

import cablecasing_core as cc
from cablecasing_core.model.load import tomllib
from cablecasing_core.structure import buckling as bk
from cablecasing_core.structure.assembly import assemble_body

ROOT = Path(__file__).resolve().parents[2]
E, I = 5e9, 2.7261e-10  # Pa, m4: the paper's casing (Table 2)
EI = E * I
RIGID = 1e12  # N/m: a translational isolator stiffness that is rigid beside the column's EI / L^3 ~ 1.4 N/m
CASING = dict(E=E, rho=4850.0, d_outer=0.0095, d_inner=0.004, I=I)


def column(supports, L=1.0, n=40, isolator=None, clips=(), loads=None, cable=False, segments=None):
    """A straight casing along x (m), ``supports`` (A, B); ``isolator``: {support: (k, k_rot)} (N/m,
    N.m/rad, numbers or [axial, lateral_1, lateral_2])."""
    geometry = {"points": [[0.0, 0, 0], [L, 0, 0]], "n_elements": n, "curve": "polyline"}
    if segments is not None:
        geometry = {"segments": segments, "n_elements": n}
    casing = dict(CASING, supports={"A": supports[0], "B": supports[1]})
    for s, (k, kr) in (isolator or {}).items():
        casing.setdefault("isolator", {})[s] = {"stiffness": k, "rotational_stiffness": kr}
    if clips:
        casing["clip"] = [dict(c) for c in clips]
    data = {"geometry": geometry, "casing": casing}
    if cable:
        data["cable"] = dict(E=5.5e10, rho=7850.0, d=0.003)
    if loads:
        data["loads"] = loads
    return cc.model_from_dict(data)


def load_of(model):
    return bk.buckling(assemble_body(model, "casing", check_buckling=False))


# ---------------------------------------------------------------- buckling against closed forms
# Tolerance 1e-5: cubic Hermite elements give the buckling load with an error ~ (h / L)^4 = 4e-7
# times a modest constant at 40 elements (the clamped-clamped case, the stiffest mode, is within
# 1e-5); a rigid-but-finite isolator (1e12 N/m, 1e9 N.m/rad) moves it by EI / (k_rot L) ~ 1e-9.
@pytest.mark.parametrize(
    "supports, isolator, factor",
    [
        (("clamped", "clamped"), None, 4.0),
        (("clamped", "free"), None, 0.25),
        (("isolator", "isolator"), {"A": (RIGID, [1e6, 0.0, 0.0]), "B": (RIGID, [1e6, 0.0, 0.0])}, 1.0),  # pinned
        (("isolator", "isolator"), {"A": (RIGID, 1e9), "B": (RIGID, 1e9)}, 4.0),  # stiff isolators: clamped
        (("isolator", "clamped"), {"A": (RIGID, 1e9)}, 4.0),  # the casing held at A by a stiff isolator
    ],
)
def test_buckling_load_of_a_straight_column_is_euler_s(supports, isolator, factor):
    b = load_of(column(supports, isolator=isolator))
    assert b.load == pytest.approx(factor * np.pi**2 * EI, rel=1e-5)
    assert b.mechanism is None and 0.0 <= b.at <= 1.0


def test_pinned_pinned_mode_is_largest_at_mid_span_and_the_message_names_the_isolators():
    b = load_of(column(("isolator", "isolator"), isolator={"A": (RIGID, [1e6, 0, 0]), "B": (RIGID, [1e6, 0, 0])}))
    assert b.at == pytest.approx(0.5, abs=0.026)  # the node nearest to mid-span (h = 0.025 m)
    assert "A isolator k = 1e+12 N/m, k_rot = [1e+06, 0, 0] N.m/rad" in b.supports


@pytest.mark.parametrize("beta", [0.5, 2.0, 10.0])
def test_a_column_on_an_elastic_rotational_spring_solves_its_transcendental_equation(beta):
    """Base held in translation, rotation on a spring C = beta EI / L, top free: k L tan(k L) =
    C L / EI, P = EI k^2 (Timoshenko & Gere, Theory of Elastic Stability, Sec. 2.9); from the
    cantilever's pi^2 EI / (4 L^2) (C -> inf) down to zero (C -> 0). Tolerance: as above."""
    C = beta * EI / 1.0
    kl = brentq(lambda x: x * np.tan(x) - beta, 1e-9, np.pi / 2 - 1e-12)
    b = load_of(column(("isolator", "free"), isolator={"A": (RIGID, [1e6, C, C])}))
    assert b.load == pytest.approx(EI * kl**2, rel=1e-5)
    assert b.load < 0.25 * np.pi**2 * EI


@pytest.mark.parametrize("share", [0.25, 0.5, 0.9, 2.0])
def test_a_pinned_column_with_a_mid_span_clip_solves_its_transcendental_equation(share):
    """Pinned ends (isolators of 1e12 N/m without bending stiffness), a clip of lateral stiffness k
    at mid-span (its node: 20 of 40). The symmetric mode on the half span a = L / 2 (w = A sin(lx) +
    B x, w'(a) = 0, the spring's k w(a) / 2 the half span's shear) buckles where k = 2 EI l^3
    (-cos la) / (sin la - la cos la), P = EI l^2, from pi^2 EI / L^2 (k = 0) up to the antisymmetric
    mode's 4 pi^2 EI / L^2, which a node at the clip leaves unchanged, from k = 16 pi^2 EI / L^3 on
    (Timoshenko & Gere, Sec. 2.6). Tolerance: as above."""
    k_full = 16 * np.pi**2 * EI  # N/m (L = 1 m)
    k, a = share * k_full, 0.5
    clip = {"at": 0.5, "stiffness": [0.0, k, k]}
    pins = {"A": (RIGID, [1e6, 0.0, 0.0]), "B": (RIGID, [1e6, 0.0, 0.0])}
    b = load_of(column(("isolator", "isolator"), isolator=pins, clips=[clip]))
    if share >= 1.0:
        expected = 4 * np.pi**2 * EI
    else:
        x = brentq(lambda x: 2 * EI * (x / a) ** 3 * -np.cos(x) / (np.sin(x) - x * np.cos(x)) - k, np.pi / 2, np.pi)
        expected = EI * (x / a) ** 2
    assert b.load == pytest.approx(expected, rel=1e-5)
    assert np.pi**2 * EI < b.load <= 4 * np.pi**2 * EI * (1 + 1e-5)


def test_stiffer_isolators_tend_to_the_clamped_value_from_below():
    stiff = [1.0, 1e2, 1e4, 1e9]  # N.m/rad
    loads = [load_of(column(("isolator", "isolator"), isolator={s: (RIGID, k) for s in "AB"})).load for k in stiff]
    clamped = 4 * np.pi**2 * EI
    assert np.all(np.diff(loads) > 0) and loads[0] < 0.5 * clamped
    # (the closed forms' tolerance above; 1e9 N.m/rad moves the load by EI / (k_rot L) ~ 1e-9)
    assert loads[-1] == pytest.approx(clamped, rel=1e-5)


def test_the_qz_fallback_gives_the_same_load_as_the_cholesky_path(monkeypatch):
    """Should the Cholesky factor of K_E fail (mounts soft beside the beam), QZ on the pencil gives
    the load: the same to 1e-8 (two LAPACK drivers on a well-conditioned pencil)."""
    model = cc.load_model(ROOT / "examples" / "installation.toml")
    ref = load_of(model).load

    def refuse(*args, **kwargs):
        raise np.linalg.LinAlgError("not positive definite")

    monkeypatch.setattr(bk, "eigh", refuse)
    assert load_of(model).load == pytest.approx(ref, rel=1e-8)


def test_a_mechanism_has_no_buckling_load():
    b = load_of(column(("free", "free")))
    assert b.load == 0.0 and b.mechanism.startswith("it is free to move: a ")
    assert "buckles under any compression (buckling load 0 N)" in b.text()


def test_the_installation_example_carries_a_tension_its_isolators_carry():
    """examples/installation.toml (isolators at both ends, two clips) buckles at ~119 N as built,
    between the same casing pinned and clamped; 2 N and 100 N are carried (the static state
    exists), and a tension above the load is refused naming the load, the place and the isolators.
    The eigenvalue agrees with the Cholesky test of the tangent on either side of it (1 %)."""
    from cablecasing_core.timedomain.static_state import static_state

    path = ROOT / "examples" / "installation.toml"
    raw = tomllib.loads(path.read_text())
    model = cc.load_model(path)
    b = load_of(model)
    assert 100.0 < b.load < 140.0
    for T, ok in ((0.99 * b.load, True), (1.01 * b.load, False)):
        system = assemble_body(model.with_overrides({"loads.cable_tension": T}), "casing", check_buckling=False)
        assert bk.is_positive_definite(system) is ok
    for T in (2.0, 100.0):
        st = static_state(cc.model_from_dict(dict(raw, loads={"cable_tension": T}), base_dir=str(path.parent)))
        assert st.prestretch_force > 0 and st.contact_nodes > 0
    with pytest.raises(cc.ModelError) as err:
        static_state(model.with_overrides({"loads.cable_tension": 130.0}))
    text = str(err.value)
    assert err.value.key == "loads.cable_tension" and f"buckling load {b.load:.4g} N" in text
    assert "its mode largest at s = " in text and "A isolator k = [4e+05, 1e+05, 1e+05] N/m" in text
    assert "clips at s = 0.4, 0.6 m" in text  # (each clip at the at the file gives it, a node there)


# ---------------------------------------------------------------- structures that cannot carry their loads
def _installation(**changes):
    """The installation example's raw tables with ``changes`` ({dotted: value}, or None to delete)."""
    raw = tomllib.loads((ROOT / "examples" / "installation.toml").read_text())
    for key, value in changes.items():
        *path, last = key.split(".")
        node = raw
        for k in path:
            node = node.setdefault(k, {})
        if value is None:
            node.pop(last, None)
        else:
            node[last] = value
    return raw


@pytest.mark.parametrize("n", [40, 64])
def test_zero_stiffness_isolators_under_gravity_are_refused_alike_on_every_mesh(n):
    raw = _installation(
        **{
            "casing.isolator.A.stiffness": 0.0,
            "casing.isolator.B.stiffness": 0.0,
            "casing.clip": None,
            "loads.gravity": [0.0, 0.0, -9.81],
            "geometry.n_elements": n,
        }
    )
    with pytest.raises(cc.ModelError) as err:
        cc.model_from_dict(raw)
    assert err.value.key == "loads.gravity"
    assert str(err.value) == (
        "loads.gravity = [0.0, 0.0, -9.81]: cannot be carried by the casing: its supports (A isolator, B isolator, "
        "no clip) leave it free in a translation along [0, 0, -1] (a mechanism: the mounts have no stiffness "
        "there), and a loaded body must be held against every rigid motion; clamp a support or give the isolators "
        "or clips stiffness in that direction"
    )


def test_a_cable_lying_in_its_casing_is_not_carried_by_the_contact_and_the_message_says_so():
    """A cable on one soft isolator, its other end free, under its weight: the casing under it does
    not hold it axially nor about its centerline (one-sided, frictionless at rest), so the model is
    refused as any other mechanism, and the message says why the contact was not counted (a
    reviewer read "the mounts" as blaming the isolator alone). The mechanism's point is the origin
    (the isolator's node), written [0, 0, 0], not rounding's 1e-16."""
    raw = _installation(
        **{
            "cable.supports": {"A": "isolator", "B": "free"},
            "cable.isolator.A.stiffness": [1e3, 1.0, 1.0],
            "loads.gravity": [0.0, 0.0, -9.81],
        }
    )
    with pytest.raises(cc.ModelError) as err:
        cc.model_from_dict(raw)
    text = str(err.value)
    assert "cannot be carried by the cable: its supports (A isolator, B free, no clip) leave it free in a rotation" in (
        text
    )
    assert "through [0, 0, 0] m" in text
    assert "; the contact with the casing is not counted (one-sided and frictionless at rest" in text
    raw["contact"] = {**raw.get("contact", {}), "enabled": False}
    with pytest.raises(cc.ModelError) as err:
        cc.model_from_dict(raw)
    assert "contact with the casing" not in str(err.value)  # (no contact, nothing to explain)


@pytest.mark.parametrize("n", [40, 200])
def test_mounts_that_hold_nothing_name_the_translation_the_weight_drives_on_every_mesh(n):
    """Isolators of no translational stiffness, and of a torsional one alone (a mount of no stiffness
    at all is refused by name first: test_review_model_file.py): every translation and most rotations
    are free, and the weight drives a translation along g, not a rotation (the weight's moment was
    taken about the nodes' centroid, which on a curved route is not the centre of mass: "a rotation
    about [0.276, 0.961, 0] through [-481, 138, 0] m" at 40 elements, [-2.35e+03, 705, 0] m at 200)."""
    raw = _installation(
        **{f"casing.isolator.{s}.stiffness": 0.0 for s in "AB"}
        | {f"casing.isolator.{s}.rotational_stiffness": [1.0, 0.0, 0.0] for s in "AB"}
        | {"casing.clip": None, "loads.gravity": [0.0, 0.0, -9.81], "geometry.n_elements": n}
    )
    with pytest.raises(cc.ModelError) as err:
        cc.model_from_dict(raw)
    assert "leave it free in a translation along [0, 0, -1] (a mechanism" in str(err.value), str(err.value)


@pytest.mark.parametrize("body", ["cable", "casing"])
def test_an_isolator_without_axial_stiffness_under_tension_is_refused(body):
    """An end isolator with no stiffness along the body's axis carries no axial force, as a free end
    carries none: under a tension the model is refused at once, naming the isolator (it ran the
    static Newton for 2-3 s and blamed a contact too soft or a tension near buckling)."""
    changes = {"loads.cable_tension": 2.0, f"{body}.isolator.A.stiffness": [0.0, 1e5, 1e5]}
    if body == "cable":
        changes |= {"cable.supports": {"A": "isolator", "B": "clamped"}}
    with pytest.raises(cc.ModelError) as err:
        cc.model_from_dict(_installation(**changes))
    assert str(err.value).startswith(
        f"loads.cable_tension = 2.0: needs both ends of the {body} held along its axis: {body}.isolator.A has no "
        f"stiffness along the {body}'s axis at A"
    ), str(err.value)
    changes[f"{body}.isolator.A.stiffness"] = [1e3, 1e5, 1e5]  # (any axial stiffness carries it)
    cc.model_from_dict(_installation(**changes))


@pytest.mark.parametrize("n", [40, 64])
def test_a_free_casing_on_one_zero_stiffness_clip_is_refused_alike_on_every_mesh(n):
    with pytest.raises(cc.ModelError) as err:
        column(  # (a clip of rotational stiffness only: one of no stiffness at all is refused by name first)
            ("free", "free"),
            n=n,
            clips=[{"at": 0.5, "stiffness": 0.0, "rotational_stiffness": 1.0}],
            loads={"gravity": [0, 0, -9.81]},
        )
    assert "translation along [0, 0, -1]" in str(err.value) and "clips at s = 0.5 m" in str(err.value)


def test_a_clip_without_rotational_stiffness_leaves_a_rotation_free():
    """One stiff clip (no rotational stiffness) holds a free-free casing's translations but not its
    rotations: the weight's moment is zero about the clip at mid-span, but the rotation is free."""
    with pytest.raises(cc.ModelError) as err:
        column(("free", "free"), clips=[{"at": 0.5, "stiffness": 1e5}], loads={"gravity": [0, 0, -9.81]})
    assert "leave it free in a rotation about" in str(err.value) and "through [0.5, 0, 0] m" in str(err.value)


def test_a_torsion_left_free_by_two_pin_isolators_is_named():
    with pytest.raises(cc.ModelError) as err:
        column(
            ("isolator", "isolator"),
            isolator={"A": (1e5, 0.0), "B": (1e5, 0.0)},
            loads={"gravity": [0.0, 0.0, -9.81]},
        )
    assert "a rotation about [1, 0, 0] through [" in str(err.value)


def test_mounts_too_soft_for_the_weight_are_refused():
    """Two isolators of 1e-6 N/m would let the casing's weight, 4850 kg/m3 x 5.83e-5 m2 x 1 m x 9.81
    m/s2 = 2.78 N, sink it by W / (2 k) = 1.39e6 m: no linear statics."""
    with pytest.raises(cc.ModelError) as err:
        column(("isolator", "isolator"), isolator={s: (1e-6, 1.0) for s in "AB"}, loads={"gravity": [0, 0, -9.81]})
    assert "so soft that its weight would move it rigidly by 1.39e+06 m, more than its length 1 m" in str(err.value)


def test_a_free_cable_end_under_tension_is_refused():
    raw = _installation(**{"cable.supports": {"A": "clamped", "B": "free"}, "loads.cable_tension": 2.0})
    with pytest.raises(cc.ModelError) as err:
        cc.model_from_dict(raw)
    assert str(err.value).startswith(
        "loads.cable_tension = 2.0: needs both ends of the cable held (clamped or isolator): cable.supports.B is free"
    )


def test_a_free_casing_end_under_tension_is_refused():
    with pytest.raises(cc.ModelError) as err:
        column(("clamped", "free"), cable=True, loads={"cable_tension": 1.0})
    assert "cable.supports" not in str(err.value) and "casing.supports.B is free" in str(err.value)


def test_unloaded_mechanisms_and_held_bodies_pass():
    column(("free", "free"))  # no load: a free-free body has rigid modes, nothing to hold
    column(("isolator", "isolator"), isolator={s: (1e5, 1.0) for s in "AB"}, loads={"gravity": [0, 0, -9.81]})
    column(("clamped", "free"), loads={"gravity": [0, 0, -9.81]})


def _zero_isolators_text():
    """examples/installation.toml with isolators of zero translational stiffness, no clips, gravity."""
    text = (ROOT / "examples" / "installation.toml").read_text()
    text = text.replace("stiffness = [4.0e5, 1.0e5, 1.0e5]", "stiffness = 0.0")
    text = text[: text.index("[[casing.clip]]")] + text[text.index("[cable]") :]
    return text + "\n[loads]\ngravity = [0.0, 0.0, -9.81]\n"


@pytest.mark.parametrize("command", ["static", "simulate", "modes", "geometry"])
def test_every_command_refuses_a_structure_that_cannot_carry_its_loads(command, tmp_path, capsys):
    from cablecasing_core.cli import main

    path = tmp_path / "m.toml"
    path.write_text(_zero_isolators_text())
    args = [command, str(path)] + (["--duration", "0.001"] if command == "simulate" else [])
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "loads.gravity" in err and "translation along [0, 0, -1]" in err and "internal error" not in err


def test_the_newcomer_s_casing_in_an_isolator_a_clamp_and_a_clip_carries_8_n():
    """The issue's case: the S-route with the casing in an isolator at A, clamped at B and a clip at
    0.51 m was refused at 8 N as a cantilever (pi^2 EI / (4 L^2): 2.919 N on its route); as built it buckles
    far above the cantilever's load, and 8 N is carried."""
    from cablecasing_core.timedomain.static_state import static_state

    raw = _installation(**{"casing.supports": {"A": "isolator", "B": "clamped"}, "loads.cable_tension": 8.0})
    del raw["casing"]["isolator"]["B"]
    raw["casing"]["clip"] = [dict(raw["casing"]["clip"][0], at=0.51)]
    model = cc.model_from_dict(raw)
    b = load_of(model)
    L = assemble_body(model, "casing", check_buckling=False).centerline.length
    assert 0.25 * np.pi**2 * EI / L**2 < 8.0 < b.load  # (3.5 N refused 8 N; 84.0 N: the clip and isolator hold it)
    assert "A isolator" in b.supports and "B clamped" in b.supports and "clips at s = 0.51 m" in b.supports
    st = static_state(model)
    assert st.clip_reactions.shape == (1, 6) and st.prestretch_force > 0


def test_the_buckling_message_gives_a_curved_body_s_isolators_as_they_were_given():
    """On a bent route the isolator's stiffness is turned into global axes and back for the message:
    a zero stays 0 (it read 3.32e-12) and three equal rotational stiffnesses one number (it read
    [100, 100, 100])."""
    segments = [{"straight": 0.3}, {"bend": {"radius": 0.2, "angle_deg": 40, "toward": [0, 1, 0]}}, {"straight": 0.3}]
    b = load_of(
        column(("isolator", "isolator"), segments=segments, isolator={s: ([0.0, 1e5, 1e5], 100.0) for s in "AB"})
    )
    assert "A isolator k = [0, 1e+05, 1e+05] N/m, k_rot = 100 N.m/rad" in b.supports, b.supports
    assert "B isolator k = [0, 1e+05, 1e+05] N/m, k_rot = 100 N.m/rad" in b.supports, b.supports
