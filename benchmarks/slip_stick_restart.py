"""What second order through slip -> stick would take (docs/time_domain.md, "Events inside the
step"): the average-acceleration step with Coulomb's switch law on one degree of freedom, in three
designs, against the event-driven reference of tests/timedomain/test_slip_reversal_events.py (the
harmonically driven block: 1 kg, 50 Hz spring, anchor 1 mm sin(2 pi 30 t), N = 200 N, mu = 0.3;
six stick phases in 0.1 s, five of them after a deceleration faster than mu N / m).

The step is the engine's rule reduced to one mass: u1 = u0 + h v0 + h^2/4 (a0 + a1), v1 = v0 +
h/2 (a0 + a1), the friction decided at the step's end (stick, v1 = 0, if the force it needs is
within mu N, else slip with the friction against v1). The designs:

- ``plain``: that step, as the engine's plain step (``contact.event_substeps = 1``);
- ``split``: a step in which the slip velocity reaches zero is split at that zero, located inside
  the step (the root of the slip's velocity, quadratic in time from the slip trial's end
  acceleration), the slip integrated to it and the rest of the step taken from it;
- ``split_restart``: the same, and the rest of the step starts from the acceleration of the law's
  right-hand limit at the event (zero when the spring's force is within mu N, so that the mass
  sticks; else the reversed slip's), not from the slip's acceleration the step carries.

Printed as ``name: value`` lines, for each design and step: x_err_<design>_<dt>,
v_err_<design>_<dt> (largest errors over 0.1 s, m and m/s), and order_x_<design>, order_v_<design>
(log2 of the error ratio per halving, from 5e-5 to 1.5625e-6 s, min-max). Seconds on one core;
nothing here depends on the machine's speed.
Run: .venv/bin/python benchmarks/slip_stick_restart.py   (no options)
"""

import importlib.util
from pathlib import Path

import numpy as np
from _options import parser

parser(__doc__).parse_args()  # (no options: --help shows the above, a typo is refused)
# the event-driven reference and the block's data, from the test that holds them (one copy)
_spec = importlib.util.spec_from_file_location(
    "slip_reversal_reference", Path(__file__).parents[1] / "tests" / "timedomain" / "test_slip_reversal_events.py"
)
ref = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(ref)
M, K, F = ref.M_, ref.K_, ref.F  # kg, N/m, N (mu N)
DTS = (5e-5, 2.5e-5, 1.25e-5, 6.25e-6, 3.125e-6, 1.5625e-6)  # s


def step(u, v, a, t1, h, slip=None):
    """One average-acceleration step of h (s) to t1 (s) from (u, v, a) (m, m/s, m/s2) with the
    switch law at its end; slip = +-1 forces a slip with the friction -slip F. Returns (u1, v1, a1,
    stuck)."""
    xa = ref.anchor(t1)[0]
    c = h * h / 4
    if slip is None:
        a1 = -a - 2 * v / h  # the stick: v1 = 0
        u1 = u + h * v + c * (a + a1)
        if abs(M * a1 + K * (u1 - xa)) <= F:  # the friction force the stick needs, within mu N
            return u1, 0.0, a1, True
    for s in (1.0, -1.0) if slip is None else (slip,):
        a1 = (-F * s - K * (u + h * v + c * a - xa)) / (M + K * c)
        v1 = v + h / 2 * (a + a1)
        if np.sign(v1) == s:
            break
    return u + h * v + c * (a + a1), v1, a1, False


def right_limit_acceleration(u, t):
    """The acceleration (m/s2) just after a slip ends at rest at u (m), time t (s): zero if the
    spring's force is within mu N (the mass sticks), else the reversed slip's."""
    spring = -K * (u - ref.anchor(t)[0])
    return 0.0 if abs(spring) <= F else (spring - F * np.sign(spring)) / M


def run(dt, design):
    """Largest errors (m, m/s) of the block over 0.1 s at step dt (s) with a design (docstring)."""
    n = round(ref.T_END / dt)
    u = v = a = 0.0
    us, vs = np.empty(n), np.empty(n)
    for k in range(n):
        t0, t1 = k * dt, (k + 1) * dt
        u1, v1, a1, stuck = step(u, v, a, t1, dt)
        if design != "plain" and v != 0.0 and (stuck or np.sign(v1) != np.sign(v)):
            # the slip's velocity v + a tau + j tau^2 / 2, j from the slip trial's end acceleration
            a_slip = step(u, v, a, t1, dt, slip=np.sign(v))[2]
            j = (a_slip - a) / dt
            roots = np.roots([j / 2, a, v]) if j != 0.0 else np.array([-v / a])
            roots = roots[np.isreal(roots)].real
            roots = roots[(roots > 0.0) & (roots < dt)]
            if roots.size:
                tau = roots.min()
                ue, _, ae, _ = step(u, v, a, t0 + tau, tau, slip=np.sign(v))
                if design == "split_restart":
                    ae = right_limit_acceleration(ue, t0 + tau)
                u1, v1, a1, stuck = step(ue, 0.0, ae, t1, dt - tau)
        u, v, a = u1, v1, a1
        us[k], vs[k] = u, v
    xr, vr = REF(np.arange(1, n + 1) * dt)
    return np.abs(us - xr).max(), np.abs(vs - vr).max()


_, REF = ref.reference()
for design in ("plain", "split", "split_restart"):
    errs = np.array([run(dt, design) for dt in DTS])
    for dt, (ex, ev) in zip(DTS, errs):
        print(f"x_err_{design}_{dt:g}: {ex:.3e}")
        print(f"v_err_{design}_{dt:g}: {ev:.3e}")
    for i, name in enumerate(("x", "v")):
        order = np.log2(errs[:-1, i] / errs[1:, i])
        print(f"order_{name}_{design}: {order.min():.2f}-{order.max():.2f} ({' '.join(f'{o:.2f}' for o in order)})")
