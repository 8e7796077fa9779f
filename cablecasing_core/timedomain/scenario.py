"""Support excitation signals of a scenario (Sections 4.1-4.2): random, harmonic, impulse, CSV.

A *motion* maps times t (s) to the displacement (m), velocity (m/s) and acceleration (m/s2) of
the 12 support channels ``model.schema.CHANNELS``. The scenario's motion is the sum of its excitations:

* ``random``: band-limited Gaussian acceleration with a flat spectrum between ``band`` (Hz) and the
  given RMS (m/s2), generated in the frequency domain (random phases, seeded) as a periodic record
  of length ``scenario.duration``; displacement and velocity are the exact periodic integrals
  (division by (i omega)^2 and i omega), so the three are consistent and free of drift.
* ``harmonic``: u = amplitude sin(2 pi f t + phase) (m).
* ``impulse``: a Hann-shaped displacement bump of the given amplitude (m) and width (s) starting at
  ``start`` (s); it returns to rest, so a clamped support comes back to its position.
* ``csv``: a table ``time_s, displacement_m``; velocity and acceleration from a cubic spline.

The summed motion fades in over ``scenario.ramp`` seconds (default 0.01 s; 0 switches it off) with
a half-cosine window r(t), differentiated exactly (u r, v r + u r', a r + 2 v r' + u r''), so the
supports start from rest instead of jumping to the signal's value at t = 0.

Targets ``<body>.<A|B>.axial`` act along the cable's (casing's) tangent at that end, pointing from
A to B (the cable's longitudinal excitation of Section 4.2).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import BPoly, CubicSpline

from ..errors import ModelError
from ..model.schema import CHANNELS, DIRECTIONS
from ..structure.geometry import centerline_of

if TYPE_CHECKING:
    from ..model import Model

#: A support motion: times t (s, n) -> (u, v, a), each (n, 12) in m, m/s, m/s2 over CHANNELS.
Motion = Callable[[np.ndarray], tuple]


def _random_record(rms, band, duration, dt, seed):
    """Grid (s) and (u, v, a) of a periodic band-limited random acceleration with RMS ``rms``."""
    n = int(np.ceil(duration / dt))
    n += n % 2
    f = np.fft.rfftfreq(n, dt)
    rng = np.random.default_rng(seed)
    inband = (f >= band[0]) & (f <= band[1])
    if not inband.any():
        raise ModelError(
            "scenario.excitation.band",
            band,
            f"holds no frequency line of a {n * dt:.6g} s record; widen the band or lengthen the duration",
        )
    A = np.zeros(len(f), complex)
    A[inband] = np.exp(2j * np.pi * rng.random(inband.sum()))
    w = 2 * np.pi * f
    acc = np.fft.irfft(A, n)
    scale = rms / np.sqrt(np.mean(acc**2))
    A *= scale
    iw = np.zeros_like(A)
    iw[1:] = 1.0 / (1j * w[1:])
    a = np.fft.irfft(A, n)
    v = np.fft.irfft(A * iw, n)
    u = np.fft.irfft(A * iw * iw, n)
    t = np.arange(n + 1) * dt
    wrap = lambda x: np.concatenate([x, x[:1]])  # noqa: E731  (periodic closure for interpolation)
    return t, wrap(u), wrap(v), wrap(a)


class _Signal:
    """One scalar excitation: callable t -> (u, v, a)."""

    def __init__(self, kind, params, dt, duration):
        self.kind = kind
        self.p = params
        if kind == "random":
            t, u, v, a = _random_record(params["rms"], params["band"], duration, dt, params["seed"])
            self.period = t[-1]
            self.grid = (t[1] - t[0], u, v, a)
            self._t = t
        elif kind == "csv":
            self._load_csv(params["file"])

    @functools.cached_property
    def poly(self):
        """Quintic Hermite through (u, v, a) at every sample of the random record (scipy BPoly):
        exact at the grid, consistent derivatives in between. Built on the first time off the grid
        (a run at the record's own step never needs it; building it costs ~3 s per 1e5 samples)."""
        _, u, v, a = self.grid
        return BPoly.from_derivatives(self._t, np.column_stack([u, v, a])[:, :, None].reshape(len(self._t), 3))

    def _load_csv(self, path):
        try:
            data = np.genfromtxt(path, delimiter=",", names=True)
        except OSError as exc:
            raise ModelError("scenario.excitation.file", path, f"must be a readable CSV file ({exc})") from None
        if data.dtype.names is None or len(data.dtype.names) < 2 or data.size < 2:
            raise ModelError(
                "scenario.excitation.file", path, "must have a header and at least two rows of time_s, displacement_m"
            )
        t = np.asarray(data[data.dtype.names[0]], float)
        u = np.asarray(data[data.dtype.names[1]], float)
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(u))):
            raise ModelError("scenario.excitation.file", path, "must hold finite numbers only")
        bad = np.nonzero(np.diff(t) <= 0)[0]
        if bad.size:
            i = bad[0] + 1
            raise ModelError(
                "scenario.excitation.file",
                path,
                f"time must increase strictly; row {i + 1} has t = {t[i]} after {t[i - 1]}",
            )
        self.t0, self.t1 = t[0], t[-1]
        self.spline = CubicSpline(t, u)

    def __call__(self, t):
        p = self.p
        if self.kind == "harmonic":
            w = 2 * np.pi * p["frequency"]
            ph = w * t + p["phase"]
            A = p["amplitude"]
            return A * np.sin(ph), A * w * np.cos(ph), -A * w * w * np.sin(ph)
        if self.kind == "impulse":
            tau = (t - p["start"]) / p["width"]
            on = (tau >= 0) & (tau <= 1)
            w = 2 * np.pi / p["width"]
            A = p["amplitude"] / 2
            u = np.where(on, A * (1 - np.cos(2 * np.pi * tau)), 0.0)
            v = np.where(on, A * w * np.sin(2 * np.pi * tau), 0.0)
            a = np.where(on, A * w * w * np.cos(2 * np.pi * tau), 0.0)
            return u, v, a
        if self.kind == "random":
            tt = np.mod(t, self.period)
            h, u, v, a = self.grid
            k = np.rint(tt / h)
            if np.all(np.abs(tt / h - k) < 1e-9):  # on the record's grid: the samples themselves
                k = k.astype(np.int64)
                return u[k], v[k], a[k]
            return self.poly(tt), self.poly(tt, 1), self.poly(tt, 2)
        tc = np.clip(t, self.t0, self.t1)
        inside = (t >= self.t0) & (t <= self.t1)
        return self.spline(tc), np.where(inside, self.spline(tc, 1), 0.0), np.where(inside, self.spline(tc, 2), 0.0)


class ScenarioMotion:
    """The summed support motion of a model's scenario: callable t (s, array) -> (u, v, a), each
    of shape (len(t), 12) in the order of ``CHANNELS`` (m, m/s, m/s2)."""

    def __init__(self, model, dt=None, duration=None):
        sc = model.scenario
        dt = sc["dt"] if dt is None else dt
        duration = sc["duration"] if duration is None else duration
        self.terms = []
        self.ramp = sc.get("ramp", 0.0)
        cl = None
        for e in sc["excitation"].values():
            body, support, direction = e["target"].split(".")
            if direction == "axial":
                cl = centerline_of(model) if cl is None else cl
                tangent = cl.tangents[0] if support == "A" else cl.tangents[-1]
                weights = tangent
            else:
                weights = np.eye(3)[DIRECTIONS.index(direction)]
            col = CHANNELS.index(f"{body}.{support}.x")
            params = dict(e)
            self.terms.append((col, np.asarray(weights, float), _Signal(e["kind"], params, dt, duration)))

    def __call__(self, t):
        t = np.atleast_1d(np.asarray(t, float))
        out = [np.zeros((len(t), len(CHANNELS))) for _ in range(3)]
        for col, wts, sig in self.terms:
            for o, s in zip(out, sig(t)):
                o[:, col : col + 3] += s[:, None] * wts[None, :]
        if self.ramp > 0 and t.min() < self.ramp:  # (past the ramp, the factor is 1)
            T = self.ramp
            on = t < T
            x = np.pi * t / T
            r = np.where(on, 0.5 * (1 - np.cos(x)), 1.0)[:, None]
            dr = np.where(on, 0.5 * np.pi / T * np.sin(x), 0.0)[:, None]
            ddr = np.where(on, 0.5 * (np.pi / T) ** 2 * np.cos(x), 0.0)[:, None]
            u, v, a = out
            out = [r * u, r * v + dr * u, r * a + 2 * dr * v + ddr * u]
        return tuple(out)


def scenario_motion(model: Model, dt: float | None = None, duration: float | None = None) -> ScenarioMotion:
    """The :class:`ScenarioMotion` of ``model``'s ``[scenario]`` (see module docstring)."""
    return ScenarioMotion(model, dt, duration)


def zero_motion(t: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Supports at rest: (u, v, a) all zero, shape (len(t), 12)."""
    t = np.atleast_1d(t)
    z = np.zeros((len(t), len(CHANNELS)))
    return z, z.copy(), z.copy()
