"""The main job (``make demo``): build the FMU, run the default scenario through it with fmpy, and
write the report of the built-in specimen (``cablecasing_core.report``) under ``results/``, with the
FMU's run checked against the core driven by the same sampled record.

    python examples/demo.py [--out results] [--duration S] [--skip S] [--seeds 6] [--study-samples 32]

Writes fmu_outputs.csv (the default scenario through the FMU) besides the report's files (see
``cablecasing_core.report``: report.html, the figures, the records and tables of its runs), and
the FMU it builds to dist/CableCasing.fmu in the repository (``make fmu``'s file), whatever
``--out`` is, under the lock the tests' FMU takes (``build_fmu.default_fmu_lock``), held until that
FMU has run and its checksum is taken. The run is written into a folder of its own inside --out and moved in at the end
(``report.staged_report``): stopped or failed before, it leaves --out as it was. A deviation of the
FMU from the core beyond 1e-8 of an output's largest value stops it with exit status 1 before the
report.
"""

from __future__ import annotations

import argparse
import contextlib
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np

from cablecasing_core.errors import ModelError, renamed
from cablecasing_core.files import WriteError, atomic_path, output_folder
from cablecasing_core.report import check_report_folder, check_report_settings

ROOT = Path(__file__).resolve().parent.parent

FMU_TOLERANCE = 1e-8  # the FMU equals the core (docs/fmu.md); fmu_outputs.csv's 9 digits round by <= 5e-9
DEVIATION = "largest deviation, relative to the output's largest value"  # (of report.runs.fmu_check's summary)


class FMUFailed(Exception):
    """The FMU deviates from the core (:func:`fmu_failure`'s message): the run is not moved in."""


def run_fmu(fmu_path, duration, out):
    """The default scenario through the FMU (fmpy), inputs at every 1e-4 s: writes fmu_outputs.csv
    and returns (t, casing.B.Fz) in s and N."""
    from fmpy import simulate_fmu

    import cablecasing_core as cc
    from cablecasing_core.model.schema import CHANNELS, SUPPORT_OUTPUTS
    from cablecasing_core.records import csv_header, unit_of
    from cablecasing_core.timedomain.scenario import scenario_motion

    h = 1e-4
    t = np.arange(0.0, duration + 0.5 * h, h)
    u, v, a = scenario_motion(cc.load_model())(t)
    names = [f"{c[:-1]}{p}{c[-1]}" for p in ("", "v", "a") for c in CHANNELS]
    sig = np.zeros(len(t), dtype=[("time", float)] + [(n, float) for n in names])
    sig["time"] = t
    for k, arr in enumerate((u, v, a)):
        for c in range(len(CHANNELS)):
            sig[names[k * len(CHANNELS) + c]] = arr[:, c]
    r = simulate_fmu(
        str(fmu_path),
        stop_time=duration,
        step_size=h,
        output_interval=h,
        input=sig,
        output=list(SUPPORT_OUTPUTS) + ["contact.active"],
    )
    cols = list(r.dtype.names)
    header = csv_header(f"{c} [{unit_of(c)}]" if unit_of(c) else c for c in cols)  # (as simulate --out writes it)
    with atomic_path(Path(out) / "fmu_outputs.csv") as tmp:
        np.savetxt(tmp, np.column_stack([r[c] for c in cols]), delimiter=",", header=header, comments="", fmt="%.9g")
    print("ran the default scenario through the FMU (fmu_outputs.csv)")
    return r["time"], r["casing.B.Fz"]


def main(argv=None):
    class Defaults(argparse.ArgumentDefaultsHelpFormatter):
        """argparse's defaults in the help, but not "(default: None)" beside an option that says its own."""

        def _get_help_string(self, action):
            return action.help if action.default is None else super()._get_help_string(action)

    p = argparse.ArgumentParser(
        description=" ".join(__doc__.split("\n\n")[0].split()),  # the first paragraph, whole
        epilog=" ".join(__doc__.split("\n\n")[-1].split()),
        formatter_class=Defaults,
    )
    p.add_argument("--out", default="results", help="folder of the report")
    p.add_argument(
        "--duration",
        type=float,
        default=None,
        help="simulated time of every run, s (default: the scenario's, 1 s)",
    )
    p.add_argument(
        "--skip",
        type=float,
        default=None,
        help="start of every record left out of the levels, s (default: the 50 Hz drive's start transient, "
        "ln 10/(zeta omega) = 0.30 s of the casing's damping, in whole periods of it: 0.32 s of 1 s)",
    )
    p.add_argument("--seeds", type=int, default=6, help="excitation seeds of the report's ensembles")
    p.add_argument(
        "--study-samples",
        type=int,
        default=32,
        help="runs of the report's small study, rounded up to whole base points of d + 2 runs (0: none)",
    )
    p.add_argument(
        "--scheduler",
        choices=("threads", "serial"),
        default="threads",
        help="the report's ensembles and study at once on threads of this process, one per core, or one after the "
        "other (serial), as `cablecasing report --scheduler`; the same report either way",
    )
    raw = list(sys.argv[1:] if argv is None else argv)
    args = p.parse_args(raw)
    try:  # (the settings and the folder before the FMU is built: a refused demo creates nothing)
        names = {"duration": "--duration", "seeds": "--seeds", "study_samples": "--study-samples", "skip": "--skip"}
        with renamed(names):
            args.duration = check_report_settings(None, args.duration, args.seeds, args.study_samples, args.skip)[4]
        out = output_folder("--out", args.out, "report.html")
        check_report_folder("--out", out)  # (every file of the report can be moved in)
    except ModelError as exc:
        p.exit(2, f"{p.prog}: error: {exc}\n")
    args.command = "python examples/demo.py " + shlex.join(raw)
    try:
        return _run(args, out)
    except KeyboardInterrupt:
        print(
            f"{p.prog}: stopped: {out} is as it was, an earlier report in it whole (this run's files were written "
            "into a folder of their own, now removed; stopped while they were moved in, it holds no report.html or "
            "runs.json)",
            file=sys.stderr,
        )
        return 130


def _run(args, out):
    with contextlib.ExitStack() as held:
        return _run_holding(args, out, held)


def _run_holding(args, out, held):
    """The demo, holding build_fmu's lock on dist/CableCasing.fmu (``held``, an ExitStack) from its
    build until its checksum is taken: no other process that takes the lock (a test worker's ``fmu``
    fixture) replaces the FMU in between, so the checksum is that of the FMU that ran."""
    sys.path.insert(0, str(ROOT))
    try:
        import build_fmu
    finally:
        sys.path.remove(str(ROOT))
    fmu = held.enter_context(build_fmu.default_fmu_lock())
    r = subprocess.run([sys.executable, str(ROOT / "build_fmu.py")], cwd=ROOT)
    if r.returncode != 0:
        print(f"FMU build failed ({r.returncode})", file=sys.stderr)
        return r.returncode
    from cablecasing_core.report import staged_report, write_report
    from cablecasing_core.report.provenance import sha256_of
    from cablecasing_core.report.runs import fmu_check

    try:
        with staged_report(out) as stage:  # (moved into out at the end, with the report)
            run_fmu(fmu, args.duration, stage)
            check = {
                "FMU": "dist/CableCasing.fmu (built by build_fmu.py), run with fmpy",
                "FMU SHA-256": sha256_of(fmu),
            }
            held.close()  # (the FMU ran and its checksum is taken: the lock is released for the report's runs)
            check.update(fmu_check(stage / "fmu_outputs.csv", 1e-4, args.duration))
            failed = fmu_failure(check)
            if failed:
                raise FMUFailed(failed)
            write_report(
                stage,
                duration=args.duration,
                seeds=args.seeds,
                study_samples=args.study_samples,
                skip=args.skip,
                fmu=check,
                command=args.command,
                staged=False,
                scheduler=args.scheduler,
            )
    except FMUFailed as exc:
        print(f"demo.py: error: {exc}", file=sys.stderr)
        return 1
    except WriteError as exc:  # (a file that could not be moved into --out: the run is kept, the error says where)
        print(f"demo.py: error: --out {exc.filename}: could not be written ({exc.strerror})", file=sys.stderr)
        return 1
    print(f"wrote {out}/ (see report.html)")
    return 0


def fmu_failure(check):
    """What is wrong when the FMU's largest deviation from the core in ``check`` (the summary of
    ``fmu_check``) exceeds :data:`FMU_TOLERANCE` (or is not a number); None when it is within it."""
    said = check[DEVIATION]
    if float(said.split()[0]) <= FMU_TOLERANCE:
        return None
    return (
        f"the FMU deviates from the core driven by the same sampled record by {said} of the output's largest "
        f"value; they agree to {FMU_TOLERANCE:g} (docs/fmu.md): the FMU is broken, the report was not written"
    )


if __name__ == "__main__":
    sys.exit(main())
