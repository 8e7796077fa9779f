"""Support excitation signals of a scenario (Sections 4.1-4.2): random, harmonic, impulse, CSV.

A *motion* maps times t (s) to the displacement (m), velocity (m/s) and acceleration (m/s2) of
the 12 support channels ``model.schema.CHANNELS``. The scenario's motion is the sum of its excitations:

* ``random``: band-limited Gaussian-like acceleration with a flat spectrum between ``band`` (Hz) and
  the given RMS (m/s2), a sum of cosines on a fixed 1/64 Hz grid of lines with seeded phases
  (:mod:`.random_record`); displacement and velocity are its exact integrals. The record is
  defined by its seed, band and RMS alone: a run's first T seconds are the same whatever its
  duration or the program that runs it.
* ``harmonic``: u = amplitude sin(2 pi f t + phase) (m).
* ``impulse``: a Hann-shaped displacement bump of the given amplitude (m) and width (s) starting at
  ``start`` (s); it returns to rest, so a clamped support comes back to its position.
* ``csv``: a table ``time_s, <value>`` of the ``quantity`` displacement (m, default), velocity (m/s)
  or acceleration (m/s2), interpolated by a cubic spline (scipy ``CubicSpline``, not-a-knot). A
  velocity or acceleration is integrated exactly (the spline's antiderivatives) with drift removal:
  the acceleration's mean over the table is removed (a sensor offset would make the velocity grow
  without bound), and each integration constant is chosen so that the velocity and then the
  displacement have zero mean over the table (the support vibrates about its rest position).
  Derivatives come from the same spline, so u, v, a stay consistent. Past the table's end the
  support holds its last displacement at rest (velocity and acceleration 0); before its start, the
  first. A table that ends before the run is warned of (:func:`warn_short_tables`): a support
  still moving at the table's end stops within one step. The time column is ``time_s`` (or
  ``time [s]``, ``time``, ``t``); ``time_ms``, ``time [ms]``, ``time_us``, ``time [us]`` are
  converted to s, another unit refused.

The summed motion fades in over ``scenario.ramp`` seconds (default 0.01 s; 0 switches it off) with
a half-cosine window r(t), differentiated exactly (u r, v r + u r', a r + 2 v r' + u r''), so the
supports start from rest instead of jumping to the signal's value at t = 0: their displacement and
velocity start at 0, their acceleration at u(0) r''(0) = u(0) (pi / ramp)^2 / 2 (the half-cosine's
curvature does not vanish at its ends, so the acceleration steps there and at t = ramp: in the
default scenario by 0.04 to 5.6 m/s^2 on casing.A.z, seeds 1-4, against its RMS of 4.9 m/s^2, a
kick of the size of one sample of the random drive; band levels skip at least the first 0.05 s,
:func:`whole_period_skip`).

Times on the grid of the scenario's time step (within 1e-9 of a multiple k dt) are taken as
exactly ``k * dt``, so a sample's motion is a function of its index alone, bitwise the same however
a run is split into calls (``Engine.advance`` forms its times as ``t0 + j dt``).

Targets ``<body>.<A|B>.axial`` act along the cable's (casing's) tangent at that end, pointing from
A to B (the cable's longitudinal excitation of Section 4.2).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ModelError, ModelWarning
from ..files import read_excitation_table
from ..model.schema import CHANNELS, DIRECTIONS, channels_of
from ..model.validate import alias
from ..structure.geometry import centerline_of
from .random_record import RandomRecord
from .start_skip import least_skip, skip_for_whole_periods

if TYPE_CHECKING:
    from ..model import Model

#: A support motion: times t (s, n) -> (u, v, a), each (n, 12) in m, m/s, m/s2 over CHANNELS.
Motion = Callable[[np.ndarray], tuple]


class _Tabulated:
    """A CSV excitation: the table's quantity as a cubic spline, integrated or differentiated to
    (u, v, a) as the module docstring says."""

    def __init__(self, path, quantity, key="scenario.excitation.file"):
        # imported here: scipy.interpolate brings scipy.optimize and scipy.special, ~0.2 s of the
        # start of every command that builds an engine, and only tabulated excitations need it
        from scipy.interpolate import CubicSpline

        t, x = read_excitation_table(path, key)
        self.t0, self.t1 = t[0], t[-1]
        if quantity == "displacement":
            self.u = CubicSpline(t, x)
        elif quantity == "velocity":
            self.u = _zero_mean(CubicSpline(t, x - _mean(CubicSpline(t, x), t)).antiderivative(), t)
        else:  # acceleration
            a = CubicSpline(t, x - _mean(CubicSpline(t, x), t))
            self.u = _zero_mean(_zero_mean(a.antiderivative(), t).antiderivative(), t)
        self.v, self.a = self.u.derivative(1), self.u.derivative(2)

    def __call__(self, t):
        tc = np.clip(t, self.t0, self.t1)
        inside = (t >= self.t0) & (t <= self.t1)
        return self.u(tc), np.where(inside, self.v(tc), 0.0), np.where(inside, self.a(tc), 0.0)


def _mean(pp, t):
    """Mean of the piecewise polynomial ``pp`` over [t[0], t[-1]] (its exact integral / length)."""
    return pp.integrate(t[0], t[-1]) / (t[-1] - t[0])


def _zero_mean(pp, t):
    """``pp`` shifted by a constant so that its mean over [t[0], t[-1]] is zero (an integration
    constant: the constant term of every piece, the last coefficient row in local coordinates)."""
    pp.c[-1] -= _mean(pp, t)
    return pp


def short_tables(model: Model, duration: float | None = None, key: str = "scenario.duration") -> list[str]:
    """What to warn of ``model``'s CSV excitations whose table ends before the run does (at
    ``duration`` s, default ``scenario.duration``, named ``key`` in the text): after its last time the
    support holds its last displacement at rest, so a support that is still moving there stops
    within one step (a force spike; the energy ledger need not close). One line per such table,
    naming the excitation, the file, its last time and the duration; [] when every table covers the
    run. A table read here is checked as the run reads it (:func:`~cablecasing_core.files.read_excitation_table`)."""
    sc = model.scenario
    T = float(sc["duration"] if duration is None else duration)
    said = []
    for name, e in sc.get("excitation", {}).items():
        if e["kind"] != "csv":
            continue
        t, _ = read_excitation_table(e["file"], f"scenario.excitation.{name}.file")
        if t[-1] < T * (1 - 1e-9):
            said.append(
                f"scenario.excitation.{name}.file = {e['file']} ends at t = {t[-1]:.6g} s, before the end of the "
                f"run, {key} = {T:.6g} s: after it the support holds its last displacement at rest (velocity "
                "and acceleration 0), so a support still moving there stops within one step (a force spike); "
                "tabulate the motion over the whole run, ending at rest, if that is not meant"
            )
    return said


def warn_short_tables(model: Model, duration: float | None = None, key: str = "scenario.duration") -> None:
    """Warn (:class:`~cablecasing_core.errors.ModelWarning`) of each line of :func:`short_tables`: the
    check of a model's tabulated excitations against the duration of its run (``simulate`` calls
    it with the run's duration; the load of a model file may call it with ``scenario.duration``)."""
    for text in short_tables(model, duration, key):
        warnings.warn(text, ModelWarning, stacklevel=3)


def _harmonic(p, t):
    w = 2 * np.pi * p["frequency"]
    ph = w * t + p["phase"]
    A = p["amplitude"]
    return A * np.sin(ph), A * w * np.cos(ph), -A * w * w * np.sin(ph)


def _impulse(p, t):
    tau = (t - p["start"]) / p["width"]
    on = (tau >= 0) & (tau <= 1)
    w = 2 * np.pi / p["width"]
    A = p["amplitude"] / 2
    u = np.where(on, A * (1 - np.cos(2 * np.pi * tau)), 0.0)
    v = np.where(on, A * w * np.sin(2 * np.pi * tau), 0.0)
    a = np.where(on, A * w * w * np.cos(2 * np.pi * tau), 0.0)
    return u, v, a


def _signal(e, dt, key="scenario.excitation.file"):
    """The excitation ``e`` (a validated table) as a callable (t, grid) -> (u, v, a); ``key``:
    its file's key in messages."""
    kind = e["kind"]
    if kind == "random":
        return RandomRecord(e["rms"], e["band"], e["seed"], dt)  # (called as (t, grid) too)
    if kind == "csv":
        tab = _Tabulated(e["file"], e.get("quantity", "displacement"), key)
        return lambda t, grid: tab(t)
    fn = _harmonic if kind == "harmonic" else _impulse
    return lambda t, grid: fn(e, t)


class ScenarioMotion:
    """The summed support motion of a model's scenario: callable t (s, array) -> (u, v, a), each
    of shape (len(t), n) in the order of the model's channels (m, m/s, m/s2; ``channels_of``: the
    12 of ``CHANNELS``, then those of its excited clips). ``dt`` (s, default the
    scenario's) is the grid on which random records are evaluated in blocks (see module docstring)."""

    def __init__(self, model, dt=None):
        sc = model.scenario
        self.dt = float(sc["dt"] if dt is None else dt)
        self.terms = []
        self.ramp = sc.get("ramp", 0.0)
        self.channels = channels_of(model)
        cl = None
        for name, e in sc["excitation"].items():
            key = f"scenario.excitation.{name}.file"
            if e["kind"] == "random" and e["band"][1] >= 0.5 / self.dt:
                # (load_model checks scenario.dt; a run's own dt is checked here, where the record is made)
                raise ModelError(
                    "dt",
                    self.dt,
                    f"must resolve the random excitation scenario.excitation.{name}'s band up to {e['band'][1]:g} Hz: "
                    f"its Nyquist frequency 1 / (2 dt) must lie above the band, so dt < {0.5 / e['band'][1]:g} s",
                )
            if e["kind"] == "harmonic" and e["frequency"] >= 0.5 / self.dt:
                # (as the random band: a harmonic above 1 / (2 dt) would run as its alias)
                raise ModelError(
                    "dt",
                    self.dt,
                    f"must resolve the harmonic excitation scenario.excitation.{name}'s frequency "
                    f"{e['frequency']:g} Hz: its Nyquist frequency 1 / (2 dt) must lie above it, so dt < "
                    f"{0.5 / e['frequency']:g} s (the steps would sample it as its alias at "
                    f"{alias(e['frequency'], self.dt):.6g} Hz)",
                )
            if e["target"].count(".") == 1:  # a clip's own channel
                clip, direction = e["target"].split(".")
                col = self.channels.index(f"{clip}.x")
                self.terms.append((col, np.eye(3)[DIRECTIONS.index(direction)], _signal(e, self.dt, key)))
                continue
            body, support, direction = e["target"].split(".")
            if direction == "axial":
                cl = centerline_of(model) if cl is None else cl
                weights = cl.tangents[0] if support == "A" else cl.tangents[-1]
            else:
                weights = np.eye(3)[DIRECTIONS.index(direction)]
            col = CHANNELS.index(f"{body}.{support}.x")
            sig = _signal(e, self.dt, f"scenario.excitation.{name}.file")
            self.terms.append((col, np.asarray(weights, float), sig))

    def prepare(self, t_end: float) -> float:
        """Compute now what is costly to evaluate over [0, ``t_end``] (s): the blocks of the random
        records (``RandomRecord.prepare``). Returns the time (s) up to which it is ready (``inf``
        when the scenario has no random record)."""
        return min((sig.prepare(t_end) for _, _, sig in self.terms if isinstance(sig, RandomRecord)), default=math.inf)

    def __call__(self, t):
        t = np.atleast_1d(np.asarray(t, float))
        k = np.rint(t / self.dt)
        on = np.abs(t / self.dt - k) < 1e-9
        t = np.where(on, k * self.dt, t)  # a sample's time is its index times dt (module docstring)
        grid = (on, k.astype(np.int64))
        # channel-major (3, channels, times), so each term adds along contiguous rows (a (times, 3)
        # slice of (times, channels) costs ~5 times more per value); the same sums in the same order
        out = np.zeros((3, len(self.channels), len(t)))
        for col, wts, sig in self.terms:
            for o, s in zip(out, sig(t, grid)):
                for d in range(3):
                    o[col + d] += s * wts[d]
        if self.ramp > 0 and t.min() < self.ramp:  # (past the ramp, the factor is 1)
            T = self.ramp
            on = t < T
            x = np.pi * t / T
            r = np.where(on, 0.5 * (1 - np.cos(x)), 1.0)
            dr = np.where(on, 0.5 * np.pi / T * np.sin(x), 0.0)
            ddr = np.where(on, 0.5 * (np.pi / T) ** 2 * np.cos(x), 0.0)
            u, v, a = out
            out = (r * u, r * v + dr * u, r * a + 2 * dr * v + ddr * u)
        return tuple(np.ascontiguousarray(o.T) for o in out)


def scenario_motion(model: Model, dt: float | None = None) -> ScenarioMotion:
    """The :class:`ScenarioMotion` of ``model``'s ``[scenario]`` (see module docstring); ``dt`` (s)
    is the run's time step (default ``scenario.dt``), on whose grid random records are tabulated."""
    return ScenarioMotion(model, dt)


def harmonic_excitations(model: Model) -> dict[str, dict]:
    """The scenario's harmonic excitations that put a line in a record: non-zero amplitude and a
    frequency (Hz) above 0, ``{name: its table}`` in the order of the model file."""
    return {
        name: e
        for name, e in model.scenario["excitation"].items()
        if e["kind"] == "harmonic" and e["amplitude"] != 0 and e["frequency"] > 0
    }


def harmonic_lines(model: Model) -> tuple[float, ...]:
    """The frequencies (Hz) of the scenario's harmonic excitations of non-zero amplitude
    (:func:`harmonic_excitations`), in the order of the model file (a run's record states them:
    ``records.Records.lines_hz``)."""
    return tuple(float(e["frequency"]) for e in harmonic_excitations(model).values())


def whole_period_skip(
    model: Model, duration: float | None = None, dt: float | None = None, least: float = 0.0
) -> float:
    """The default start of a record of ``model``'s scenario left out of its band levels (s): the
    least skip at or above 0.05 s, ``scenario.ramp`` (:func:`~cablecasing_core.timedomain.start_skip.least_skip`)
    and ``least`` (s; the report's :func:`~cablecasing_core.report.start_transient` with a
    harmonic drive) after which the rest of the record, ``duration`` (s, default
    ``scenario.duration``), holds whole periods of the scenario's harmonic excitations (:func:`harmonic_lines`;
    :func:`~cablecasing_core.timedomain.start_skip.skip_for_whole_periods`, on the grid of ``dt``, s, default
    ``scenario.dt``): 0.06 s of the specimens' 1 s and 0.5 s records with their 50 Hz drive. A run's
    record states the lines and the ramp, so that ``Records.default_skip`` gives the same start."""
    sc = model.scenario
    T = float(sc["duration"] if duration is None else duration)
    step = float(sc["dt"] if dt is None else dt)
    return skip_for_whole_periods(harmonic_lines(model), T, step, max(least_skip(sc["ramp"]), float(least)))


def zero_motion(t: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Supports at rest at the times ``t`` (s): (u, v, a) all zero (m, m/s, m/s2), each of shape
    (len(t), 12), the 12 support channels."""
    t = np.atleast_1d(t)
    z = np.zeros((len(t), len(CHANNELS)))
    return z, z.copy(), z.copy()
