"""The time step on the installed specimen, one record per step: does the band level converge?

On the installed specimen the drive's response dominates octaves 3-9 and is hardly chaotic there
(a 1e-9 change of the input moves those bands by under 0.3 %; ``benchmarks/bench_time.py --model
installed``), so one record per time step shows the discretisation error of those bands directly,
without an ensemble. Runs the default scenario of a model (default: ``installed``) for
``--duration`` s at each of ``--dts`` and prints as ``name: value`` lines, per time step, the nine
Table 3 band levels of casing.B.Fz after ``--skip`` s (N), their relative difference from the finest step, the contacts
per step, the stick share of the closed contacts and the contact Newton iterations per step.

A run is ``DT`` or ``DT:SUBSTEPS`` (``contact.event_substeps``: the steps in which a contact
switches between stick and slip recomputed in that many sub-steps; docs/time_domain.md); the finest
DT without sub-steps is the reference. Each run also prints its wall time and the share of its
steps that were recomputed.

The installed specimen's friction is regularised (no events; ``DT:SUBSTEPS`` then changes nothing);
``--set contact.friction_law='"switch"'`` gives the paper's switch law, whose events the sub-steps
treat.

``--window boxcar|hann``: the window of the band levels (default boxcar, the window of the docs'
tables and of the cached references ``levels_N`` and ``levels_regularized_N``; ``hann``, the package's
default, that of ``levels_regularized_hann_N`` in ``installed_reference_levels.json``).

Run: .venv/bin/python benchmarks/installed_time_step.py [--dts 1e-5 1e-5:8 2.5e-6 6.25e-7] [--seed 1]
[--duration 1.0] [--set contact.damping=0] [--window hann] (about 2 min for the default steps on the
shared machine)
"""

import json
import time

import numpy as np
from _options import checked, output_file, parser, seconds, seeds, step_runs
from _options import model as model_option
from _record_length import require_band_record

from cablecasing_core.errors import ModelError
from cablecasing_core.files import write_text
from cablecasing_core.model.load import toml_value
from cablecasing_core.model.schema import SUPPORT_OUTPUTS
from cablecasing_core.nvh.bands import window_options
from cablecasing_core.records import after_skip
from cablecasing_core.studies import octave_rms
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion

p = parser(__doc__)
p.add_argument("--model", default="installed", help="a built-in specimen (installed, default) or a model file")
p.add_argument("--dts", nargs="+", default=["1e-5", "5e-6", "2.5e-6", "1.25e-6"], help="DT or DT:SUBSTEPS (s, 1)")
p.add_argument("--seed", type=int, default=1, help="seed of the casing's random excitation")
p.add_argument("--duration", type=float, default=1.0, help="s per run")
p.add_argument("--skip", type=float, default=0.06, help="s left out (0.06: whole periods of the 50 Hz drive)")
p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="a model override for every run")
p.add_argument(
    "--window",
    choices=("boxcar", "hann"),
    default="boxcar",
    help="window of the band levels (default boxcar: the docs' tables and the cached references levels_N and "
    "levels_regularized_N; hann, the package's default: levels_regularized_hann_N)",
)
p.add_argument(
    "--json", help="write the band levels of every run to this file (bench_time.py reads it as the reference)"
)
args = p.parse_args()
with checked(p):
    seeds("--seed", args.seed)
    seconds("--duration", args.duration)
    seconds("--skip", args.skip, zero_ok=True)
    over = {}
    for kv in args.set:
        k, eq, v = kv.partition("=")
        if not (k and eq):
            raise ModelError("--set", kv, "must be KEY=VALUE, e.g. contact.damping=0")
        over[k] = toml_value(v)
    own = model_option("--model", args.model)
    try:
        model = own.with_overrides({**over, "scenario.excitation.casing_random.seed": args.seed})
    except ModelError as exc:
        raise ModelError("--set", args.set, str(exc)) from None
    runs = step_runs("--dts", args.dts, model)
    output_file("--json", args.json, (".json",))
require_band_record(p, args.duration, args.skip)
col = SUPPORT_OUTPUTS.index("casing.B.Fz")
runs.sort(key=lambda r: (-r[0], r[1]))
levels = {}
for dt, nsub in runs:
    eng = Engine(model.with_overrides({"contact.event_substeps": nsub}), dt=dt, ledger=False, record=True)
    wall = time.perf_counter()
    eng.advance(args.duration, scenario_motion(model, dt=dt))
    wall = time.perf_counter() - wall
    name = f"dt{dt:g}" + (f"_sub{nsub}" if nsub > 1 else "")
    h = eng.history(sparse=True)
    F = h["support_forces"][:, col]
    t = dt * np.arange(1, len(F) + 1)
    after = after_skip(t, args.skip)
    levels[name] = octave_rms(F[after], 1 / dt, **window_options(args.window)).rms
    kept = after[h["contact_step"]]  # the sparse contact entries after the skip
    s = h["contact_state"][kept]
    steps = args.duration / dt
    print(f"octave_rms_{name}: " + " ".join(f"{x:.5g}" for x in levels[name]))
    print(f"contacts_per_step_{name}: {len(s) / np.count_nonzero(after):.3f}")
    print(f"stick_share_{name}: {np.count_nonzero(s == 1) / max(np.count_nonzero(s), 1):.3f}")
    print(f"contact_newton_iterations_per_step_{name}: {eng.solver_counts[0] / steps:.3f}")
    print(f"refined_share_{name}: {eng.refined_steps / steps:.4f}")
    print(f"wall_s_{name}: {wall:.2f}")
if args.json:
    meta = {"model": args.model, "seed": args.seed, "duration_s": args.duration, "skip_s": args.skip, "set": over}
    meta["window"] = args.window
    write_text(args.json, json.dumps({**meta, "levels_N": {k: v.tolist() for k, v in levels.items()}}, indent=1))
plain = [dt for dt, n in runs if n == 1]  # the reference: the finest step without sub-steps, if any
finest = f"dt{min(plain):g}" if plain else None
for name in levels:
    if finest and name != finest:
        r = (levels[name] - levels[finest]) / levels[finest]
        print(f"rel_diff_{name}_vs_{finest}: " + " ".join(f"{x:+.4f}" for x in r))
        print(f"max_abs_rel_diff_{name}_vs_{finest}: {np.abs(r).max():.4f}")
