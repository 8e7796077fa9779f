"""The rattle of a contact that lets go, followed under time-step refinement.

In the reference case a cable node that has been pressed onto the casing wall does not simply lift
off: with the contact damper on (c_n = 100 kg/s), it leaves and touches again in a sequence of ever
shorter bounces that lasts about 0.35 ms. At dt = 1e-5 s the bounces show as contact episodes of one
or two steps, which look like chatter at the scale of the time step. This script shows they are
the model's own motion: from one state it runs the same 0.5 ms at dt = 1e-5 / 2^k and prints the
node's episodes, which converge as dt shrinks.

The state at ``--start`` comes from the default scenario run at dt = 1e-5 s; every continuation
starts from that state and is driven by the same support motion (a function of time), so the runs
differ by their time step alone. Then the same with the contact damper off (c_n = 0).

Prints ``name: value`` lines, per damper c and time step dt (labels ``c<c_n>_dt<dt>``):
* ``_episodes``: the node's contact episodes in the window;
* ``_contact_time_us``: the time it spends in contact (stick or slip), µs;
* ``_last_contact_end_us``: when its last episode ends, µs after ``--start``;
* ``_first_episodes_us``: the first eight episodes as start+duration, µs after ``--start`` (``none``: no
  episode).
``--plot PATH`` draws the node's contact over the window for each dt (damper on).

Run: .venv/bin/python benchmarks/rattle.py [--node 8 --start 0.06049 --window 5e-4] [--plot f.png]
(about 10 s; the default node and start are a rattle of the reference record, seed 1, of the records of issue 25)
"""

from _options import checked, output_file, parser

import cablecasing_core as cc
from cablecasing_core.cli.paths import PLOT_SUFFIXES
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion

p = parser(__doc__)
p.add_argument("--node", type=int, default=8, help="cable node to follow")
p.add_argument("--start", type=float, default=0.06049, help="s: where the continuations start")
p.add_argument("--window", type=float, default=5e-4, help="s simulated from --start")
p.add_argument("--levels", type=int, default=9, help="time steps 1e-5 / 2^k, k = 0 .. levels - 1")
p.add_argument("--plot", default=None, help="write the contact-over-time figure here (.png, .pdf, .svg)")
args = p.parse_args()
model = cc.load_model()
DT0 = 1e-5
nodes = model.geometry["n_elements"] + 1
if not 0 <= args.node < nodes:
    p.error(f"--node {args.node}: must be a cable node, 0 .. {nodes - 1}")
if not DT0 <= args.start <= 0.9:
    p.error(f"--start {args.start}: must lie between {DT0} s and 0.9 s")
if not 1e-5 <= args.window <= 1e-2:
    p.error(f"--window {args.window}: must lie between 1e-5 s and 1e-2 s")
if not 1 <= args.levels <= 12:
    p.error(f"--levels {args.levels}: must lie between 1 and 12")
with checked(p):
    output_file("--plot", args.plot, PLOT_SUFFIXES)  # (before the runs, not after them)

motion = scenario_motion(model, dt=DT0)
eng = Engine(model, dt=DT0, ledger=False)
eng.advance(args.start, motion)
state = eng.get_state()
print(f"node_{args.node}_in_contact_at_start: {int(state['cstate'][args.node] > 0)}")

dts = [DT0 / 2**k for k in range(args.levels)]
bars = {}
for c_n in (model.contact["damping"], 0.0):
    m = model.with_overrides({"contact.damping": c_n})
    for dt in dts:
        e = Engine(m, dt=dt, ledger=False, record=True)
        # (the state without its model's fingerprint: continued on purpose with another contact damper)
        e.set_state({k: v for k, v in state.items() if k != "model"})
        e.advance(args.window, motion)
        node, start, length = cc.contact_episodes(e.history()["contact_state"])
        mine = node == args.node
        t0, dur = start[mine] * dt * 1e6, length[mine] * dt * 1e6  # µs after --start
        label = f"c{c_n:g}_dt{dt:.4g}"
        print(f"{label}_episodes: {mine.sum()}")
        print(f"{label}_contact_time_us: {dur.sum():.2f}")
        print(f"{label}_last_contact_end_us: {(t0 + dur).max() if mine.any() else 0.0:.2f}")
        first = " ".join(f"{a:.2f}+{b:.2f}" for a, b in zip(t0[:8], dur[:8]))
        print(f"{label}_first_episodes_us: {first or 'none'}")
        if c_n > 0:
            bars[dt] = list(zip(t0, dur))

if args.plot:
    from cablecasing_core.files import atomic_path
    from cablecasing_core.plotting import plt  # (matplotlib with Agg)

    fig, ax = plt.subplots(figsize=(8, 0.35 * len(dts) + 1.2))
    for row, dt in enumerate(dts):
        ax.broken_barh(bars[dt], (row - 0.35, 0.7), color="tab:blue")
    ax.set_yticks(range(len(dts)), [f"{dt:.3g}" for dt in dts])
    ax.invert_yaxis()
    ax.set_ylabel("time step dt (s)")
    ax.set_xlabel(f"time after t = {args.start} s (µs)")
    ax.set_xlim(0, args.window * 1e6)
    ax.set_title(f"cable node {args.node} in contact (c_n = {model.contact['damping']:g} kg/s), one start state")
    fig.tight_layout()
    with atomic_path(args.plot) as tmp:  # (written whole or not at all)
        fig.savefig(tmp, dpi=120)
    print(f"figure: {args.plot}")
