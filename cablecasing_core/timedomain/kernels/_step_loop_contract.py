"""What the step loop (:func:`run_steps`) takes and gives back, by name: the argument records of a
body, of the contact law and of the contact, the recording buffers, the status codes, the contact
states, and the names of the slots of the ledger, info and diag arrays. The engine and the kernels
both use these names; numba reads the slot names as compile-time constants.
"""

from __future__ import annotations

from collections import namedtuple

# contact state of a cable node (int64 in the engine's state, int8 in the recorded history)
OPEN, STICK, SLIP = 0, 1, 2

# status codes of run_steps
OK, ERR_NAN, ERR_PENETRATION, ERR_SEARCH, ERR_INPUT = 0, 1, 2, 3, 4

# the energy ledger (J; the last two W), accumulated by the trapezoidal rule
LEDGER_SUPPORT_WORK = 0  # work done by the supports on both bodies
LEDGER_RAYLEIGH_DISSIPATION = 1  # dissipated by Rayleigh damping (only with ledger_on)
LEDGER_START_ENERGY = 2  # energy at the start of the run (set by the engine)
LEDGER_FRICTION_DISSIPATION = 3  # dissipated by friction in the contacts
LEDGER_CONTACT_WORK = 4  # work of the contact forces on both bodies
LEDGER_DAMPING_DISSIPATION = 5  # dissipated by the contact damper
LEDGER_FRICTION_POWER = 6  # friction power of the last step (W)
LEDGER_DAMPING_POWER = 7  # contact-damping power of the last step (W)
LEDGER_MOUNT_DISSIPATION = 8  # dissipated by the dampers of the isolators and clips
LEDGER_SIZE = 9

# the info array: what went wrong (status != OK), then running totals of the contact solve
INFO_TIME = 0  # time of the failure (s); the end time after OK
INFO_NODE = 1  # cable node of the failure, -1 for the support forces
INFO_VALUE = 2  # the offending value (a penetration in m, a force sum in N)
INFO_INPUT_ROW = 0  # ERR_INPUT: row of the support motion,
INFO_INPUT_CHANNEL = 1  #   its channel (index into CHANNELS),
INFO_INPUT_KIND = 2  #   0, 1, 2 for displacement, velocity, acceleration
INFO_NEWTON_ITERATIONS = 3  # contact Newton iterations, summed over steps
INFO_ACTIVE_SET_PASSES = 4  # stick/slip and active-set passes, summed over steps
INFO_UNCONVERGED_STEPS = 5  # steps in which a contact Newton did not converge
INFO_REFINED_STEPS = 6  # steps recomputed in sub-steps (ContactLaw.nsub): events and the tolerance's
INFO_TOLERANCE_STEPS = 7  # of them, those recomputed for their estimated local error (ContactLaw.tol)
INFO_MAX_LOCAL_ERROR = 8  # m: the largest local error estimated for a (sub-)step kept (with ContactLaw.tol > 0)
INFO_SIZE = 9

# the diag array of one contact solve (one step)
DIAG_MAX_PENETRATION = 0  # m
DIAG_NEWTON_FAILED = 1  # 1.0 when the last pass's Newton did not converge (the forces kept are its last iterate)
DIAG_DAMPING_POWER = 2  # W, N_d g_dot of the contact damper
DIAG_FRICTION_POWER = 3  # W, -P_t . w_t
DIAG_NEWTON_ITERATIONS = 4  # summed over the step's passes
DIAG_ACTIVE_SET_PASSES = 5
DIAG_SLOW_SLIP = 6  # 1.0 when a slipping contact's friction could reverse its slip in the step, turning
DIAG_SLIP_REVERSED = 7  # 1.0 when a contact slipping at the last solve slips again with its friction turned > pi/2
DIAG_SIZE = 8
#: rad: a slowly slipping contact is an event of the step (DIAG_SLOW_SLIP) only when its friction force
#: turned by more than this since the last solve (by EVENT_TURN / nsub in a sub-step); a slow slip that
#: keeps its direction is integrated as well by the step as by its sub-steps (docs/time_domain.md, the
#: table of the turn)
EVENT_TURN = 0.2

#: One body for the step loop (SI units; arrays in the engine's storage, see the engine's _Body).
#: on: the body is there and has free DOFs; Md, Kd: M and K in diagonal storage; Dinv, L, LT: the
#: block LDL^T factor of the effective stiffness over the node blocks g0 .. g0+ng-1 that hold the
#: free DOFs f0 .. f0+nf-1; alpha (1/s), beta (s): Rayleigh factors; U, V, A: the state (m, m/s,
#: m/s2 and rad...); pres, pchan, pslot: the prescribed DOFs, their support channel (-1 for a
#: rotation) and their slot among the support's six reactions; Kinv: the effective compliance
#: (m/N) over all DOFs, zero on the prescribed ones; sup, sup_lo: the rows of M and K of the
#: prescribed DOFs over their band and its first column; cpl_i, cpl_v: the stiffness between free
#: and prescribed DOFs as triplets; fc: the generalized contact forces on the body (N, N.m);
#: loaded: the body carries a constant load at rest (an installed model, docs/installed.md): fext
#: (N, N.m, all DOFs) the load, uext (m, rad) the free DOFs' response Keff^-1 fext to it, which the
#: step adds to the contact-free predictor, and fext at the prescribed DOFs goes into the reactions.
#: the mounts (isolators and clips, ``structure/mount_element.py``): mi (nm, 5) int64 rows [first
#: DOF of the node, channels of the support's x, y, z (-1: fixed), reaction slot (-1: a clip)],
#: mKC (nm, 2, 6, 6) their stiffness K6 and damping C6 in global axes, mb (nm, 2, 6) the
#: supports' displacement and velocity now, mF (nm, 6) the force through each mount now (N, N.m).
#: fDinv, fL, fLT, fKinv, fuext: Dinv, L, LT, Kinv and uext at the sub-step dt / nsub of a step
#: recomputed around a contact event (``ContactLaw.nsub``; the same arrays when nsub = 1).
BodyArrays = namedtuple(
    "BodyArrays",
    "on Md Kd Dinv L LT g0 ng f0 nf alpha beta U V A pres pchan pslot Kinv sup sup_lo cpl_i cpl_v fc loaded fext uext "
    "mi mKC mb mF fDinv fL fLT fKinv fuext",
)

#: The contact law and its switches: on (contact between the bodies), gap (m, radial gap e of
#: Eqs. 30-31), r_in (m, casing inner radius), r_cable (m, the penetration that counts as a
#: blow-up), law (the index in ``model.schema.CONTACT_LAWS``: 0 Hertz, Eq. 29; 1 linear, Eq. 24;
#: 2 Hunt-Crossley), k_lin (N/m), k_hertz (N/m^1.5), c_n (kg/s, contact damping, Eq. 16; for
#: Hunt-Crossley its 3/2 alpha in s/m), mu (Coulomb friction coefficient), v_stick (m/s, stick
#: band); nsub: a step in which a closed contact switches between stick and slip, slips so slowly
#: that its friction could reverse the slip within the step, or reverses its slip (DIAG_SLIP_REVERSED),
#: is recomputed as nsub equal sub-steps (1: never; ``contact.event_substeps``, docs/time_domain.md
#: "Events inside the step"); reuse: its sub-steps after the first keep the Delassus matrix while the
#: same contacts are closed.
#: vreg (m/s): 0 for the switch law of Section 2.1; > 0 for Coulomb's law regularised over that
#: slip speed (``contact.friction_law = "regularized"``, docs/time_domain.md), no stick-slip events.
#: tol (m): 0, or a step whose estimated local error in displacement, dt^2 / 12 max |a_(n+1) - a_n|
#: over the translations of both bodies (Zienkiewicz and Xie's estimate for beta = 1/4), exceeds it
#: is recomputed as nsub sub-steps too (``contact.event_tolerance``, docs/time_domain.md "A tolerance
#: instead of a bare step").
ContactLaw = namedtuple("ContactLaw", "on gap r_in r_cable law k_lin k_hertz c_n mu v_stick nsub reuse vreg tol")

#: The contact's geometry at rest and its memory: Xc, Tc (cable nodes and unit tangents), Xs, Rs,
#: Ls (casing nodes, element frames and lengths); per cable node: state (OPEN/STICK/SLIP), elem
#: and xi (the casing element and its coordinate last found), Pn (N, contact force), vrel (m/s,
#: tangential relative speed), N (N, normal force), g (m, penetration), time (s in contact);
#: ws: the contact solve's scratch (``contact_workspace``); chan (3, n channels): the support
#: channels' displacement, velocity and acceleration now (m, m/s, m/s2), where the sub-steps' motion
#: of a recomputed step starts; subG (18 x 6): the quintic Hermite's coefficient matrix of the step
#: dt (``support_motion._coefficient_matrix``) that carries it to the step's end; again (1,): 1 when
#: the last step ended in its sub-steps with an event still on, so that the next starts in them;
#: share (one per cable node, dimensionless): the node's share of the contact law, its stiffness and
#: damper (``engine.contact_shares``: 1 everywhere unless ``contact.law_length`` > 0).
ContactArrays = namedtuple("ContactArrays", "Xc Tc Xs Rs Ls state elem xi Pn Pp vrel N g time ws chan subG again share")

#: The step loop's scratch, made once per engine and time step (``step_scratch``) instead of at every
#: call of :func:`run_steps`, whose allocations and their reference counts cost ~5 us a call (a fifth
#: of an FMU call of three steps, docs/performance-history.md): the bodies' state at the step's start
#: (sUo .. cAo, the mounts' smbo .. cmFo), the predictors' and ledgers' work arrays (sy1, sr, cy1,
#: cr, sq, cq), the step's new contact forces and reactions (fcs_new, fcc_new, reac_new), the contact
#: solve's diag, the contact memory at the step's start (state0 .. gn0) and the sub-steps' motion
#: (subrows, subc, subt, subm). run_steps sets each as it did when it made them.
StepScratch = namedtuple(
    "StepScratch",
    "sUo sVo sAo cUo cVo cAo smbo smFo cmbo cmFo sy1 sr cy1 cr sq cq fcs_new fcc_new reac_new diag state0 elem0 "
    "xi0 Pn0 Pp0 vrel0 Nn0 gn0 subrows subc subt subm",
)


def step_scratch(casing, cable, contact, nch, nsub):
    """The :class:`StepScratch` of run_steps for these records (:class:`BodyArrays` of both bodies,
    :class:`ContactArrays`), ``nch`` support channels and ``nsub`` sub-steps of a recomputed step."""
    import numpy as np  # (the contract module itself needs no numpy)

    def work(body):
        n, b = body.U.shape[0], (body.Md.shape[0] - 1) // 2
        return np.zeros(n + 2 * b), np.zeros(max(body.ng, 1)), np.zeros((2, n)), np.zeros(n)

    sy1, sr, sq, fcs_new = work(casing)
    cy1, cr, cq, fcc_new = work(cable)
    like = [np.zeros_like(x) for x in (casing.U, casing.V, casing.A, cable.U, cable.V, cable.A)]
    mounts = [np.zeros_like(x) for x in (casing.mb, casing.mF, cable.mb, cable.mF)]
    memory = [np.zeros_like(x) for x in (contact.state, contact.elem, contact.xi, contact.Pn, contact.Pp)]
    memory += [np.zeros_like(x) for x in (contact.vrel, contact.N, contact.g)]
    nm = max(nsub, 1)
    return StepScratch(
        *like, *mounts, sy1, sr, cy1, cr, sq, cq, fcs_new, fcc_new, np.zeros(24), np.zeros(DIAG_SIZE), *memory,
        np.zeros((6, nch)), np.zeros((3, 6, nch)), np.zeros(nm), np.zeros((3, nm, nch)),
    )  # fmt: skip


#: Recorded histories, written by step k into row off + k: on, F (n x 24 reactions), and the
#: sparse contact history ptr, node, state, N, g (see run_steps).
Recording = namedtuple("Recording", "on F ptr node state N g off")
