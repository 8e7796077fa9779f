"""The default specimen's cost per step against its time step, in one process.

One engine per time step (the built-in model, its scenario, records on, ledger off, as
``cc.simulate`` runs it), advanced in turn by ``--chunk`` s (0.02 by default;
``_alternating.alternate``), ``--duration`` s each after a 2 ms warm-up. Printed per step as
``name: value`` lines (``<dt>`` to four digits, 1.333e-05 for 1/75000 s):
* rtf_coupled_dt<dt>: simulated over wall-clock time;
* us_per_step_dt<dt>: wall-clock µs per step;
* contacts_per_step_dt<dt>: closed contacts per recorded step (mean);
* contact_newton_iterations_per_step_dt<dt>: the contact solve's Newton iterations per step.
What each step does to the expected band levels (456 seeds against 2.5e-6 s) is the table in
docs/time_domain.md, "The time step on 456 seeds", with the commands that produce it.
Run: .venv/bin/python benchmarks/default_time_step.py [--dt 1e-5,1.3333333333333333e-5,...]
[--duration 2.0] (about 10 s on one core at the defaults).
"""

import numpy as np
from _alternating import alternate
from _options import checked, divides, parser, seconds, time_step

import cablecasing_core as cc
from cablecasing_core.errors import ModelError
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion

p = parser(__doc__)
p.add_argument(
    "--dt",
    default="1e-5,1.3333333333333333e-5,1.6666666666666667e-5,2e-5",
    help="comma-separated time steps (s); each must divide --chunk",
)
p.add_argument("--duration", type=float, default=2.0, help="s simulated per time step")
p.add_argument("--chunk", type=float, default=0.02, help="s simulated per turn")
args = p.parse_args()
with checked(p):
    seconds("--chunk", args.chunk)
    if not args.duration >= args.chunk:
        raise ModelError("--duration", args.duration, f"must be at least --chunk = {args.chunk:g} s")
    dts = []
    for text in args.dt.split(","):
        try:
            dts.append(float(text))
        except ValueError:
            raise ModelError("--dt", text, "must be comma-separated time steps in s, e.g. 1e-5,2e-5") from None
        time_step("--dt", dts[-1])
        divides("--dt", dts[-1], "--chunk", args.chunk)
names = [f"{dt:.4g}" for dt in dts]
model = cc.load_model()
engines = [Engine(model, dt=dt, ledger=False, record=True) for dt in dts]
motions = [scenario_motion(model, dt=dt) for dt in dts]
for eng, motion in zip(engines, motions):
    eng.advance(0.002, motion)  # compiles, and starts every engine past its first contacts
before = [eng.solver_counts[0] for eng in engines]
rounds = int(round(args.duration / args.chunk))
calls = [lambda e=eng, mo=motion: e.advance(args.chunk, mo) for eng, motion in zip(engines, motions)]
walls = alternate(calls, rounds).sum(axis=0)
simulated = rounds * args.chunk
for name, dt, eng, wall, start in zip(names, dts, engines, walls, before):
    steps = simulated / dt
    closed = np.count_nonzero(eng.history()["contact_state"], axis=1).mean()  # warm-up included
    iterations = eng.solver_counts[0] - start
    print(f"rtf_coupled_dt{name}: {simulated / wall:.4f}")
    print(f"us_per_step_dt{name}: {wall / steps * 1e6:.3f}")
    print(f"contacts_per_step_dt{name}: {closed:.3f}")
    print(f"contact_newton_iterations_per_step_dt{name}: {iterations / steps:.3f}")
