"""``cablecasing simulate``: run a model's scenario in the time domain."""

from __future__ import annotations

import math

import numpy as np

from .assignments import add_model_argument, assignments, model_argument, typed, with_assignments
from .helptext import key_help

OUT_SUFFIXES = (".csv", ".npz", ".uff")


def cmd_simulate(args):
    from ..errors import renamed
    from ..timedomain.simulation import simulate
    from .paths import PLOT_SUFFIXES, check_distinct, check_output_path, kept

    check_output_path("--out", args.out, OUT_SUFFIXES)
    check_output_path("--plot", args.plot, PLOT_SUFFIXES)
    check_distinct(("--out", args.out), ("--plot", args.plot))
    model = model_argument(args.model)
    if args.set:  # (a key that --duration, --dt or --no-contact takes the place of would do nothing: refused)
        from ..studies.evaluators import check_not_overridden

        shown = typed(args.set)  # (the values as typed, for the message)
        check_not_overridden(
            {k: (f"--set {k}", shown[k]) for k in assignments("--set", args.set)},
            {
                "duration": ("--duration", args.duration),
                "dt": ("--dt", args.dt),
                "contact": ("--no-contact", False if args.no_contact else None),
            },
            "the run",
            "; give one of them",
        )
    model = with_assignments(model, "--set", args.set)
    if args.output_interval is not None:  # checked before the run against the time step
        _check_interval(
            args.output_interval,
            model.scenario["dt"] if args.dt is None else args.dt,
            model.scenario["duration"] if args.duration is None else args.duration,
        )
    plot = args.plot if isinstance(args.plot, str) else ("simulation.png" if args.plot else None)
    if args.plot is True:
        check_output_path("--plot", plot)
    args.interrupted = kept("the run was stopped", args.out, plot)
    names = {"duration": "--duration", "dt": "--dt"}
    if args.duration is not None:  # (the memory check names the scenario's key: here the option gave it)
        names["scenario.duration"] = "--duration"
    with renamed(names):
        contact = False if args.no_contact else None
        res = simulate(model, duration=args.duration, dt=args.dt, contact=contact, progress=args.progress)
    print(f"simulated {res.time[-1]:.6g} s in {len(res.time)} steps{_refined(res.solver)}")
    print(output_summary(model, res))
    print(
        f"  contact: {int((res.contact_state != 0).any(axis=0).sum())} cable nodes touched, "
        f"max penetration {res.penetration.max(initial=0.0):.3g} m"
    )
    print(energy_report(res.energies))
    if res.contact_state.any():
        print(
            "  note: with contact the response is chaotic, so one record's band levels are one draw "
            "(the CV of the built-in specimen's 1 s records through Hann's window is 9-26 % per octave over 32 "
            "seeds; more in shorter records, and a CV of a few seeds, as the report's, scatters itself);\n"
            "        for expected levels use 'cablecasing ensemble' (docs/studies.md)"
        )
    if args.out:
        # (the core names its arguments; here the options gave them)
        with renamed({"path": "--out", "output_interval": "--output-interval", "decimation": "--decimation"}):
            rec = res.save(args.out, output_interval=args.output_interval, decimation=args.decimation)
        every = ", t = 0 and every step"
        if args.output_interval:
            how = _decimated(rec, args.output_interval, res.dt)
            every = f", t = 0, {args.output_interval:g}, ... s ({how})"
        if res.whole_steps < len(res.time):
            every += (
                f"; the last step, {res.time[-1] - res.time[-2]:.3g} s, is shorter than dt (the duration is not a "
                f"whole number of steps): the record ends at the last whole step, t = {res.time[-2]:.6g} s"
            )
        print(f"wrote {args.out}{every}")
    if args.plot:
        from ..plotting import plot_time_result

        path = args.plot if isinstance(args.plot, str) else "simulation.png"
        plot_time_result(res, path)
        print(f"wrote {path}")
    return 0


def _decimated(rec, interval, dt):
    """How the record ``rec`` written every ``interval`` s of a run of step ``dt`` (s) was decimated:
    picked, or low-pass filtered with its passband in Hz (the one ``rec`` states,
    ``SimulationResult.records``: stated in a .csv, .npz or .uff file)."""
    if round(interval / dt) == 1:
        return "every step"
    if "passband_hz" not in rec.extra:
        return f"picked: content above the Nyquist frequency {1 / (2 * interval):.4g} Hz aliases"
    passband = float(rec.extra["passband_hz"])
    return (
        f"low-pass filtered against aliasing, flat within 0.01 dB up to its passband {passband:.4g} Hz, which the "
        "file states"
    )


def _check_interval(interval, dt, duration):
    """``--output-interval`` must be a whole number of time steps and the duration a whole number
    of intervals (so that the record ends at T: the grid t = 0, S, 2S, ..., T)."""
    from ..errors import ModelError
    from ..model.validators import seconds

    seconds("--output-interval", interval)
    m = round(interval / dt)
    if not interval > 0 or m < 1 or abs(m * dt - interval) > 1e-6 * dt:
        raise ModelError("--output-interval", interval, f"must be a whole number of time steps (dt = {dt:g} s)")
    k = round(duration / interval)
    if k < 1 or abs(k * interval - duration) > 1e-6 * dt:
        n = round(duration / dt)  # the run's steps; an interval of d steps with d dividing n ends at T
        whole = n >= 1 and abs(n * dt - duration) <= 1e-6 * dt
        small = [d for d in range(1, math.isqrt(n) + 1) if n % d == 0] if whole else []
        divisors = small + [n // d for d in small]
        near = min(divisors, key=lambda d: (abs(d - m), -d)) if divisors else None
        if near:
            hint = f" (e.g. {near * dt:.6g} s, {near} steps)"
        else:
            hint = (
                f"; the duration itself is not a whole number of time steps (dt = {dt:g} s), so no interval "
                "does: give a duration of whole steps"
            )
        raise ModelError(
            "--output-interval",
            interval,
            f"must divide the duration ({duration:g} s) into whole intervals of whole time steps, so that "
            f"the record ends at t = {duration:g} s{hint}",
        )


#: The kind of each support's output line in the summary, by support type.
_SUPPORT_KIND = {"clamped": "support", "isolator": "isolator"}


def output_summary(model, res) -> str:
    """Lines of every support, isolator and clip output of a run (``res.force_names``; free supports
    and absent bodies have none): the mean (over the run: preload, gravity, what friction holds), the total RMS, the
    dynamic RMS (mean removed: what vibrates) and the peak of the dynamic part, in N or N.m."""
    from ..model.schema import output_spec

    rows = []
    for i, name in enumerate(res.force_names):
        body, where, _ = name.split(".")
        if where.startswith("clip"):
            kind = "clip"
        else:
            kind = _SUPPORT_KIND.get(model.data.get(body, {}).get("supports", {}).get(where))
        if kind is None:
            continue
        x = res.support_forces[:, i]
        mean = float(x.mean())
        rows.append(
            f"  {name:<18} {kind:<8} {output_spec(name)[0]:<4} {mean:>11.4g} {float(np.sqrt(np.mean(x**2))):>11.4g} "
            f"{float(x.std()):>11.4g} {float(np.abs(x - mean).max()):>11.4g}"
        )
    head = (
        f"  {'output':<18} {'kind':<8} {'unit':<4} {'mean':>11} {'RMS total':>11} {'RMS dynamic':>11} {'peak dyn.':>11}"
    )
    note = (
        "  (RMS dynamic: the mean removed, what vibrates; the mean is the force averaged over the run: an installed "
        "preload, and what friction has shifted between the bodies since)"
    )
    return "\n".join(["  force each body exerts on its supports and clips, over the run:", head, *rows, note])


def _j(x):
    """An energy (J) to 4 significant digits, never '-0'."""
    return f"{float(x) + 0.0:.4g}"


def energy_report(e):
    """The energy ledger (J) as lines that say what each figure is and how they balance."""
    split = e["contact_damping_dissipation"] + e["friction_dissipation"]
    lines = ["  energy balance (J) since t = 0:"]
    if e.get("start_energy"):  # (an installed model's static state: strain and contact energy at rest)
        lines.append(f"    stored at t = 0                 {_j(e['start_energy'])}")
    lines.append(f"    supplied by the supports        {_j(e['support_work'])}")
    if e.get("load_work"):
        lines.append(f"    supplied by the constant loads  {_j(e['load_work'])}  (gravity, the tension's pre-stretch)")
    lines += [
        f"    dissipated by Rayleigh damping  {_j(e['rayleigh_dissipation'])}",
        f"    dissipated in the contacts      {_j(e['contact_dissipation'])}"
        "  (work of the contact forces less the energy they store; the balance uses this)",
    ]
    if e["contact_dissipation"] or split:
        lines += [
            f"      its parts, from their powers: contact damping {_j(e['contact_damping_dissipation'])}, friction "
            f"{_j(e['friction_dissipation'])} (sum {_j(split)}); the rest, {_j(e['contact_normal_dissipation'])}, is",
            "      the normal forces' own work (negative: energy made; the normal-plane contact on a mesh of a curved",
            "      casing, falling as its elements shorten: docs/time_domain.md, 'Energy ledger')",
        ]
    if e.get("mount_dissipation"):
        lines.append(f"    dissipated in the mounts        {_j(e['mount_dissipation'])}  (their dampers)")
    lines += [
        f"    stored now: kinetic {_j(e['kinetic'])}, strain {_j(e['strain'])}, contact {_j(e['contact_potential'])}",
        f"    residual {_j(e['residual'])} (stored now - stored at t = 0 - supplied + dissipated: the ledger's error)",
    ]
    return "\n".join(lines)


def add_parser(sub):
    p = sub.add_parser("simulate", help="time-domain run of the scenario (Newmark + contact)")
    add_model_argument(p, settable=True)
    p.add_argument("--duration", type=float, default=None, help=key_help("scenario.duration", "simulated time"))
    p.add_argument("--dt", type=float, default=None, help=key_help("scenario.dt"))
    p.add_argument(
        "--out",
        help="record to write: .csv (columns 'casing.B.Fz [N]', ...), .npz (every array) or .uff (UFF 58 time records)",
    )
    p.add_argument(
        "--output-interval",
        type=float,
        default=None,
        metavar="S",
        help="write t = 0, S, 2S, ..., the duration: S a whole number of time steps dividing the duration "
        "(default: every step); low-pass filtered against aliasing (see --decimation)",
    )
    p.add_argument(
        "--decimation",
        choices=["filter", "pick"],
        default="filter",
        help="with --output-interval: filter (a zero-phase FIR, flat to 0.7 and 80 dB down above 1/(2 S) Hz, "
        "so nothing aliases) or pick the samples as they are (content above 1/(2 S) Hz aliases)",
    )
    p.add_argument(
        "--plot", nargs="?", const=True, default=None, help="write a figure (PNG path; default simulation.png)"
    )
    p.add_argument("--no-contact", action="store_true", help="switch contact off")
    p.add_argument(
        "--no-progress",
        dest="progress",
        action="store_false",
        help="no progress bar (default: a bar of the simulated time on stderr)",
    )
    p.set_defaults(func=cmd_simulate)


def _refined(solver: dict) -> str:
    """', N of them recomputed, each in k sub-steps, around stick-slip events' when any were, ', friction
    regularised (no stick-slip events)' with that law, and with contact.event_tolerance how many
    steps it recomputed and the largest local error estimated, an estimate of one step's or sub-step's
    displacement error, not an accuracy of the outputs (the run's
    ``SimulationResult.solver``; docs/time_domain.md, "Events inside the step", "A friction law
    whose limit exists", "A tolerance instead of a bare step")."""
    tol = solver.get("event_tolerance", 0.0)
    n_tol = solver.get("tolerance_steps", 0)
    n_events = solver.get("event_steps", 0)
    if solver.get("friction_law") == "regularized":
        text = ", friction regularised (no stick-slip events)"
    elif n_events:
        k = solver["event_substeps"]
        text = f", {n_events} of them recomputed, each in {k} sub-steps, around stick-slip events"
    else:
        text = ""
    if tol > 0.0:
        over = "" if solver.get("tolerance_met", True) else ", a sub-step's, above the tolerance"
        text += (
            f", {n_tol} recomputed, each in {solver['event_substeps']} sub-steps, for contact.event_tolerance "
            f"= {tol:g} m (largest estimated local displacement error of a step or sub-step kept "
            f"{solver['max_local_error']:.3g} m{over})"
        )
    return text
