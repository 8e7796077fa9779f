"""Orchestration of a time-domain run: the scenario's motion through the engine, with results.

>>> import cablecasing_core as cc
>>> res = cc.simulate(cc.load_model(), duration=0.05)
>>> res.support_force("casing.B.Fz")       # N, one value per time step
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ModelError
from ..model.schema import SUPPORT_OUTPUTS, lookup, output_spec
from ..model.validators import Choice
from .engine import Engine
from .scenario import scenario_motion

if TYPE_CHECKING:
    from ..model import Model
    from .scenario import Motion


@dataclass
class SimulationResult:
    """Histories of a run (SI units).

    time (s, n); support_forces (N, N.m; n x 24 in the order of ``SUPPORT_OUTPUTS``: the
    force each body exerts on each support); contact_state (n x nodes: 0 open, 1 stick, 2 slip);
    normal_force (N) and penetration (m) per cable node; contact_time (s per cable node: the
    highest-contact-area histogram of Fig. 22); curvature (1/m per node); energies (J).
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

    def support_force(self, name: str) -> np.ndarray:
        """History of one support output, e.g. ``"casing.B.Fz"`` (N or N.m)."""
        Choice(*SUPPORT_OUTPUTS)("output", name)
        return self.support_forces[:, SUPPORT_OUTPUTS.index(name)]

    def save(self, path: str | os.PathLike) -> None:
        """Write the support forces and contact summary: ``.csv`` (time and the 24 support outputs)
        or ``.npz`` (every array)."""
        path = str(path)
        if path.endswith(".npz"):
            np.savez_compressed(
                path,
                time=self.time,
                support_forces=self.support_forces,
                contact_state=self.contact_state,
                normal_force=self.normal_force,
                penetration=self.penetration,
                contact_time=self.contact_time,
                curvature=self.curvature,
                arc_length=self.arc_length,
                support_names=np.array(SUPPORT_OUTPUTS),
            )
        elif path.endswith(".csv"):
            active = np.count_nonzero(self.contact_state, axis=1)
            table = np.column_stack([self.time, self.support_forces, active, self.penetration.max(axis=1)])
            units = [output_spec(n)[0].replace(".", "") for n in SUPPORT_OUTPUTS]  # N, Nm
            header = ",".join(
                ["time_s"]
                + [f"{n}_{u}" for n, u in zip(SUPPORT_OUTPUTS, units)]
                + ["contact_active", "max_penetration_m"]
            )
            np.savetxt(path, table, delimiter=",", header=header, comments="", fmt="%.9g")
        else:
            raise ModelError("--out", path, "must end in .csv or .npz")


def simulate(
    model: Model,
    duration: float | None = None,
    dt: float | None = None,
    contact: bool | None = None,
    motion: Motion | None = None,
) -> SimulationResult:
    """Run the model's scenario (or ``motion``) for ``duration`` s with time step ``dt`` s.

    Defaults come from ``[scenario]``; ``contact`` defaults to ``[contact] enabled``. Returns a
    :class:`SimulationResult`. Raises :class:`~cablecasing_core.errors.SimulationError` on blow-up.
    """
    sc = model.scenario
    duration = sc["duration"] if duration is None else duration
    dt = sc["dt"] if dt is None else dt
    lookup("scenario.duration").check(duration, "duration")
    lookup("scenario.dt").check(dt, "dt")
    if duration < dt:
        raise ModelError("duration", duration, f"must be at least one time step (dt = {dt} s)")
    motion = scenario_motion(model, dt=dt, duration=duration) if motion is None else motion
    eng = Engine(model, dt=dt, contact=contact, ledger=True, record=True)
    eng.advance(duration, motion)
    h = eng.history()
    n = len(h["support_forces"])
    cl = eng.bodies[next(iter(eng.bodies))].system.centerline
    # the step ends; a duration that is not a whole number of steps ends with a shorter one
    time = np.minimum(dt * np.arange(1, n + 1), eng.time)
    return SimulationResult(
        time=time,
        support_forces=h["support_forces"],
        contact_state=h["contact_state"],
        normal_force=h["normal_force"],
        penetration=h["penetration"],
        contact_time=eng.contact_time.copy(),
        curvature=cl.curvature,
        arc_length=cl.s,
        energies=eng.energies(),
    )


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
