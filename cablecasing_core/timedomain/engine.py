"""The single time-stepping engine: Newmark average acceleration of casing and cable coupled by
frictional contact (Section 2.1, Eqs. 14-24, 27-34, 36-39;
Eqs. 25-26 are not implemented: :func:`hertz_constant`). Used by :func:`simulate`, the CLI and the FMU.

Each step (gamma = 1/2, beta = 1/4, Eq. 18 with C = alpha M + beta K) first predicts both bodies
without contact forces (the supports prescribed at the new time, Eq. 13), then searches every cable
node's normal plane for the casing axis, and solves the contact forces at the new time implicitly
in the small space of active contacts (see ``kernels.solve_contact_forces``); the bodies respond
to them through their effective compliance, exactly, because the structure is linear. The
reactions (Eq. 13) follow from the partitioned equations at the prescribed DOFs.

The engine can advance from any time by any step (a step that is not a multiple of ``dt`` ends
with one shorter sub-step, whose factorisation is cached; a rest within the rounding of a clock is
no time, and one too short for Newmark is taken by the last step: :func:`whole_steps`) and can copy
out and restore its
complete state (:meth:`Engine.get_state`, :meth:`Engine.set_state`).

This module is over 400 lines because it is one class whose state, stepping and outputs belong
together; the bodies' matrices are in ``body_storage.py``, the kernels in ``kernels/``.
"""

from __future__ import annotations

import io
import math
import threading
from collections.abc import Mapping
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from ..errors import CableCasingError, ModelError, RunStopped, SimulationError
from ..model.schema import BODY_NAMES, CHANNELS, CONTACT_LAWS, OUTPUTS, SUPPORT_NAMES, channels_of, lookup, outputs_of
from ..model.validate import check_tolerance_substeps
from ..model.validators import contact_in_force, seconds
from . import kernels as K
from .body_storage import FACTOR_CACHE_SIZE, BodyStorage, BoundedCache, body_arrays
from .support_motion import _coefficient_matrix

if TYPE_CHECKING:
    from ..model import Model
    from .scenario import Motion
    from .support_motion import GridMotion, SupportReconstruction


#: What stops this thread's runs (``stop``: a ``threading.Event`` or None): :func:`stop_runs_on`.
_THIS_THREAD = threading.local()


def stop_runs_on(event: threading.Event | None) -> None:
    """Make every :meth:`Engine.advance` in the calling thread end at its next chunk of
    :attr:`Engine.CHUNK` steps once ``event`` is set (None: never), by raising
    :class:`~cablecasing_core.errors.RunStopped` with the engine as it was before that call.

    The threads scheduler of studies sets it on its threads, so that Ctrl-C ends the samples in
    progress within a chunk (tens of ms) instead of at their end: a thread cannot be interrupted from
    outside, and the step kernels run without the interpreter's lock."""
    _THIS_THREAD.stop = event


def hertz_constant(model: Model) -> float:
    """4/3 E* r^1/2 of Eq. (29) in N/m^1.5: E* from both moduli and Poisson ratios (Eq. 28), r from
    the cable radius (convex, r1 = d/2) and the casing's inner radius (concave, r2 = -d_inner/2),
    1/r = 1/r1 + 1/r2 (Eq. 27). Hertz's point-contact law; a wire lying in a tube is closer to a line
    contact, so the law is a stiffness model for the penalty method, as in the paper (Fig. 19).

    Eqs. 25-26 (the largest penetration of an impact from its normal velocity, with the two bodies'
    effective mass) are not implemented and not needed: the engine applies the force law of Eq. 29
    at every step to the penetration it computes (``kernels.contact_law``), so an impact's depth
    comes out of the integration."""
    ca, cb = model.bodies["casing"], model.bodies["cable"]
    Es = 1.0 / ((1 - cb.nu**2) / cb.E_ref + (1 - ca.nu**2) / ca.E_ref)
    r1, r2 = cb.d_outer / 2.0, -ca.d_inner / 2.0
    r = 1.0 / (1.0 / r1 + 1.0 / r2)
    return 4.0 / 3.0 * Es * np.sqrt(r)


def hunt_crossley_restitution(alpha: float, v_in: float) -> float:
    """The coefficient of restitution (dimensionless, rebound speed over impact speed) of a mass
    striking a rigid wall at ``v_in`` (m/s, > 0) under Hunt and Crossley's law N = k g^n (1 + 3/2
    ``alpha`` ġ) (``alpha`` in s/m, ``contact.hunt_crossley_alpha``; N >= 0), exact for any mass,
    any stiffness k and any exponent n (the package's law has n = 3/2).

    m g'' = -N is separable in the speed v = ġ: m v dv / (1 + a v) = -k g^n dg with a = 3/2 alpha,
    so the same integral of the left side from v_in to 0 (compression) and from 0 to -e v_in
    (restitution) balances k g_max^(n+1) / (n+1), and with x = a v_in, e is the root in (0, 1/x) of
    -e x - ln(1 - e x) = x - ln(1 + x) (the force stays >= 0 throughout: e x < 1). For small x, e =
    1 - alpha v_in + O((alpha v_in)^2); at alpha = 10 s/m and v_in = 0.05 m/s it is 0.663, where
    that linear form gives 0.50 (docs/time_domain.md, "Contact", item 3)."""
    alpha, v_in = float(alpha), float(v_in)
    if not (np.isfinite(alpha) and alpha >= 0.0):
        raise ModelError("alpha", alpha, "must be a finite number >= 0 in s/m (contact.hunt_crossley_alpha)")
    if not (np.isfinite(v_in) and v_in > 0.0):
        raise ModelError("v_in", v_in, "must be a finite impact speed > 0 in m/s")
    x = 1.5 * alpha * v_in
    if x < 1e-4:  # (the sides cancel digits as 2 eps / x: the series, its next term ~x^3 below 1e-12)
        return 1.0 - 2.0 / 3.0 * x + 4.0 / 9.0 * x * x
    from scipy.optimize import brentq

    # in z = -ln(1 - e x), z > 0, the equation reads z + expm1(-z) = x - ln(1 + x), whose left side
    # rises from 0 past the right side at z = x - ln(1 + x) + 1: bracketed, and exact however large x
    rhs = x - math.log1p(x)
    z = brentq(lambda z: z + math.expm1(-z) - rhs, 0.0, rhs + 1.0, xtol=1e-300, rtol=4 * np.finfo(float).eps)
    return -math.expm1(-z) / x


def contact_shares(model: Model, element_lengths: np.ndarray) -> np.ndarray:
    """Each cable node's share of the contact law (dimensionless, one per node; ``element_lengths``
    in m, those of the cable's elements in order). With ``contact.law_length`` = 0 every node
    carries the whole law, its stiffness (Eqs. 24, 29) and damper (Eq. 16), as in the paper: 1
    everywhere. With ``contact.law_length`` = L_c > 0 (m) the law stands for that length of cable,
    so node i carries l_i / L_c of it, l_i its tributary length (half of each element it ends;
    m): a law per unit length, whose wall does not change with the mesh (docs/time_domain.md, "A
    contact law per unit length")."""
    lengths = np.asarray(element_lengths, dtype=float)
    L_c = float(model.contact["law_length"])
    if L_c == 0.0:
        return np.ones(len(lengths) + 1)
    l = np.zeros(len(lengths) + 1)
    l[:-1] += 0.5 * lengths
    l[1:] += 0.5 * lengths
    return l / L_c


def compiled_entry(dispatcher, args):
    """The compiled entry point of the numba ``dispatcher`` for the types of ``args``, or the
    dispatcher itself when there is none. Calling it skips numba's type dispatch, which types the
    arrays in tuples in Python (~100 arrays in run_steps' records: ~20 us per call, a fifth of what
    the ten steps of an FMU call at 1e-4 s cost). The engine builds every argument of run_steps itself,
    with fixed dtypes and dimensions (the support motion as C-contiguous float64, shape (n, 12)), so
    the types of later calls are those of the first one."""
    try:
        return dispatcher.overloads[tuple(dispatcher.typeof_pyval(a) for a in args)].entry_point
    except (AttributeError, KeyError):  # (another numba, or not compiled for these types)
        return dispatcher


#: A step that differs from a whole number of time steps by at most this share of dt is that whole
#: number: the rest is the rounding of a master's clock (t_(k+1) - t_k at t = 1e4 s is 1e-4 s
#: within 2e-12 s, 2e-7 dt at dt = 1e-5 s), not time to integrate.
ROUNDING_OF_TIME = 1e-6

#: The shortest step Newmark takes on its own, as a share of dt: the update a = 4 (u - u_old) / dt**2
#: - ... (Eq. 18) cancels digits as (dt / h)**2, and an extra step of 2e-5 dt put an error of the
#: support forces' RMS into them (1e-3 dt: ~4e-4 of it; 1e-2 dt: ~4e-6). A shorter rest of a longer
#: step is taken by its last step (dt + rest).
SHORTEST_STEP = 1e-2

#: The shortest step Newmark takes when it is the whole call, as a share of dt: there is no longer
#: step to take it as its rest (a master's last step clamped to its stop time), and refusing it ends
#: the master's run, so it is taken down to where its lost digits show. Measured on the installed
#: specimen under a 300 Hz drive (tests/timedomain/test_engine.py), the largest error of the twelve
#: support forces, at t + h and over the next 100 steps of dt, against the unbroken run interpolated
#: to t + h, as a share of each force's RMS: 1e-2 dt 9.9e-5 (the interpolation's own), 5e-3 dt
#: 1.5e-4, 1e-3 dt 3.6e-4, 1e-4 dt 9.4e-3 (growing as dt / h below 1e-3 dt).
SHORTEST_LONE_STEP = 1e-3

#: A run whose contact made more energy than this share of the work supplied (the supports' and the
#: constant loads' work, |W_sup| + |W_load|) warns (:meth:`Engine.solver_warnings`). Measured on the
#: built-in specimens (docs/time_domain.md, "Energy ledger"): with their friction the contact's net
#: dissipation is positive all along (installed, 1 s at 1e-5 and 1/30000 s: at least +0.075 of that
#: work; default, seeds 1-3 at 1e-5 and 2e-5 s: not below -0.0005); without friction the normal-plane search
#: on the curved casing makes energy of its own, at most 0.078 of the work supplied at 35 elements
#: (installed, mu = 0, Hunt-Crossley, sampled every 0.1 ms over 0.1 s, at 0.01 s, where the work
#: supplied passes through a minimum) and 0.28 at 10 elements (no damper); a step that is too long
#: for the contact made 500 times it (review T's bar at 1/30000 s with the switch law) and more.
ENERGY_MADE_SHARE = 0.5

#: Friction does work on the bodies (``friction_dissipation`` < 0) only when the step is too long
#: for it: on the built-in specimens it is positive, or round-off (within 3e-17 of the work supplied
#: without friction); review T's runs that blew up had -1e6 times the work supplied. A run warns
#: beyond this share.
FRICTION_MADE_SHARE = 0.01

#: What the energy checks ignore, as a share of the energy held at the end (kinetic, strain and
#: contact energy): an installed specimen left at rest books -1.5e-8 J of contact dissipation, 6.4e-8
#: of its 0.235 J of static strain energy, as its static state (solved to a tolerance) settles.
ENERGY_CHECK_FLOOR = 1e-6


def whole_steps(h: float, dt: float) -> tuple[int, float]:
    """(n, rest): h (s) = n dt + rest with 0 <= rest < dt (s), rest 0.0 when h is within
    :data:`ROUNDING_OF_TIME` dt of a whole number of steps (then n is that number)."""
    x = h / dt
    n = round(x)  # (math and builtins: numpy's scalar calls cost ~1 µs each)
    if abs(x - n) <= ROUNDING_OF_TIME:
        return int(n), 0.0
    n = math.floor(x)
    return n, h - n * dt


def motion_arrays(motion, times, nch=None):
    """(u, v, a) of ``motion(times)`` (``times`` s) as C-contiguous float arrays (m, m/s, m/s2), or
    a ModelError naming ``motion`` (not three real arrays; an error the motion raises itself passes
    as it is). A model of ``nch`` channels (None: as the motion gives them), more than the 12 of
    CHANNELS (excited clips'), takes a motion of those 12 alone (an FMU's): its arrays of shape
    (len(times), 12) are given the clips' supports at rest (zeros) up to (len(times), nch)."""
    try:
        got = motion(times)
        if len(got) != 3 or any(np.iscomplexobj(x) for x in got):
            raise TypeError
        u, v, a = (np.ascontiguousarray(x, dtype=float) for x in got)
    except CableCasingError:
        raise
    except (TypeError, ValueError):
        raise ModelError(
            "motion", type(motion).__name__, "must be a callable t -> (u, v, a) of three real arrays (m, m/s, m/s2)"
        ) from None
    n = len(times)
    if nch is not None and nch > len(CHANNELS) and u.shape == (n, len(CHANNELS)):
        u, v, a = (np.hstack([x, np.zeros((n, nch - len(CHANNELS)))]) for x in (u, v, a))
    return u, v, a


class EndOffsets(NamedTuple):
    """What :meth:`Engine.end_offset_excess` returns: the offset of the casing's support against the
    cable's across the route at ends A and B (m, (2,)), the radial gap (m) and the route's unit
    tangents at A and B ((2, 3), global axes). The cable is pressed into the wall at an end by
    ``across - gap`` where that is positive."""

    across: np.ndarray
    gap: float
    tangent: np.ndarray


class Engine:
    """Newmark stepping engine for a :class:`~cablecasing_core.model.Model`.

    Parameters
    ----------
    model : Model
    dt : float, time step in s (default ``model.scenario["dt"]``).
    contact : bool, contact between cable and casing (default ``model.contact["enabled"]``; needs
        both bodies).
    ledger : bool, accumulate the Rayleigh dissipation each step (one extra matrix product).
    record : bool, keep per-step histories (support forces, contact state, normal force,
        penetration) for :meth:`history`.
    """

    def __init__(
        self,
        model: Model,
        dt: float | None = None,
        contact: bool | None = None,
        ledger: bool = True,
        record: bool = False,
    ):
        dt = model.scenario["dt"] if dt is None else dt
        lookup("scenario.dt").check(dt, "dt")
        contact = contact_in_force(model, contact)
        self.model = model
        self._structure = model.fingerprint(scenario=False)  # (what a state of this engine belongs to)
        self.dt = float(dt)
        #: the support channels (``channels_of``: the 12 of CHANNELS, then the excited clips') and
        #: the outputs (``outputs_of``: OUTPUTS, then the clips' forces) of this model
        self.channels, self.output_names = channels_of(model), outputs_of(model)
        self.bodies = {n: BodyStorage(model, n, channels=self.channels) for n in model.bodies}
        self.n_forces = 24 + (len(self.output_names) - len(OUTPUTS))  # recorded: the supports', the clips' forces
        both = "casing" in self.bodies and "cable" in self.bodies
        self.contact = contact
        self.static = self._install(model)
        self.ledger_on = bool(ledger)
        self.record = bool(record)
        c = model.contact
        if both:
            cab, cas = self.bodies["cable"].system, self.bodies["casing"].system
            self.Xc = cab.centerline.nodes.copy()
            self.Tc = cab.centerline.tangents.copy()
            self.Xs = cas.centerline.nodes.copy()
            self.Rs = cas.centerline.frames.copy()
            self.Ls = cas.centerline.lengths.copy()
            self.gap = model.radial_gap
            self.r_in = cas.section.r_inner
            self.r_cable = cab.section.r_outer
            self.k_hertz = hertz_constant(model)
            #: each cable node's share of the contact law (dimensionless; :func:`contact_shares`)
            self.share = contact_shares(model, cab.centerline.lengths)
        else:
            self.Xc = np.zeros((0, 3))
            self.Tc = self.Xs = np.zeros((0, 3))
            self.Rs = np.zeros((0, 3, 3))
            self.Ls = np.zeros(0)
            self.gap = self.r_in = self.r_cable = self.k_hertz = 0.0
            self.share = np.zeros(0)
        self.law = CONTACT_LAWS.index(c["law"])  # the kernels' code of the law
        self.k_lin, self.mu, self.v_stick = c["stiffness"], c["friction"], c["stick_velocity"]
        #: the slip speed over which Coulomb's law is regularised (m/s; 0: the switch law of Section 2.1)
        self.vreg = c["stick_velocity"] if c["friction_law"] == "regularized" else 0.0
        if c["friction_law"] == "regularized" and not self.vreg > 0.0 and self.contact and self.mu > 0.0:
            raise ModelError(
                "contact.stick_velocity",
                self.vreg,
                'must be > 0 m/s with contact.friction_law = "regularized" (the speed the law is regularised over)',
            )
        # the damper's coefficient: c_n (kg/s, Eq. 16), or Hunt-Crossley's 3/2 alpha (s/m)
        self.c_n = 1.5 * c["hunt_crossley_alpha"] if c["law"] == "hunt_crossley" else c["damping"]
        self._substeps = int(c["event_substeps"])
        self.event_tolerance = float(c["event_tolerance"])
        #: the sub-steps of a recomputed step after the first keep the Delassus matrix while the same
        #: contacts are closed (docs/time_domain.md, "Events inside the step"); False recomputes it
        self.reuse_delassus = True
        self._hist = []
        self._end_rows = None  # (end_offset_excess: its projections and tangents)
        self._snap = None  # roll-back buffer of advance (see snapshot)
        self._ws = K.contact_workspace(len(self.Xc))
        self._allocate_state()
        self._call_args = BoundedCache(FACTOR_CACHE_SIZE)  # (dt, settings) -> the step loop's arguments and entry point
        self._cstep_parts = self._cstep_context = self._cstep_scratch = self._cstep_entry = (
            None  # see advance_reconstructed
        )
        self._cstep_memo = None
        self._cstep_G = np.zeros((18, 6))  # the quintic matrix of the context (support_motion)
        self._no_record = K.Recording(
            False,
            np.zeros((1, 24)),
            np.zeros(2, np.int64),
            np.zeros(1, np.int32),
            np.zeros(1, np.int8),
            np.zeros(1),
            np.zeros(1),
            0,
        )
        self.reset()

    def _allocate_state(self):
        """All state arrays as views into two flat buffers (floats, integers), so that a snapshot is
        two copies (:meth:`snapshot`); the arrays are never rebound, only written."""
        nn = len(self.Xc)
        ns = self.bodies["casing"].system.ndof if "casing" in self.bodies else 1
        nc = self.bodies["cable"].system.ndof if "cable" in self.bodies else 1
        floats = [(b, k, (len(b.U),)) for b in self.bodies.values() for k in "UVA"]
        floats += [(b, k, getattr(b, k).shape) for b in self.bodies.values() for k in ("mb", "mF")]
        floats += [
            (self, k, shape)
            for k, shape in (
                ("cxi", (nn,)),
                ("Pn", (nn, 3)),
                ("Pn_prev", (nn, 3)),
                ("vrel", (nn,)),
                ("Nn", (nn,)),
                ("gn", (nn,)),
                ("fcs", (ns,)),
                ("fcc", (nc,)),
                ("reac", (24,)),
                ("ledger", (K.LEDGER_SIZE,)),
                ("contact_time", (nn,)),
                ("_info", (K.INFO_SIZE,)),
                ("chan", (3, len(self.channels))),
            )
        ]
        ints = [(self, "cstate", (nn,)), (self, "celem", (nn,)), (self, "crefine", (1,))]
        for items, dtype, name in ((floats, float, "_fbuf"), (ints, np.int64, "_ibuf")):
            buf = np.zeros(sum(int(np.prod(shape)) for _, _, shape in items), dtype)
            o = 0
            for owner, key, shape in items:
                size = int(np.prod(shape))
                setattr(owner, key, buf[o : o + size].reshape(shape))
                o += size
            setattr(self, name, buf)
        # the step loop's info array (K.INFO_*): what failed, then the solver counters: contact Newton
        # iterations, stick/slip passes, unconverged steps
        self.solver_counts = self._info[K.INFO_NEWTON_ITERATIONS : K.INFO_UNCONVERGED_STEPS + 1]

    @property
    def refined_steps(self) -> int:
        """Steps recomputed in :attr:`event_substeps` sub-steps around a stick-slip event since
        the start (docs/time_domain.md, "Events inside the step")."""
        return int(self._info[K.INFO_REFINED_STEPS])

    @property
    def event_substeps(self) -> int:
        """Sub-steps of a step recomputed around a stick-slip event or for its local error
        (``contact.event_substeps``; 1: none): the regularised law has no stick-slip events, so it
        takes them only with a tolerance (:attr:`event_tolerance` and :attr:`vreg` may be changed
        between calls, as the other attributes of the law)."""
        return self._substeps if self.vreg == 0.0 or self.event_tolerance > 0.0 else 1

    @property
    def event_tolerance(self) -> float:
        """m: a step whose estimated local error exceeds this is recomputed in :attr:`event_substeps`
        sub-steps (0: off; ``contact.event_tolerance``); may be changed between calls, and is
        refused (ModelError) where there are no sub-steps to recompute in."""
        return self._tolerance

    @event_tolerance.setter
    def event_tolerance(self, value: float) -> None:
        value = float(value)
        lookup("contact.event_tolerance").check(value, "event_tolerance")
        check_tolerance_substeps(value, self._substeps)
        self._tolerance = value

    @property
    def event_steps(self) -> int:
        """Of :attr:`refined_steps`, those recomputed around a stick-slip event (the rest were
        recomputed for :attr:`event_tolerance`)."""
        return self.refined_steps - self.tolerance_steps

    @property
    def tolerance_steps(self) -> int:
        """Of :attr:`refined_steps`, those recomputed because their estimated local error exceeded
        :attr:`event_tolerance` (docs/time_domain.md, "A tolerance instead of a bare step")."""
        return int(self._info[K.INFO_TOLERANCE_STEPS])

    @property
    def max_local_error(self) -> float:
        """m: the largest estimated local error of a step or sub-step kept since the start (only
        with :attr:`event_tolerance` > 0, else 0): dt^2 / 12 max |a_(n+1) - a_n| over the bodies'
        translations."""
        return float(self._info[K.INFO_MAX_LOCAL_ERROR])

    @property
    def tolerance_met(self) -> bool:
        """Whether every step and sub-step kept since the start is within :attr:`event_tolerance`
        (True without a tolerance): :attr:`max_local_error` at most the tolerance."""
        return self.event_tolerance == 0.0 or self.max_local_error <= self.event_tolerance

    def solver_warnings(self) -> list[str]:
        """What the step loop did not achieve since the start, one sentence each (for a warning;
        empty when it achieved everything asked):

        - ``contact.event_tolerance`` not met (:attr:`max_local_error` above it): a step over the
          tolerance is recomputed in :attr:`event_substeps` sub-steps once and they are not refined
          further, so where the acceleration jumps (an impact, a release) their estimate can stay
          above it (docs/time_domain.md, "A tolerance instead of a bare step");
        - the contact Newton not converged in some steps (``solver_counts[2]``): their forces are
          its last iterate (docs/time_domain.md, "Contact", item 5);
        - the contact made energy (:meth:`contact_energy_warnings`)."""
        said = []
        if not self.tolerance_met:
            n = self.event_substeps
            said.append(
                f"contact.event_tolerance = {self.event_tolerance:g} m was not met: the largest local error "
                f"estimated in a sub-step kept is {self.max_local_error:.3g} m (in the {n} sub-steps of dt/{n} of "
                "a step recomputed for it, which are not refined further; it is an estimate of one sub-step's local "
                "error in displacement, not an accuracy of the outputs); raise contact.event_substeps or shorten "
                "the time step (docs/time_domain.md, A tolerance instead of a bare step)"
            )
        failed = int(self.solver_counts[2])
        if failed:
            said.append(
                f"the contact Newton did not converge in {failed} of the {round(self.time / self.dt)} steps (or "
                "sub-steps): their contact forces are its last iterate; it happens where the contact law is nearly "
                "non-smooth, such as a contact.stick_velocity far below the slip speeds or a contact.damping far "
                "above the specimens' (docs/time_domain.md, Contact, item 5)"
            )
        return said + self.contact_energy_warnings()

    def contact_energy_warnings(self) -> list[str]:
        """A sentence (for a warning) for each sign of a contact that made energy since the start,
        which the ledger's residual cannot show (it closes by construction, docs/time_domain.md,
        "Energy ledger"): the contact's net dissipation (``contact_dissipation``, J) below
        -:data:`ENERGY_MADE_SHARE` times the work supplied (``support_work`` and ``load_work``, J,
        in absolute value), or the friction's (``friction_dissipation``) below
        -:data:`FRICTION_MADE_SHARE` times it, each beyond :data:`ENERGY_CHECK_FLOOR` of the
        energy held (kinetic, strain and contact energy). Empty without contact or when neither."""
        if not self.contact or self.time == 0.0:
            return []
        e = self.energies()
        supplied = abs(e["support_work"]) + abs(e["load_work"])
        floor = ENERGY_CHECK_FLOOR * (e["kinetic"] + e["strain"] + e["contact_potential"])
        remedy = (
            "a discrete contact that makes energy is the step's error, not the model's: shorten scenario.dt until "
            'the results stop changing (with contact.friction_law = "regularized" they converge as it shrinks: '
            "docs/time_domain.md, A friction law whose limit exists; Energy ledger)"
        )
        said = []
        made = -e["contact_dissipation"]
        if made > ENERGY_MADE_SHARE * supplied + floor:
            said.append(
                f"the contact made energy: its net dissipation contact_dissipation = {e['contact_dissipation']:.3g} J "
                f"(friction_dissipation {e['friction_dissipation']:.3g} J, contact_damping_dissipation "
                f"{e['contact_damping_dissipation']:.3g} J, contact_normal_dissipation "
                f"{e['contact_normal_dissipation']:.3g} J) against {supplied:.3g} J of work "
                f"supplied by the supports and the constant loads (|support_work| + |load_work|), more than "
                f"{ENERGY_MADE_SHARE:g} of it; {remedy}"
            )
        if -e["friction_dissipation"] > FRICTION_MADE_SHARE * supplied + floor:
            said.append(
                f"friction did work on the bodies: friction_dissipation = {e['friction_dissipation']:.3g} J against "
                f"{supplied:.3g} J of work supplied by the supports and the constant loads, where friction can only "
                f"take energy; {remedy}"
            )
        return said

    # -------------------------------------------------------------------------------- state
    def _install(self, model):
        """The static state the run starts from (an installed model: gravity, a cable tension, a
        straight cable; timedomain/static_state.py), with each body's constant load set to the one
        of that state (the cable's tension as its pre-stretch force); None for a model without
        loads, which starts at rest in the routing."""
        if not model.installed:
            return None
        from .static_state import solve_static

        st = solve_static(model, {n: b.system for n, b in self.bodies.items()}, self.contact)
        for n, b in self.bodies.items():
            b.set_load(st.loads[n])
        self._warn_switch_law_at_rest_on_the_wall(model, st)
        return st

    def _warn_switch_law_at_rest_on_the_wall(self, model, st):
        """Warn (a ModelWarning, once per process and model) when the static state lays the cable on
        the casing's wall and the friction is the paper's switch law: there its stick-slip switches
        multiply as the step shrinks and the band levels do not converge (docs/time_domain.md, "A
        friction law whose limit exists"). The loader warns of a cable tension on that law already
        (model/validate.py); this is the case it cannot judge, gravity or a rest shape alone, where
        only the static state tells whether the cable touches the wall."""
        c = model.contact
        if not self.contact or c["friction"] <= 0.0 or c["friction_law"] != "switch":
            return
        if model.loads["cable_tension"] > 0.0:  # (warned when the model was loaded)
            return
        touching = int(np.count_nonzero(st.normal_force > 0.0))
        if not touching:
            return
        from ..errors import ModelPropertyWarning, warn_once_per_process

        warn_once_per_process(
            f"{model.source}: the cable rests on the casing's wall at {touching} nodes in its static state (its "
            f'largest contact force {float(np.max(st.normal_force)):.3g} N), where contact.friction_law = "switch" '
            "does not converge with the time step (its stick-slip switches multiply as it shrinks) and recomputes "
            'most steps: set contact.friction_law = "regularized", as the built-in installed specimen does '
            '(docs/time_domain.md, "A friction law whose limit exists")',
            ModelPropertyWarning,
            stacklevel=5,  # (simulate's caller, through Engine.__init__ and _install)
            key=f"switch law at rest on the wall: {model.fingerprint()}",
        )

    def reset(self) -> None:
        """Back to t = 0 with both bodies at rest: in the static state of an installed model
        (:attr:`static`: its displacements, and the contacts closed where it has them, sticking, with
        its forces), else in the reference configuration."""
        self.time = 0.0
        self._fbuf[:] = 0.0
        self._ibuf[:] = 0
        self.celem[:] = np.clip(np.arange(len(self.celem)) - 1, 0, max(len(self.Ls) - 1, 0))
        self._hist = []
        st = self.static
        if st is not None:
            for n, b in self.bodies.items():
                b.U[:] = st.U[n]
                for m, mt in enumerate(b.mounts):  # the mounts' static forces (their supports at rest)
                    b.mF[m] = mt.K6 @ b.U[6 * mt.node : 6 * mt.node + 6]
            self.reac[:] = st.reactions
            if self.contact:
                on = st.normal_force > 0.0
                self.cstate[on] = K.STICK  # at rest
                self.celem[:] = st.element
                self.cxi[:], self.Pn[:] = st.xi, st.contact_force
                self.Nn[:], self.gn[:] = st.normal_force, st.penetration
                self.fcs[:] = st.generalized_contact["casing"]
                self.fcc[:] = st.generalized_contact["cable"]
        self._pot0 = self.contact_potential()
        # the energy of this state (J), for the ledger's start (:meth:`_begin`): computed here, in a
        # reset (an FMU's initialisation), not in the first step; dropped when the state is set
        kin, strain = (sum(x) for x in zip(*(b.energy() for b in self.bodies.values())))
        self._reset_energy = kin + strain + self._pot0

    _ARRAYS = (
        "cstate", "celem", "cxi", "Pn", "Pn_prev", "vrel", "Nn", "gn", "fcs", "fcc", "reac", "ledger", "contact_time",
        "chan", "crefine",
    )  # fmt: skip

    def get_state(self) -> dict[str, np.ndarray]:
        """The complete state as ``{name: array}`` (copies): ``time`` (s); ``<body>.U``, ``.V``,
        ``.A`` of each body (m, m/s, m/s2 and rad, rad/s, rad/s2 by DOF) and, with mounts, ``.mb``
        (their supports' displacement and velocity, m, m/s) and ``.mF`` (their forces, N, N.m); the
        contact memory per cable node: ``cstate`` (OPEN/STICK/SLIP), ``celem`` and ``cxi`` (casing
        element and its coordinate, dimensionless), ``Pn`` and ``Pn_prev`` (contact force now and a
        step before, N), ``vrel`` (tangential relative speed, m/s), ``Nn`` (normal force, N), ``gn``
        (penetration, m), ``contact_time`` (s); ``fcs``, ``fcc`` (contact forces on the casing's and
        the cable's DOFs, N, N.m), ``reac`` (the last support reactions, N, N.m), ``ledger`` (the
        energy ledger, J), ``chan`` (the support channels' displacement, velocity and acceleration,
        m, m/s, m/s2), ``crefine`` (1 when the last step ended inside its sub-steps); and ``model``,
        the fingerprint of the structure it belongs to (``Model.fingerprint(scenario=False)``: the
        same bodies, mounts, loads and contact; the scenario may differ)."""
        s = {"time": np.array([self.time]), "model": np.array(self._structure)}
        for n, b in self.bodies.items():
            s[f"{n}.U"], s[f"{n}.V"], s[f"{n}.A"] = b.U.copy(), b.V.copy(), b.A.copy()
            if b.mounts:
                s[f"{n}.mb"], s[f"{n}.mF"] = b.mb.copy(), b.mF.copy()
        for a in self._ARRAYS:
            s[a] = getattr(self, a).copy()
        return s

    def snapshot(self, into: list | None = None) -> list:
        """The complete state (what :meth:`get_state` holds, and the solver counters) as an opaque
        list, cheaply: two buffer copies, written into ``into`` (an earlier snapshot of this engine)
        when given. For roll-back (:meth:`restore`); recorded histories are not part of it."""
        if into is None:
            return [self.time, self._fbuf.copy(), self._ibuf.copy()]
        into[0] = self.time
        np.copyto(into[1], self._fbuf)
        np.copyto(into[2], self._ibuf)
        return into

    def restore(self, snap: list) -> None:
        """Return to a :meth:`snapshot` of this engine (continuation is bit-identical); what is not
        one (its buffers' shapes and types) is a ModelError, with nothing changed."""
        ok = len(snap) == 3 and all(
            isinstance(x, np.ndarray) and x.shape == b.shape and x.dtype == b.dtype
            for x, b in ((snap[1], self._fbuf), (snap[2], self._ibuf))
        )
        if not ok or not math.isfinite(snap[0]):
            raise ModelError("snap", type(snap).__name__, "must be a snapshot of this engine (Engine.snapshot)")
        self.time, self._reset_energy = snap[0], None
        np.copyto(self._fbuf, snap[1])
        np.copyto(self._ibuf, snap[2])

    def set_state(self, state: Mapping[str, ArrayLike]) -> None:
        """Restore a state from :meth:`get_state` (continuation is bit-identical). Every entry is
        checked before any is written, so a bad state leaves the engine as it was."""
        targets = [(f"{n}.{k}", getattr(b, k)) for n, b in self.bodies.items() for k in "UVA"]
        targets += [(f"{n}.{k}", getattr(b, k)) for n, b in self.bodies.items() if b.mounts for k in ("mb", "mF")]
        targets += [(a, getattr(self, a)) for a in self._ARRAYS]
        if "model" in state and str(np.asarray(state["model"])) != self._structure:  # (older states have none)
            raise ModelError(
                "state.model",
                str(np.asarray(state["model"])),
                f"is the fingerprint of another model's structure (this engine's is {self._structure}): a state "
                "continues only the bodies, mounts, loads and contact it was taken from",
            )
        try:
            time = float(np.asarray(state["time"]).reshape(-1)[0])
            new = [(dst, np.asarray(state[key], dst.dtype)) for key, dst in targets]
        except KeyError as exc:
            raise ModelError("state", str(exc), "is missing from the state") from None
        except (TypeError, ValueError, IndexError):
            raise ModelError("state", type(state).__name__, "must be a state of Engine.get_state") from None
        if not (math.isfinite(time) and time >= 0.0):
            raise ModelError("state.time", time, "must be a finite number of seconds >= 0")
        n_elem = len(self.Ls)  # (0 without a casing)
        for (key, dst), (_, arr) in zip(targets, new):
            if arr.shape != dst.shape:
                raise ModelError(f"state.{key}", arr.shape, f"must have shape {dst.shape}")
            if arr.dtype.kind == "f" and not np.isfinite(arr).all():
                raise ModelError(f"state.{key}", "a non-finite value", "must hold finite numbers")
            if arr.dtype.kind in "iu" and not np.array_equal(np.asarray(state[key]), arr):
                raise ModelError(f"state.{key}", np.asarray(state[key]).tolist(), "must hold whole numbers")
            if key == "cstate" and not np.isin(arr, (K.OPEN, K.STICK, K.SLIP)).all():
                raise ModelError("state.cstate", arr.tolist(), f"must hold {K.OPEN}, {K.STICK} or {K.SLIP}")
            if key == "celem" and n_elem and not ((arr >= 0) & (arr < n_elem)).all():
                raise ModelError("state.celem", arr.tolist(), f"must hold casing elements 0 to {n_elem - 1}")
        for dst, arr in new:
            dst[...] = arr
        self.time, self._reset_energy = time, None

    # -------------------------------------------------------------------------------- stepping
    def _run(self, dt, up, vp, ap, times):
        n = len(up)
        if self.record:
            # contact histories sparse (the nodes in contact, ~2 of 36): np.empty of the worst case
            # is only address space until written; the used part is copied out below
            cap = n * len(self.Xc)
            rec = K.Recording(
                True,
                np.zeros((n, self.n_forces)),
                np.zeros(n + 1, np.int64),
                np.empty(cap, np.int32),
                np.empty(cap, np.int8),
                np.empty(cap),
                np.empty(cap),
                0,
            )
        else:
            rec = self._no_record
        # the arrays are never rebound (see _allocate_state), so the arguments are built once per
        # time step and setting (a changed attribute, e.g. contact or mu, builds them anew)
        law = self._law()
        key = (dt, self.ledger_on, self.record, law)
        args, step_loop = self._call_args.get(key, (None, None))
        if args is None:
            contact = K.ContactArrays(
                self.Xc,
                self.Tc,
                self.Xs,
                self.Rs,
                self.Ls,
                self.cstate,
                self.celem,
                self.cxi,
                self.Pn,
                self.Pn_prev,
                self.vrel,
                self.Nn,
                self.gn,
                self.contact_time,
                self._ws,
                self.chan,
                _coefficient_matrix(dt),
                self.crefine,
                self.share,
            )
            casing = body_arrays(self.bodies.get("casing"), dt, self.contact, self.fcs, law.nsub)
            cable = body_arrays(self.bodies.get("cable"), dt, self.contact, self.fcc, law.nsub)
            scratch = K.step_scratch(casing, cable, contact, len(self.channels), law.nsub)
            args = (casing, cable, law, contact, self.reac, self.ledger, self.ledger_on, scratch)
        info = self._info  # info[K.INFO_NEWTON_ITERATIONS:] are the solver counters (a view)
        info[: K.INFO_NEWTON_ITERATIONS] = 0.0
        if step_loop is None:
            status = K.run_steps(self.time, dt, up, vp, ap, *args, rec, info)  # compiles or loads it
            self._call_args[key] = (args, compiled_entry(K.run_steps, (self.time, dt, up, vp, ap, *args, rec, info)))
        else:
            status = step_loop(self.time, dt, up, vp, ap, *args, rec, info)
        if status != K.OK:
            self._raise_for_status(status, up, vp, ap, times)
        if self.record:
            m = int(rec.ptr[-1])
            self._hist.append((rec.F, rec.ptr) + tuple(x[:m].copy() for x in (rec.node, rec.state, rec.N, rec.g)))
        self.time = float(info[K.INFO_TIME])

    def _on_grid(self, t: float) -> float:
        """t (s), or the multiple k dt of the time step it lies within :data:`ROUNDING_OF_TIME` dt
        of: a run split into calls stays on the grid of one call (the sum t + m dt of each call's
        steps drifts from it by its rounding, past 1e-9 steps after 8 s of 16384-step pieces, where
        the scenario's motion is then evaluated off its grid: other values, ~1e4 times the cost)."""
        k, rest = whole_steps(t, self.dt)
        return float(k * self.dt) if rest == 0.0 else float(t)

    def _law(self):
        """The contact law's record (from the attributes, which a caller may change between steps;
        mu and vreg are checked here, as :attr:`event_tolerance` is in its setter)."""
        for key, value in (("mu", self.mu), ("vreg", self.vreg)):
            if not (math.isfinite(value) and value >= 0.0):
                raise ModelError(key, value, "must be a finite number >= 0 (the friction coefficient, -; m/s)")
        return K.ContactLaw(
            self.contact, self.gap, self.r_in, self.r_cable, self.law, self.k_lin, self.k_hertz, self.c_n, self.mu,
            self.v_stick, self.event_substeps if self.contact else 1, self.reuse_delassus,
            self.vreg, self._tolerance,
        )  # fmt: skip

    def _raise_for_status(self, status, up, vp, ap, times):
        """The error of a step loop's status other than OK (the motion, the times it was given at)."""
        info = self._info
        if status == K.ERR_INPUT:
            r, c, q = (int(info[i]) for i in (K.INFO_INPUT_ROW, K.INFO_INPUT_CHANNEL, K.INFO_INPUT_KIND))
            name = ("displacement", "velocity", "acceleration")[q]
            raise ModelError(
                f"{self.channels[c]} {name}", float((up, vp, ap)[q][r, c]), f"must be finite (at t = {times[r]:.6g} s)"
            )
        what = {
            K.ERR_NAN: "the solution is no longer finite (NaN/inf): the step is unstable (a time step too long "
            "for the model), or the support motion is too large for double precision",
            K.ERR_PENETRATION: f"penetration {info[K.INFO_VALUE]:.4g} m exceeds the cable radius "
            f"{self.r_cable:.4g} m (contact too soft for this load, the time step too large, or a "
            "contact stiffness so far above the bodies' that the contact solve loses its digits: a linear "
            "contact.stiffness of 1e25 N/m did)",
        }[status]
        node = info[K.INFO_NODE]
        where = f"cable node {int(node)}" if node >= 0 else "the support forces"
        error = SimulationError(f"at t = {info[K.INFO_TIME]:.6g} s, {where}: {what}")
        error.non_finite = status == K.ERR_NAN  # (a caller may name the input that overflowed: the FMU does)
        raise error

    CHUNK = 2048  # steps per evaluation of the support motion (see advance)

    def advance(self, h: float, motion: Motion) -> None:
        """Integrate from ``self.time`` to ``self.time + h`` (s) with the support ``motion``
        (callable t -> (u, v, a), each (len(t), 12), in m, m/s, m/s2 over ``CHANNELS``; a function
        of t alone, evaluated in chunks of :attr:`CHUNK` steps).

        h is taken as whole steps of dt and a rest (:func:`whole_steps`): a rest within
        :data:`ROUNDING_OF_TIME` dt is the rounding of the caller's clock and is not integrated (the
        engine's time advances by the whole steps), a rest shorter than :data:`SHORTEST_STEP` dt is
        taken by the last step (dt + rest); an h shorter than dt is one step of h when it is at least
        :data:`SHORTEST_LONE_STEP` dt, a ``ModelError`` when it is shorter.

        The motion is evaluated chunk by chunk, so its arrays stay small and in cache whatever the
        duration (1 s at dt = 1e-5 in one piece would be 29 MB of motion alone, and faulting them
        in cost ~10 % of the step loop's time). Bad input (a non-finite or misshaped motion, or an
        error raised by ``motion``) in any chunk leaves the engine as it was before the call: a
        later chunk's error restores the state (:meth:`snapshot`) and drops that call's recorded
        history. So does a blow-up (:class:`SimulationError`, whose message says when, where and
        what): the engine is then as it was before the call, and can be advanced again (e.g. by
        a smaller step, or after :meth:`set_state`). So does a stop from another thread
        (:func:`stop_runs_on`), checked before each chunk."""
        seconds("h", h)
        n, rest = whole_steps(h, self.dt)
        segments = []
        if 0 < rest < SHORTEST_STEP * self.dt and n == 0:  # the call is one short step
            if rest < SHORTEST_LONE_STEP * self.dt:
                raise ModelError(
                    "h",
                    h,
                    f"must be at least {SHORTEST_LONE_STEP:g} of the time step dt = {self.dt!r} s (a step of at most "
                    f"{ROUNDING_OF_TIME:g} dt is taken as the rounding of a clock: no time): a Newmark step of "
                    "h << dt loses the digits of its accelerations as (dt / h)**2 (Eq. 18); take a longer step",
                )
            segments = [(rest, 1)]
        elif 0 < rest < SHORTEST_STEP * self.dt:  # too short for a step of its own: the last step takes it
            segments = [(self.dt, n - 1)] if n > 1 else []
            segments.append((self.dt + rest, 1))
        else:
            if n:
                segments.append((self.dt, n))
            if rest:
                segments.append((rest, 1))
        # roll-back for a blow-up, or for bad input in a later chunk (the shorter last substep is a
        # chunk of its own); the snapshot buffer is reused (two buffer copies per call)
        self._snap = snap = self.snapshot(self._snap)
        nhist = len(self._hist)
        stop = getattr(_THIS_THREAD, "stop", None)
        try:
            self._begin(motion)
            for dt, m in segments:
                t = self.time
                for j0 in range(0, m, self.CHUNK):
                    if stop is not None and stop.is_set():
                        raise RunStopped(f"stopped at t = {t + j0 * dt:.6g} s")
                    j1 = min(m, j0 + self.CHUNK)
                    times = t + dt * np.arange(j0 + 1, j1 + 1)  # as if evaluated in one piece
                    nch = len(self.channels)
                    u, v, a = motion_arrays(motion, times, nch)  # (a motion of the 12 fixed channels: clips at rest)
                    for x in (u, v, a):
                        if x.shape != (j1 - j0, nch):
                            raise ModelError("motion", x.shape, f"must return arrays of shape ({j1 - j0}, {nch})")
                    self._run(dt, u, v, a, times)  # (non-finite motion is refused there, before any step)
                self.time = self._on_grid(t + m * dt)
        except BaseException:
            self.restore(snap)
            del self._hist[nhist:]
            raise

    # -------------------------------------------------------------------------------- outputs
    def contact_potential(self) -> float:
        """Elastic energy stored in the contacts (J), from the penetrations at the current time."""
        return K.contact_potential(self.gn, self.law, self.k_lin, self.k_hertz, self.share)

    def load_work(self) -> float:
        """Work (J) of the constant loads at rest since t = 0: f . (U - U_static) over all DOFs of
        both bodies (a constant force's trapezoidal work over the steps sums to exactly that)."""
        if self.static is None:
            return 0.0
        return float(sum(b.f @ (b.U - self.static.U[n]) for n, b in self.bodies.items()))

    def energies(self) -> dict[str, float]:
        """Energy ledger in J: kinetic, strain (with the mounts' springs), contact potential, work
        done by the supports (through the mounts too) and by the constant loads at rest (an
        installed model's gravity, tension and rest shape), dissipated by Rayleigh damping, by the
        mounts' dampers (``mount_dissipation``), dissipated in the contacts (``contact_dissipation``:
        the work of the contact forces less the change of the stored contact energy, which the
        balance uses), its parts integrated from their powers (``contact_damping_dissipation``,
        ``friction_dissipation``) and what is left of it (``contact_normal_dissipation``: the work of
        the normal forces beyond their law's potential and damper; zero for a conservative contact,
        made non-zero by the normal-plane search on a curved casing, negative where it makes energy,
        falling as the mesh is refined: docs/time_domain.md, "Energy ledger"), and the balance
        residual (energy now minus the energy at the start plus supplied work less dissipation).
        Strain and contact energy are totals, the static state's included."""
        kin = sum(b.energy()[0] for b in self.bodies.values())
        strain = sum(b.energy()[1] for b in self.bodies.values())
        pot = self.contact_potential()
        w_sup, d_ray, e_start, d_fric, w_con, d_damp, d_mount = (
            self.ledger[i]
            for i in (
                K.LEDGER_SUPPORT_WORK,
                K.LEDGER_RAYLEIGH_DISSIPATION,
                K.LEDGER_START_ENERGY,
                K.LEDGER_FRICTION_DISSIPATION,
                K.LEDGER_CONTACT_WORK,
                K.LEDGER_DAMPING_DISSIPATION,
                K.LEDGER_MOUNT_DISSIPATION,
            )
        )
        d_con = 0.0 - w_con - (pot - self._pot0)  # (+0, not -0, where nothing was dissipated)
        w_ext = self.load_work()
        residual = kin + strain + pot - (e_start + w_sup + w_ext - d_ray - d_con - d_mount)
        return {
            "kinetic": kin,
            "strain": strain,
            "contact_potential": pot,
            "start_energy": e_start,
            "support_work": w_sup,
            "load_work": w_ext,
            "rayleigh_dissipation": d_ray if self.ledger_on else np.nan,
            "contact_dissipation": d_con,
            "contact_damping_dissipation": d_damp,
            "friction_dissipation": d_fric,
            "contact_normal_dissipation": d_con - d_damp - d_fric,
            "mount_dissipation": d_mount,
            "residual": residual if self.ledger_on else np.nan,  # (it holds the Rayleigh dissipation)
        }

    def output_values(self, out: np.ndarray | None = None) -> np.ndarray:
        """The values of :meth:`outputs` as an array in the order of :attr:`output_names`
        (:data:`OUTPUTS`, then the clips' forces; written into ``out`` when given, which may hold
        OUTPUTS only): one call instead of a dict, for the FMU's per-step reads."""
        out = np.empty(len(self.output_names)) if out is None else self._checked_out(out)
        K.step_outputs(
            self.reac,
            self.cstate,
            self.gn,
            self.ledger,
            self.law,
            self.k_lin,
            self.k_hertz,
            self.share,
            self._pot0,
            out,
        )
        b = self.bodies.get("casing")
        if b is not None and len(out) > len(OUTPUTS):  # the clips' forces, as the fused step writes them
            K.clip_force_outputs(b.mi, b.mF, out, len(OUTPUTS))
        return out

    def _checked_out(self, out):
        """``out`` if the compiled output writer may fill it: a writable, C-contiguous 1-D float64
        array of at least len(OUTPUTS) values (it writes them without bounds checks)."""
        if not (
            isinstance(out, np.ndarray)
            and out.dtype == np.float64
            and out.ndim == 1
            and out.flags.c_contiguous
            and out.flags.writeable
            and len(out) >= len(OUTPUTS)
        ):
            shown = f"{type(out).__name__} {getattr(out, 'dtype', '')} of shape {getattr(out, 'shape', '?')}"
            raise ModelError(
                "out", shown, f"must be a writable, C-contiguous 1-D float64 array of at least {len(OUTPUTS)} values"
            )
        return out

    def end_offset_excess(self, u: ArrayLike) -> EndOffsets | None:
        """How far the support displacements ``u`` set the casing's and the cable's supports at each
        end apart across the route, against the radial gap; None when that cannot matter (contact
        off, or one body).

        ``u``: displacement (m, global axes) of each channel of :attr:`channels` (or of the first 12,
        :data:`CHANNELS`), from the reference position the bodies start from at rest. The two bodies
        share their end nodes (one centerline: cable node 0 is casing node 0), and the contact measures
        the cable node's distance from the casing's axis in the node's normal plane, across the
        route's unit tangent t there: at end A (node 0) and B (the last node), with d = u(casing) -
        u(cable) at that end, ``across = |d - (d . t) t|`` (m). An offset along t slides the cable in
        the casing; across the route beyond the gap the cable is pressed into the casing's wall there
        by ``across - gap`` (m). An end where either body's support is free (its displacement moves
        nothing) has ``across = 0``.

        Returns :class:`EndOffsets` ``(across, gap, tangent)``: across (2,) m, A then B; gap (m,
        ``model.radial_gap``); tangent (2, 3), the unit tangents at A and B (global axes).
        """
        if not (self.contact and len(self.Tc)):
            return None
        if self._end_rows is None:  # (4 x 12: two unit vectors normal to t at each end, on casing - cable)
            rows = np.zeros((4, len(CHANNELS)))
            tangent = np.zeros((2, 3))
            supports = {b: self.model.data[b]["supports"] for b in BODY_NAMES}
            for k, (end, node) in enumerate(zip(SUPPORT_NAMES, (0, -1))):
                t = self.Tc[node] / np.linalg.norm(self.Tc[node])
                tangent[k] = t
                if any(supports[b][end] == "free" for b in BODY_NAMES):
                    continue
                e1 = np.cross(t, np.eye(3)[int(np.argmin(np.abs(t)))])
                e1 /= np.linalg.norm(e1)
                e2 = np.cross(t, e1)
                casing, cable = (CHANNELS.index(f"{b}.{end}.x") for b in BODY_NAMES)
                for j, e in enumerate((e1, e2)):
                    rows[2 * k + j, casing : casing + 3] = e
                    rows[2 * k + j, cable : cable + 3] = -e
            self._end_rows = rows, tangent
        rows, tangent = self._end_rows
        r = rows @ np.asarray(u, dtype=float)[: len(CHANNELS)]
        return EndOffsets(np.hypot(r[0::2], r[1::2]), float(self.gap), tangent)

    def clip_forces(self) -> np.ndarray:
        """(n_clips, 6): the force and moment (N, N.m, global axes) the casing exerts through each
        clip on its support now, in file order."""
        b = self.bodies.get("casing")
        n = 0 if b is None else int(np.count_nonzero(b.mi[:, 4] < 0))  # (a clip: a mount without a support slot)
        out = np.zeros(6 * n)
        if n:
            K.clip_force_outputs(b.mi, b.mF, out, 0)  # (the selection the outputs and the FMU use)
        return out.reshape(n, 6)

    def advance_reconstructed(
        self,
        h: float,
        recon: SupportReconstruction,
        u: np.ndarray,
        v: np.ndarray,
        a: np.ndarray,
        out: np.ndarray,
        base: GridMotion | None = None,
    ) -> None:
        """An FMU communication step: ``m = recon.motion(self.time, h, u, v, a)``,
        ``self.advance(h, m)``, ``recon.accept(m)`` and ``self.output_values(out)`` (h in s; u, v, a
        the support inputs at the step start in m, m/s, m/s2, C-contiguous float64, one per channel
        of :attr:`channels`, or of the 12 of CHANNELS alone: the excited clips' supports then stay
        at rest), with the same results to the bit. When h is a whole number of steps of ``dt`` (at most
        :attr:`CHUNK`) and nothing is recorded, the four are one compiled call
        (``kernels.communication_step_in_context``, on a context of its arrays made once for these
        buffers and this h): the Python and numba dispatch around them otherwise cost as much as
        the ten steps of a 1e-4 s communication step. ``base`` (a
        :class:`~.support_motion.GridMotion` on this engine's dt) is added to the reconstructed
        motion. Errors as :meth:`advance` (the engine and ``recon`` are then as before the call)."""
        undo = None
        try:
            if self.time == 0.0 and not self.record:  # (the run's start, as advance begins it: then one compiled call)
                undo = (self.chan.copy(), self.ledger.copy())
                self._begin(self._reconstructed_motion(recon.motion(self.time, h, u, v, a), base))
            self._step_reconstructed(h, recon, u, v, a, out, base)
        except BaseException:
            if undo is not None:  # (a refused first step leaves no start behind: the engine as before the call)
                np.copyto(self.chan, undo[0])
                np.copyto(self.ledger, undo[1])
            raise

    def _step_reconstructed(self, h, recon, u, v, a, out, base):
        """:meth:`advance_reconstructed`'s step, its run begun."""
        law = self._law()
        key = (h, self.dt, self.ledger_on, law)
        held = self._cstep_memo  # the last fused call's (key, recon, u, v, a, out, base, m)
        if (
            held is not None
            and held[0] == key
            and held[1] is recon
            and held[2] is u
            and held[3] is v
            and held[4] is a
            and held[5] is out
            and held[6] is base
            and not self.record
        ):
            m, ctx = held[7], self._cstep_context
        else:
            m, ctx = self._fused_context(key, recon, u, v, a, out, base)
        k0 = base.grid_index(self.time) if base is not None else 0
        if ctx is None or k0 is None:
            self._cstep_memo = None  # recon.motion may change recon's G
            quintic = recon.motion(self.time, h, u, v, a)
            self.advance(h, self._reconstructed_motion(quintic, base))
            recon.accept(quintic)
            self.output_values(out)
            return
        if base is not None:
            base.fill(k0, self._cstep_scratch[4])
        t0 = self.time
        # the step itself saves the state for the roll-back, zeroes the per-call counters, and
        # accepts the supports' new state into recon.state when it succeeds
        if self._cstep_entry is None:
            status = K.communication_step_in_context(ctx, t0, self.dt, h, self._pot0)  # compiles or loads it
            self._cstep_entry = compiled_entry(K.communication_step_in_context, (ctx, t0, self.dt, h, self._pot0))
        else:
            status = self._cstep_entry(ctx, t0, self.dt, h, self._pot0)
        if status != K.OK:
            _, _, times, motion, *_ = self._cstep_scratch
            try:  # (the error is worded from the step's _info before the restore overwrites it)
                self._raise_for_status(status, motion[0], motion[1], motion[2], times)
            finally:
                self.restore([t0, *self._cstep_scratch[5:]])  # the snapshot the step took of itself
        self.time = self._on_grid(t0 + m * self.dt)

    def _reconstructed_motion(self, quintic, base):
        """The motion of :meth:`advance_reconstructed`'s step: the quintic, plus ``base`` when given."""
        if base is None:
            return quintic
        return lambda t: tuple(self._widen(x) + y for x, y in zip(quintic(t), base(t)))

    def _begin(self, motion) -> None:
        """At a run's start (t = 0, the ledger empty), what its first step needs besides its motion:
        the energy at the start in the ledger (J) and the supports' state at t = 0 in ``chan``
        (where a recomputed first step's sub-steps begin), from ``motion`` (:data:`Motion`); else
        nothing."""
        if self.time != 0.0 or self.ledger.any():
            return
        energy = self._reset_energy
        if energy is None:
            kin, strain = (sum(x) for x in zip(*(b.energy() for b in self.bodies.values())))
            energy = kin + strain + self.contact_potential()
        self.ledger[K.LEDGER_START_ENERGY] = energy
        for row, x in zip(self.chan, motion_arrays(motion, np.array([self.time]))):
            x = np.asarray(x, dtype=float).reshape(-1)
            row[: min(len(x), len(row))] = x[: len(row)]

    def _widen(self, x):
        """A motion's (n, 12) array with zero columns for the model's further channels (an excited
        clip's support at rest unless the model's own scenario moves it)."""
        extra = len(self.channels) - x.shape[1]
        return np.hstack([x, np.zeros((x.shape[0], extra))]) if extra > 0 else x

    def _fused_context(self, key, recon, u, v, a, out, base):
        """(m, the context of :meth:`advance_reconstructed`) when its step ``key[0]`` (s) is one
        compiled call (a whole number m of steps of ``dt``, at most :attr:`CHUNK`, nothing
        recorded, the step loop's arguments built, an input per channel of
        :attr:`channels`), else (m, None); remembered for the next call with the same key and buffers."""
        h, law = key[0], key[3]
        self._checked_out(out)
        m, rest = whole_steps(h, self.dt)
        if not (0 < m <= self.CHUNK and rest == 0.0 and not self.record):
            return m, None
        if not (len(u) == len(v) == len(a) == recon.state.shape[1] == len(self.channels)) or len(recon.state) != 5:
            return m, None  # (inputs of the 12 channels alone for a model with excited clips: widened in advance)
        cached = self._call_args.get((self.dt, self.ledger_on, False, law))
        if cached is None:
            return m, None
        ctx = self._communication_context(cached[0], m, recon, u, v, a, out, base is not None)
        np.copyto(self._cstep_G, recon.coefficient_matrix(h))  # the exact h's (the context holds this array)
        self._cstep_memo = (key, recon, u, v, a, out, base, m)
        return m, ctx

    def _communication_context(self, args, m, recon, u, v, a, out, use_base):
        """The context of :meth:`advance_reconstructed` for these records and buffers (made anew
        when any of them or m changes: the arrays are never rebound, see _allocate_state). Its
        quintic matrix is the engine's own array ``_cstep_G``, which the caller fills with the G of
        each call's exact h: a master whose steps differ in the last bits keeps its context."""
        parts = (args, recon.state, u, v, a, out)
        held = self._cstep_parts
        if held is not None and held[0] == (m, use_base) and all(x is y for x, y in zip(held[1], parts)):
            return self._cstep_context
        n = len(self.channels)
        scratch = (
            np.empty((6, n)),
            np.empty((3, 6, n)),
            np.empty(m),
            np.empty((3, m, n)),
            np.zeros((3, m, n)),
            np.empty_like(self._fbuf),  # the roll-back copy of the state
            np.empty_like(self._ibuf),
        )
        G = self._cstep_G
        fields = (G, recon.state, u, v, a, *scratch[:5], bool(use_base), *args, self._no_record, self._info, out)
        ctx = K.new_communication_context(*fields, self._fbuf, self._ibuf, *scratch[5:])
        self._cstep_parts, self._cstep_context, self._cstep_scratch = ((m, use_base), parts), ctx, scratch
        return ctx

    def outputs(self) -> dict[str, float]:
        """Current outputs ``{name: value}`` for the names in :attr:`output_names` (N, N.m, m, J)."""
        out = dict(zip(self.output_names, self.output_values().tolist()))
        out["contact.active"] = int(out["contact.active"])
        return out

    def history(self, sparse: bool = False) -> dict[str, np.ndarray]:
        """Recorded histories (``record=True``) over all steps so far: ``support_forces`` (n x 24,
        N and N.m, :data:`SUPPORT_OUTPUTS`) and, per cable node, ``contact_state`` (0 open, 1 stick,
        2 slip), ``normal_force`` (N) and ``penetration`` (m), each n x nodes. The rows are the steps
        this engine took, in order: :meth:`set_state` does not rewind or extend them (a state is not
        a history), only a failed :meth:`advance` drops its own.

        The engine stores the contact histories sparse (the nodes in contact at the end of each
        step: about 2 of 36 in the default scenario, some 40 bytes per step instead of 600);
        ``sparse=True`` returns them so, as ``contact_step``, ``contact_node`` (row and column of
        each entry) with ``contact_state``, ``normal_force`` and ``penetration`` of that entry."""
        if not self._hist:
            return {}
        F = np.concatenate([h[0] for h in self._hist])
        rows = np.concatenate([np.repeat(np.arange(len(h[0])), np.diff(h[1])) for h in self._hist])
        rows += np.repeat(np.cumsum([0] + [len(h[0]) for h in self._hist[:-1]]), [len(h[2]) for h in self._hist])
        node, state, N, g = (np.concatenate([h[i] for h in self._hist]) for i in range(2, 6))
        if sparse:
            return {
                "support_forces": F,
                "contact_step": rows,
                "contact_node": node,
                "contact_state": state,
                "normal_force": N,
                "penetration": g,
            }
        shape = (len(F), len(self.Xc))
        out = {
            "support_forces": F,
            "contact_state": np.zeros(shape, np.int8),
            "normal_force": np.zeros(shape),
            "penetration": np.zeros(shape),
        }
        for key, v in (("contact_state", state), ("normal_force", N), ("penetration", g)):
            out[key][rows, node] = v
        return out


def state_to_bytes(state: Mapping[str, ArrayLike]) -> bytes:
    """Serialise a state dict of arrays (np.savez, no pickle)."""
    buf = io.BytesIO()
    np.savez(buf, **state)
    return buf.getvalue()


def state_from_bytes(data: bytes) -> dict[str, np.ndarray]:
    """Inverse of :func:`state_to_bytes`."""
    with np.load(io.BytesIO(bytes(data)), allow_pickle=False) as z:
        return {k: z[k] for k in z.files}
