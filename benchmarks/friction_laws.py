"""What the regularised friction law costs against the switch law on the installed specimen.

Both engines (``contact.friction_law`` "switch" at its default settings, with the sub-steps around
stick-slip events, and "regularized", which has no events) advance the installed specimen's
scenario at Δt = 1e-5 s in alternating chunks of ``--chunk`` s within one process
(``_alternating.alternate``: the order reversed every other round), so that the machine's drift
falls on both alike (docs/performance.md). Prints name: value lines:
* us_per_step_switch, us_per_step_regularized: the sum of each engine's chunk walls over its steps;
* regularized_over_switch_step_cost: the median of the chunk-by-chunk ratios, with the quartiles
  (``_alternating.ratio_quartiles``; the same figure as bench_time.py's
  ``installed_default_over_switch_cost``, whose inverse it is, there among other variants);
* contact_newton_iterations_per_step_<law>, refined_share_<law>, unconverged_steps_<law> (steps whose
  contact Newton stopped at its iteration cap).
Run: .venv/bin/python benchmarks/friction_laws.py [--duration 0.3] [--chunk 0.01]   (about 1 min)
"""

from _alternating import alternate, ratio_quartiles
from _options import parser

import cablecasing_core as cc
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion

DT = 1e-5
p = parser(__doc__)
p.add_argument("--duration", type=float, default=0.3, help="s simulated by each engine")
p.add_argument("--chunk", type=float, default=0.01, help="s per alternating chunk")
args = p.parse_args()
if not args.duration >= args.chunk > 0:
    p.error(f"--duration {args.duration}, --chunk {args.chunk}: need duration >= chunk > 0 (s)")
model = cc.load_model("installed")
laws = ("switch", "regularized")
engines = {law: Engine(model.with_overrides({"contact.friction_law": law}), dt=DT, ledger=False) for law in laws}
motion = scenario_motion(model, dt=DT)
for eng in engines.values():  # compile (or load the cache) outside the timing
    eng.advance(DT, motion)
rounds = int(round(args.duration / args.chunk))
walls = dict(zip(laws, alternate([lambda e=engines[law]: e.advance(args.chunk, motion) for law in laws], rounds).T))
steps = args.chunk / DT
for law in laws:
    eng = engines[law]
    total = eng.time / DT
    print(f"us_per_step_{law}: {sum(walls[law]) / (len(walls[law]) * steps) * 1e6:.2f}")
    print(f"contact_newton_iterations_per_step_{law}: {eng.solver_counts[0] / total:.2f}")
    print(f"refined_share_{law}: {eng.refined_steps / total:.3f}")
    print(f"unconverged_steps_{law}: {int(eng.solver_counts[2])} of {int(round(total))}")
q1, med, q3 = ratio_quartiles(walls["regularized"], walls["switch"])
print(f"regularized_over_switch_step_cost: {med:.3f} (quartiles {q1:.3f}-{q3:.3f})")
