"""How many stick-slip switches the installed specimen makes, and whether that converges as dt shrinks.

A switch is a cable node that is closed at the end of two consecutive recorded steps and sticks
at one of them and slips at the other (with sub-steps, the record holds only the step's ends, so
a switch and its return inside one step are not counted). For each run ``DT`` or
``DT:SUBSTEPS`` (``contact.event_substeps``) the installed specimen's scenario (seed ``--seed``)
runs for ``--duration`` s, and this prints name: value lines counted after ``--skip`` s:
* switches_per_s_<run>: all switches per simulated second, and stick_to_slip_per_s_<run>;
* switches_per_s_per_node_<run>: the same for each cable node that switches (node:count; ``none``);
* nodes_at_drive_rate_<run>: how many of the closed nodes switch at most 4 times per period of
  the 50 Hz drive (400 /s: a stick at each of its two reversals and the slip after it);
* stick_share_<run>: the share of the closed contacts that stick; wall_s_<run>.

Under the 50 Hz drive a contact sticks at most at each reversal, some 200 switches per second
per node. A count that doubles with each halving of the step, at nodes that switch thousands of
times per second, is chatter at the step's own scale: the events of the switch model (Section
2.1) multiply as 1/dt, so they cannot be located one by one (docs/time_domain.md, "How many
events there are").
Run: .venv/bin/python benchmarks/stick_slip_switches.py [--dts 1e-5:8 6.25e-7 3.125e-7 1.5625e-7 7.8125e-8]
[--duration 0.06]   (about 4 min for the default runs on one core)
"""

import time

import numpy as np
from _options import checked, parser, seconds, seeds, step_runs

import cablecasing_core as cc
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion

STICK, SLIP = 1, 2
DRIVE_RATE = 400.0  # switches per second per node that the 50 Hz drive's reversals allow (1/s)

p = parser(__doc__)
p.add_argument(
    "--dts",
    nargs="+",
    default=["1e-5:8", "6.25e-7", "3.125e-7", "1.5625e-7", "7.8125e-8"],
    help="DT or DT:SUBSTEPS (s, 1)",
)
p.add_argument("--seed", type=int, default=1, help="seed of the casing's random excitation")
p.add_argument("--duration", type=float, default=0.06, help="s simulated per run")
p.add_argument("--skip", type=float, default=0.02, help="s left out at the start")
args = p.parse_args()
if not args.duration > args.skip >= 0:
    p.error(f"--duration {args.duration}, --skip {args.skip}: need duration > skip >= 0 (s)")
with checked(p):
    seeds("--seed", args.seed)
    seconds("--duration", args.duration)
    # the paper's switch law (the specimen's own friction is regularised and has no switches to count)
    switch = {"contact.friction_law": "switch", "scenario.excitation.casing_random.seed": args.seed}
    model = cc.load_model("installed").with_overrides(switch)
    runs = step_runs("--dts", args.dts, model)
for dt, nsub in runs:
    eng = Engine(model.with_overrides({"contact.event_substeps": nsub}), dt=dt, ledger=False, record=True)
    wall = time.perf_counter()
    eng.advance(args.duration, scenario_motion(model, dt=dt))
    wall = time.perf_counter() - wall
    S = eng.history()["contact_state"][int(round(args.skip / dt)) :]
    a, b = S[:-1], S[1:]
    switch = (a > 0) & (b > 0) & (a != b)
    span = args.duration - args.skip
    per_node = switch.sum(axis=0) / span
    closed = (S > 0).any(axis=0)
    name = f"dt{dt:g}" + (f"_sub{nsub}" if nsub > 1 else "")
    print(f"switches_per_s_{name}: {switch.sum() / span:.0f}")
    print(f"stick_to_slip_per_s_{name}: {np.count_nonzero((a == STICK) & (b == SLIP)) / span:.0f}")
    nodes = " ".join(f"{i}:{x:.0f}" for i, x in enumerate(per_node) if x > 0)
    print(f"switches_per_s_per_node_{name}: {nodes or 'none'}")
    calm = np.count_nonzero(np.round(per_node[closed]) <= DRIVE_RATE)  # (counts / span: 400.0000001)
    print(f"nodes_at_drive_rate_{name}: {calm} of {np.count_nonzero(closed)}")
    print(f"stick_share_{name}: {np.count_nonzero(S == STICK) / max(np.count_nonzero(S), 1):.4f}")
    print(f"wall_s_{name}: {wall:.1f}")
