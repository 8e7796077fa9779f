"""How fast two records of the reference case separate: the chaos behind issue 3's accuracy figure.

Each variant of the reference case (default model, its scenario, ``--duration`` s, the same
excitation record throughout: the random record depends on its seed, band and RMS only) runs once, and its
casing.B.Fz history is compared with the record at dt = 1e-5 s:
* eps_1e-12, eps_1e-09, eps_1e-06: the casing's RMS scaled by 1 + eps, dt 1e-5 (a perturbation of the
  input alone);
* dt_5e-06, dt_2.5e-06: the same input at a finer time step (every 2nd or 4th sample is on the
  1e-5 grid); dt_2.5e-06 is the pair behind ``octave_rms_max_rel_diff`` in bench_time.py;
* contact_off_eps_1e-09, contact_off_dt_2.5e-06: the same two comparisons without contact.

Separation s(t): the RMS of the difference over windows of ``--window`` s, over the RMS of the
reference after 0.05 s. Printed per variant, as ``name: value`` lines:
* <variant>_initial_separation: s in the window ending at 0.02 s (after the 0.01 s fade-in);
* <variant>_crossing_s: the first time s exceeds 1e-10, 1e-9, ..., 1e-1 (nan: never);
* <variant>_efold_s: the e-folding time of s, the least-squares slope of those crossing times
  against ln(threshold) over the thresholds from 100 x the initial separation up to 1e-2 (needs
  three of them);
* <variant>_final_separation: s over the last tenth of the record.
Chaos shows as: the three input perturbations grow at one rate (the same e-folding time) from
wherever they start, so each 1000 x smaller one takes ln(1000) e-folding times longer to reach the
same separation, and all end at the separation of two unrelated records (order 1); the finer time
step reaches it too, from the discretisation error it starts with; without contact neither grows.
Run: .venv/bin/python benchmarks/chaos.py [--duration 0.5] [--window 0.002] [--plot FILE.png]
[--set contact.damping=0 --set contact.friction=0 ...] (numeric model overrides for every run; about 40 s
on the shared 2-core machine, one core).
"""

import numpy as np
from _options import checked, output_file, parser

import cablecasing_core as cc
from cablecasing_core.cli.paths import PLOT_SUFFIXES
from cablecasing_core.errors import ModelError

p = parser(__doc__)
p.add_argument("--duration", type=float, default=0.5, help="s simulated per run")
p.add_argument("--window", type=float, default=0.002, help="s per window of the separation")
p.add_argument("--plot", default=None, help="write the separation histories to this figure (.png, .pdf, .svg)")
p.add_argument(
    "--set",
    action="append",
    default=[],
    metavar="KEY=VALUE",
    help="numeric model override for every run, e.g. contact.damping=0 (repeatable)",
)
args = p.parse_args()
if not args.duration >= 0.1:
    p.error(f"--duration {args.duration}: must be at least 0.1 s (the RMS is taken after 0.05 s)")
if not 1e-5 <= args.window <= args.duration / 10:
    p.error(f"--window {args.window}: must be between 1e-5 s and a tenth of the duration")

DT = 1e-5
THRESHOLDS = 10.0 ** np.arange(-10, 0)  # 1e-10 .. 1e-1
model = cc.load_model()
overrides = {}
for kv in args.set:
    key, _, value = kv.partition("=")
    try:
        overrides[key] = float(value)
    except ValueError:
        p.error(f"--set {kv!r}: expected KEY=NUMBER, e.g. contact.damping=0")
with checked(p):
    try:
        model = model.with_overrides(overrides) if overrides else model  # with_overrides checks the keys
    except ModelError as exc:
        raise ModelError("--set", args.set, str(exc)) from None
    output_file("--plot", args.plot, PLOT_SUFFIXES)  # (before the runs, not after them)
rms0 = model.scenario["excitation"]["casing_random"]["rms"]


def casing_force(eps=0.0, dt=DT, contact=None):
    """casing.B.Fz (N) on the 1e-5 s grid, casing RMS scaled by 1 + eps."""
    m = model.with_overrides({"scenario.excitation.casing_random.rms": rms0 * (1 + eps)}) if eps else model
    res = cc.simulate(m, duration=args.duration, dt=dt, contact=contact)
    stride = int(round(DT / dt))  # samples at dt, 2 dt, ...: every stride-th is on the grid
    return res.time[stride - 1 :: stride], res.support_force("casing.B.Fz")[stride - 1 :: stride]


def separation(F, Fref, t, width):
    """Window end times (s) and the RMS of F - Fref per window over the RMS of Fref after 0.05 s."""
    n = int(round(width / DT))
    k = len(F) // n
    d = (F[: k * n] - Fref[: k * n]).reshape(k, n)
    return t[n - 1 : k * n : n], np.sqrt(np.mean(d**2, axis=1)) / np.sqrt(np.mean(Fref[t > 0.05] ** 2))


def crossings(tw, s):
    """First window end time where s exceeds each threshold (nan: never)."""
    return np.array([tw[np.argmax(s > th)] if np.any(s > th) else np.nan for th in THRESHOLDS])


def efold(tc, s0):
    """Slope of the crossing times against ln(threshold), over thresholds 100 s0 .. 1e-2."""
    use = (THRESHOLDS >= 100 * s0) & (THRESHOLDS <= 1e-2) & np.isfinite(tc)
    if use.sum() < 3:
        return np.nan
    return np.polyfit(np.log(THRESHOLDS[use]), tc[use], 1)[0]


t, ref = casing_force()
_, ref_off = casing_force(contact=False)
variants = {f"eps_{e:.0e}": (casing_force(eps=e), ref) for e in (1e-12, 1e-9, 1e-6)}
variants.update({f"dt_{dt:g}": (casing_force(dt=dt), ref) for dt in (5e-6, 2.5e-6)})
variants["contact_off_eps_1e-09"] = (casing_force(eps=1e-9, contact=False), ref_off)
variants["contact_off_dt_2.5e-06"] = (casing_force(dt=2.5e-6, contact=False), ref_off)

curves = {}
for name, ((tv, F), Fref) in variants.items():
    assert np.allclose(tv, t, rtol=0, atol=1e-9), name
    tw, s = separation(F, Fref, t, args.window)
    curves[name] = (tw, s)
    s0 = s[np.searchsorted(tw, 0.02 - 1e-12)]
    tc = crossings(tw, s)
    print(f"{name}_initial_separation: {s0:.2e}")
    print(f"{name}_crossing_s: " + " ".join(f"{th:.0e}:{x:.3f}" for th, x in zip(THRESHOLDS, tc)))
    print(f"{name}_efold_s: {efold(tc, s0):.4f}")
    print(f"{name}_final_separation: {np.sqrt(np.mean(s[-max(len(s) // 10, 1) :] ** 2)):.3f}")

if args.plot:
    from cablecasing_core.plotting import plt, save_figure  # (matplotlib with Agg)

    fig, ax = plt.subplots(figsize=(8, 4.5))
    for name, (tw, s) in curves.items():
        ax.semilogy(tw, s, "--" if name.startswith("contact_off") else "-", label=name.replace("_", " "))
    ax.set_xlabel("time (s)")
    ax.set_ylabel("RMS difference of casing.B.Fz / RMS")
    ax.set_title(
        f"Separation from the record at dt = 1e-5 s ({args.window * 1e3:g} ms windows)"
        + ("\n" + ", ".join(args.set) if args.set else ""),
        fontsize=10,
    )
    ax.grid(True, which="major", alpha=0.4)
    ax.legend(fontsize=8, ncol=2)
    save_figure(fig, args.plot)  # (laid out, 110 dpi, written atomically)
    print(f"plot: {args.plot}")
