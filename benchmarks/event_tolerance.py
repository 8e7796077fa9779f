"""What a tolerance on the step's local error buys on a built-in specimen (contact.event_tolerance;
docs/time_domain.md, "A tolerance instead of a bare step"), against uniformly shorter steps.

For each setting: record_err_<name> (casing.B.Fz over the first --early s, on the 1e-5 s grid,
max difference from a uniform --reference-dt over the reference's RMS: the trajectory's error
before the contact response decorrelates), refined_share_<name> (steps recomputed in sub-steps)
and cost_<name> (the engine's wall time over the plain 1e-5 s step's, median of 0.01 s chunks over
--duration s, every setting alternating in one process, so robust to the machine's drift; with the
quartiles).
Prints ``name: value`` lines.
Run: .venv/bin/python benchmarks/event_tolerance.py [--model installed] [--duration 0.4] [--early 0.05]
(docs/time_domain.md: the command as it is, and ``--model default``)
"""

import time

import numpy as np
from _options import checked, divides, model, parser, time_step, whole_steps

from cablecasing_core.model.schema import SUPPORT_OUTPUTS
from cablecasing_core.model.validators import number
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion

DT = 1e-5
p = parser(__doc__)
p.add_argument("--model", default="installed", help="a built-in specimen (installed, default) or a model file")
p.add_argument("--duration", type=float, default=0.4, help="s of the cost comparison")
p.add_argument("--early", type=float, default=0.05, help="s of the record compared with the reference")
p.add_argument("--reference-dt", type=float, default=3.125e-7, help="s: the uniform step of the reference")
args = p.parse_args()
with checked(p):
    specimen = model("--model", args.model)
    number("--duration", args.duration, ge=0.01, unit="s")  # (one 0.01 s chunk at least)
    whole_steps("--early", args.early, DT)  # (compared on the 1e-5 s grid)
    time_step("--reference-dt", args.reference_dt)
    divides("--reference-dt", args.reference_dt, "the grid's step", DT)

FZ = SUPPORT_OUTPUTS.index("casing.B.Fz")
# name: (time step s, contact.event_tolerance m)
SETTINGS = {
    "plain": (DT, 0.0),
    "tol1e-8": (DT, 1e-8),
    "tol1e-9": (DT, 1e-9),
    "tol3e-10": (DT, 3e-10),
    "tol1e-10": (DT, 1e-10),
    "dt5e-6": (5e-6, 0.0),
    "dt2.5e-6": (2.5e-6, 0.0),
    "dt1.25e-6": (1.25e-6, 0.0),
}


def engine(dt, tol):
    model = specimen.with_overrides({"contact.event_tolerance": tol})
    return Engine(model, dt=dt, ledger=False, record=True), scenario_motion(model, dt=dt)


def record(dt, tol):
    """casing.B.Fz (N) on the 1e-5 s grid over the first args.early s, and the engine."""
    eng, motion = engine(dt, tol)
    eng.advance(args.early, motion)
    k = round(DT / dt)
    return eng.history()["support_forces"][k - 1 :: k, FZ], eng


ref, _ = record(args.reference_dt, 0.0)
rms = np.sqrt(np.mean(ref**2))
for name, (dt, tol) in SETTINGS.items():
    F, eng = record(dt, tol)
    print(f"record_err_{name}: {np.abs(F - ref).max() / rms:.3e}")
    print(f"refined_share_{name}: {eng.refined_steps / round(args.early / dt):.4f}")

engines = {name: engine(dt, tol) for name, (dt, tol) in SETTINGS.items()}
chunk, ratios = 0.01, {name: [] for name in SETTINGS}
names = list(SETTINGS)
for k in range(int(round(args.duration / chunk))):
    walls = {}
    for name in names if k % 2 == 0 else names[::-1]:
        eng, motion = engines[name]
        t0 = time.perf_counter()
        eng.advance(chunk, motion)
        walls[name] = time.perf_counter() - t0
    for name in names:
        ratios[name].append(walls[name] / walls["plain"])
for name in names[1:]:
    q = np.percentile(ratios[name][min(5, len(ratios[name]) // 2) :], [25, 50, 75])  # after the first 0.05 s
    print(f"cost_{name}: {q[1]:.3f} (quartiles {q[0]:.3f}-{q[2]:.3f}, over the plain 1e-5 s step)")
