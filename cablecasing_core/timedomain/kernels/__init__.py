"""The numba kernels of the time domain, split by concern into private modules, compiled as ONE
cache unit.

=======================================  ==============================================================
module                                   what
=======================================  ==============================================================
``_step_loop_contract.py``               the records :func:`run_steps` takes, status codes, contact
                                         states, the names of the ledger, info and diag slots
``_banded_products_and_block_solve.py``  products in diagonal storage, the block-tridiagonal solve
``_hermite_interpolation.py``            the casing axis and the interpolation matrix on an element (Eq. 9)
``_contact_search_and_law.py``           normal-plane search (Eqs. 36-39; frame Eqs. 32-35), contact law (Eqs. 24, 29;
                                         its Hertz constant, Eqs. 27-28, is ``engine.hertz_constant``)
``_contact_newton_for_fixed_modes.py``   the contact forces for fixed stick/slip modes (Eqs. 15-23)
``_contact_forces_with_active_set.py``   the implicit contact solve of a step (Eqs. 14-24, 29-39)
``_newmark_per_body.py``                 one body's predictor, update and reactions (Eqs. 13, 18)
``_newmark_step_loop_with_ledger.py``    the step loop over both bodies and the contact, energy ledger
``_quintic_support_motion.py``           the support motion inside an FMU communication step
``_communication_step_with_quintic_motion.py``  an FMU communication step in one call: motion, steps, outputs
``_static_contact.py``                   every cable node's frictionless contact at a state (the static state)
``_compile_options.py``                  ``fastmath`` flags, compilation without the runtime
``_numba_cache.py``                      where the machine code is cached (compiles nothing)
=======================================  ==============================================================

**Why one cache unit.** numba caches each ``cache=True`` function by its own source file and does
not invalidate that cache when a function it calls or inlines changes in *another* file: the step
loop would go on running the machine code of an old contact solve. So the package is one unit:
:mod:`._numba_cache` is installed here, before any kernel is decorated, and keys the cache of every
kernel on a hash of all the package's source files (:data:`KERNELS_HASH`); any edit to any file of
the package recompiles all of it, into a new folder (:func:`kernels_cache_dir`; a fallback folder,
or no cache, when the usual one cannot be written, said in a warning). Keep every numba kernel of
cablecasing_core in this package, and nothing else.

All kernels are plain functions over arrays. The orchestration (building matrices, factorising,
evaluating the support motion, packing results) stays in plain Python in ``timedomain/engine.py``
and ``timedomain/support_motion.py``. Nothing in a step or a call of the step loop allocates: the
engine makes the contact solve's workspace (:func:`contact_workspace`) and the step loop's scratch
(:func:`step_scratch`) once, and scalar helpers return tuples. The effective compliance (dense, over
all DOFs of a body, zero on the prescribed ones) gives the Delassus matrix of the contacts; the
bodies' response to the contact forces is one more solve with the step's block factor. The small
helpers of the contact solve are inlined into their callers (``inline="always"``).

``fastmath`` (``_compile_options.py``): none. A flag such as contraction into FMA acts only where
LLVM inlines a callee, and it inlines only callees compiled in the same process, not those loaded
from numba's cache; so with it a cold and a warm cache gave different records. Without, a run is
reproducible to the bit in any process, compiled or loaded (the FMU is checked against the core to
the bit on a chaotic contact run, and a compiling FMU against a loading one).

Reference counting: numba increments the reference count of every array a function receives on
entry and decrements it on every exit (atomic operations, each a barrier for the memory pipeline).
LLVM's pruning pass removes these pairs in small functions, but gives up on large ones. The
kernels the step loop calls that would have them, and never allocate, are compiled without the
runtime (``NO_RT``), and so are :func:`run_steps` itself and the FMU's :func:`communication_step`
(their records' ~100 arrays are then not counted at each call: an FMU call 0.96-0.98 of its cost
with them; the context's fields are still counted as it reads them, which a structref needs the
runtime for). For the same reason
no call inside the step loop passes more than 30 arguments (Python then passes them as one built
tuple, whose every array numba counts around the call), and :func:`run_steps` unpacks its records
(:class:`BodyArrays`, :class:`ContactLaw`, :class:`ContactArrays`, :class:`StepScratch`,
:class:`Recording`) once, before its loop: a record's array read inside the loop would be counted at
every step. docs/performance.md has the figures.

The interpreter's lock: the two entry points Python calls for a run's steps, :func:`run_steps` and
:func:`communication_step_in_context`, are compiled ``nogil``. They touch no Python object and
write only their engine's arrays (no kernel writes a module-level array: numba freezes those as
constants), so runs and FMU instances on several threads step in parallel (docs/performance.md, "A
master's thread pool"). A kernel that kept a buffer of its own between calls would break that.
"""

from ._numba_cache import KERNELS_HASH, install, kernels_cache_dir, settle

install()  # before any cache=True kernel below is decorated

from ._banded_products_and_block_solve import block_solve  # noqa: E402
from ._communication_step_with_quintic_motion import (  # noqa: E402
    clip_force_outputs,
    communication_step,
    communication_step_in_context,
    new_communication_context,
    step_outputs,
)
from ._contact_forces_with_active_set import contact_workspace, solve_contact_forces  # noqa: E402
from ._contact_search_and_law import contact_law, contact_potential, search_node  # noqa: E402
from ._hermite_interpolation import axis_at, element_dofs, hermite_cubics, hermite_matrix, hermite_matrix_slope  # noqa: E402
from ._newmark_per_body import newmark_coefficients  # noqa: E402
from ._newmark_step_loop_with_ledger import run_steps  # noqa: E402
from ._quintic_support_motion import accept_rows, quintic_coefficients, quintic_values, taylor_rows  # noqa: E402
from ._static_contact import static_contact  # noqa: E402
from ._step_loop_contract import (  # noqa: E402
    DIAG_ACTIVE_SET_PASSES,
    DIAG_DAMPING_POWER,
    DIAG_FRICTION_POWER,
    DIAG_MAX_PENETRATION,
    DIAG_NEWTON_FAILED,
    DIAG_NEWTON_ITERATIONS,
    DIAG_SIZE,
    DIAG_SLIP_REVERSED,
    DIAG_SLOW_SLIP,
    ERR_INPUT,
    ERR_NAN,
    ERR_PENETRATION,
    ERR_SEARCH,
    EVENT_TURN,
    INFO_ACTIVE_SET_PASSES,
    INFO_INPUT_CHANNEL,
    INFO_INPUT_KIND,
    INFO_INPUT_ROW,
    INFO_MAX_LOCAL_ERROR,
    INFO_NEWTON_ITERATIONS,
    INFO_NODE,
    INFO_REFINED_STEPS,
    INFO_SIZE,
    INFO_TIME,
    INFO_TOLERANCE_STEPS,
    INFO_UNCONVERGED_STEPS,
    INFO_VALUE,
    LEDGER_CONTACT_WORK,
    LEDGER_DAMPING_DISSIPATION,
    LEDGER_DAMPING_POWER,
    LEDGER_FRICTION_DISSIPATION,
    LEDGER_FRICTION_POWER,
    LEDGER_MOUNT_DISSIPATION,
    LEDGER_RAYLEIGH_DISSIPATION,
    LEDGER_SIZE,
    LEDGER_START_ENERGY,
    LEDGER_SUPPORT_WORK,
    OK,
    OPEN,
    SLIP,
    STICK,
    BodyArrays,
    ContactArrays,
    ContactLaw,
    Recording,
    StepScratch,
    step_scratch,
)

settle()  # after every kernel is decorated, before any is called (a cache folder that cannot be written)

__all__ = [
    "clip_force_outputs",
    "communication_step",
    "communication_step_in_context",
    "new_communication_context",
    "step_outputs",
    "DIAG_ACTIVE_SET_PASSES",
    "DIAG_DAMPING_POWER",
    "DIAG_FRICTION_POWER",
    "DIAG_MAX_PENETRATION",
    "DIAG_SLIP_REVERSED",
    "DIAG_SLOW_SLIP",
    "DIAG_NEWTON_FAILED",
    "DIAG_NEWTON_ITERATIONS",
    "DIAG_SIZE",
    "ERR_INPUT",
    "ERR_NAN",
    "ERR_PENETRATION",
    "ERR_SEARCH",
    "EVENT_TURN",
    "INFO_ACTIVE_SET_PASSES",
    "INFO_INPUT_CHANNEL",
    "INFO_INPUT_KIND",
    "INFO_INPUT_ROW",
    "INFO_NEWTON_ITERATIONS",
    "INFO_NODE",
    "INFO_SIZE",
    "INFO_TIME",
    "INFO_REFINED_STEPS",
    "INFO_TOLERANCE_STEPS",
    "INFO_MAX_LOCAL_ERROR",
    "INFO_UNCONVERGED_STEPS",
    "INFO_VALUE",
    "LEDGER_CONTACT_WORK",
    "LEDGER_DAMPING_DISSIPATION",
    "LEDGER_DAMPING_POWER",
    "LEDGER_FRICTION_DISSIPATION",
    "LEDGER_FRICTION_POWER",
    "LEDGER_MOUNT_DISSIPATION",
    "LEDGER_RAYLEIGH_DISSIPATION",
    "LEDGER_SIZE",
    "LEDGER_START_ENERGY",
    "LEDGER_SUPPORT_WORK",
    "OK",
    "OPEN",
    "SLIP",
    "STICK",
    "KERNELS_HASH",
    "BodyArrays",
    "ContactArrays",
    "ContactLaw",
    "Recording",
    "StepScratch",
    "step_scratch",
    "accept_rows",
    "axis_at",
    "block_solve",
    "contact_law",
    "contact_potential",
    "contact_workspace",
    "element_dofs",
    "hermite_cubics",
    "hermite_matrix",
    "hermite_matrix_slope",
    "kernels_cache_dir",
    "newmark_coefficients",
    "quintic_coefficients",
    "quintic_values",
    "run_steps",
    "search_node",
    "solve_contact_forces",
    "static_contact",
    "taylor_rows",
]
