"""The support motion inside a communication step (``timedomain.support_motion.QuinticStep``, used
by the FMU): the Taylor target of the inputs and the state the next step starts from, the quintic
Hermite's power-basis coefficients and its values by Horner's scheme. The arithmetic is a few
hundred operations; as numpy calls it cost ~10 us per communication step in call overhead alone,
as much as one Newmark step."""

from __future__ import annotations

from numba import njit

from ._compile_options import FM


@njit(cache=True, fastmath=FM, error_model="numpy")
def taylor_rows(state, u, v, a, t0, h, rows):
    """rows (6 x n) = [state[:3] (u, v, a at the step start); the Taylor target at t0 + h of the
    inputs u (m), v (m/s), a (m/s2) given at t0 (s), h in s]. The target is Taylor's to third
    order, u + v h + a h^2/2 + j h^3/6, v + a h + j h^2/2, a + j h, with the jerk j (m/s3) the
    backward difference of the acceleration inputs, (a - state[3]) / max(t0 - state[4], h): state[3]
    is the acceleration input of the previous communication point and state[4] its time (NaN, or a
    time not before t0: none, and j = 0). Over a step longer than the last one the difference is
    taken over h, so the target's change of acceleration, j h, never exceeds the inputs' last change
    (a master that shortens one step to meet an event would otherwise have the next step
    extrapolate the event's jump by h over that short step: 1000 times for 1e-7 s before 1e-4 s)."""
    dt_in = t0 - state[4, 0] if state.shape[1] else 0.0
    has = dt_in > 0.0  # (False for NaN)
    over = max(dt_in, h) if has else 1.0
    for j in range(state.shape[1]):
        rows[0, j], rows[1, j], rows[2, j] = state[0, j], state[1, j], state[2, j]
        jerk = (a[j] - state[3, j]) / over if has else 0.0
        rows[3, j] = u[j] + v[j] * h + (0.5 * h * h) * a[j] + (h * h * h / 6.0) * jerk
        rows[4, j] = v[j] + a[j] * h + (0.5 * h * h) * jerk
        rows[5, j] = a[j] + jerk * h


@njit(cache=True, fastmath=FM, error_model="numpy")
def accept_rows(state, rows, a, t0):
    """The support state after a communication step from t0 (s) that took the motion of ``rows``
    (:func:`taylor_rows`): state[:3] = its end (u, v, a), state[3] = the acceleration inputs a
    (m/s2) and state[4] = t0, the memory the next step's jerk is taken from."""
    for j in range(state.shape[1]):
        state[0, j], state[1, j], state[2, j] = rows[3, j], rows[4, j], rows[5, j]
        state[3, j] = a[j]
        state[4, j] = t0


@njit(cache=True, fastmath=FM, error_model="numpy")
def quintic_coefficients(G, rows, c):
    """c[d, k, j] = sum_m G[3 k + d, m] rows[m, j]: the power-basis coefficients of s^k of the
    displacement (d = 0, m), velocity (1, m/s) and acceleration (2, m/s2) of channel j, from the
    18 x 6 matrix G of ``support_motion`` (its coefficient matrix) and rows (6 x n, start and end states)."""
    for k in range(6):
        for d in range(3):
            for j in range(rows.shape[1]):
                s = 0.0
                for m in range(6):
                    s += G[3 * k + d, m] * rows[m, j]
                c[d, k, j] = s


@njit(cache=True, fastmath=FM, error_model="numpy")
def quintic_values(c, t0, h, t, out):
    """out[d, i, j] = sum_k c[d, k, j] s_i^k (Horner), s_i = (t_i - t0) / h clipped to [0, 1]: the
    motion (m, m/s, m/s2 for d = 0, 1, 2) of channel j at the times t (s) of the step [t0, t0 + h]."""
    for i in range(t.shape[0]):
        s = min(max((t[i] - t0) / h, 0.0), 1.0)
        for d in range(3):
            for j in range(c.shape[2]):
                acc = c[d, 5, j]
                for k in range(4, -1, -1):
                    acc = acc * s + c[d, k, j]
                out[d, i, j] = acc
