"""Speed and accuracy of the time domain: the reference case of issue 3.

Default model (35 + 35 elements), contact with friction, random excitation 10-1000 Hz at 5 m/s2 RMS at
casing end A plus the cable's 50 Hz axial excitation, dt = 1e-5 s, on one core.
Run: .venv/bin/python benchmarks/bench_time.py [--duration 1.0] [--repeat 3] [--model installed] [--speed-only]
(prints name: value lines; docs/performance.md's figures: ``--duration 1.0 --repeat 1``)

The installed specimen (docs/installed.md; the same scenario from the static state, the cable on
the wall in the bends): rtf_installed, us_per_step_installed, mean_active_contacts_installed (and
by tenth), its contact Newton iterations and stick/slip passes per step, the stick share of its
closed contacts, engine_setup_installed_s; what bounds rtf_installed whatever the contacts cost:
us_per_step_installed_contact_free (the same step without contact), us_per_step_installed_block_solves
(its two block LDLT solves alone), installed_contact_us_per_contact (the contact part per contact,
beside the budget that rtf 1 leaves it at dt = 1e-5), rtf_installed_bound_at_accurate_dt (the
rtf at dt = 1.25e-6, the step whose band levels are within 5 %, with contacts that cost nothing, and
with only the block solves); static_state_s, static_cli_wall_s (``cablecasing static
installed --json`` in a fresh process) beside cli_help_wall_s (``cablecasing --help``: the
interpreter and the imports), installed_over_default_step_cost (the two engines alternating in
0.01 s chunks in one process: the ratio of their step costs, robust to the machine's drift).
At its default settings (Coulomb's friction regularised, ``contact.friction_law = "regularized"``,
docs/time_domain.md "A friction law whose limit exists"): installed_band_max_rel_err (the worst
Table 3 band of seeds 1 and 2 through Hann's window, the package's default, against the finest step
of its levels in ``installed_reference_levels.json``, ``levels_regularized_hann_N``: 3.125e-7 s,
written by installed_time_step.py --window hann --json; with ``--duration 1.0`` only, the
reference's) with its per-band values and the reference's own distance from the next coarser step
(what the reference leaves open), and ``_boxcar`` the same through the rectangular window against
``levels_regularized_N`` (the docs' earlier tables); the same with the paper's switch law at its
default settings (the sub-steps around stick-slip events, contact.event_substeps):
installed_band_max_rel_err_switch against its finest plain step (``levels_N``: 7.8125e-8 s, the
rectangular window), and installed_refined_share_switch (the steps recomputed in
sub-steps); the same with the specimen's own law and a tolerance on the step's local error
(``contact.event_tolerance`` = 1e-9 m, docs/time_domain.md "A tolerance instead of a bare step"):
installed_band_max_rel_err_tolerance, installed_refined_share_tolerance, and its cost
installed_default_over_tolerance_cost (alternating chunks, as the switch law's). The real-time
setting, scenario.dt = 1/30000 s (docs/time_domain.md, "Real time on the installed specimen"):
rtf_installed_realtime (timed as rtf_installed), its Newton iterations per step, and
installed_band_max_rel_err_realtime against the same reference. Band levels take the samples after
``--skip`` with ``records.after_skip`` (47 whole periods of the drive after 0.06 s).
``--model`` chooses the model of the accuracy checks and the ensemble below (default: the built-in
specimen).

Speed: wall time of Engine.advance over the whole duration (support motion evaluated inside), the
fastest of ``--repeat`` runs (the machine is shared; the spread is printed too). simulate_wall_s:
the whole ``cc.simulate`` call of the same case (set-up, ledger, recording), what a user waits for.
rtf_coupled_realtime: the same at the default specimen's real-time setting, scenario.dt = 2e-5 s
(docs/time_domain.md, "Δt = 2e-5 for real time").
mean_active_contacts_by_tenth: the contacts per step in each tenth of the coupled run. The cost of a
step grows with them, and a record can move from the usual ~2 contacts into a regime of ~5.5 for
the rest of the run, which costs about twice as much per step (docs/performance.md).

Accuracy (octave-band RMS of casing.B.Fz, Table 3, samples after ``--skip``, 0.06 s, through Hann's
window, the package's defaults):
* octave_rms_max_rel_diff: dt = 1e-5 against dt = 2.5e-6, one record each (the issue's figure);
* the same with contact off (the linear discretisation error alone), and with contact off at
  dt = 2e-5 (``_dt2e-05``: the FMU's real-time setting, docs/fmu.md);
* perturbation_max_rel_diff: dt = 1e-5 against dt = 1e-5 with the casing RMS scaled by 1 + 1e-9. The
  contact response is chaotic: two records that differ by 1e-9 in the input differ by as much as
  two time steps do, so the single-record comparison measures the scatter of a 1 s record;
* early_force_err_*: max |F(dt) - F(2.5e-6)| / RMS(F) over t < 0.05 s, before the trajectories
  separate: the discretisation error proper, which shrinks with dt (at 2e-5, 1e-5 and 5e-6).

Ensemble accuracy (``--ensemble N``, default 0 = skipped): N seeds of the casing's random excitation
(``scenario.excitation.casing_random.seed`` = 1..N, everything else default), each run at dt = 1e-5
and at ``--ensemble-reference-dt`` (default 2.5e-6; 3.125e-7 resolves the rattle of the contacts,
about 30 s per run) and, for the chaos baseline, at 1e-5 with the casing RMS scaled by 1 + 1e-9, ``--duration``
s each, on ``--workers`` processes (default 2). Per band, the relative difference of the ensemble
means r = (mean_N L(1e-5) - mean_N L(ref)) / mean_N L(ref), its standard error from the N paired
differences (each seed drives both runs), and |r| / SE (an SE from fewer than about 8 seeds is itself
too uncertain to read |r| / SE; records shorter than about 0.5 s have not fully decorrelated):
* octave_rms_ensemble_max_rel_diff: max over bands of |r| (issue 3's bar, 5 %, on ensemble means);
* octave_rms_ensemble_rel_diff_per_band (signed r), ..._rel_diff_se_per_band, ..._diff_over_se_per_band,
  ..._max_diff_over_se (max over bands of |r| / SE);
* octave_rms_ensemble_max_abs_plus_2se: max over bands of |r| + 2 SE, the bound on the true
  difference at about 95 % confidence per band;
* octave_rms_ensemble_max_rel_diff_by_n: the max over bands for the first n = 1, 2, 4, ... seeds;
* octave_rms_single_record_max_rel_diff_median_over_seeds: what one record of each would show;
* ensemble_seeds, ensemble_wall_s, ensemble_reference_dt, octave_rms_ensemble_mean_dt<ref> (band
  levels, N); ``--ensemble-save FILE.npz`` keeps the per-seed band levels (dt1e5, reference,
  dt1e5_perturbed; the name must end in .npz, the file is checked before the runs and written
  atomically after them);
* perturbation_ensemble_*: the same for the chaos baseline, whose true value is 0: it shrinks like
  1 / sqrt(N), and so does every band where the dt comparison is chaos scatter rather than bias.
Run: .venv/bin/python benchmarks/bench_time.py --duration 1.0 --ensemble 16   (17.5 min on the shared
2-core machine, 14.3 of them the ensemble; see docs/time_domain.md for the figures)
"""

import json
import time
from multiprocessing import get_context
from pathlib import Path

import numpy as np
from _alternating import alternate, ratio_quartiles
from _options import checked, integer, output_file, parser, seconds
from _options import model as model_option
from _record_length import require_band_record
from numba import njit

import cablecasing_core as cc
from cablecasing_core.files import atomic_path
from cablecasing_core.model.schema import SUPPORT_OUTPUTS
from cablecasing_core.nvh.bands import window_options
from cablecasing_core.records import after_skip
from cablecasing_core.studies import octave_rms, paired_difference
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.kernels import block_solve
from cablecasing_core.timedomain.scenario import scenario_motion


@njit
def _block_solve_loop(n, Dinv, L, LT, x):
    for _ in range(n):
        block_solve(Dinv, L, LT, x)


def block_solves_us(factors, n=20000):
    """us per step of one block LDLT solve per body (``factors``: each body's (Dinv, L, LT)), in a
    compiled loop (no Python call per solve; a zero right-hand side stays clear of subnormals)."""
    total = 0.0
    for Dinv, L, LT in factors:
        x = np.zeros(6 * len(Dinv))
        _block_solve_loop(1, Dinv, L, LT, x)
        t0 = time.perf_counter()
        _block_solve_loop(n, Dinv, L, LT, x)
        total += (time.perf_counter() - t0) / n
    return total * 1e6


p = parser(__doc__)
p.add_argument("--duration", type=float, default=1.0, help="s simulated per run")
p.add_argument(
    "--model",
    default="default",
    help="model of the accuracy checks and the ensemble: a TOML file or a built-in specimen (default, installed)",
)
p.add_argument("--speed-only", action="store_true", help="the speed figures only (no accuracy runs)")
p.add_argument(
    "--skip",
    type=float,
    default=0.06,
    help="s of each record left out of the band levels (default 0.06, the package's default for both specimens' "
    "1 s records: the rest then holds 47 whole periods of the 50 Hz drive, whose strong line would otherwise "
    "leak into the bands beside it)",
)
p.add_argument("--repeat", type=int, default=3, help="timed runs of each kind; the fastest counts (shared machine)")
p.add_argument("--ensemble", type=int, default=0, help="seeds of the ensemble accuracy check (0: skip it; else >= 2)")
p.add_argument("--workers", type=int, default=2, help="processes of the ensemble runs")
p.add_argument(
    "--ensemble-save",
    default=None,
    metavar="FILE.npz",
    help="write the ensemble's band levels to this file (its name ends in .npz; written atomically)",
)
p.add_argument(
    "--ensemble-reference-dt",
    type=float,
    default=2.5e-6,
    help="s: the time step the ensemble compares dt = 1e-5 with (default 2.5e-6; 3.125e-7 resolves "
    "the contacts' rattle, docs/time_domain.md)",
)
args = p.parse_args()
with checked(p):
    seconds("--duration", args.duration)
    seconds("--skip", args.skip, zero_ok=True)
    integer("--repeat", args.repeat, 1)
    integer("--workers", args.workers, 1)
    if args.ensemble != 0:
        integer("--ensemble", args.ensemble, 2)  # (a standard error needs two seeds)
    if args.speed_only and args.ensemble:
        p.error(f"--ensemble = {args.ensemble} with --speed-only: the ensemble is an accuracy check; leave one out")
    if args.ensemble_save is not None and not args.ensemble:
        p.error(f"--ensemble-save = {args.ensemble_save!r}: needs --ensemble N (the levels it writes)")
    output_file("--ensemble-save", args.ensemble_save, (".npz",))
    model_option("--model", args.model)
if not 1e-8 <= args.ensemble_reference_dt < 1e-5:
    p.error(f"--ensemble-reference-dt {args.ensemble_reference_dt}: must lie in [1e-8 s, 1e-5 s)")
if not args.speed_only:  # the accuracy checks take band levels of the records
    require_band_record(p, args.duration, args.skip)
REF = args.ensemble_reference_dt
model = cc.load_model()
DT = 1e-5
t0 = time.perf_counter()
Engine(model, dt=DT, ledger=False).advance(DT, scenario_motion(model))
print(f"numba_compile_or_cache_load_s: {time.perf_counter() - t0:.2f}")


def timed_advance(m, dt, contact=None, record=False):
    """(the wall times (s) of Engine.advance over --duration s of m's scenario at dt s, one per
    --repeat run, the last engine's set-up time (s), the last engine)."""
    walls = []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        run = Engine(m, dt=dt, contact=contact, ledger=False, record=record)
        setup = time.perf_counter() - t0
        mo = scenario_motion(m, dt=dt)
        t0 = time.perf_counter()
        run.advance(args.duration, mo)
        walls.append(time.perf_counter() - t0)
    return walls, setup, run


for contact, label in ((True, "coupled"), (False, "linear")):
    walls, _, eng = timed_advance(model, DT, contact=contact, record=contact)
    wall = min(walls)
    steps = args.duration / DT
    print(f"rtf_{label}: {args.duration / wall:.4f}")
    print(f"us_per_step_{label}: {wall / steps * 1e6:.2f}")
    print(f"us_per_step_{label}_slowest_run: {max(walls) / steps * 1e6:.2f}")
    if contact:
        h = eng.history()
        nc = np.count_nonzero(h["contact_state"], axis=1)
        print(f"mean_active_contacts: {np.mean(nc):.3f}")
        # the cost of a step grows with the contacts (Delassus O(n^2); Newton on one unknown per
        # slipping contact, three per sticking one), and a record can settle into a regime with many
        # more of them (see docs/performance.md)
        print(
            "mean_active_contacts_by_tenth:", " ".join(f"{x:.2f}" for x in (c.mean() for c in np.array_split(nc, 10)))
        )
        its, passes, failed = eng.solver_counts
        print(f"contact_newton_iterations_per_step: {its / steps:.3f}")
        print(f"contact_stick_slip_passes_per_step: {passes / steps:.3f}")
        print(f"contact_unconverged_steps: {int(failed)}")

# The default specimen's real-time setting (docs/time_domain.md, "Δt = 2e-5 for real time": its
# ensemble band means within 0.5 % of 2.5e-6's up to 1.4 kHz and 4.1 % in octave 9, 456 seeds;
# the FMU's solver.dt, docs/fmu.md; other steps: benchmarks/default_time_step.py):
# timed as rtf_coupled, right after it
COUPLED_REALTIME_DT = 2e-5
walls, _, _ = timed_advance(model, COUPLED_REALTIME_DT, contact=True, record=True)
print(f"rtf_coupled_realtime: {args.duration / min(walls):.4f} (scenario.dt = {COUPLED_REALTIME_DT:.6g} s)")
print(f"us_per_step_coupled_realtime: {min(walls) / (args.duration / COUPLED_REALTIME_DT) * 1e6:.2f}")

# What a user waits for: cc.simulate of the same case as a whole (scenario set-up, engine with the
# energy ledger and dense recording, result arrays), not only the step loop.
t0 = time.perf_counter()
cc.simulate(model, duration=args.duration)
print(f"simulate_wall_s: {time.perf_counter() - t0:.2f}")

# The installed specimen (issue 23): the same scenario from the static state, with the cable on the
# wall in the bends (the many-contact regime), and the static state itself.
installed = cc.load_model("installed")
walls, t_setup, eng = timed_advance(installed, DT, record=True)
wall_installed = min(walls)
nc = np.count_nonzero(eng.history()["contact_state"], axis=1)
print(f"rtf_installed: {args.duration / wall_installed:.4f}")
# The real-time setting of the installed specimen (docs/time_domain.md, "Real time on the installed
# specimen"): scenario.dt = 1/30000 s, three steps per FMU communication step of 1e-4 s and 600 per
# period of the 50 Hz drive; timed as rtf_installed, right after it
REALTIME_DT = 1.0 / 30000.0
walls, _, rt = timed_advance(installed, REALTIME_DT, record=True)
print(f"rtf_installed_realtime: {args.duration / min(walls):.4f} (scenario.dt = {REALTIME_DT:.6g} s)")
rt_its = rt.solver_counts[0] / (args.duration / REALTIME_DT)
print(f"contact_newton_iterations_per_step_installed_realtime: {rt_its:.3f}")
print(f"us_per_step_installed: {wall_installed / (args.duration / DT) * 1e6:.2f}")
print(f"mean_active_contacts_installed: {np.mean(nc):.3f}")
print("mean_active_contacts_installed_by_tenth:", " ".join(f"{c.mean():.2f}" for c in np.array_split(nc, 10)))
its, passes, failed = eng.solver_counts
print(f"contact_newton_iterations_per_step_installed: {its / (args.duration / DT):.3f}")
print(f"contact_stick_slip_passes_per_step_installed: {passes / (args.duration / DT):.3f}")
print(f"contact_unconverged_steps_installed: {int(failed)}")
st_hist = eng.history()["contact_state"]
print(f"stick_share_of_contacts_installed: {np.count_nonzero(st_hist == 1) / max(np.count_nonzero(st_hist), 1):.3f}")
print(f"engine_setup_installed_s: {t_setup:.3f} (assembly, factors, the static state)")

# Accuracy at the default settings (docs/time_domain.md, "A friction law whose limit exists"): the
# band levels of seeds 1 and 2 with the specimen's own regularised friction against the finest step
# of its levels in installed_reference_levels.json (levels_regularized_hann_N through Hann's window,
# levels_regularized_N through the rectangular one; the next finest's distance printed beside, what
# the reference leaves open); then the paper's switch law at its default
# settings (the sub-steps around stick-slip events) against the finest plain step of its levels
# (levels_N), which do not converge (docs/time_domain.md, "How many events there are").
reference = json.loads((Path(__file__).parent / "installed_reference_levels.json").read_text())
TOLERANCE = 1e-9  # m: contact.event_tolerance of the *_tolerance lines


def installed_band_errors(name, overrides, refs, done=None, dt=DT):
    """Print installed_band_max_rel_err<name> and its companions: the band levels of seeds 1 and 2
    at dt (s) with the model overrides against the finest plain step of each reference in ``refs``,
    a list of (suffix, window, levels): levels[seed][key], keys "dt<seconds>", "_sub" for
    sub-stepped runs, computed through ``window`` ("hann" or "boxcar"); the figures of a reference
    are named <name><suffix>, with the next finest step's distance from the finest beside them.
    done: an engine that already ran the specimen's own seed with these overrides. Returns the
    last seed's engine."""
    records = {}
    for seed in (1, 2):
        run = done if done is not None and seed == installed.scenario["seed"] else None
        if run is None:
            m = installed.with_overrides({"scenario.seed": seed, **overrides})
            run = Engine(m, dt=dt, ledger=False, record=True)
            run.advance(args.duration, scenario_motion(m, dt=dt))
        F = run.history()["support_forces"][:, SUPPORT_OUTPUTS.index("casing.B.Fz")]
        records[seed] = F[after_skip(dt * np.arange(1, len(F) + 1), reference["skip_s"])]
    for suffix, window, levels in refs:
        plain = sorted((k for k in levels["1"] if "_sub" not in k), key=lambda k: float(k[2:]))
        finest, next_finest = plain[0], plain[1]
        errs, spread = [], []
        for seed in (1, 2):
            level = octave_rms(records[seed], 1 / dt, **window_options(window)).rms
            ref = levels[str(seed)]
            errs.append(np.abs(level / np.array(ref[finest]) - 1))
            spread.append(np.abs(np.array(ref[next_finest]) / np.array(ref[finest]) - 1))
        worst, spread = np.max(errs, axis=0), np.max(spread, axis=0)
        key = name + suffix
        what = f"seeds 1-2, against {finest[2:]} s, {window} window"
        print(f"installed_band_max_rel_err{key}: {worst.max():.4f} ({what})")
        print(f"installed_band_max_rel_err{key}_octaves_3_9: {worst[2:].max():.4f}")
        print(f"installed_band_rel_err{key}_per_band:", " ".join(f"{x:.4f}" for x in worst))
        spread_txt = " ".join(f"{x:.4f}" for x in spread)
        print(f"installed_reference{key}_spread_per_band: {spread_txt} ({next_finest[2:]} against {finest[2:]} s)")
    return run


if not args.speed_only and args.duration == reference["duration_s"]:
    own = installed.contact["friction_law"]
    print(f"installed_friction_law: {own}")
    # the regularised law's references through Hann's window (the package's default) and the
    # rectangular one (the docs' earlier tables); the switch law's through the rectangular one only
    # (its finest step, 7.8125e-8 s, costs ~8 min per seed)
    if own == "regularized":
        refs = [("", "hann", reference["levels_regularized_hann_N"])]
        refs.append(("_boxcar", "boxcar", reference["levels_regularized_N"]))
    else:
        refs = [("", "boxcar", reference["levels_N"])]
    installed_band_errors("", {}, refs, done=eng)
    if own == "regularized":
        switch_refs = [("", "boxcar", reference["levels_N"])]
        switch = installed_band_errors("_switch", {"contact.friction_law": "switch"}, switch_refs)
        share = switch.refined_steps / (args.duration / DT)
        print(f"installed_refined_share_switch: {share:.3f} (steps recomputed in sub-steps with the switch law)")
    # a tolerance on the step's local error (docs/time_domain.md, "A tolerance instead of a bare step")
    tolerant = installed_band_errors("_tolerance", {"contact.event_tolerance": TOLERANCE}, refs[:1])
    share = tolerant.tolerance_steps / (args.duration / DT)
    print(f"installed_tolerance_m: {TOLERANCE:g} (contact.event_tolerance of the _tolerance lines)")
    print(f"installed_refined_share_tolerance: {share:.3f} (steps recomputed for their estimated local error)")
    # the real-time setting (docs/time_domain.md, "Real time on the installed specimen")
    installed_band_errors("_realtime", {}, refs, dt=REALTIME_DT)

# What bounds rtf_installed whatever the contact solve costs (docs/performance.md, "What bounds
# rtf_installed at 1e-5 s, part by part"): the installed step without contact
# (the two bodies' Newmark step: predictor, update, reactions, the constant load), and within it
# the two block-tridiagonal solves, the least an implicit step of these bodies does. With the
# regularised friction the default step is the accurate one (within 0.8 % in every band,
# docs/time_domain.md, "A friction law whose limit exists"): real time allows 10 us per step.
ACCURATE_DT = DT
us_installed = wall_installed / (args.duration / DT) * 1e6
walls, _, eng_free = timed_advance(installed, DT, contact=False)
us_free = min(walls) / (args.duration / DT) * 1e6
solves = [b.factors(DT, False)[:3] for b in eng_free.bodies.values()]
us_solves = min(block_solves_us(solves) for _ in range(args.repeat))
contacts = float(np.mean(nc))
print(f"us_per_step_installed_contact_free: {us_free:.2f} (the same step without contact)")
print(f"us_per_step_installed_block_solves: {us_solves:.2f} (the two bodies' block LDLT solves alone)")
print(
    f"installed_contact_us_per_contact: {(us_installed - us_free) / contacts:.2f} (the contact part of a step per "
    f"contact) against a budget for rtf 1 at dt 1e-5 of {(DT * 1e6 - us_free) / contacts:.2f}"
)
print(
    f"rtf_installed_bound_at_accurate_dt: {ACCURATE_DT * 1e6 / us_free:.3f} (at dt {ACCURATE_DT:g} s with contacts "
    f"that cost nothing); with only the block solves {ACCURATE_DT * 1e6 / us_solves:.3f}"
)
from cablecasing_core.timedomain.static_state import static_state  # noqa: E402

t0 = time.perf_counter()
st = static_state(installed)
print(f"static_state_s: {time.perf_counter() - t0:.3f} ({st.iterations} Newton iterations, {st.load_steps} load steps)")
import subprocess  # noqa: E402
import sys  # noqa: E402


def fresh_process_wall_s(argv):
    """The fastest of args.repeat wall times (s) of a fresh Python process running argv."""
    walls = []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, *argv], check=True, capture_output=True)
        walls.append(time.perf_counter() - t0)
    return min(walls)


cli_wall = fresh_process_wall_s(["-m", "cablecasing_core.cli", "static", "installed", "--json"])
print(f"static_cli_wall_s: {cli_wall:.2f} (cablecasing static installed --json, a fresh process: imports included)")
# What any process that does what `cablecasing static` does pays before our code runs: the
# interpreter, numpy, scipy's linalg and sparse, and numba's first call of a cached kernel (its CPU
# target's set-up), and their teardown at exit.
FLOOR = (
    "import numpy as np, scipy.linalg, scipy.sparse; "
    "from cablecasing_core.timedomain.kernels._banded_products_and_block_solve import copy_into; "
    "copy_into(np.zeros(3), np.ones(3))"
)
floor_wall = fresh_process_wall_s(["-c", FLOOR])
print(
    f"static_cli_library_floor_wall_s: {floor_wall:.2f} (the libraries alone: numpy, scipy.linalg and sparse, "
    "numba's first cached call)"
)
print(f"static_cli_own_wall_s: {cli_wall - floor_wall:.2f} (the command's own part: its modules, the model, the solve)")
help_wall = fresh_process_wall_s(["-m", "cablecasing_core.cli", "--help"])
print(f"cli_help_wall_s: {help_wall:.2f} (cablecasing --help, a fresh process: the interpreter, the CLI's imports)")

# The cost of an installed step against a default one, robust to the shared machine's drift: both
# engines advance alternately in 0.01 s chunks in this process, and the ratio is taken chunk by chunk.
engines = {name: Engine(m, dt=DT, ledger=False) for name, m in (("default", model), ("installed", installed))}
motions = {"default": scenario_motion(model, dt=DT), "installed": scenario_motion(installed, dt=DT)}
chunk = 0.01
calls = [lambda name=name: engines[name].advance(chunk, motions[name]) for name in ("default", "installed")]
w_default, w_installed = alternate(calls, int(round(args.duration / chunk))).T
q = ratio_quartiles(w_installed, w_default, skip=10)  # without the first 0.1 s: contacts build up
print(f"installed_over_default_step_cost: {q[1]:.2f} (quartiles {q[0]:.2f}-{q[2]:.2f}, per 0.01 s chunk, alternating)")

# The default settings of the installed specimen (1e-5 s, friction regularised: no events) against
# the paper's switch law at its default settings (the steps around stick-slip events in 8
# sub-steps) and against the switch law's plain 1e-5 s step without sub-steps, alternating in
# 0.01 s chunks in this process.
switch = installed.with_overrides({"contact.friction_law": "switch"})
variants = {
    "default": Engine(installed, dt=DT, ledger=False),
    "switch": Engine(switch, dt=DT, ledger=False),
    "switch_plain": Engine(switch.with_overrides({"contact.event_substeps": 1}), dt=DT, ledger=False),
    "tolerance": Engine(installed.with_overrides({"contact.event_tolerance": TOLERANCE}), dt=DT, ledger=False),
}
calls = [lambda e=eng: e.advance(chunk, motions["installed"]) for eng in variants.values()]
walls = dict(zip(variants, alternate(calls, int(round(min(args.duration, 0.3) / chunk))).T))
for name, what in (
    ("switch", "the switch law with its sub-steps"),
    ("switch_plain", "the switch law's 1e-5 s without sub-steps"),
    ("tolerance", "its own law with contact.event_tolerance = 1e-9 m"),
):
    # (friction_laws.py's regularized_over_switch_step_cost is the first of these, alone)
    q = ratio_quartiles(walls["default"], walls[name], skip=5)  # without the first 0.05 s
    print(f"installed_default_over_{name}_cost: {q[1]:.2f} (quartiles {q[0]:.2f}-{q[2]:.2f}; against {what})")
if args.speed_only:
    raise SystemExit(0)
model = cc.load_model(args.model)  # the accuracy checks and the ensemble below
print(f"accuracy_model: {args.model}")


def force(m, dt, duration, contact=None, motion=None):
    """Time (s) and casing.B.Fz (N) of a run: the engine as ``cc.simulate`` runs it (the ledger does
    not change the state), its contact history kept sparse (a 1 s run at dt = 3e-7 would need 2 GB
    as ``simulate``'s dense arrays)."""
    eng = Engine(m, dt=dt, contact=contact, ledger=False, record=True)
    eng.advance(duration, scenario_motion(m, dt=dt) if motion is None else motion)
    F = eng.history(sparse=True)["support_forces"][:, SUPPORT_OUTPUTS.index("casing.B.Fz")]
    return np.minimum(dt * np.arange(1, len(F) + 1), eng.time), F


def bands(t, F, dt):
    """The Table 3 band levels (N) of F after ``--skip`` through Hann's window (the package's default)."""
    return octave_rms(F[after_skip(t, args.skip)], 1 / dt, **window_options("hann")).rms


def rel(a, b):
    return np.abs(a - b) / b


runs = {dt: force(model, dt, args.duration) for dt in (1e-5, 2.5e-6)}
lv = {dt: bands(*runs[dt], dt) for dt in runs}
r = rel(lv[1e-5], lv[2.5e-6])
print(f"octave_rms_max_rel_diff: {r.max():.4f}")
print("octave_rms_rel_diff_per_band: " + " ".join(f"{x:.3f}" for x in r))

perturbed = model.with_overrides({"scenario.excitation.casing_random.rms": 5.0 * (1 + 1e-9)})
r = rel(bands(*force(perturbed, 1e-5, args.duration), 1e-5), lv[1e-5])
print(f"perturbation_max_rel_diff: {r.max():.4f}")
print("perturbation_rel_diff_per_band: " + " ".join(f"{x:.3f}" for x in r))

lin = {dt: bands(*force(model, dt, args.duration, contact=False), dt) for dt in (1e-5, 2e-5, 2.5e-6)}
r = rel(lin[1e-5], lin[2.5e-6])
print(f"octave_rms_max_rel_diff_contact_off: {r.max():.4f}")
print("octave_rms_rel_diff_per_band_contact_off: " + " ".join(f"{x:.3f}" for x in r))
# dt = 2e-5: the FMU's real-time setting (docs/fmu.md, "Real time"); Newmark's period error grows
# as dt^2, so the linear part shows it best
r = rel(lin[2e-5], lin[2.5e-6])
print(f"octave_rms_max_rel_diff_contact_off_dt2e-05: {r.max():.4f}")
print("octave_rms_rel_diff_per_band_contact_off_dt2e-05: " + " ".join(f"{x:.3f}" for x in r))

# the trajectories before chaos separates them (t < 0.05 s): error against dt = 2.5e-6
tr, Fr = runs[2.5e-6]
rms = np.sqrt(np.mean(Fr[tr > 0.05] ** 2))
for dt in (2e-5, 1e-5, 5e-6):
    # the same excitation record (its length sets its frequency lines), only 0.05 s of it
    t, F = runs[dt] if dt in runs else force(model, dt, 0.05, motion=scenario_motion(model, dt=dt))
    e = t < 0.05
    Fref = np.interp(t[e], tr, Fr)  # the reference at the coarse times (common grid points)
    print(f"early_force_err_dt{dt:g}: {np.max(np.abs(F[e] - Fref)) / rms:.2e}")


# ------------------------------------------------------------------------------------------------
# Ensemble accuracy (--ensemble N): the same comparisons on means over N excitation seeds.
#
# Statistic: cablecasing_core.studies.paired_difference, the relative difference of the ensemble
# means with its standard error from the paired seeds. Its docstring says why it is not the mean of
# the per-seed relative differences (that estimates E[a/b] - 1, positive by about CV^2 even for two
# identically distributed records, a floor of up to 5 % in octave 9 that does not shrink with N).
#
# Runs: a fork pool of --workers processes (default 2, the machine's cores). Every run is an
# independent single-threaded engine, so two processes nearly halve the wall time; fork keeps the
# kernels already compiled or loaded above, and the pool needs nothing beyond the standard library
# (dask is only the study extra, and its scheduler adds nothing for 3N equal jobs).

RANDOM_KEY = "scenario.excitation.casing_random"


def ensemble_run(job):
    seed, dt, scale = job
    m = model.with_overrides(
        {f"{RANDOM_KEY}.seed": seed, f"{RANDOM_KEY}.rms": model.scenario["excitation"]["casing_random"]["rms"] * scale}
    )
    return job, bands(*force(m, dt, args.duration), dt)


def report(name, a, b):
    d = paired_difference(a, b)
    r, se = d.r, d.se
    print(f"{name}_ensemble_max_rel_diff: {np.abs(r).max():.4f}")
    print(f"{name}_ensemble_rel_diff_per_band: " + " ".join(f"{x:+.3f}" for x in r))
    print(f"{name}_ensemble_rel_diff_se_per_band: " + " ".join(f"{x:.3f}" for x in se))
    print(f"{name}_ensemble_diff_over_se_per_band: " + " ".join(f"{x:+.1f}" for x in r / se))
    print(f"{name}_ensemble_max_diff_over_se: {np.max(np.abs(r) / se):.2f}")
    # the bound at about 95 % confidence per band: the true difference of the expected levels is
    # below |r| + 2 SE (what the 5 % bar is read against when single records are chaotic)
    print(f"{name}_ensemble_max_abs_plus_2se: {np.max(np.abs(r) + 2 * se):.4f}")
    ns = [n for n in (1, 2, 4, 8, 16, 32, 64, 128) if n < len(a)] + [len(a)]
    print(
        f"{name}_ensemble_max_rel_diff_by_n: "
        + " ".join(f"{n}:{np.abs(paired_difference(a[:n], b[:n]).r).max():.4f}" for n in ns)
    )
    single = np.abs(a - b) / b
    print(f"{name}_single_record_max_rel_diff_median_over_seeds: {np.median(single.max(axis=1)):.4f}")


if args.ensemble > 0:
    seeds = range(1, args.ensemble + 1)
    variants = ((REF, 1.0), (1e-5, 1.0), (1e-5, 1 + 1e-9))  # longest jobs first
    jobs = [(s, dt, sc) for dt, sc in variants for s in seeds]
    t0 = time.perf_counter()
    with get_context("fork").Pool(args.workers) as pool:
        levels = dict(pool.imap_unordered(ensemble_run, jobs, chunksize=1))
    L = {v: np.array([levels[(s, *v)] for s in seeds]) for v in variants}
    print(f"ensemble_seeds: {args.ensemble}")
    print(f"ensemble_wall_s: {time.perf_counter() - t0:.1f}")
    print(f"ensemble_reference_dt: {REF:g}")
    print(f"octave_rms_ensemble_mean_dt{REF:g}: " + " ".join(f"{x:.4g}" for x in L[(REF, 1.0)].mean(axis=0)))
    report("octave_rms", L[(1e-5, 1.0)], L[(REF, 1.0)])
    report("perturbation", L[(1e-5, 1 + 1e-9)], L[(1e-5, 1.0)])
    if args.ensemble_save:
        with atomic_path(args.ensemble_save) as tmp:
            np.savez(
                tmp,
                seeds=np.array(list(seeds)),
                duration=args.duration,
                dt1e5=L[(1e-5, 1.0)],
                reference=L[(REF, 1.0)],
                reference_dt=REF,
                dt1e5_perturbed=L[(1e-5, 1 + 1e-9)],
            )
