"""The static state of an installed model: both bodies at rest under their constant loads (gravity,
the cable's tension and the casing's compression, a cable that is stress-free straight;
structure/loads.py), held apart by frictionless contact across the radial gap. The vibration of
the time domain starts from it (docs/installed.md).

Equilibrium of the free DOFs of both bodies, z = (u_cable, u_casing):

    R(z) = K z - f - f_c(z) = 0,

K the tangent stiffness K_E + K_G of each body (block diagonal), f the constant loads, f_c the
generalized contact forces of the time domain's own contact search and law (Eqs. 14, 24/29,
30-39; ``kernels.static_contact``): at each cable node in contact with penetration g and unit
normal n (from the casing axis towards the node), the normal force N(g) pushes the cable back, -N n,
and the casing out, H^T N n. Without friction and damping this is the contact of a body at rest.

The solver is a semi-smooth Newton method with a backtracking (Armijo) line search on the potential
energy that also accepts a step halving |R| (:func:`_newton`), on the whole
system, with every node's contact searched anew at every iterate (contacts open and close as they
go). Its tangent is K plus, per contact, dN/dg b b^T (b = D^T n, D the map of the DOFs to the
relative displacement of the cable node and the casing axis point) and the rotation of the normal,
N/h D^T (I - n n^T) D (h the distance of the node from the axis). The Hertz law's g^1.5 is smooth
enough away from g = 0, where its slope vanishes and the line search keeps a step from jumping
across. The loads are applied in steps of a load factor (continuation): a step that does not
converge is halved. The result is an equilibrium of the time domain's own discrete equations, so a
run that starts from it at rest stays there (to the solver's tolerance).

The contact search keeps each node's casing element from one evaluation to the next (its guess):
a trial point of the line search that is rejected, and a load step that fails, leave it as it was
at the iterate they started from. The residual converges to the larger of a fraction of the loads
and the rounding floor of K z and of the contact forces (a stiff contact's force is its slope times
the rounding of the positions whose difference is its distance; see ``_Problem.tolerance``).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from scipy.linalg import solve_banded

from ..errors import ModelPropertyWarning, ModelWarning, SimulationError, warn_once_per_process
from ..model.schema import BODY_NAMES, CONTACT_LAWS, FORCE_NAMES, SUPPORT_NAMES, SUPPORT_OUTPUTS
from ..model.validators import Choice, check_model, contact_in_force
from ..structure.loads import gravity_load
from . import kernels as K

if TYPE_CHECKING:
    from ..model import Model

#: Newton's tolerance: |R|_inf below this fraction of the largest load or contact force (N)
TOLERANCE = 1e-10
#: the contact forces' rounding floor in units of eps |X| max dN/dg (``_Evaluator.rounding``): a few
#: roundings of positions of size |X| in x - P; the stalls it ends sat at 0.02-0.2 of one unit, and
#: the installed specimen's tolerance (1e-10 of its forces, 14 units) stays what decides there
CONTACT_ROUNDING_ULPS = 4.0
MAX_ITERATIONS = 60  # Newton iterations per load step
MIN_LOAD_STEP = 1e-4  # the smallest load-factor step before the solve gives up


@dataclass
class StaticState:
    """The static state of a model (SI units, global axes).

    U: {body: displacement over all its DOFs (m, rad)}; contact_force (nodes x 3, N): the force of
    the casing on each cable node; normal_force (N), penetration (m), element and xi (the casing
    element and its coordinate where each node's normal plane cuts the axis) per cable node;
    generalized_contact: {body: the contact's generalized forces on its DOFs (N, N.m)};
    reactions (24, N and N.m): the force and moment each body exerts on each support, in the order
    of ``SUPPORT_OUTPUTS`` (the time domain's sign convention); arc_length (m) and curvature (1/m)
    of the cable nodes; loads: {body: the constant load at rest over all its DOFs, N and N.m, with
    the cable's tension as its pre-stretch force: what the time domain applies throughout};
    prestretch_force (N): the cable's axial force at rest in the routing before it moves (the
    installation's shortening of the cable is prestretch_force L / EA) when the contact pulls it
    taut against the bends (``pulled``), else the tension as a fixed prestress; iterations (Newton, all load
    steps), residual (N, |R|_inf at the end), load_steps; weight: {body: its weight, N, global};
    clip_reactions (clips x 6, N and N.m): the force and moment the casing exerts through each clip
    on its support (as the time domain's ``casing.clip<i>.Fx .. Mz``); balance: {body: {"weight",
    "prestress", "contact", "reactions", "residual"}}: the resultant forces (N, global) of the body's
    weight, of the rest of its constant load (the tension's or the compression's in the routing, a
    straight cable's rest shape), of the contact on it, the sum of its reactions (supports,
    isolators, clips), and weight + prestress + contact - reactions (zero to the solver's tolerance);
    largest_displacement: {body: (m, m)}, its largest translation from the routing and the arc
    length of the node that moves most (:func:`largest_displacement`).
    """

    U: dict
    contact_force: np.ndarray
    normal_force: np.ndarray
    penetration: np.ndarray
    element: np.ndarray
    xi: np.ndarray
    generalized_contact: dict
    reactions: np.ndarray
    arc_length: np.ndarray
    curvature: np.ndarray
    loads: dict = field(default_factory=dict)
    prestretch_force: float = 0.0
    pulled: bool = False
    iterations: int = 0
    residual: float = 0.0
    load_steps: int = 0
    weight: dict = field(default_factory=dict)
    clip_reactions: np.ndarray = field(default_factory=lambda: np.zeros((0, 6)))
    balance: dict = field(default_factory=dict)
    largest_displacement: dict = field(default_factory=dict)

    @property
    def contact_nodes(self) -> int:
        """Number of cable nodes in contact."""
        return int(np.count_nonzero(self.normal_force))

    @property
    def max_penetration(self) -> float:
        """Largest penetration (m), 0 without contact."""
        return float(self.penetration.max()) if len(self.penetration) else 0.0

    @property
    def support_names(self) -> tuple[str, ...]:
        """The names :meth:`reaction` takes: ``<body>.A``, ``<body>.B`` of each body of the model,
        then ``casing.clip0`` .. ``casing.clip<N-1>`` of its clips."""
        supports = tuple(n.rsplit(".", 1)[0] for n in SUPPORT_OUTPUTS[::6] if n.split(".")[0] in self.U)
        return supports + tuple(f"casing.clip{i}" for i in range(len(self.clip_reactions)))

    def reaction(self, support: str) -> np.ndarray:
        """[Fx, Fy, Fz, Mx, My, Mz] (N, N.m) the body exerts on ``support`` (a copy): a support
        ``"casing.A"`` (clamped or an isolator; zeros when free) or a clip ``"casing.clip0"``
        (:attr:`support_names`; any other name raises
        :class:`~cablecasing_core.errors.ModelError` naming ``support``, the value and those)."""
        Choice(*self.support_names)("support", support)
        name = support.split(".", 1)[1]
        if name.startswith("clip"):
            return self.clip_reactions[int(name[4:])].copy()
        i = SUPPORT_OUTPUTS.index(f"{support}.Fx")
        return self.reactions[i : i + 6].copy()

    def as_dict(self) -> dict:
        """The JSON form of ``cablecasing static --json``: ``contact_force_N`` (per cable node,
        [Fx, Fy, Fz] of the casing on the cable, global), ``support_reactions_N`` (per support
        ``<body>.<A|B>`` and clip ``casing.clip<i>``: [Fx, Fy, Fz, Mx, My, Mz] the body exerts on
        it, N and N.m: the sign of the time-domain outputs), ``balance_N`` (per body: the resultant
        forces ``weight``, ``prestress``, ``contact``, ``reactions`` and ``residual``, N, global),
        ``contact_nodes``, ``max_penetration_m`` and ``largest_displacement_m`` (per body:
        [its largest translation from the routing, the arc length of that node], m)."""
        supports = sorted(s for s in self.support_names if ".clip" not in s)
        supports += [s for s in self.support_names if ".clip" in s]
        return {
            "contact_force_N": self.contact_force.tolist(),
            "support_reactions_N": {s: self.reaction(s).tolist() for s in supports},
            "balance_N": {b: {k: np.asarray(v).tolist() for k, v in d.items()} for b, d in self.balance.items()},
            "contact_nodes": self.contact_nodes,
            "max_penetration_m": self.max_penetration,
            "largest_displacement_m": {b: list(v) for b, v in self.largest_displacement.items()},
        }


def static_state(model: Model, contact: bool | None = None) -> StaticState:
    """The static state of ``model`` (see the module docstring): both bodies at rest under their
    constant loads, with frictionless contact when ``contact`` (None: ``contact.enabled``, True or
    False, as :func:`~cablecasing_core.simulate`'s; needs both bodies): R(z) = K z - f - f_c(z) = 0
    with the contact of Eqs. (30-39). The bodies as the time domain assembles them (a
    frequency-dependent modulus at the first natural frequency). Raises
    :class:`~cablecasing_core.errors.SimulationError` when the Newton method does not converge, and
    ModelError for a model that cannot be installed (a tension above the casing's buckling load),
    for a ``model`` that is no :class:`~cablecasing_core.Model` and for a ``contact`` that is not
    None, True or False. Its warnings (ModelWarning: a large displacement, a prestress not kept)
    point at the caller's line."""
    from .body_storage import time_domain_system

    check_model(model)
    contact = contact_in_force(model, contact)
    systems = {n: time_domain_system(model, n) for n in model.bodies}
    return solve_static(model, systems, contact, warn_at=2)


def _law(model):
    from .engine import hertz_constant

    c = model.contact
    return CONTACT_LAWS.index(c["law"]), c["stiffness"], hertz_constant(model)


def solve_static(model: Model, systems: dict, contact: bool, warn_at: int = 1) -> StaticState:
    """The static state for the assembled ``systems`` ({body: BodySystem}) of ``model``; the engine
    passes its own (:class:`~cablecasing_core.timedomain.engine.Engine`). Its warnings point at the
    line ``warn_at`` frames above this function's caller (1: the caller's caller's call)."""
    names = [n for n in BODY_NAMES if n in systems]
    offs = _unknowns(systems, names)
    o = sum(len(v) for v in offs.values())
    Kz = np.zeros((o, o))
    loads = {n: np.asarray(systems[n].f, dtype=float).copy() for n in names}
    T = model.loads["cable_tension"] if "cable" in systems else 0.0
    p = np.zeros(o)  # the cable's load per newton of pre-stretch force, on the unknowns
    a = 0.0  # EA / L of the cable: its mean axial force per unit of mean shortening
    # The tension pulls the cable taut against the inside of every bend, where the contact holds it
    # (Problem). Without contact nothing holds it there, and solving for sigma would straighten the
    # cable through the wall (sigma ~ 8e4 N on the installed specimen): the tension is then a fixed
    # prestress, sigma = T, carried by the curved cable's hoop stiffness (it moves by ~ T R / EA).
    pulled = T > 0.0 and contact
    if pulled:
        cab = systems["cable"]
        loads["cable"] -= T * cab.f_axial  # the tension's share is the pre-stretch force's, solved for
        p[offs["cable"]] = cab.f_axial[cab.free]
        a = cab.E * cab.section.A / cab.centerline.lengths.sum()
    fz = np.zeros(o)
    for n in names:
        s, i = systems[n], offs[n]
        Kz[np.ix_(i, i)] = s.K_blocks[0]  # (the free DOFs' tangent stiffness, the mounts' springs with it)
        fz[i] = loads[n][s.free]
    U = {n: np.zeros(systems[n].ndof) for n in names}
    ev = _Evaluator(model, systems, U, offs) if contact else _NoContact(o)
    problem = _Problem(Kz, fz, p, a, T if pulled else 0.0, ev, _slope_floor(model, fz, T) if contact else 0.0)
    if not np.any(fz) and not pulled:
        # nothing loads the bodies: they rest in the routing, with nothing to solve for (a body held
        # against no rigid motion, free at both ends, would make the tangent singular; unloaded it is
        # a valid model, which the time domain runs)
        z, sigma, iterations, steps, residual = np.zeros(o), T, 0, 0, 0.0
    else:
        try:
            z, sigma, iterations, steps, residual = _continuation(
                problem, model.data["cable"]["d"] / 2 if contact else 0.0
            )
        except np.linalg.LinAlgError:
            check_stiffness_representable(systems)  # (a body's stiffness underflowed: named; else a bug)
            raise
    _scatter(z, U, systems, offs)
    ev.evaluate(z)
    touching = contact and bool(np.any(ev.N > 0.0))
    check_kept_prestress(
        systems,
        U,
        exclude=("cable",) if pulled else (),
        gravity=model.loads["gravity"],
        contact=touching,
        held=contact,
        stacklevel=2 + warn_at,
    )
    moved = {n: largest_displacement(systems[n], U[n]) for n in names}
    check_small_displacements(systems, moved, stacklevel=2 + warn_at)
    if pulled:
        loads["cable"] += sigma * systems["cable"].f_axial
    else:
        sigma = T
    nn = systems[names[0]].n_nodes
    fc = {n: (ev.fc[n].copy() if contact else np.zeros(systems[n].ndof)) for n in names}
    reac = np.zeros(len(SUPPORT_OUTPUTS))
    clips = np.zeros((0, 6))
    balance = {}
    for n in names:
        s = systems[n]
        r = loads[n] + fc[n] - s.K @ U[n]  # the force the body exerts on its supports
        total = np.zeros(3)
        for sup in SUPPORT_NAMES:
            i = SUPPORT_OUTPUTS.index(f"{n}.{sup}.{FORCE_NAMES[0]}")
            if s.spec.supports[sup] == "clamped":
                reac[i : i + 6] = r[s.support_dofs(sup)]
            elif s.spec.supports[sup] == "isolator":  # the force through the isolator, K6 u_node
                mt = s.mounts[s.mount_of_support(sup)]
                reac[i : i + 6] = mt.K6 @ U[n][6 * mt.node : 6 * mt.node + 6]
            total += reac[i : i + 3]
        if n == "casing":  # the force through each clip, K6 u_node (its support at rest)
            clips = np.array([m.K6 @ U[n][6 * m.node : 6 * m.node + 6] for m in s.mounts if m.support is None])
            clips = clips.reshape(-1, 6)
            total += clips[:, :3].sum(axis=0)
        weight = _resultant(gravity_load(s.M, model.loads["gravity"]))
        contact_n = _resultant(fc[n])
        balance[n] = {
            "weight": weight,
            "prestress": _resultant(loads[n]) - weight,
            "contact": contact_n,
            "reactions": total,
            "residual": _resultant(loads[n]) + contact_n - total,
        }
    zeros = np.zeros(nn)
    return StaticState(
        U=U,
        contact_force=ev.P.copy() if contact else np.zeros((nn, 3)),
        normal_force=ev.N.copy() if contact else zeros.copy(),
        penetration=ev.g.copy() if contact else zeros.copy(),
        element=ev.elem.copy() if contact else np.zeros(nn, np.int64),
        xi=ev.xi.copy() if contact else zeros.copy(),
        generalized_contact=fc,
        reactions=reac,
        arc_length=systems[names[0]].centerline.s.copy(),
        curvature=systems[names[0]].centerline.curvature.copy(),
        loads=loads,
        prestretch_force=sigma if T > 0.0 else 0.0,
        pulled=pulled,
        iterations=iterations,
        residual=residual,
        load_steps=steps,
        weight={n: _weight(systems[n], model) for n in names},
        clip_reactions=clips,
        balance=balance,
        largest_displacement=moved,
    )


def check_stiffness_representable(systems):
    """Refuse (ModelError naming ``<body>.E``, or ``<body>.I`` when the model sets a second moment
    below 1e-3 of its tube's, the bound below which the loader warns) a body whose tangent stiffness
    on its free DOFs is not positive definite: a modulus or second moment so small that K_E underflows
    in double precision (cable.E = 5e-324 Pa, inside the schema's bounds, under gravity made the static
    state's solve an internal LinAlgError). The buckling check names a tension's share
    (``loads.cable_tension``) before the static state is solved; this is the stiffness alone."""
    from ..errors import ModelError
    from ..structure.buckling import _stiffness, is_positive_definite

    for name, s in systems.items():
        if is_positive_definite(s):
            continue
        spec = s.spec
        small_I = spec.I_override is not None and spec.I_override < 1e-3 * s.section.Ip / 2.0
        key, value = (f"{name}.I", spec.I_override) if small_I else (f"{name}.E", spec.E_ref)
        raise ModelError(
            key,
            value,
            f"makes the {name}'s stiffness matrix singular in double precision ({_stiffness(s)}: its bending "
            f"stiffness underflows), so its static state under the model's loads has no solution; give {name}.E "
            f"the {name}'s modulus (Pa)" + (f" and {name}.I its section's second moment (m4)" if small_I else ""),
        )


class KeptPrestressWarning(ModelPropertyWarning):
    """A body's static state carries another axial force than the prestress its geometric stiffness
    assumes (:func:`check_kept_prestress`). A property of the model, not of a run: said once per
    process and model (:func:`~cablecasing_core.errors.warn_once_per_process`), not again in every
    run of a command or every seed of an ensemble; a :class:`ModelWarning`, filterable on its own."""


#: The least difference, as a fraction of |N0|, between the axial force a body's end elements
#: carry in the static state and the prestress N0 its K_G and buckling check take as given, that
#: is warned of (with :data:`KEPT_PRESTRESS_OF_BUCKLING`).
KEPT_PRESTRESS = 0.05

#: The least difference, as a fraction of the body's buckling load P_cr as built, that is warned
#: of (with :data:`KEPT_PRESTRESS`): what the given N0 is used for is K_G and the buckling check,
#: and K_G's error against the body's bending stiffness in its lowest mode is about |N - N0| / P_cr.
KEPT_PRESTRESS_OF_BUCKLING = 0.02


#: The largest translation of a body in its static state, as a fraction of its length, that is not
#: warned of: the statics are linear (small displacements and rotations), and 2 % of the length
#: (17 mm of the 0.85 m specimens, whose installed cable moves by 7.6 mm) keeps the rotations of a
#: bent beam near 0.06 rad, whose geometric nonlinearity (~ theta^2 / 2) is below 0.2 %.
SMALL_DISPLACEMENT = 0.02


def largest_displacement(system, U):
    """(m, m): the largest translation of the body's nodes in ``U`` (its DOFs, m) and the arc length
    of the node that moves most."""
    d = np.linalg.norm(U.reshape(-1, 6)[:, :3], axis=1)
    i = int(np.argmax(d))
    return float(d[i]), float(system.centerline.s[i])


def check_small_displacements(systems, moved, stacklevel=3):
    """Warn (ModelWarning) when a body moves, in the static state (``moved``: {body: its
    :func:`largest_displacement`, (m, m)}), by more than :data:`SMALL_DISPLACEMENT` of its length:
    a linear model (Eqs. 1-9, small displacements and rotations) then answers for a shape far from
    its own (a cantilever casing under its weight, isolators so soft that the body sags on them)."""
    for name, s in systems.items():
        d, at = moved[name]
        length = s.centerline.length
        if d > SMALL_DISPLACEMENT * length:
            warnings.warn(
                f"{name}: the static state moves it by up to {d:.4g} m (at s = {at:.4g} m), {100 * d / length:.3g} % "
                f"of its length {length:.4g} m: the model is linear (small displacements and rotations), "
                "so its answer for so large a motion is a linear extrapolation; stiffer supports, isolators or clips "
                "hold it nearer to its routing",
                ModelWarning,
                stacklevel=stacklevel,
            )


def end_axial_forces(system, U):
    """The axial force (N, tension positive) in the first and the last element of an assembled
    body (``system``, with its given prestress N0) at the displacements U (all its DOFs, m):
    N0 + EA / L_e t_e . (u2 - u1), t_e the element's chord."""
    cl = system.centerline
    EA = system.E * system.section.A
    u = U.reshape(-1, 6)[:, :3]
    out = []
    for e in (0, cl.n_elements - 1):
        out.append(system.N0 + EA / cl.lengths[e] * (cl.frames[e, 0] @ (u[e + 1] - u[e])))
    return np.array(out)


def _frequency_effect(ratio, N0, P_cr):
    """The relative shift of the lowest bending frequency that a K_G off by ``ratio`` P_cr gives a
    body under the axial force ``N0`` (N, compression negative): f = f0 sqrt(1 + N0 / P_cr) (a
    compression lowers it, a tension raises it), so f^2 moves by ``ratio`` of f0^2 and f by about
    ratio / (2 (1 + N0 / P_cr))."""
    return 0.5 * ratio / max(1.0 + N0 / P_cr, 1e-3) if P_cr > 0.0 else float("inf")


def check_kept_prestress(systems, U, exclude=(), gravity=(0.0, 0.0, 0.0), contact=False, held=True, stacklevel=3):
    """Warn (KeptPrestressWarning, a ModelWarning; once per process and model:
    :func:`warn_once_per_process`) when a body with a given prestress N0 (the casing's compression -T, the
    cable's tension +T when it is a fixed prestress) carries, in the static state U ({body:
    displacements}), an axial force N in an end element that differs from N0 by more than
    KEPT_PRESTRESS |N0| and by more than KEPT_PRESTRESS_OF_BUCKLING P_cr (its buckling load as
    built, structure/buckling.py; computed only when the first test fails). Its geometric
    stiffness K_G and the buckling check assume N0. With contact off (``held`` False) every body is
    checked, clamped or not; with contact on, a body whose ends keep N0 along its axis (clamped,
    or isolators whose share k_s / (k_s + EA/L) departs from 1 by no more than a tenth of
    KEPT_PRESTRESS) is not, the same for both (a documented choice: see docs/installed.md). The
    message names the causes the model has that its figures show, without weighing them: the
    isolators' axial compliance (a straight body between isolators of axial stiffness k keeps about
    k / (k + 2 EA / L) of N0; named only when that share departs from 1 by more than a tenth of
    KEPT_PRESTRESS), the body's curvature when nothing holds it in its bends (``held`` False:
    contact off, where a fixed prestress relaxes in the bends), the body's weight along its axis
    (``gravity``, m/s2), its clips and the contact load (``contact``: the cable touches it).
    ``exclude``: bodies whose axial force the static state
    solves for (the cable's pre-stretch force under a tension, with contact)."""
    from ..structure.buckling import buckling_load

    for name, s in systems.items():
        if name in exclude or s.N0 == 0.0:
            continue
        if held and 1.0 - _kept_share(s)[0] <= 0.1 * KEPT_PRESTRESS:
            # Ends that keep N0 (clamped, or isolators as stiff: 1e12 N/m keep 1 - 2e-6 of it) with
            # contact on are not checked, whichever they are (the same state gives the same answer):
            # a choice, not physics. The installed specimen's clamped casing, with its weight and the
            # contact of its straight cable, carries -15.2 and -14.1 N at T = 10 N (0.095 P_cr):
            # checking it would warn at every run of the default model.
            continue
        N = end_axial_forces(s, U[name])
        dN = float(np.abs(N - s.N0).max())
        # Two tests, both needed. 5 % of |N0|: the given prestress is then visibly not the one the
        # static state carries. 2 % of P_cr: what N0 is used for is K_G (and the buckling check),
        # and K_G's error against the bending stiffness in the lowest mode is about |dN| / P_cr: the
        # lowest bending frequency goes as f = f0 sqrt(1 + N0 / P_cr) (N0 < 0 a compression), so f^2
        # moves by |dN| / P_cr of f0^2 and f by about half of it divided by (1 + N0 / P_cr); below
        # 2 % that is ~1 % (at most 1.7 %: the second test decides only while 0.05 P < 0.02 P_cr,
        # P < 0.4 P_cr). A small tension on a compliant or clipped casing is not warned of.
        if dN <= KEPT_PRESTRESS * abs(s.N0):
            continue
        P_cr = buckling_load(s)  # (an eigenproblem, ~0.1 s: only when the first test fails)
        ratio = dN / P_cr if P_cr > 0.0 else float("inf")
        if ratio <= KEPT_PRESTRESS_OF_BUCKLING:
            continue
        word = "compression" if s.N0 < 0.0 else "tension"
        # (one line of three sentences: what it found, what it moves, why; docs/installed.md says the rest)
        warn_once_per_process(
            f"{name}: the static state leaves an axial force of {N[0]:.4g} N at end A and {N[1]:.4g} N at end B "
            f"(tension positive), not the given {word} N0 = {s.N0:.4g} N of loads.cable_tension that its K_G and "
            f"the buckling check assume: |N - N0| = {dN:.4g} N is {ratio:.3g} of its buckling load as built P_cr = "
            f"{P_cr:.4g} N, so its lowest bending frequency may be off by about "
            f"{_frequency_effect(ratio, s.N0, P_cr):.2g} (relative). {_prestress_causes(s, gravity, contact, held)}. "
            "The model keeps N0 as given: read the results with this limit (docs/installed.md)",
            KeptPrestressWarning,
            stacklevel=stacklevel,
        )


def _kept_share(system):
    """(k_s / (k_s + EA/L), k_s, EA/L): the share of N0 a straight ``system`` keeps between its end
    isolators (k_s their axial stiffnesses in series, N/m; inf and a share of 1 when both ends are
    clamped, 0 when an end gives no axial stiffness) and EA/L (N/m)."""
    from ..structure.support_check import axial_stiffness

    kA = [axial_stiffness(system.mounts, s) for s in "AB"]  # (a clamped end: inf, 1/k = 0)
    EA_L = system.E * system.section.A / system.centerline.length
    compliance = sum(1.0 / x for x in kA) if all(x > 0.0 for x in kA) else float("inf")
    k = 1.0 / compliance if compliance > 0.0 else float("inf")
    return (k / (k + EA_L) if np.isfinite(k) else 1.0), k, EA_L


def _prestress_causes(system, gravity, contact, held=True):
    """The causes the model has of an axial force other than N0 along ``system`` that its figures
    show, in words, not weighed against each other (see :func:`check_kept_prestress`)."""
    kept, k, EA_L = _kept_share(system)
    causes = []
    if 1.0 - kept > 0.1 * KEPT_PRESTRESS:  # (1e12 N/m isolators keep all of N0: not a cause)
        causes.append(
            f"its isolators give way along its axis (between them a straight {system.name} keeps about "
            f"k_s/(k_s + EA/L) = {kept:.3g} of N0, k_s = {k:.3g} N/m in series, EA/L = {EA_L:.3g} N/m)"
        )
    kappa = float(np.max(system.centerline.curvature, initial=0.0))
    if not held and kappa > 0.0:
        causes.append(
            f"it is curved (radius down to {1.0 / kappa:.3g} m) and with contact off nothing holds it in its bends, "
            "where a fixed prestress relaxes (with contact the tension pulls the cable against the walls)"
        )
    g = np.asarray(gravity, dtype=float)
    if np.abs(system.centerline.frames[:, 0] @ g).max() > 1e-9 * np.linalg.norm(g):  # (a share along its axis)
        causes.append(f"the {system.name}'s weight along its axis")
    clips = sum(m.support is None for m in system.mounts)
    if clips:
        causes.append(f"its {clips} clip{'s' if clips > 1 else ''}")
    if contact:
        causes.append("the cable's contact load on it")
    if not causes:
        return "Causes: none of those the model knows (isolators, bends without contact, weight, clips, contact)"
    head = "Causes (not weighed against each other): " if len(causes) > 1 else "Cause: "
    return head + "; ".join(causes)


def _resultant(f):
    """The resultant force (N, 3) of a load over all of a body's DOFs (its translations)."""
    return np.asarray(f, dtype=float).reshape(-1, 6)[:, :3].sum(axis=0)


def _slope_floor(model, f, T):
    """The least contact slope (N/m) of Newton's tangent: the whole law's slope at a tenth of the
    largest nodal load or tension (the forces the contacts will carry are of that order); a node
    carrying the share s of the law (``contact.law_length``) takes it times s (linear) or s^(2/3)
    (Hertz, at the same force: :meth:`_Evaluator.tangent`)."""
    law, k_lin, k_hertz = _law(model)
    F = 0.1 * max(np.abs(f).max(initial=0.0), T, 1e-6)
    return k_lin if law == 1 else 1.5 * k_hertz ** (2.0 / 3.0) * F ** (1.0 / 3.0)


def _weight(system, model):
    """The body's weight (N, global vector): its mass (the consistent mass of a rigid translation,
    kg) times gravity."""
    ex = np.zeros(system.ndof)
    ex[0::6] = 1.0
    return float(ex @ (system.M @ ex)) * np.asarray(model.loads["gravity"], dtype=float)


def _unknowns(systems, names):
    """{body: the positions of its free DOFs among the unknowns}: the bodies' DOFs interleaved node
    by node (cable and casing of node j next to each other), so that the static tangent, whose
    contacts couple a cable node with the casing element beside it, is banded."""
    keys = [(int(d) // 6, b, int(d) % 6) for b, n in enumerate(names) for d in systems[n].free]
    order = np.argsort([k[0] * 64 + k[1] * 8 + k[2] for k in keys], kind="stable")
    pos = np.empty(len(keys), np.int64)
    pos[order] = np.arange(len(keys))
    out, o = {}, 0
    for n in names:
        m = len(systems[n].free)
        out[n] = pos[o : o + m]
        o += m
    return out


def _scatter(z, U, systems, offs):
    for n, i in offs.items():
        U[n][:] = 0.0
        U[n][systems[n].free] = z[i]


class _NoContact:
    """The contact of :class:`_Evaluator` when there is none (contact off, or one body)."""

    def __init__(self, n):
        self.zero = np.zeros(n)

    def evaluate(self, z):
        return self.zero

    def potential(self):
        return 0.0

    def rounding(self):
        return 0.0

    def search_state(self):
        return None

    def restore(self, state):
        pass

    def tangent(self, J, k_min=0.0, fresh=None):
        return 0

    @property
    def closed(self):
        return None


class _Evaluator:
    """The contact of the cable nodes at a state z: forces, and the tangent's contact part."""

    def __init__(self, model, systems, U, offs):
        cab, cas = systems["cable"], systems["casing"]
        self.systems, self.U, self.offs = systems, U, offs
        self.Xc, self.Tc = cab.centerline.nodes, cab.centerline.tangents
        self.Xs, self.Rs, self.Ls = cas.centerline.nodes, cas.centerline.frames, cas.centerline.lengths
        self.gap = model.radial_gap
        self.law, self.k_lin, self.k_hertz = _law(model)
        from .engine import contact_shares

        self.share = contact_shares(model, cab.centerline.lengths)
        nn = len(self.Xc)
        self.elem = np.clip(np.arange(nn) - 1, 0, len(self.Ls) - 1).astype(np.int64)
        self.extent = max(np.abs(self.Xc).max(initial=0.0), np.abs(self.Xs).max(initial=0.0))  # m
        self.g, self.h, self.N, self.kn, self.xi = (np.zeros(nn) for _ in range(5))
        self.nrm = np.zeros((nn, 3))
        self.H = np.zeros((nn, 6, 12))
        self.fc = {"cable": np.zeros(cab.ndof), "casing": np.zeros(cas.ndof)}
        # unknown index of every DOF of each body (-1 for a prescribed one)
        self.index = {}
        for n in ("cable", "casing"):
            idx = -np.ones(systems[n].ndof, np.int64)
            idx[systems[n].free] = offs[n]
            self.index[n] = idx

    @property
    def closed(self):
        """The nodes in contact at the last evaluated state (bool per node)."""
        return self.N > 0.0

    @property
    def P(self):
        """Force of the casing on each cable node (N, global): -N n."""
        return -self.N[:, None] * self.nrm

    def evaluate(self, z):
        """Contact forces at the state z; returns the generalized contact force on the unknowns."""
        _scatter(z, self.U, self.systems, self.offs)
        K.static_contact(
            self.Xc, self.Tc, self.U["cable"], self.Xs, self.Rs, self.Ls, self.U["casing"], self.elem,
            self.gap, self.law, self.k_lin, self.k_hertz, self.share, self.g, self.h, self.N, self.kn, self.nrm,
            self.xi, self.H, self.fc["cable"], self.fc["casing"],
        )  # fmt: skip
        out = np.zeros(len(z))
        for n in ("cable", "casing"):
            idx = self.index[n]
            free = idx >= 0
            out[idx[free]] = self.fc[n][free]
        return out

    def potential(self):
        """Elastic energy in the contacts (J) at the last evaluated state (the time domain's)."""
        return K.contact_potential(self.g, self.law, self.k_lin, self.k_hertz, self.share)

    def rounding(self):
        """The rounding of the contact forces (N) at the last evaluated state: the largest slope
        dN/dg times CONTACT_ROUNDING_ULPS eps |X| (|X| = ``extent``). A distance h = |x - P| is the
        difference of positions of size ``extent`` (x = X + u, P a sum of Hermite terms of that
        size), each rounded to eps/2 of it: h, and so N, cannot be resolved more finely (the
        linear law at 1e7 N/m on a 0.83 m route: eps |X| k = 1.8e-9 N, against forces of 0.2 N)."""
        return CONTACT_ROUNDING_ULPS * np.finfo(float).eps * self.extent * self.kn.max(initial=0.0)

    def search_state(self):
        """A copy of the search's guess (each node's casing element), for :meth:`restore`."""
        return self.elem.copy()

    def restore(self, state):
        """Put back the guess of :meth:`search_state`: a rejected trial point must not leave the
        search starting from an element it found there (a trial step can carry a node past the end
        of the casing, or across several elements, where the search from the iterate's own element
        would not go)."""
        self.elem[:] = state

    def tangent(self, J, k_min=0.0, fresh=None):
        """Subtract the contact forces' derivative (N/m) at the last evaluated state from J (over
        the unknowns): J = K - d f_c / dz, the exact first-order derivative of the time domain's
        contact forces (see :meth:`_node_derivative`). The slope dN/dg of a ``fresh`` contact (a
        bool per node: closed since the last iterate) is taken at least ``k_min`` (N/m, the whole
        law's; times the node's share s, or s^(2/3) for Hertz's law, whose slope at a force F is
        1.5 (s k_H)^(2/3) F^(1/3)): the Hertz
        law's slope vanishes as a contact begins, where Newton would take it for no stiffness at
        all (and push the node deep into the wall); a contact that stays closed gets its true
        slope, for Newton's quadratic convergence. Returns the bandwidth of the entries it touched
        (the largest |row - column|)."""
        bw = 0
        for i in np.flatnonzero(self.N > 0.0):
            e = self.elem[i]
            dofs = np.concatenate([self.index["cable"][6 * i : 6 * i + 6], self.index["casing"][6 * e : 6 * e + 12]])
            least = k_min * (self.share[i] if self.law == 1 else self.share[i] ** (2.0 / 3.0))
            kn = max(self.kn[i], least) if fresh is None or fresh[i] else self.kn[i]
            dF = self._node_derivative(i, kn)
            keep = dofs >= 0
            d = dofs[keep]
            J[np.ix_(d, d)] -= dF[np.ix_(keep, keep)]
            if len(d):
                bw = max(bw, int(d.max() - d.min()))
        return bw

    def _node_derivative(self, i, kn):
        """d(generalized contact forces)/d(DOFs) (N/m, 18 x 18) of cable node i's contact: its six
        DOFs (translation x, rotation theta) and the twelve of its casing element e (q).

        The contact point P(xi, q) = X0(xi) + A(xi) q on the casing axis (A: the displacement rows
        of the Hermite interpolation, Eq. 9) lies in the normal plane of the node's tangent t:
        (P - x) . t = 0, which moves xi by d xi = -[t . (A dq - dx) - h n . dt] / (P' . t); the
        node's offset r = x - P (h = |r|, n = r / h, g = h - e) changes by dr = dx - A dq - P' d xi,
        the normal force by kn n . dr and the normal by (I - n n^T) dr / h. Forces: -N n on the
        node, N A^T n on the element, whose A moves with xi (dA/dxi)."""
        e, xi, h, N, n = self.elem[i], self.xi[i], self.h[i], self.N[i], self.nrm[i]
        Uc, Us = self.U["cable"], self.U["casing"]
        T0 = self.Tc[i]
        # dtheta x T0 = C dtheta (the rotated tangent, small rotations)
        cross = np.array([[0.0, T0[2], -T0[1]], [-T0[2], 0.0, T0[0]], [T0[1], -T0[0], 0.0]])
        tr = T0 + cross @ Uc[6 * i + 3 : 6 * i + 6]
        tl = np.sqrt(tr @ tr)
        t = tr / tl
        A = self.H[i, :3, :]
        Ap = np.zeros((3, 12))
        K.hermite_matrix_slope(xi, self.Ls[e], self.Rs[e], Ap)  # dA/dxi, the cubics' exact slopes
        q = Us[6 * e : 6 * e + 12]
        Pp = self.Xs[e + 1] - self.Xs[e] + Ap @ q  # dP/dxi (m)
        # local DOFs w = [dx (3), dtheta (3), dq (12)]
        Dx = np.zeros((3, 18))
        Dx[:, :3] = np.eye(3)
        Mt = np.zeros((3, 18))  # dt = (I - t t^T) (dtheta x T0) / |t_raw|
        Mt[:, 3:6] = (np.eye(3) - np.outer(t, t)) @ cross / tl
        Dq = np.zeros((3, 18))
        Dq[:, 6:] = A
        cxi = -(t @ (Dq - Dx) - h * (n @ Mt)) / (Pp @ t)  # d xi (18)
        Mr = Dx - Dq - np.outer(Pp, cxi)  # dr (3 x 18)
        Pn = (np.eye(3) - np.outer(n, n)) @ Mr / h  # dn
        dN = kn * (n @ Mr)  # (18)
        dF = np.zeros((18, 18))
        dF[:3] = -np.outer(n, dN) - N * Pn
        dF[6:] = np.outer(A.T @ n, dN) + N * (A.T @ Pn) + N * np.outer(Ap.T @ n, cxi)
        return dF


def bandwidth(J):
    """The largest |i - j| over the nonzero entries of the square matrix J."""
    r, c = np.nonzero(J)
    return int(np.abs(r - c).max()) if len(r) else 0


def banded_solve(J, b, bw):
    """J^-1 b for the static tangent J (dense, zero beyond the bandwidth bw: banded by the
    interleaved unknowns): LAPACK's banded LU (scipy.linalg.solve_banded) over that bandwidth, some
    50 times fewer operations than a dense solve of the ~400 unknowns, and no threaded level-3 BLAS
    (which on a loaded machine made a dense solve take 0.1 s instead of 2 ms)."""
    n = J.shape[0]
    if 4 * bw > n:
        return np.linalg.solve(J, b)
    j = np.arange(n)
    i = j + np.arange(-bw, bw + 1)[:, None]  # ab[bw + i - j, j] = J[i, j]
    inside = (i >= 0) & (i < n)
    ab = np.where(inside, J[np.clip(i, 0, n - 1), j], 0.0)
    return solve_banded((bw, bw), ab, b, check_finite=False)


class _Problem:
    """The static equations at load factor lam, over x = (z, sigma):

        R_z = K z - lam f - sigma p - f_c(z) = 0,     R_s = sigma - a p.z - lam T = 0,

    z the free DOFs of both bodies, f their constant loads without the cable tension's, sigma the
    cable's pre-stretch force (N): the axial force it would carry at rest in the routing before it
    moves, whose load is sigma p. The second equation fixes the cable's mean axial force, sigma +
    EA/L mean(t . du), to the tension T (a = EA/L, N/m; p.z = -sum_e t_e . (u2 - u1), the chords'
    total shortening): the tension is applied like a cable pulled at its end, taut against the
    inside of every bend, not relaxed by the cable's own axial stiffness (a fixed prestress in a
    curved elastic rod is carried by its hoop stiffness within micrometres). Without a tension
    (T = 0) sigma stays zero and the second equation is left out."""

    def __init__(self, Kz, f, p, a, T, ev, k_min=0.0):
        self.Kz, self.f, self.p, self.a, self.T, self.ev, self.k_min = Kz, f, p, a, T, ev, k_min
        self.bw = bandwidth(Kz)
        self.tension = T > 0.0

    def residual(self, x, lam):
        """(R, Pi): the residual (N) and the potential energy (J) at x; R is Pi's gradient with the
        second equation times a (to first order: the normal-plane search makes the contact forces
        the potential's gradient only up to the slope of the casing axis against the cable)."""
        z, sigma = x[:-1], x[-1]
        Kz = self.Kz @ z
        Rz = Kz - lam * self.f - sigma * self.p - self.ev.evaluate(z)
        Pi = 0.5 * (z @ Kz) - lam * (self.f @ z) + self.ev.potential()
        if not self.tension:
            return np.append(Rz, 0.0), Pi
        pz = self.p @ z
        Pi += -sigma * pz + (sigma * sigma - 2.0 * lam * self.T * sigma) / (2.0 * self.a)
        return np.append(Rz, sigma - self.a * pz - lam * self.T), Pi

    def gradient(self, R):
        """The potential's gradient from the residual: the second equation over a."""
        return np.append(R[:-1], R[-1] / self.a if self.tension else 0.0)

    def step(self, x, R, fresh=None):
        """The Newton step of the bordered system [[J, -p], [-a p^T, 1]] (J: K and the contact's
        tangent at the last evaluated state; ``fresh``: the contacts closed since the last iterate)."""
        J = self.Kz.copy()
        bw = max(self.bw, self.ev.tangent(J, self.k_min, fresh))
        if not self.tension:
            return np.append(banded_solve(J, -R[:-1], bw), 0.0)
        x1, x2 = banded_solve(J, np.column_stack([-R[:-1], self.p]), bw).T
        ds = (-R[-1] + self.a * (self.p @ x1)) / (1.0 - self.a * (self.p @ x2))
        return np.append(x1 + ds * x2, ds)

    def tolerance(self, x, lam, tol):
        """|R|_inf (N) that counts as converged: ``tol`` times the force scale (the loads, the
        contact forces, the tension), and at least the rounding floor of K z, 64 eps (|K| |z|)_inf
        (a stiff body's residual cannot be smaller), plus that of the contact forces
        (:meth:`_Evaluator.rounding`: a stiff linear contact's, eps |X| k = 1.8e-9 N at 1e7 N/m, is far
        above 1e-10 of loads of 0.2 N, where Newton used to cycle at |R| ~ 1e-10 N to its last
        load step)."""
        z = x[:-1]
        fc = self.ev.evaluate(z)
        scale = max(np.abs(lam * self.f).max(initial=0.0), np.abs(fc).max(initial=0.0), lam * self.T, 1e-30)
        floor = 64.0 * np.finfo(float).eps * (np.abs(self.Kz) @ np.abs(z)).max(initial=0.0)
        return max(tol * scale, floor + self.ev.rounding())


def _newton(problem, x, lam, tol):
    """Semi-smooth Newton from x at load factor lam, with a backtracking (Armijo) line search on
    the potential energy: the problem is the minimum of a convex potential (for the gaps
    linearised at each iterate), and along a Newton step the energy tells a step that pushes
    nodes deep into the wall from one that closes them, where |R| jumps either way. A step that
    lowers the energy too little is taken when it lowers |R| (the forces are the energy's gradient
    only to first order). Every trial point is searched from the iterate's own casing elements (a
    rejected one leaves no guess behind), and a Newton that fails leaves the search where it found
    it. Returns (x, its, |R|_inf, converged, failure): failure, when not converged, the evidence for
    the message of :func:`_continuation` (the tolerance, the nodes whose contact opened or closed in
    the last SWITCH_WINDOW iterations, the largest penetration)."""
    ev = problem.ev
    start = ev.search_state()
    R, Pi = problem.residual(x, lam)
    closed = ev.closed
    fresh = None  # the first iterate: every contact is new to this load step
    switched = []  # per accepted iterate: the nodes whose contact opened or closed
    for it in range(1, MAX_ITERATIONS + 1):
        dx = problem.step(x, R, fresh)
        slope = problem.gradient(R) @ dx  # < 0: a descent direction
        alpha = 1.0
        guess = ev.search_state()
        for _ in range(40):
            xt = x + alpha * dx
            ev.restore(guess)
            Rt, Pt = problem.residual(xt, lam)
            if Pt <= Pi + 1e-4 * alpha * min(slope, 0.0) or np.linalg.norm(Rt) < 0.5 * np.linalg.norm(R):
                break
            alpha *= 0.5
        else:  # no step lowers the energy or |R|: converged if |R| is at its rounding floor
            ev.restore(guess)
            problem.residual(x, lam)  # (leaves the evaluator at x)
            limit = problem.tolerance(x, lam, tol)
            ok = np.abs(R).max() <= limit
            return x, it, float(np.abs(R).max()), ok, None if ok else _failure(ev, start, limit, switched)
        x, R, Pi = xt, Rt, Pt
        now = ev.closed
        fresh = None if now is None else (now & ~closed)
        switched.append(np.zeros(0, np.int64) if now is None else np.flatnonzero(now != closed))
        closed = now
        if np.abs(R).max() <= problem.tolerance(x, lam, tol):
            problem.residual(x, lam)
            return x, it, float(np.abs(R).max()), True, None
    limit = problem.tolerance(x, lam, tol)
    return x, MAX_ITERATIONS, float(np.abs(R).max()), False, _failure(ev, start, limit, switched)


SWITCH_WINDOW = 5  # the last Newton iterations whose contact changes name a failure's cause


def _failure(ev, start, limit, switched):
    """The evidence of a failed Newton (at its last evaluated state), and the search put back as
    the Newton found it: {"tolerance": N, "switching": the nodes whose contact opened or closed in
    the last SWITCH_WINDOW iterations, "penetration": the largest, m}."""
    recent = switched[-SWITCH_WINDOW:]
    nodes = np.unique(np.concatenate(recent)) if recent else np.zeros(0, np.int64)
    pen = float(ev.g.max(initial=0.0)) if hasattr(ev, "g") else 0.0
    ev.restore(start)
    return {"tolerance": float(limit), "switching": nodes, "penetration": pen}


def _cause(failure, residual, r_cable):
    """Why the last Newton failed, for the SimulationError: from its evidence (:func:`_failure`)."""
    head = f"|R| = {residual:.3g} N against a tolerance of {failure['tolerance']:.3g} N"
    if r_cable > 0.0 and failure["penetration"] > r_cable:
        return (
            f"{head}; the contact is too soft for the loads: a penetration of {failure['penetration']:.3g} m "
            f"exceeds the cable radius {r_cable:.3g} m"
        )
    nodes = failure["switching"]
    if len(nodes):
        shown = ", ".join(str(int(n)) for n in nodes[:8]) + (", ..." if len(nodes) > 8 else "")
        return (
            f"{head}; Newton cycles between sets of closed contacts (cable nodes {shown} opened or closed in its "
            f"last {SWITCH_WINDOW} iterations)"
        )
    if residual <= 1e3 * failure["tolerance"]:
        return (
            f"{head}, the same contacts closed throughout: Newton stalled just above its tolerance (the "
            "equilibrium's rounding larger than the tolerance allows for)"
        )
    return (
        f"{head}, the same contacts closed throughout: no equilibrium near the last one (the tension close to "
        "the casing's buckling load, or loads the supports and contacts cannot hold)"
    )


def _continuation(problem, r_cable=0.0):
    """Load stepping in the load factor lam from 0 to 1: Newton at each step from the last
    converged state; a step that fails is halved. ``r_cable`` (m): the cable's radius, for the
    message of a failure. Returns (z, sigma, iterations, steps, |R|_inf)."""
    x = np.zeros(len(problem.f) + 1)
    lam, step, total, steps = 0.0, 1.0, 0, 0
    residual = 0.0
    while lam < 1.0:
        target = min(1.0, lam + step)
        xt, its, residual, ok, failure = _newton(problem, x, target, TOLERANCE)
        total += its
        if ok:
            x, lam, steps = xt, target, steps + 1
            step = min(1.0, 2.0 * step) if its < 10 else step
        else:
            step *= 0.5
            if step < MIN_LOAD_STEP:
                raise SimulationError(
                    f"the static state did not converge: at load factor {lam:.4g} a step of {2 * step:.3g} "
                    f"failed ({total} Newton iterations): {_cause(failure, residual, r_cable)}"
                )
    return x[:-1], x[-1], total, steps, residual
