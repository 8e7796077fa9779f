"""``cablecasing report``: the report of a model (figures and tables from one set of runs)."""

from __future__ import annotations

from .assignments import add_model_argument, model_argument


def cmd_report(args):
    import shlex

    from ..errors import renamed
    from ..files import output_folder
    from ..model.limits import check_time_domain
    from ..report import check_report_folder, check_report_settings, write_report
    from .paths import check_plotting

    # (the settings before the folder: a refused report creates nothing)
    names = {"model": "MODEL", "duration": "--duration", "scenario.duration": "--duration", "seeds": "--seeds"}
    with renamed({**names, "study_samples": "--study-samples", "skip": "--skip"}):
        model, _, _, _, duration = check_report_settings(
            model_argument(args.model), args.duration, args.seeds, args.study_samples, args.skip
        )
        check_time_domain(model, duration, model.scenario["dt"])  # (a run too large for the machine)
    check_plotting()  # (its figures: matplotlib must start, before the runs and the folder is made)
    output_folder("--out", args.out, "report.html")  # (before the runs)
    check_report_folder("--out", args.out)  # (every file the report writes can be moved in)
    args.interrupted = (
        "the report was not finished: --out is as it was, an earlier report in it whole (this run's files are "
        "written into a folder of their own and moved in only at the end; interrupted while they were moved in, "
        "--out holds no report.html or runs.json); run the report again"
    )
    html = write_report(
        args.out,
        model=model,
        duration=duration,
        seeds=args.seeds,
        study_samples=args.study_samples,
        skip=args.skip,
        progress=args.progress,
        command="cablecasing " + shlex.join(getattr(args, "argv", [])),
        scheduler=args.scheduler,
    )
    print(f"wrote {html}")
    return 0


def add_parser(sub):
    r = sub.add_parser(
        "report",
        help="run a model (default: the built-in specimen) and write its report: figures, tables, report.html",
    )
    add_model_argument(r)
    r.add_argument("--out", default="results", help="folder to write into (nothing is written elsewhere)")
    r.add_argument(
        "--duration",
        type=float,
        default=None,
        help="simulated time of every run of the report, s (default: the model's scenario.duration, 1 s for the "
        "built-in specimens)",
    )
    r.add_argument(
        "--skip",
        type=float,
        default=None,
        help="start of every record left out of levels and spectra, s (default: [LEAST_SKIP], at least the start "
        "transient of each harmonic excitation, ln 10/(zeta omega) of the casing's Rayleigh damping at its "
        "frequency, then whole periods of them: 0.32 s of the built-in specimen's 1 s, 0.30 s at its 50 Hz drive)",
    )
    r.add_argument("--seeds", type=int, default=6, help="excitation seeds of the band-level ensembles (1..N)")
    r.add_argument(
        "--study-samples",
        type=int,
        default=32,
        help="runs of the small study of Fig. 23, rounded up to whole base points of d + 2 runs (0: no study)",
    )
    r.add_argument(
        "--scheduler",
        choices=("threads", "serial"),
        default="threads",
        help="the ensembles' and the study's runs at once on threads of this process, one per core (threads, the "
        "default), or one after the other (serial); the same report either way",
    )
    r.add_argument(
        "--no-progress", dest="progress", action="store_false", help="no progress bars (default: bars on stderr)"
    )
    r.set_defaults(func=cmd_report)
