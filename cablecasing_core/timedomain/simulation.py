"""Orchestration of a time-domain run: the scenario's motion through the engine, with results.

>>> import cablecasing_core as cc
>>> res = cc.simulate(cc.load_model(), duration=0.05)
>>> res.support_force("casing.B.Fz")       # N, one value per time step
"""

from __future__ import annotations

import math
import os
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike
from scipy import signal

from ..errors import ModelError, ModelWarning, SolverWarning, plain
from ..model.limits import check_time_domain
from ..model.schema import CONTACT_OUTPUTS, INPUTS, OUTPUTS, SUPPORT_OUTPUTS, clip_outputs, inputs_of, lookup
from ..model.validate import step_checks
from ..model.validators import Choice, check_model, seconds
from .engine import ROUNDING_OF_TIME, SHORTEST_STEP, Engine, motion_arrays
from .scenario import harmonic_lines, scenario_motion, warn_short_tables

if TYPE_CHECKING:
    from ..model import Model
    from ..records import Records
    from .scenario import Motion

#: Steps per call of Engine.advance when a run shows its progress: a whole number of the engine's
#: chunks, so the run is split where the engine splits it anyway (the record is bitwise the same).
PROGRESS_STEPS = 8 * Engine.CHUNK
#: The part of the new Nyquist frequency up to which :func:`decimate` is flat (0.01 dB).
PASSBAND = 0.7
_NODE_ARRAYS = ("contact_state", "normal_force", "penetration")
#: Rows of the support motion evaluated at once when a run's inputs are recorded (65536 rows of 36
#: inputs: 19 MB), so that a long run's motion is never held whole (:func:`_recorded_inputs`).
INPUT_PIECE = 65536


@dataclass
class SimulationResult:
    """Histories of a run (SI units).

    time (s, n); support_forces (N, N.m; n x 24 in the order of ``SUPPORT_OUTPUTS``: the
    force each body exerts on each support, then six per clip of the casing, the force it exerts
    through the clip: ``force_names``); contact_state (n x nodes: 0 open, 1 stick, 2 slip);
    normal_force (N) and penetration (m) per cable node; contact_time (s per cable node: the
    highest-contact-area histogram of Fig. 22); curvature (1/m per node); arc_length (m per node);
    energies (J, plain floats: :meth:`Engine.energies`); inputs: {name: (n,)} the support motion
    of the driven channels at ``time`` (``casing.A.az`` m/s2 etc., ``model.schema.INPUTS``): the
    channels the scenario's excitations drive, or, for a run of a motion of its own, the channels
    whose displacement, velocity or acceleration that motion makes non-zero in the run. ``time``
    holds the end of each step (dt, 2 dt, ..., T); the state at t = 0 is kept apart (``initial_*``)
    and :meth:`records` puts it first, so that a record starts at t = 0. solver: what the step loop
    did, ``steps`` (of dt), ``refined_steps`` (recomputed in ``event_substeps`` sub-steps around a contact event or for
    the tolerance, docs/time_domain.md), ``event_steps`` (of them, around an event),
    ``tolerance_steps``, ``max_local_error`` (m) and ``tolerance_met`` with ``event_tolerance`` (m;
    :func:`solver_report`), the contact Newton's ``newton_iterations`` and ``unconverged_steps``.
    """

    time: np.ndarray
    support_forces: np.ndarray
    contact_state: np.ndarray
    normal_force: np.ndarray
    penetration: np.ndarray
    contact_time: np.ndarray
    curvature: np.ndarray
    arc_length: np.ndarray
    energies: dict
    inputs: dict = field(default_factory=dict)
    force_names: tuple = SUPPORT_OUTPUTS
    solver: dict = field(default_factory=dict)
    #: the state at t = 0, before the first step: the support and clip outputs (in ``force_names``
    #: order), (``contact.active``, ``contact.max_penetration``) and the driven inputs {name: value};
    #: None for a result without it (then :meth:`records` starts at the first step's end)
    initial_forces: np.ndarray | None = None
    initial_contact: tuple = (0.0, 0.0)
    initial_inputs: dict = field(default_factory=dict)
    #: the frequency (Hz) up to which the histories hold the run's content unaltered: None for a
    #: run, which holds it up to the Nyquist frequency; a result loaded from a record decimated with
    #: the filter (:meth:`load`) keeps that record's passband, and :meth:`records` passes it on
    passband_hz: float | None = None
    #: True for a result loaded from a record that states no passband (a picked one): its histories
    #: may hold content aliased from above their Nyquist frequency, and no record of it states one
    aliased: bool = False
    #: the frequencies (Hz) of the scenario's harmonic excitations (``scenario.harmonic_lines``; ()
    #: for a run of a motion of its own): its records state them, so that band levels keep whole
    #: periods of them by default (``records.Records.default_skip``)
    lines_hz: tuple = ()
    #: the supports' fade-in (s; ``scenario.ramp``, 0 for a run of a motion of its own): its records
    #: state it, so that band levels leave out at least that start by default
    ramp_s: float = 0.0

    def support_force(self, name: str) -> np.ndarray:
        """History of one support output, e.g. ``"casing.B.Fz"`` or a clip's ``"casing.clip0.Fy"``
        (N or N.m), or of a sum of them (``"net.B.Fz"``, ``"paths.Fz"``, ``"a+b"``: the force on
        what those supports hold, :func:`~cablecasing_core.records.derived_terms`): a copy, yours to
        change (``f -= f.mean()`` leaves the result, its :meth:`records` and :meth:`save` as they
        were). A name that is neither among :attr:`force_names` nor a sum of them raises
        :class:`~cablecasing_core.errors.ModelError` naming ``output``."""
        if name in self.force_names:
            return self.support_forces[:, self.force_names.index(name)].copy()
        from ..records import Records, check_column_name, unit_of

        check_column_name(name, self.force_names, "output")
        forces = {n: self.support_forces[:, i] for i, n in enumerate(self.force_names)}
        rec = Records(time=self.time, columns=forces, units={n: unit_of(n) for n in forces})
        return rec.column(name, "output").copy()

    def records(self, output_interval: float | None = None, decimation: str = "filter") -> Records:
        """The run as a :class:`~cablecasing_core.records.Records` on the grid t = 0, Δ, 2Δ, ..., T
        (Δ = ``output_interval`` s, a whole number of time steps; default every step; T the end of
        the run when the duration is a whole number of Δ; a run whose duration is not a whole number
        of steps ends with a shorter step, off the grid, which the record leaves out: it ends at the
        last whole step, so that it is evenly sampled): the support and clip outputs,
        ``contact.active`` (cable nodes in contact), ``contact.max_penetration`` (m) and the driven
        inputs. The row at t = 0 is the state the run starts from (at rest, or an installed model's
        static state), as an FMU reports it at its first communication point: exactly so where the
        samples are picked; the filter blends the first and last ~17 rows with the record's
        continuation by its end samples (:func:`decimate`).

        ``decimation`` (when Δ > dt): ``"filter"`` (default) low-pass filters the forces and inputs
        before taking every m-th sample (:func:`decimate`: a zero-phase FIR, flat to 0.7 of the new
        Nyquist frequency 1/(2Δ), at least 80 dB down above it, so nothing aliases); ``"pick"``
        takes the samples as they are (content above 1/(2Δ) Hz then aliases). ``contact.active`` and
        ``contact.max_penetration`` are always picked (a count and a maximum are not filtered).
        The per-node histories in ``extra`` are picked at the end of each interval (row k: t = (k+1) Δ);
        a filtered record states its passband, 0.7/(2Δ) Hz, in ``extra["passband_hz"]``, a record of
        every step its Nyquist frequency (nothing aliased; kept in ``.npz`` and ``.csv`` files;
        :attr:`~cablecasing_core.records.Records.passband_hz`); a picked one none; a result loaded from
        such a file keeps its passband (:attr:`passband_hz`), the lower of the two when filtered
        again, and one loaded from a record that states none states none (:attr:`aliased`). Δ longer
        than the run (a record of one row) is refused; a bad ``output_interval`` raises
        :class:`~cablecasing_core.errors.ModelError` naming it.
        """
        from ..records import Records, unit_of

        Choice("filter", "pick")("decimation", decimation)
        m = self._stride(output_interval)
        whole = self.whole_steps
        step = slice(m - 1, whole, m)  # the per-node histories: rows at t = m dt, 2 m dt, ...
        first = self.initial_forces is not None
        time = np.concatenate([[0.0], self.time[:whole]]) if first else self.time[:whole]

        def grid(values, initial, filtered):
            values = values[:whole]
            v = np.concatenate([[initial], values]) if first else values
            if m == 1:
                return v
            return decimate(v, m) if filtered else v[::m]

        filt = decimation == "filter"
        f0 = self.initial_forces if first else [None] * len(self.force_names)
        cols = {n: grid(self.support_forces[:, i], f0[i], filt) for i, n in enumerate(self.force_names)}
        active = np.count_nonzero(self.contact_state, axis=1).astype(float)
        pen = self.penetration.max(axis=1) if self.penetration.shape[1] else np.zeros(len(self.time))
        c0 = self.initial_contact if first else (None, None)
        cols[CONTACT_OUTPUTS[0]] = grid(active, c0[0], False)
        cols[CONTACT_OUTPUTS[1]] = grid(pen, c0[1], False)
        cols.update({n: grid(v, self.initial_inputs.get(n, v[0]), filt) for n, v in self.inputs.items()})
        extra = {n: getattr(self, n)[step] for n in _NODE_ARRAYS}
        extra.update(contact_time=self.contact_time, curvature=self.curvature, arc_length=self.arc_length)
        extra["energies"] = np.array([[k, repr(float(v))] for k, v in self.energies.items()]).reshape(-1, 2)
        extra["starts_at_zero"] = np.array(first)
        if self.lines_hz:
            extra["lines_hz"] = np.array(self.lines_hz, dtype=float)
        if self.ramp_s > 0:
            extra["ramp_s"] = np.array(float(self.ramp_s))
        # (read by Records.passband_hz: bands and lines above it are left out; a record that states none
        # may hold aliases: a picked one, or one of a loaded result that stated none)
        if not (self.aliased or (m > 1 and not filt)):
            loaded = math.inf if self.passband_hz is None else float(self.passband_hz)
            # every step: the run's own samples, nothing aliased from above the Nyquist frequency
            extra["passband_hz"] = np.array(
                min(loaded, PASSBAND / (2 * m * self.dt) if m > 1 else 1.0 / (2.0 * self.dt))
            )
        return Records(time[::m], cols, {n: unit_of(n) for n in cols}, "simulation", extra)

    @property
    def dt(self) -> float:
        """The run's time step (s): ``solver["dt"]``, or for a result read from a file (whose steps
        are whole) the spacing of its times."""
        if "dt" in self.solver:
            return float(self.solver["dt"])
        return float(self.time[1] - self.time[0]) if len(self.time) > 1 else float(self.time[0])

    @property
    def whole_steps(self) -> int:
        """The number of steps of the run that are whole time steps: all of them, or all but the last
        when the duration is not a whole number of steps and the run ended with a shorter one."""
        n = len(self.time)
        last = self.time[-1] - (self.time[-2] if n > 1 else 0.0)
        return n - 1 if n and last < self.dt * (1 - 1e-6) else n

    def _stride(self, output_interval):
        if output_interval is None:
            return 1
        seconds("output_interval", output_interval)
        dt = self.dt
        m = round(output_interval / dt)
        if m < 1 or abs(m * dt - output_interval) > 1e-6 * dt:
            raise ModelError(
                "output_interval", output_interval, f"must be a whole number of time steps (dt = {dt:g} s)"
            )
        whole = self.whole_steps
        if (whole // m + 1 if self.initial_forces is not None else -(-whole // m)) < 2:
            raise ModelError(
                "output_interval",
                output_interval,
                f"must be at most the run's duration ({whole * dt:g} s): a record needs at least two rows",
            )
        return m

    def save(
        self, path: str | os.PathLike, output_interval: float | None = None, decimation: str = "filter"
    ) -> Records:
        """Write the run by suffix (``.csv``, ``.npz``, ``.uff``; :mod:`~cablecasing_core.records`),
        atomically, on the grid t = 0, Δ, ..., T of :meth:`records` (Δ = ``output_interval`` s,
        default every step; ``decimation`` as there). ``.npz`` also keeps the per-node contact
        histories, so :meth:`load` gives the result back. A bad argument raises
        :class:`~cablecasing_core.errors.ModelError` naming it (``path``: a suffix it does not
        write; ``output_interval``); a folder that does not exist, or a failed write,
        :class:`~cablecasing_core.files.WriteError`. Returns the record written (its passband in
        ``extra``, which every suffix keeps)."""
        from ..records import write_records

        rec = self.records(output_interval, decimation)
        write_records(path, rec)
        return rec

    @classmethod
    def load(cls, path: str | os.PathLike) -> SimulationResult:
        """A result written by :meth:`save` to ``.npz`` (every array as it was saved; a decimated
        record's passband too, :attr:`passband_hz`)."""
        from ..records import read_records

        rec = read_records(path)
        missing = [n for n in (*_NODE_ARRAYS, "contact_time", "energies") if n not in rec.extra]
        if missing or not str(path).lower().endswith(".npz"):  # (X.NPZ too, as save writes it)
            raise ModelError("file", str(path), "must be an .npz file written by SimulationResult.save")
        x = rec.extra
        names = SUPPORT_OUTPUTS + tuple(n for n in rec.columns if n.startswith("casing.clip"))
        first = bool(x.get("starts_at_zero", False))  # the row at t = 0 (records())
        cols = {n: v[1:] for n, v in rec.columns.items()} if first else rec.columns
        initial = {}
        if first:
            initial = dict(
                initial_forces=np.array([rec.columns[n][0] for n in names]),
                initial_contact=tuple(float(rec.columns[n][0]) for n in CONTACT_OUTPUTS[:2]),
                initial_inputs={n: float(v[0]) for n, v in rec.columns.items() if _is_input(n)},
            )
        rec = type(rec)(rec.time[1:] if first else rec.time, cols, rec.units, rec.source, rec.extra)
        return cls(
            time=rec.time,
            support_forces=np.column_stack([rec.columns[n] for n in names]),
            force_names=names,
            contact_time=x["contact_time"],
            curvature=x["curvature"],
            arc_length=x["arc_length"],
            energies={str(k): float(v) for k, v in x["energies"]},
            inputs={n: rec.columns[n] for n in rec.columns if _is_input(n)},
            passband_hz=float(x["passband_hz"]) if "passband_hz" in x else None,
            aliased="passband_hz" not in x,
            lines_hz=tuple(float(f) for f in np.atleast_1d(x.get("lines_hz", ()))),
            ramp_s=float(x.get("ramp_s", 0.0)),
            **{n: x[n] for n in _NODE_ARRAYS},
            **initial,
        )


def _is_input(name: str) -> bool:
    """Whether a column of a run's record is one of its driven inputs: a support's (``casing.A.az``,
    :data:`INPUTS`) or an excited clip's, ``<excitation>.z`` (one dot, as ``contact.active`` has,
    which is an output)."""
    return name in INPUTS or (name.count(".") == 1 and name not in CONTACT_OUTPUTS)


def simulate(
    model: Model,
    duration: float | None = None,
    dt: float | None = None,
    contact: bool | None = None,
    motion: Motion | None = None,
    progress: bool = False,
) -> SimulationResult:
    """Run the model's scenario (or ``motion``) for ``duration`` s with time step ``dt`` s.

    ``model`` is a :class:`~cablecasing_core.Model` (anything else raises a ModelError naming
    ``model``). Defaults come from ``[scenario]``; ``contact`` defaults to ``[contact] enabled``.
    ``motion`` (a callable of the times, s, returning the channels' displacements, velocities and
    accelerations, m, m/s, m/s2) replaces the scenario's excitations; the result's
    :attr:`SimulationResult.inputs` then holds the channels it moves (non-zero in the run). ``progress``
    shows a tqdm bar of the simulated time (the run is the same with or without it, bit for bit when
    the duration is a whole number of steps; otherwise the shorter last step's length may differ in
    its last bits, and with it the last row). A model
    without excitations warns (its supports stay at rest), and so does a CSV excitation whose table
    ends before the run (its support then holds its last displacement at rest): both
    :class:`~cablecasing_core.errors.ModelWarning`; what the step loop did not achieve (a contact
    Newton that did not converge, a step above the event tolerance, a contact that made energy) warns
    :class:`~cablecasing_core.errors.SolverWarning`, a ModelWarning too. The step loop integrates
    Eqs. (14-24, 27-34, 36-39; 25-26 are not implemented: ``engine.hertz_constant``) (Newmark,
    docs/time_domain.md). Returns a :class:`SimulationResult`.
    Raises :class:`~cablecasing_core.errors.SimulationError` on blow-up; an interrupt (Ctrl-C)
    propagates as KeyboardInterrupt.
    """
    from ..records import driven_inputs

    check_model(model)
    sc = model.scenario
    duration = sc["duration"] if duration is None else duration
    dt = sc["dt"] if dt is None else dt
    lookup("scenario.duration").check(duration, "duration")
    lookup("scenario.dt").check(dt, "dt")
    if duration < dt:
        raise ModelError("duration", duration, f"must be at least one time step (dt = {dt} s)")
    check_time_domain(model, duration, dt)  # (before any work: model/limits.py)
    if dt != sc["dt"]:
        step_checks(model.data, dt, "dt")
        why = lookup("scenario.dt").implausible(dt)  # (as scenario.dt is checked in a model file)
        if why:
            warnings.warn(f"dt = {dt:g} s is {why}", ModelWarning, stacklevel=2)
    inputs = ()
    given_motion = motion
    still = motion is None and not sc["excitation"]
    if motion is None:
        motion = scenario_motion(model, dt=dt)
        inputs = driven_inputs(model)
        given = duration != sc["duration"]  # (a CSV excitation that ends before the run: warned)
        warn_short_tables(model, duration, "duration" if given else "scenario.duration")
    eng = Engine(model, dt=dt, contact=contact, ledger=True, record=True)
    if still:
        stays = (
            "every output stays at its static value (the reactions of its static state)"
            if eng.static is not None
            else "every output stays zero"
        )
        warnings.warn(
            f"the model {model.source} has no excitation ([scenario.excitation.<name>]): its supports stay at rest "
            f"and {stays} (docs/model_file.md, Excitations)",
            ModelWarning,
            stacklevel=2,
        )
    out0 = eng.output_values().copy()  # the state at t = 0 (records() puts it first)
    _advance(eng, duration, motion, progress)
    for said in eng.solver_warnings():
        warnings.warn(said, SolverWarning, stacklevel=2)
    h = eng.history()
    n = len(h["support_forces"])
    cl = eng.bodies[next(iter(eng.bodies))].system.centerline
    # the step ends; the last ends where the engine is (a duration that is not a whole number of
    # steps ends with a shorter step, or a rest under 1e-2 dt taken by the last step)
    time = dt * np.arange(1, n + 1)
    if n:
        time[-1] = eng.time
    # (of a motion of its own, the channels it moves: those it leaves at zero are not driven)
    recorded = inputs if given_motion is None else None
    inputs, histories, initial = _recorded_inputs(motion, time, inputs_of(model), recorded)
    return SimulationResult(
        time=time,
        support_forces=h["support_forces"],
        contact_state=h["contact_state"],
        normal_force=h["normal_force"],
        penetration=h["penetration"],
        contact_time=eng.contact_time.copy(),
        curvature=cl.curvature,
        arc_length=cl.s,
        energies={k: float(v) for k, v in eng.energies().items()},
        inputs=histories,
        force_names=SUPPORT_OUTPUTS + clip_outputs(model),
        solver=solver_report(eng, n),
        initial_forces=np.concatenate([out0[:24], out0[len(OUTPUTS) :]]),
        initial_contact=(float(out0[24]), float(out0[25])),
        initial_inputs=initial,
        lines_hz=harmonic_lines(model) if given_motion is None else (),
        ramp_s=float(model.scenario["ramp"]) if given_motion is None else 0.0,
    )


def _recorded_inputs(motion, time, names, inputs=None):
    """The support inputs a run records, ``motion`` evaluated once at t = 0 and once at each of
    ``time`` (s, the step ends), in pieces of :data:`INPUT_PIECE` rows: (the inputs, {input: its
    history at ``time``}, {input: its value at t = 0}), the inputs (m, m/s, m/s2) of ``names`` (the
    model's :func:`~cablecasing_core.model.schema.inputs_of`, kind-major) in that order. ``inputs``:
    the ones to record (a scenario's :func:`~cablecasing_core.records.driven_inputs`); None: those of
    the channels whose displacement, velocity or acceleration the motion makes non-zero at t = 0 or
    at any of ``time``, for each such channel its three, as ``driven_inputs`` gives a scenario's.

    The channels moved are learned as the pieces come, so that only their histories are held, not
    those of every input of a long run (10 s at dt = 1e-5 s: 8 MB an input, 288 MB for 36): an
    input's history is kept from the first piece in which it is not +0.0 throughout, and the rows
    before it, +0.0 all, are so in the history (an input at -0.0 is kept as such, bit for bit, until
    it is known not to move)."""
    nch = len(names) // 3
    cols = None if inputs is None else [names.index(name) for name in inputs]
    if cols == []:
        return (), {}, {}
    start = np.hstack(motion_arrays(motion, np.zeros(1), nch))[0]
    moved = start != 0.0
    kept = {}  # (column: its history, from the first piece in which it is not +0.0 throughout)
    for i in range(0, len(time), INPUT_PIECE):
        x = np.hstack(motion_arrays(motion, time[i : i + INPUT_PIECE], nch))
        if inputs is None:
            moved |= np.any(x != 0.0, axis=0)
            cols = np.flatnonzero(np.any((x != 0.0) | np.signbit(x), axis=0))
        for c in cols:
            if c not in kept:
                kept[c] = np.zeros(len(time))
            kept[c][i : i + len(x)] = x[:, c]
    if inputs is None:
        channel = moved.reshape(3, nch).any(axis=0)
        inputs = tuple(names[k * nch + c] for k in range(3) for c in np.flatnonzero(channel))
    cols = [names.index(name) for name in inputs]
    histories = {name: kept[c] if c in kept else np.zeros(len(time)) for name, c in zip(inputs, cols)}
    return inputs, histories, {name: float(start[c]) for name, c in zip(inputs, cols)}


def solver_report(eng: Engine, steps: int) -> dict:
    """What the engine's step loop did over ``steps`` steps: {dt (s, its time step), steps,
    event_substeps, refined_steps
    (around events or for the tolerance), event_steps (around events), tolerance_steps (for the
    tolerance), newton_iterations,
    unconverged_steps} (counts), friction_law ("switch" or "regularized": with the latter there
    are no stick-slip events), event_tolerance (m, 0: off), max_local_error (m: the largest
    estimated local error of a step or sub-step kept, with a tolerance; docs/time_domain.md, "A
    tolerance instead of a bare step") and tolerance_met (False when max_local_error exceeds a
    tolerance; :meth:`Engine.solver_warnings` says why, and
    ``simulate`` warns it)."""
    its, _, failed = (int(x) for x in eng.solver_counts)
    return {
        "friction_law": eng.model.contact["friction_law"],
        "dt": eng.dt,
        "steps": int(steps),
        "event_substeps": eng.event_substeps,
        "refined_steps": eng.refined_steps,
        "event_steps": eng.event_steps,
        "event_tolerance": eng.event_tolerance,
        "tolerance_steps": eng.tolerance_steps,
        "max_local_error": eng.max_local_error,
        "tolerance_met": eng.tolerance_met,
        "newton_iterations": its,
        "unconverged_steps": failed,
    }


def decimate(x: ArrayLike, m: int) -> np.ndarray:
    """Every ``m``-th sample of ``x`` (starting with the first) after a low-pass filter against
    aliasing: ``scipy.signal.resample_poly`` (polyphase, zero phase: the FIR is symmetric and its
    delay compensated) with a Kaiser-window FIR from ``scipy.signal.kaiserord``/``firwin`` that is
    flat (0.01 dB) to 0.7 of the new Nyquist frequency fs/(2m) and at least 80 dB down above it;
    the record is continued beyond its ends by its first and last sample (``padtype="edge"``: a run
    is at rest, or in its static state, before t = 0), so a static preload leaves no edge step.
    Samples within about 17 output steps of either end see that continuation (and a sudden start
    rings there as any low-passed step does). Returns ``ceil(len(x) / m)`` samples (unit of x)."""
    x = np.asarray(x, float)
    m = int(m)
    if m == 1:
        return x.copy()
    # (designed for 82 dB: kaiserord's estimate for 80 dB falls short by up to 1.3 dB near the band
    # edge for small m, 78.7 dB at m = 2; 82 dB gives at least 81 dB for every m)
    numtaps, beta = signal.kaiserord(82.0, (1 - PASSBAND) / m)
    h = signal.firwin(numtaps | 1, 0.85 / m, window=("kaiser", beta))
    return signal.resample_poly(x, 1, m, window=h, padtype="edge")


def simulate_sampled(
    model: Model, step: float, duration: float, table: np.ndarray | None = None, contact: bool | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """The core's run of what an FMU master gets that sends the model's scenario sampled every
    ``step`` s: the inputs (u, v, a of the model's channels, m, m/s, m/s2: the 12 supports', then
    an excited clip's) at the communication points t_k = k step (``table`` (n, 3 x channels): the
    channels' displacements, then their velocities, then their accelerations, as the FMU's inputs;
    for the 12 supports ``model.schema.INPUTS``; default the scenario's record at k = 0..n-1,
    n = round(duration / step)), each communication step's motion reconstructed as the FMU does
    (:class:`~.support_motion.SupportReconstruction`), one ``Engine.advance(t_(k+1) - t_k)`` per
    input row. The steps are the differences of the points
    as a master computes them in floating point (fmpy: ``(k + 1) h - k h``, which differs from h in
    the last bits; the contact's chaos would make any such difference visible within ~0.1 s).
    Returns the times (s, n: the end of each step) and the outputs after each step (n x the
    engine's outputs, ``Engine.output_names``: ``model.schema.OUTPUTS``, then a clip's forces):
    what the FMU returns at those times.

    The run takes n = round(``duration`` / ``step``) steps, at least one, with or without a
    ``table``; a given ``table`` must have a row for each of them (rows beyond the n-th are not
    used) and ``3 * len(channels_of(model))`` columns (36: ``model.schema.INPUTS``), or a
    :class:`~cablecasing_core.errors.ModelError` names ``duration`` or ``table``. A CSV excitation
    of the scenario that ends before ``duration`` warns (as :func:`simulate`)."""
    from ..model.schema import channels_of
    from .support_motion import SupportReconstruction

    seconds("step", step)
    seconds("duration", duration)
    n = int(round(duration / step))
    if n < 1:
        raise ModelError("duration", duration, f"must be at least one communication step (step = {step:g} s)")
    nch = len(channels_of(model))  # (the 12 supports' channels, then an excited clip's)
    width = 3 * nch
    if table is None:
        warn_short_tables(model, duration, "duration")
        t = step * np.arange(n)
        table = np.hstack(scenario_motion(model)(t))
    else:
        try:
            table = np.asarray(table, float)
            what = f"an array of shape {table.shape}"
        except (TypeError, ValueError):
            table, what = None, "not an array of numbers"
        if table is None or table.ndim != 2 or table.shape[1] != width or len(table) < n:
            raise ModelError(
                "table",
                plain(what),
                f"must be an array of shape (n, {width}): per row the displacement, velocity and acceleration of "
                f"the model's {width // 3} channels (model.schema.INPUTS), a row for each of the n = duration / "
                f"step = {n} steps (duration = {duration:g} s, step = {step:g} s)",
            )
        if not np.all(np.isfinite(table[:n])):
            raise ModelError("table", plain(what), "must hold finite numbers (it holds nan or inf)")
        table = table[:n]
    eng = Engine(model, contact=contact, ledger=False)
    rec = SupportReconstruction(nch)
    out = np.zeros((len(table), len(eng.output_names)))
    points = step * np.arange(len(table) + 1)
    for k, row in enumerate(table):
        h = float(points[k + 1] - points[k])
        motion = rec.motion(eng.time, h, row[:nch], row[nch : 2 * nch], row[2 * nch :])
        eng.advance(h, motion)
        rec.accept(motion)
        eng.output_values(out[k])
    return points[1:], out


def _advance(eng, duration, motion, progress):
    """``eng.advance(duration, motion)``, in pieces of :data:`PROGRESS_STEPS` steps with a tqdm bar
    of the simulated time (s) when ``progress``."""
    if not progress:
        eng.advance(duration, motion)
        return
    from tqdm.auto import tqdm

    piece = PROGRESS_STEPS * eng.dt
    with tqdm(total=duration, unit="s", desc="simulate", dynamic_ncols=True, bar_format=_BAR) as bar:
        done = 0.0
        while duration - done > ROUNDING_OF_TIME * eng.dt:
            # (a rest shorter than SHORTEST_STEP dt goes with the last piece, whose last step takes it)
            h = piece if duration - done > piece + SHORTEST_STEP * eng.dt else duration - done
            eng.advance(h, motion)
            done += h
            bar.update(h)


_BAR = "{desc}: {percentage:3.0f}%|{bar}| {n:.3g}/{total:.3g} s simulated [{elapsed}<{remaining}]"


def contact_episodes(contact_state: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The contact episodes of a record: runs of consecutive steps in which a cable node is in
    contact (stick or slip).

    contact_state: (steps x nodes) array, 0 open, 1 stick, 2 slip (``SimulationResult.contact_state``
    or ``Engine.history()["contact_state"]``). Returns three int arrays with one entry per episode,
    ordered by node and then by time: ``node``, ``start`` (the row of its first step) and
    ``length`` (steps; times dt for seconds). An episode that is still on at the end of the record
    ends there. The gaps between a node's episodes follow as ``start[1:] - (start + length)[:-1]``
    where ``node[1:] == node[:-1]``.
    """
    s = np.asarray(contact_state)
    if s.ndim != 2:
        raise ModelError("contact_state", s.shape, "must be a (steps x nodes) array")
    on = np.zeros((s.shape[1], s.shape[0] + 2), np.int8)
    on[:, 1:-1] = (s > 0).T
    edges = np.diff(on, axis=1)  # +1 where an episode starts, -1 one past its last step
    node, start = np.nonzero(edges == 1)
    end = np.nonzero(edges == -1)[1]  # in the same (node, time) order: they alternate per node
    return node, start, end - start
