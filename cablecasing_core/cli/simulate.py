"""``cablecasing simulate``: run a model's scenario in the time domain."""

from __future__ import annotations

from .helptext import key_help


def cmd_simulate(args):
    from ..model import load_model
    from ..timedomain.simulation import simulate
    from .paths import check_output_path

    check_output_path("--out", args.out, (".csv", ".npz"))
    check_output_path("--plot", args.plot)
    model = load_model(args.model)
    res = simulate(model, duration=args.duration, dt=args.dt, contact=False if args.no_contact else None)
    rms = {n: float((res.support_force(n) ** 2).mean() ** 0.5) for n in ("casing.B.Fx", "casing.B.Fy", "casing.B.Fz")}
    print(f"simulated {res.time[-1]:.6g} s in {len(res.time)} steps")
    for n, v in rms.items():
        print(f"  RMS {n}: {v:.6g} N")
    print(
        f"  contact: {int((res.contact_state != 0).any(axis=0).sum())} cable nodes touched, "
        f"max penetration {res.penetration.max():.3g} m"
    )
    e = res.energies
    print("  energy (J): " + ", ".join(f"{k} {v:.4g}" for k, v in e.items()))
    if res.contact_state.any():
        print(
            "  note: with contact the response is chaotic, so one record's band levels are one draw "
            "(3-20 % scatter per octave);\n        for expected levels use 'cablecasing ensemble' (docs/studies.md)"
        )
    if args.out:
        res.save(args.out)
        print(f"wrote {args.out}")
    if args.plot:
        from ..plotting import plot_time_result

        path = args.plot if isinstance(args.plot, str) else "simulation.png"
        plot_time_result(res, path)
        print(f"wrote {path}")
    return 0


def add_parser(sub):
    p = sub.add_parser("simulate", help="time-domain run of the scenario (Newmark + contact)")
    p.add_argument("model", nargs="?", default=None, help="model TOML (default: built-in specimen)")
    p.add_argument("--duration", type=float, default=None, help=key_help("scenario.duration", "simulated time"))
    p.add_argument("--dt", type=float, default=None, help=key_help("scenario.dt"))
    p.add_argument("--out", help="results file, .csv or .npz")
    p.add_argument("--plot", nargs="?", const=True, default=None, help="write a figure (PNG path)")
    p.add_argument("--no-contact", action="store_true", help="switch contact off")
    p.set_defaults(func=cmd_simulate)
