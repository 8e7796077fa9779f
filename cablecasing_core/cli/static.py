"""``cablecasing static``: the static state of a model, the state an installed cable vibrates from
(gravity, the cable's tension, a cable straight off the reel; docs/installed.md)."""

from __future__ import annotations

import json

import numpy as np

from ..model.schema import BODY_NAMES, SUPPORT_NAMES
from .assignments import add_model_argument, model_argument, typed


def cmd_static(args):
    from ..model.validators import contact_in_force
    from ..timedomain.body_storage import time_domain_system
    from ..timedomain.static_state import solve_static
    from .paths import PLOT_SUFFIXES, check_output_path

    check_output_path("--plot", args.plot, PLOT_SUFFIXES)
    if args.no_contact:  # (a change of contact.enabled that --no-contact takes the place of would do nothing)
        from ..studies.evaluators import check_not_overridden

        check_not_overridden(
            {k: (f"--set {k}", v) for k, v in typed(args.set).items()},
            {"contact": ("--no-contact", False)},
            "the static state",
            "; give one of them",
        )
    model = model_argument(args.model, args.set)
    # (the bodies as the time domain assembles them, once: the solve and the end forces of a tension
    # without contact read these; static_state would assemble its own)
    systems = {n: time_domain_system(model, n) for n in model.bodies}
    contact = contact_in_force(model, False if args.no_contact else None)
    st = solve_static(model, systems, contact)
    buckled = _buckling(model)
    if args.json:
        out = st.as_dict()
        out["buckling"] = {b.body: b.as_dict() for b in buckled}
        print(json.dumps(out))
    else:
        _print(model, st, systems, buckled)
    if args.plot:
        from ..timedomain.static_plot import plot_static_state

        plot_static_state(st, args.plot, title=model.source)
        if not args.json:
            print(f"wrote {args.plot}")
    return 0


def _buckling(model):
    """The casing's buckling load as built (``body_buckling``: at its reference modulus, as the
    refusal of a tension takes it), when it carries the cable's tension as compression (both
    bodies); else none."""
    if not set(BODY_NAMES) <= set(model.bodies):
        return []
    from ..timedomain.body_storage import body_buckling

    return [body_buckling(model, "casing")]


def _print(model, st, systems, buckled=()):
    from ..structure.mount_element import clip_positions

    g, T = model.loads["gravity"], model.loads["cable_tension"]
    cable = "cable" in model.bodies  # (a model without one: no tension, rest shape or contact to show)
    what = f", cable tension {T:g} N, cable rest shape {model.bodies['cable'].rest_shape}" if cable else " (no cable)"
    print(f"static state of {model.source}: gravity {g} m/s2{what}")
    touching = f"{st.contact_nodes} cable nodes in contact, max penetration {st.max_penetration:.4g} m; " * cable
    print(f"  {touching}Newton {st.iterations} iterations in {st.load_steps} load steps, |R| = {st.residual:.2g} N")
    if T > 0.0 and st.pulled:
        print(
            f"  cable pre-stretch force {st.prestretch_force:.4g} N (its axial force at rest in the routing "
            "before it is pulled against the walls)"
        )
    elif T > 0.0:
        print(f"  contact off: {_unheld(st, systems, T)}")
    nodes = np.flatnonzero(st.normal_force > 0.0) if cable else []
    if cable and not len(nodes):
        print("  contact force of the casing on each cable node: none (no cable node in contact)")
    elif cable:
        print("  contact force of the casing on each cable node (N, global axes):")
        print("    node    s (m)   kappa (1/m)        Fx          Fy          Fz         |F|   penetration (m)")
    for i in nodes:
        F = st.contact_force[i]
        print(
            f"    {i:4d} {st.arc_length[i]:8.4f} {st.curvature[i]:10.4f}  {F[0]:10.4f}  {F[1]:10.4f}  {F[2]:10.4f}  "
            f"{np.linalg.norm(F):10.4f}   {st.penetration[i]:.4g}"
        )
    print(
        "  reactions: force and moment each body exerts on its supports, isolators and clips (N, N.m, global; the "
        "time-domain outputs' sign):"
    )
    print("    support                 Fx          Fy          Fz          Mx          My          Mz")
    for body in st.U:
        for s in SUPPORT_NAMES:
            kind = model.bodies[body].supports[s]
            if kind != "free":
                r = st.reaction(f"{body}.{s}")
                print(f"    {f'{body}.{s} {kind}':22s}" + " ".join(f"{v:11.5g}" for v in r))
    for i, (r, at) in enumerate(zip(st.clip_reactions, clip_positions(model))):  # (where each acts: its node)
        print(f"    {f'casing.clip{i} s={at:.4g}':22s}" + " ".join(f"{v:11.5g}" for v in r))
    moved = [f"{body} {d:.4g} m at s = {at:.4g} m" for body, (d, at) in st.largest_displacement.items()]
    print(f"  largest displacement from the routing: {', '.join(moved)}")
    print("  force balance of each body (N, global): weight + prestress + contact = reactions")
    for body, b in st.balance.items():
        terms = " + ".join(f"{_vec(b[k])}" for k in ("weight", "prestress", "contact"))
        print(f"    {body}: {terms} = {_vec(b['reactions'])} (residual {np.abs(b['residual']).max():.2g} N)")
    if any(g):
        W = sum(st.weight.values())
        print(f"  weight of the bodies (N): {np.round(W, 6).tolist()}")
    for b in buckled:
        print(f"  buckling: {b.text()}")


def _unheld(st, systems, T):
    """What a tension does without contact, with the end elements' axial forces it leaves (of the
    bodies as solved, ``systems``)."""
    from ..timedomain.static_state import end_axial_forces

    ends = []
    for body in st.U:
        N = end_axial_forces(systems[body], st.U[body])
        ends.append(f"{body} {N[0]:.4g} and {N[1]:.4g} N")
    return (
        f"the tension {T:g} N is applied as a fixed prestress (nothing pulls the cable against the walls), which "
        f"relaxes where the route bends: the end elements carry {', '.join(ends)} (tension positive) against "
        f"+{T:g} N (cable) and -{T:g} N (casing), which the geometric stiffness K_G and the buckling check assume, "
        "and the support reactions carry what the ends carry"
    )


def _vec(v):
    return "[" + ", ".join(f"{x:.5g}" for x in np.where(np.abs(v) < 1e-12, 0.0, v) + 0.0) + "]"


def add_parser(sub):
    p = sub.add_parser(
        "static",
        help="the static state: contact forces and support reactions under gravity, tension and rest shape",
    )
    add_model_argument(p, settable=True)
    p.add_argument(
        "--json",
        action="store_true",
        help="print JSON: contact_force_N (per cable node [Fx, Fy, Fz], the casing's force on the cable), "
        "support_reactions_N ({body.support or casing.clip<i>: [Fx, Fy, Fz, Mx, My, Mz]}, the force (N) and moment "
        "(N.m) the body exerts on it), balance_N ({body: weight, prestress, contact, reactions, residual}), "
        "contact_nodes, max_penetration_m, largest_displacement_m ({body: [largest translation from the routing, m; "
        "the arc length of its node, m]}), buckling ({casing: load_N, at_m, supports, mechanism})",
    )
    p.add_argument(
        "--plot", help="figure (.png, .pdf or .svg): contact force along the arc length beside the curvature"
    )
    p.add_argument("--no-contact", action="store_true", help="the bodies under their loads without contact")
    p.set_defaults(func=cmd_static)
