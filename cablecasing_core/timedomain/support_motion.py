"""Support motion inside a communication step, reconstructed from sampled inputs (used by the FMU).

A co-simulation master gives the support inputs only at the start ``t`` of a communication step
``[t, t + h]``: displacement ``u`` (m), velocity ``v`` (m/s) and acceleration ``a`` (m/s2) of each
of the 12 channels (``model.schema.CHANNELS``). The engine needs the motion at every internal time step
inside the interval. The reconstruction used here:

* **target at the step end** - the Taylor extrapolation of the inputs to third order,
  ``u1 = u + v h + a h^2/2 + j h^3/6``, ``v1 = v + a h + j h^2/2``, ``a1 = a + j h``, with the
  jerk ``j`` the backward difference of the acceleration inputs, ``(a - a_prev) / (t - t_prev)``
  (the previous communication point's; ``j = 0`` at the first step; over ``h`` instead when the
  step is longer than the last, so that ``j h`` never exceeds the inputs' last change)
  (:func:`taylor_target`);
* **start** - the support state the engine has actually reached at ``t`` (the previous step's
  target; zero before the first step, where the engine is at rest);
* **inside** - the quintic Hermite polynomial matching displacement, velocity and acceleration at
  both ends (:class:`QuinticStep`).

So the prescribed support motion is C2-continuous across steps (it never jumps, whatever the
inputs do); a polynomial input of degree <= 2 is reproduced exactly, and one of degree 3 from the
third step on. For smooth inputs the errors at the step ends are the remainders of the jerk's
difference: O(h^4) in displacement, O(h^3) in velocity and O(h^2) in acceleration; they do not
accumulate, because each target is built from the current inputs, not from the previous
reconstruction. For a harmonic input of angular frequency w, x = w h, the targets carry, against
the true values at the communication points, the gains (1 + ix - x^2/2 - x^2 (1 - e^{-ix})/6)
e^{-ix} = 1 - x^4/8 + O(x^5) (displacement), (1 + ix + ix (1 - e^{-ix})/2) e^{-ix} = 1 + 5i x^3/12
+ O(x^4) (velocity) and 2 e^{-ix} - e^{-2ix} = 1 + x^2 - i x^3 + O(x^4) (acceleration); the component at w of the
reconstructed motion (the same for all three, as they are one function) is the displacement's
gain times the Hermite blend's 1 + O(x^4) (|1 - gain| = 1.8e-4 at 300 Hz and 0.9 % at 800 Hz with
h = 1e-4 s). The acceleration matters beyond the motion itself: the force a driven support
exerts contains the inertia of the support's own node, mass times the support's acceleration at
the output instant, so a target acceleration held at ``a`` (Taylor to second order, gain e^{-ix})
would make that output's error first order in h (19 % of the inertial part at 300 Hz with h = 1e-4
s; 3.5 % with the jerk). The rest of
the error lies at w + 2 pi m / h (m != 0), i.e. at and above the communication rate, and the
jerk's difference amplifies input content near the Nyquist rate of h (a gain of up to 3 at
w h = pi): the inputs should be band-limited well below it, as they must be anyway.

Nothing here is physics: it is interpolation, shared by the FMU and by tests that drive the core
engine exactly as the FMU does.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..model.validators import seconds
from . import kernels as K

if TYPE_CHECKING:
    from .scenario import Motion

# Power-basis coefficients of the quintic p(s) = sum_k c_k s^k on s in [0, 1] are
# c = _HERMITE_TO_POWER @ [p(0), p'(0), p''(0), p(1), p'(1), p''(1)] (derivatives in s). The
# per-step arithmetic (K.taylor_rows, K.quintic_coefficients, K.quintic_values) is compiled: as a
# dozen numpy calls on 12 channels it cost ~10 µs per communication step, as much as a Newmark step.
_HERMITE_TO_POWER = np.array(
    [
        [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.5, 0.0, 0.0, 0.0],
        [-10.0, -6.0, -1.5, 10.0, -4.0, 0.5],
        [15.0, 8.0, 1.5, -15.0, 7.0, -1.0],
        [-6.0, -3.0, -0.5, 6.0, -3.0, 0.5],
    ]
)
_K1 = np.arange(1, 6, dtype=float)[:, None]  # k for the first derivative
_K2 = (np.arange(2, 6) * np.arange(1, 5)).astype(float)[:, None]  # k (k - 1)


def taylor_target(
    u: ArrayLike, v: ArrayLike, a: ArrayLike, h: float, a_prev: ArrayLike | None = None, h_prev: float | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(u, v, a) at ``t + h`` extrapolated from the inputs at ``t`` (m, m/s, m/s2; h in s):
    ``u + v h + a h^2/2 + j h^3/6``, ``v + a h + j h^2/2``, ``a + j h``, with the jerk
    ``j = (a - a_prev) / max(h_prev, h)`` from the acceleration inputs ``a_prev`` (m/s2) given
    ``h_prev`` (s) before t (both None: j = 0, the first step). Arrays of any (equal) shape; new arrays (the
    arithmetic of :func:`kernels.taylor_rows`, which the reconstruction calls)."""
    if (a_prev is None) != (h_prev is None):
        raise ValueError("a_prev and h_prev go together: give both or neither")
    u, v, a = (np.asarray(x, dtype=float) for x in (u, v, a))
    ap = np.zeros(()) if a_prev is None else np.asarray(a_prev, dtype=float)
    shape = np.broadcast_shapes(u.shape, v.shape, a.shape, ap.shape)
    u, v, a, ap = (np.ascontiguousarray(np.broadcast_to(x, shape)).reshape(-1) for x in (u, v, a, ap))
    state = np.zeros((5, u.size))
    state[3] = ap
    state[4] = np.nan if h_prev is None else -seconds("h_prev", h_prev)  # (the inputs at t = 0)
    rows = np.empty((6, u.size))
    K.taylor_rows(state, u, v, a, 0.0, float(h), rows)
    return tuple(rows[3 + q].reshape(shape) for q in range(3))


def _coefficient_matrix(h):
    """G (18 x 6): the power-basis coefficients of displacement, velocity and acceleration, rows
    ordered power-major (row 3 k + j: the s^k coefficient of u, v, a for j = 0, 1, 2), from
    [start u, v, a; end u, v, a] (6 x n, SI units). Zero rows where a derivative has no such power."""
    scale = np.diag([1.0, h, h * h, 1.0, h, h * h])
    c = _HERMITE_TO_POWER @ scale  # displacement coefficients, m
    G = np.zeros((6, 3, 6))
    G[:, 0] = c
    G[:5, 1] = _K1 * c[1:] / h  # velocity, m/s
    G[:4, 2] = _K2 * c[2:] / (h * h)  # acceleration, m/s2
    return G.reshape(18, 6)


class QuinticStep:
    """Motion over ``[t0, t0 + h]`` (s): the quintic Hermite polynomial per channel from ``start``
    to ``end``, each (u, v, a) as a tuple of three arrays or a (3, n) array, in m, m/s, m/s2.

    Calling it with an array of times t (s) returns (u, v, a), each of shape (len(t), n), the
    engine's motion contract. Times outside the interval are clipped to it (the engine asks only
    for times in (t0, t0 + h]; the clip absorbs round-off at the end point).

    An FMU step evaluates this once or a few times per communication step on 12 channels, where a
    numpy call costs more than its arithmetic: construction (:meth:`from_rows`) and evaluation
    (Horner's scheme) are one compiled call each.
    """

    def __init__(self, t0, h, start, end):
        h = seconds("h", h)
        rows = np.concatenate([np.asarray(start, dtype=float), np.asarray(end, dtype=float)])
        self._setup(float(t0), h, rows, _coefficient_matrix(h))

    @classmethod
    def from_rows(cls, t0, h, rows, G, inputs_a=None):
        """The step from ``rows`` (6 x n: start u, v, a, end u, v, a) and ``G`` =
        ``_coefficient_matrix(h)`` (no checks; for :class:`SupportReconstruction`, which passes the
        acceleration inputs ``inputs_a`` at t0 that the next step's jerk needs)."""
        self = cls.__new__(cls)
        self._setup(t0, h, rows, G)
        self.inputs_a = inputs_a
        return self

    def _setup(self, t0, h, rows, G):
        self.t0, self.h = t0, h
        self.rows, self.inputs_a = rows, None
        self.start, self.end = rows[:3], rows[3:]  # (3, n) each
        # (3, 6, n): the power-basis coefficients of u, v and a
        self._c = np.empty((3, 6, rows.shape[1]))
        K.quintic_coefficients(G, rows, self._c)

    def __call__(self, t):
        t = np.ascontiguousarray(t, dtype=float).reshape(-1)
        r = np.empty((3, len(t), self._c.shape[2]))  # u, v, a: each block contiguous
        K.quintic_values(self._c, self.t0, self.h, t, r)
        return r[0], r[1], r[2]

    def end_state(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(u, v, a) at ``t0 + h`` (s): displacement (m), velocity (m/s) and acceleration (m/s2) of
        every channel (copies)."""
        return tuple(x.copy() for x in self.end)


class SupportReconstruction:
    """Input reconstruction with memory: the support state (u, v, a) of every channel at the
    engine's current time, the acceleration inputs of the last communication point and its time
    (the jerk of the next target is their backward difference), and the motion of the next
    communication step.

    >>> rec = SupportReconstruction(12)
    >>> motion = rec.motion(t0, h, u, v, a)      # inputs at t0 -> QuinticStep over [t0, t0 + h]
    >>> engine.advance(h, motion)
    >>> rec.accept(motion)                       # the supports are now at the step's end state

    :attr:`state` (5 x n): rows u (m), v (m/s), a (m/s2) of the supports, then the last acceleration
    inputs (m/s2) and their time (s, the same in every column; NaN before the first step).
    """

    def __init__(self, n):
        self.state = np.zeros((5, int(n)))
        self.state[4] = np.nan
        self._h = None
        self._Gs = {}  # h -> G of the last few step sizes

    #: Step sizes whose G is kept: a master that computes its steps as t_(k+1) - t_k (fmusim,
    #: libcosim) passes a few values that differ in the last bits, each needing its own exact G.
    KEPT_STEP_SIZES = 8

    def coefficient_matrix(self, h: float) -> np.ndarray:
        """G (18 x 6) of a step of ``h`` s (see :func:`_coefficient_matrix`), kept for the last
        :attr:`KEPT_STEP_SIZES` values of h (a bounded dict by hand: functools.lru_cache would
        hold every instance's matrices for the life of the process)."""
        if h != self._h:
            G = self._Gs.get(h)
            if G is None:
                h = seconds("h", h)
                G = self._Gs[h] = _coefficient_matrix(h)
                if len(self._Gs) > self.KEPT_STEP_SIZES:
                    del self._Gs[next(iter(self._Gs))]  # the oldest
            self._h, self._G = h, G
        return self._G

    def motion(self, t0: float, h: float, u: ArrayLike, v: ArrayLike, a: ArrayLike) -> QuinticStep:
        """The :class:`QuinticStep` from the current support state to the Taylor target of the
        inputs (u, v, a) given at ``t0`` (s) over the step ``h`` (s)."""
        self.coefficient_matrix(h)
        n = self.state.shape[1]
        u, v, a = (np.ascontiguousarray(x, dtype=float) for x in (u, v, a))
        if u.shape != (n,) or v.shape != (n,) or a.shape != (n,):  # (the kernel does not check bounds)
            raise ValueError(f"inputs of shapes {u.shape}, {v.shape}, {a.shape}: each must have shape ({n},)")
        if self.state.shape != (5, n):
            raise ValueError(f"state of shape {self.state.shape}: it must have shape (5, {n}) (see the class)")
        rows = np.empty((6, n))
        K.taylor_rows(self.state, u, v, a, float(t0), self._h, rows)
        return QuinticStep.from_rows(float(t0), self._h, rows, self._G, a.copy())

    def accept(self, motion: QuinticStep) -> None:
        """Advance the support state to the end of ``motion`` (a step of :meth:`motion`, after the
        engine took it) and remember its inputs; in place, so the array stays the one a caller holds."""
        if motion.inputs_a is None:
            raise ValueError("accept takes a step made by SupportReconstruction.motion (it carries the inputs)")
        K.accept_rows(self.state, motion.rows, motion.inputs_a, motion.t0)

    def reset(self) -> None:
        """Supports at rest at their reference position, no inputs remembered."""
        self.state[:] = 0.0
        self.state[4] = np.nan


class GridMotion:
    """A support motion (``Motion``: t -> (u, v, a), each (len(t), 12), m, m/s, m/s2) evaluated on
    the time grid k dt in chunks of :attr:`CHUNK` steps, kept, as ``Engine.advance`` evaluates a
    motion from t = 0: the FMU adds it to the reconstructed motion when it drives its supports with
    the model's own scenario (``scenario.drive``), so that a run with zero inputs is the core's run
    of the scenario to the bit: the values at t are those at the grid time k dt nearest to t.
    Times off the grid are evaluated directly."""

    CHUNK = 8192  # (3 x 8192 x 12 values, 2.4 MB: the motion's cost per call is paid 4 times less often)

    def __init__(self, motion: Motion, dt: float):
        self._width = None
        self.motion, self.dt = motion, float(dt)
        self._k0, self._values = None, None

    # A time within this share of dt of k dt is k dt: the engine's time, a sum of steps, drifts from
    # k dt by a few ulps per step (1e-14 dt after some thousand steps), far below this.
    GRID_TOLERANCE = 1e-6

    def grid_index(self, t: float) -> int | None:
        """k if t is k dt (to GRID_TOLERANCE dt), else None."""
        k = round(t / self.dt)
        return k if abs(t - k * self.dt) <= self.GRID_TOLERANCE * self.dt else None

    def prepare(self, t_end: float) -> float:
        """Compute now what is costly in the motion over [0, ``t_end``] (s) (the motion's own
        ``prepare``: a scenario's random records, whose blocks cost ~30 ms each, one every 0.66 s at
        dt = 1e-5 s), so that a real-time master does not meet it inside one of its steps: an FMU
        driven by its scenario does this in initialisation. What is left within the steps is a chunk
        of :data:`CHUNK` steps every 0.08 s (~1-2 ms), which stays in the cache for the calls that
        read it. The values are the same to the bit. Returns the time (s) up to which the costly
        part is ready (``inf``: nothing costly; 0: the motion has no ``prepare``)."""
        prepare = getattr(self.motion, "prepare", None)
        return prepare(t_end) if prepare is not None else 0.0

    def fill(self, k0: int, out: np.ndarray) -> None:
        """out (3, m, 12) = u, v, a at the times (k0 + 1 ... k0 + m) dt."""
        m, done = out.shape[1], 0
        while done < m:
            k = k0 + 1 + done
            if self._k0 is None or not (self._k0 <= k < self._k0 + self.CHUNK):
                self._k0 = k
                self._values = np.stack(self.motion(self.dt * np.arange(k, k + self.CHUNK)))
            i = k - self._k0
            take = min(m - done, self.CHUNK - i)
            out[:, done : done + take] = self._values[:, i : i + take]
            done += take

    def __call__(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        t = np.asarray(t, dtype=float)
        k = np.rint(t / self.dt)
        on_grid = (
            len(t) and np.all(np.abs(t - k * self.dt) <= self.GRID_TOLERANCE * self.dt) and np.all(np.diff(k) == 1)
        )
        if not on_grid:
            return self.motion(t)
        if self._width is None:  # (the motion's channels: 12, or more with excited clips)
            self._width = np.shape(self.motion(t[:1])[0])[1]
        out = np.empty((3, len(t), self._width))
        self.fill(int(k[0]) - 1, out)
        return out[0], out[1], out[2]
