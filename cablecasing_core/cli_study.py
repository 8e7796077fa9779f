"""``cablecasing study``, ``cablecasing bands``, ``cablecasing report`` (Section 4)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .errors import ModelError


def cmd_study(args):
    from .studies import DEFAULT_EVALUATE, correlations, plot_correlations, run_study

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    kwargs = {"model_file": args.model, "duration": args.duration, "skip": args.skip}
    res = run_study(out / "study.csv", DEFAULT_EVALUATE, n_samples=args.samples, seed=args.seed,
                    scheduler=args.scheduler, n_workers=args.workers, evaluate_kwargs=kwargs)
    print(f"{int(np.sum(res.ok))} of {len(res.status)} samples ok; results in {out / 'study.csv'}")
    if np.sum(res.ok) >= 3:
        corr = correlations(res, "pearson")
        table = corr.as_dict()
        for p, row in table.items():
            print(f"  {p:45s} " + " ".join(f"{row[b]:+.2f}" for b in row))
        plot_correlations(res, out / "correlations.png")
        print(f"wrote {out / 'correlations.png'}")
    return 0


def cmd_bands(args):
    from .studies import octave_rms

    data = np.genfromtxt(args.results, delimiter=",", names=True)
    names = data.dtype.names or ()
    col = args.column.replace(".", "")
    if col not in names:
        raise ModelError("--column", args.column, "must be a column of the results CSV: " + ", ".join(names))
    t = data[names[0]]
    keep = t > args.skip
    fs = 1.0 / np.median(np.diff(t))
    bands = octave_rms(data[col][keep], fs, args.kind, beyond_nyquist="drop")
    print("band,f_low_hz,f_high_hz,rms")
    for lab, lo, hi, r in zip(bands.labels, bands.lower, bands.upper, bands.rms):
        print(f"{lab},{lo:.6g},{hi:.6g},{r:.6g}")
    return 0


def cmd_report(args):
    from .demo import main as demo_main

    return demo_main(["--out", args.out, "--duration", str(args.duration)])


def add_parser(sub):
    p = sub.add_parser("study", help="Monte-Carlo correlation study of Section 4.4 (dask)")
    p.add_argument("model", nargs="?", default=None, help="model TOML (default: built-in specimen)")
    p.add_argument("--samples", type=int, default=300)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--scheduler", default=None, help="dask scheduler address tcp://host:8786, 'serial', or local (default)")
    p.add_argument("--workers", type=int, default=None, help="local cluster workers (default: one per core)")
    p.add_argument("--duration", type=float, default=None, help="simulated time per sample, s")
    p.add_argument("--skip", type=float, default=0.05, help="start of each record left out, s")
    p.add_argument("--out", default="study")
    p.set_defaults(func=cmd_study)

    b = sub.add_parser("bands", help="octave-band RMS of a column of a results CSV")
    b.add_argument("results", help="CSV written by 'cablecasing simulate --out'")
    b.add_argument("--column", default="casing.B.Fz_N")
    b.add_argument("--kind", choices=["table3", "octave", "third"], default="table3")
    b.add_argument("--skip", type=float, default=0.05, help="s left out at the start")
    b.set_defaults(func=cmd_bands)

    r = sub.add_parser("report", help="run the default model and write results/ with report.html")
    r.add_argument("--out", default="results")
    r.add_argument("--duration", type=float, default=0.2)
    r.set_defaults(func=cmd_report)
