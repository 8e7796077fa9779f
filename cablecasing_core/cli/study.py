"""``cablecasing study``, ``ensemble``, ``pool`` (Section 4)."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

from ..errors import ModelError, plain, renamed
from ..files import output_folder
from ..model.changes import with_changes
from ..model.limits import MAX_ENSEMBLE_SEED, MAX_SEEDS, MAX_STUDY_SAMPLES, PROGRESS_TIMEOUT
from ..model.schema import STUDY_OUTPUT
from ..model.validators import integer, number
from ..records import unit_of
from .assignments import add_model_argument, assignments, model_argument, typed
from .helptext import ASSIGNMENT_HELP, FromApi, add_window_argument, choice_argument, key_help
from .paths import PLOT_SUFFIXES, check_distinct, check_output_path, check_plotting, kept


def _count(n, noun):
    """``"1 parameter"``, ``"2 parameters"``."""
    return f"{n} {noun}{'' if n == 1 else 's'}"


#: --skip of study and ensemble.
SKIP_HELP = (
    "start of each record left out, s (default: [LEAST_SKIP] lengthened so that the rest of the record holds whole "
    "periods of the model's harmonic excitations: 0.06 s of 1 s with a 50 Hz drive; docs/studies.md)"
)


def study_bounds(args, model):
    """The study's parameters and bounds from ``--vary`` and ``--vary-file`` (default: the paper's six),
    checked against the model and the schema (before any run), and the names of their keys as the
    user gave them (``{"bounds.casing.E": "--vary casing.E"}``, for run_study's errors); an error
    names the option as typed and the key (``--vary casing.E``, ``--vary-file vf.toml: casing.E``)."""
    from ..studies.sampling import check_bounds, parse_vary, read_vary_file

    bounds, given = {}, {}
    if args.vary_file:
        bounds.update(read_vary_file(args.vary_file))
    in_file = set(bounds)
    for text in args.vary:
        key, b = parse_vary(text)
        if key in given:
            raise ModelError("--vary", text, f"must name each key once: {key} is already varied by {given[key]}")
        if key in bounds:
            raise ModelError(
                "--vary", text, f"must not vary a key the --vary-file {args.vary_file} varies too: {key} is in both"
            )
        bounds[key] = b
        given[key] = f"--vary {text}"
    names = {f"bounds.{k}": f"--vary {k}" for k in given} | {
        f"bounds.{k}": f"--vary-file {args.vary_file}: {k}" for k in in_file
    }
    # (--duration takes the place of scenario.duration in every sample: not varied beside it)
    with renamed(names):  # (check_bounds names a key bounds.<key>: here the option and the key the user wrote)
        return check_bounds(bounds or None, model=model, settings={"duration": ("--duration", args.duration)}), names


def study_output(name, model):
    """``--output``: a support, isolator or clip output of the model (force or moment, N or N.m),
    or a sum of them (``net.B.Fz``, ``paths.Fz``, ``a+b``: records.derived_terms)."""
    from ..model.schema import SUPPORT_OUTPUTS, clip_outputs
    from ..records import check_column_name

    known = SUPPORT_OUTPUTS + clip_outputs(model)
    check_column_name(name, known, "--output")  # (with the closest name and the sums it takes)
    return name


def _excitation(model, k):
    """What excitation each sample of a study runs (the plan's line): the model's own random
    excitation with its seeds (``scenario.excitation.casing_random.seed = 1``), once, or the mean
    over the ensemble's seeds 1..k (``--excitation-seeds k``)."""
    from ..studies.ensemble_runs import random_excitations

    names = random_excitations(model)
    if k is not None:
        return f"each sample: the mean of {k} runs on the excitation seeds 1..{k} (as ensemble --seeds {k})"
    if not names:
        return "each sample: one run (the model has no random excitation)"
    seeds = ", ".join(f"scenario.excitation.{n}.seed = {model.scenario['excitation'][n]['seed']}" for n in names)
    return (
        f"each sample: one run on the model's own random excitation ({seeds}), one draw of a response that "
        "with contact is chaotic: its scatter over seeds enters r, S1 and ST (docs/studies.md; --excitation-seeds K "
        "averages K seeds per sample); --seed is the Sobol' sequence's"
    )


def _first_of(res, kinds):
    """The first run (lowest index) of status ``kinds`` (a status or several) of the study ``res``:
    ``sample 5 (casing.d_inner = 0.00977, ...): ModelError: ...``."""
    kinds = (kinds,) if isinstance(kinds, str) else tuple(kinds)
    j = int(np.flatnonzero(np.isin(np.asarray(res.status), kinds))[0])
    said = ", ".join(f"{p} = {v:.6g}" for p, v in zip(res.parameters, res.X[j]))
    return f"sample {int(res.index[j])} ({said}): {res.error[j]}"


def cmd_study(args):
    from ..model.load import specimen_names
    from ..nvh.bands import WINDOW_NAMES
    from ..studies import DEFAULT_EVALUATE, plot_correlations, plot_sobol, run_study
    from ..studies.results_store import COMMAND_QUANTITY_WHAT, read_meta
    from ..studies.sampling import base_points, group_size
    from ..studies.sensitivity import sobol_shown

    model = model_argument(args.model)
    bounds, bound_names = study_bounds(args, model)  # (before anything is written)
    output = study_output(args.output, model)
    unit = unit_of(output)
    integer("--samples", args.samples, 2, MAX_STUDY_SAMPLES)
    integer("--seed", args.seed, 0)
    progress_timeout = number("--timeout", args.timeout, gt=0, unit="s")
    _check_workers(args)
    from ..studies.executor import check_packages, check_scheduler

    with renamed({"scheduler": "--scheduler"}):
        check_scheduler(args.scheduler)
    check_packages(args.scheduler, key="--scheduler")  # (SALib, and dask unless serial: before anything is made)
    _check_record_settings(args, model)
    out = Path(args.out)  # (created by run_study once every setting is checked and the scheduler answers)
    if out.exists() and not out.is_dir():
        raise ModelError("--out", args.out, "must be a folder (of study.csv and the figures); it is a file")
    # (the string as given: Path("") would be ".", the current folder, which '' must not name)
    output_folder("--out", args.out, "study.csv", create=False)  # (before the plan is printed)
    check_plotting()  # (its figures: matplotlib must start, before the runs)
    # a file by its absolute path (dask workers run in any folder); a built-in specimen by its name
    model_file = args.model if args.model in (None, *specimen_names()) else str(Path(args.model).resolve())
    kwargs = {"model_file": model_file, "duration": args.duration, "skip": args.skip, "window": args.window}
    if output != STUDY_OUTPUT:  # (the default's settings stay as earlier versions wrote them: they resume)
        kwargs["output"] = output
    if args.excitation_seeds is not None:  # (likewise: only when given)
        kwargs["excitation_seeds"] = integer("--excitation-seeds", args.excitation_seeds, 2, MAX_SEEDS)
    quantity = {"name": output, "unit": unit, "what": COMMAND_QUANTITY_WHAT}  # (the command's: results_store)
    with renamed({"path": "--out"}):
        old = read_meta(out / "study.csv")
    _check_resume(args, old, out / "study.csv", bounds, kwargs, model, bound_names)
    g = group_size(bounds)
    if args.skip is None:  # (each sample takes whole periods of its own drive: the model's, unless a study varies it)
        from ..timedomain.scenario import whole_period_skip

        skip = f"after {whole_period_skip(model, args.duration):g} s (whole periods of the model's drive)"
        if any(k.startswith("scenario.") for k in bounds):  # (a sample's drive or fade-in may differ)
            skip = (
                f"after {whole_period_skip(model, args.duration):g} s at the model's values (whole periods of its "
                "drive; each sample takes the whole periods of its own drive and fade-in)"
            )
    else:
        skip = f"after {args.skip:g} s"
    d = len(bounds)
    print(
        f"# study of {model.source}: {_count(d, 'parameter')}, the Table 3 band RMS of {output} ({unit}) {skip} "
        f"through the {WINDOW_NAMES[args.window]} window, Saltelli's design on a "
        f"scrambled Sobol' sequence (seed {args.seed}); results in {out / 'study.csv'}"
    )
    nb = base_points(bounds, args.samples)
    if old is not None and isinstance(old.get("n_base"), int) and old["n_base"] > nb:  # (run_study's rule)
        print(
            f"#   {old['n_base'] * g} runs: {old['n_base']} base points x {g}, the size of the study in "
            f"{out / 'study.csv'}: --samples {args.samples} asks for {nb * g} runs, and a study is never shrunk "
            "(it resumes at its size)"
        )
    else:
        rounded = "" if nb * g == args.samples else f"; --samples {args.samples} is rounded up to whole groups"
        print(
            f"#   {nb * g} runs: {nb} base points x {g} (d + 2 runs per base point for d = {_count(d, 'parameter')}, "
            f"at least 2 base points{rounded})"
        )
    print(f"#   {_excitation(model, args.excitation_seeds)}")
    args.interrupted = f"the rows finished so far are in {out / 'study.csv'}; run the same command again to go on"
    with renamed({"path": "--out", "scheduler": "--scheduler", **bound_names}):
        res = run_study(
            out / "study.csv",
            DEFAULT_EVALUATE,
            bounds=bounds,
            n_samples=args.samples,
            seed=args.seed,
            scheduler=args.scheduler,
            n_workers=args.workers,
            evaluate_kwargs=kwargs,
            quantity=quantity,
            model=model,
            progress_timeout=progress_timeout,
            progress=args.progress,
        )
    n_ok = int(np.sum(res.ok))
    status = np.asarray(res.status)
    others = "".join(f", {int(np.sum(status == k))} {k}" for k in ("failed", "infeasible") if np.any(status == k))
    print(f"{n_ok} of {len(status)} runs ok{others} ({res.n_base} base points); results in {out / 'study.csv'}")
    if n_ok:  # (a partly failed study: how many, and the first of each kind with its sample)
        for kind in ("failed", "infeasible"):
            if np.any(status == kind):
                print(
                    f"cablecasing: warning: {int(np.sum(status == kind))} of {len(status)} runs {kind}; the first, "
                    f"{_first_of(res, kind)} (the column 'error' of {out / 'study.csv'} says why for each)",
                    file=sys.stderr,
                )
    n_warned = int(np.sum(res.warned))
    if n_warned:
        print(
            f"cablecasing: warning: {n_warned} of {len(res.status)} runs warned (the column 'warnings' of "
            f"{out / 'study.csv'} says which and what)",
            file=sys.stderr,
        )
    if not len(status):  # (nothing was run: a sample left to run was lost, or none was asked for)
        print(f"cablecasing: error: no run is in {out / 'study.csv'}", file=sys.stderr)
        return 1
    if n_ok == 0:
        kinds = tuple(sorted(set(status.tolist())))  # (failed, infeasible or both)
        what = {("failed",): "failed", ("infeasible",): "was infeasible"}.get(kinds, "failed or was infeasible")
        print(f"cablecasing: error: every run {what}; the first: {_first_of(res, kinds)}", file=sys.stderr)
        return 1
    if n_ok < 3:
        print("cablecasing: warning: fewer than 3 ok runs: no correlation", file=sys.stderr)
        return 0
    cors, sob = print_study(res)
    plot_correlations(res, out / "correlations.png", cors=cors)
    print(f"wrote {out / 'correlations.png'}")
    if sob is not None and sobol_shown(sob):
        plot_sobol(res, out / "sobol.png", sob=sob)
        print(f"wrote {out / 'sobol.png'}")
    return 0


def _check_resume(args, old, path, bounds, kwargs, model, bound_names):
    """A study in ``path`` (its sidecar ``old``; None: a new study) resumes only with its settings:
    checked before anything is printed, each named by the option that differs (run_study checks
    them again, by the names of its settings); ``bound_names``: {``bounds.<key>``: the option that
    gave it} (:func:`study_bounds`; the paper's bounds are in none)."""
    from ..studies.evaluators import EARLIER_RECORD_SETTINGS
    from ..studies.results_store import begun_by_other, begun_by_run_study

    if old is None:
        return
    if begun_by_run_study(old):  # (first: none of the command's settings would resume it)
        with renamed({"path": "--out"}):
            raise begun_by_other("run_study", str(path))
    if "bounds" in old and list(old["bounds"]) != list(bounds):  # (dicts compare equal in any order)
        flag = "--vary" if args.vary else "--vary-file" if args.vary_file else "--vary (not given: the paper's six)"
        raise ModelError(
            flag,
            list(bounds),
            f"must name the parameters of the study in {path} in its order, {list(old['bounds'])} (its "
            "columns and design follow that order), to resume it; or choose another --out",
        )
    for key, (lo, hi) in bounds.items():  # (the same parameters: each with the bounds it was run with)
        then = old.get("bounds", {}).get(key)
        if isinstance(then, list) and [float(x) for x in then] != [float(lo), float(hi)]:
            # (named as the option that gave it; the values as Python writes floats: two that differ read apart)
            flag = bound_names.get(f"bounds.{key}", f"--vary {key} (the paper's)")
            raise ModelError(
                flag,
                plain(f"{float(lo)!r}:{float(hi)!r}"),
                f"must be {float(then[0])!r}:{float(then[1])!r}, the bounds the study in {path} was run with, to "
                "resume it; or choose another --out",
            )
    was = {"seed": old["seed"]} if "seed" in old else {}
    if isinstance(old.get("evaluate_kwargs"), dict):  # (an output of its own only when not casing.B.Fz;
        # a study begun before the window was a setting took the earlier skip and window)
        earlier = EARLIER_RECORD_SETTINGS if "window" not in old["evaluate_kwargs"] else {}
        was.update({"output": STUDY_OUTPUT, "excitation_seeds": None} | earlier | old["evaluate_kwargs"])
    now = {"seed": args.seed, "output": STUDY_OUTPUT, "excitation_seeds": None} | kwargs
    for flag, key, given in (
        ("--seed", "seed", args.seed),
        ("MODEL", "model_file", args.model),
        ("--duration", "duration", args.duration),
        ("--skip", "skip", args.skip),
        ("--window", "window", args.window),
        ("--output", "output", args.output),
        ("--excitation-seeds", "excitation_seeds", args.excitation_seeds),
    ):
        then = was.get(key, now[key])  # (what the sidecar does not hold is run_study's to check)
        if then != now[key]:
            raise ModelError(
                flag,
                "not given" if given is None else given,
                f"must be what the study in {path} was run with, {'none given' if then is None else repr(then)}, "
                "to resume it; or choose another --out",
            )
    fingerprint = model.fingerprint()
    if old.get("model_fingerprint", fingerprint) != fingerprint:
        raise ModelError(
            "MODEL",
            args.model or "default",
            f"holds another model than when the study in {path} began (an edited file, or its CSV excitation): "
            "a resume runs the same model; choose another --out to start a study",
        )


def _check_record_settings(args, model):
    """``--duration`` and ``--skip`` of a study (and a run too large for the machine) checked before
    anything is printed, named by their options (run_study checks them again, by the names of its
    settings)."""
    from ..studies.evaluators import check_record_settings

    names = {"duration": "--duration", "skip": "--skip"}
    if args.duration is not None:  # (else the model's scenario.duration, named as in its file)
        names["scenario.duration"] = "--duration"
    with renamed(names):
        check_record_settings(model, duration=args.duration, skip=args.skip)


def _sobol_or_none(res):
    from ..studies import sobol_indices

    try:
        return sobol_indices(res)
    except ModelError:
        return None


def print_study(res):
    """Correlation (Pearson, Spearman) and Sobol tables of a study, one column per band with its
    edges, and the warnings when it is too small to mean anything; returns the two correlations and
    the Sobol indices (None when the study has too few complete base points)."""
    from ..nvh.bands import octave_bands
    from ..studies import correlations, size_warnings
    from ..studies.sensitivity import SOBOL_SHOWN, complete_groups, sobol_shown, widest_interval

    edges = {}
    for kind in ("table3", "octave", "third"):
        b = octave_bands(kind)
        edges.update({lab: f"{lo:.4g}-{hi:.4g}" for lab, lo, hi in zip(b.labels, b.lower, b.upper)})
    w = max([10] + [len(edges.get(o, o)) + 2 for o in res.outputs])
    head = "".join(f"{o:>{w}}" for o in res.outputs)
    hz = "".join(f"{edges.get(o, ''):>{w}}" for o in res.outputs)
    q = res.quantity
    of = f"{q['name']} ({q['unit']})" if q else "the output"
    cors = [correlations(res, method) for method in ("pearson", "spearman")]
    for c in cors:
        print(
            f"\n{c.method.capitalize()} correlation r (-) of each parameter with the band RMS of {of} "
            f"({c.n} runs used); bands (Hz):"
        )
        print(f"  {'band':40s}{head}\n  {'':40s}{hz}")
        for i, p in enumerate(c.parameters):
            cells = (f"{v:+.2f}{'*' if q < 0.05 else ' '}" for v, q in zip(c.r[i], c.pvalue[i]))
            print(f"  {p:40s}" + "".join(f"{cell:>{w + 1}}" for cell in cells))
        print(f"  ({c.legend()})")
    sob = _sobol_or_none(res)
    if sob is not None and not sobol_shown(sob):  # (intervals wider than the indices' range: no table)
        print(
            f"cablecasing: warning: Sobol indices from {sob.n_base} complete base points are not shown: their "
            f"intervals reach +-{widest_interval(sob):.3g} (shown up to +-{SOBOL_SHOWN:g}); a larger study gives them "
            "(--samples), and sobol_indices(load_results(...)) computes them from the CSV",
            file=sys.stderr,
        )
    elif sob is not None:
        print(
            f"\nSobol indices (-) of the band RMS of {of}, first order S1 and total ST with their "
            f"{sob.conf_level:.0%} intervals, from {sob.n_base} complete base points:"
        )
        print(f"  {'band':40s}{head}\n  {'':40s}{hz}")
        for i, p in enumerate(sob.parameters):
            print(f"  {p + ' S1':40s}" + "".join(f"{v:+{w}.2f}" for v in sob.S1[i]))
            print(f"  {'   +-':40s}" + "".join(f"{v:{w}.2f}" for v in sob.S1_conf[i]))
            print(f"  {p + ' ST':40s}" + "".join(f"{v:+{w}.2f}" for v in sob.ST[i]))
            print(f"  {'   +-':40s}" + "".join(f"{v:{w}.2f}" for v in sob.ST_conf[i]))
    if sob is None:
        n = len(complete_groups(res)) if res.group_size else 0
        print(
            f"cablecasing: warning: no Sobol indices: they need 4 complete base points, this study has {n}",
            file=sys.stderr,
        )
    for w in size_warnings(res, sob if sob is not None and sobol_shown(sob) else None):
        print(f"cablecasing: warning: {w}", file=sys.stderr)
    return cors, sob


def cmd_ensemble(args):
    from ..studies import paired_difference, seed_ensemble
    from ..studies.ensemble_runs import seed_keys, seeds_varied
    from ..studies.evaluators import check_model_runs, check_not_overridden

    integer("--seeds", args.seeds, 2, MAX_SEEDS)
    integer(
        "--first-seed",
        args.first_seed,
        0,
        MAX_ENSEMBLE_SEED + 1 - args.seeds,
        " (the last seed must be at most 2**53: an ensemble's CSV holds its seeds exactly up to there)",
    )
    _check_confidence(args.confidence)
    _check_workers(args)
    from ..studies.executor import check_packages, check_scheduler

    with renamed({"scheduler": "--scheduler"}):
        check_scheduler(args.scheduler)
    check_packages(args.scheduler, salib=False, key="--scheduler", name="ensemble")  # (dask unless serial)
    args.interrupted = kept("the ensemble was stopped", *_check_outputs(args))
    seeds = list(range(args.first_seed, args.first_seed + args.seeds))
    common = dict(
        seeds=seeds,
        output=args.output,
        bands=args.kind,
        duration=args.duration,
        dt=args.dt,
        skip=args.skip,
        window=args.window,
        scheduler=args.scheduler,
        n_workers=args.workers,
        progress=args.progress,
    )
    base = assignments("--set", args.set)
    against = assignments("--against", args.against)
    # (a key that --duration or --dt takes the place of would be recorded and do nothing)
    settings = {"duration": ("--duration", args.duration), "dt": ("--dt", args.dt)}
    runs = "every run of both ensembles" if against else "every run"
    shown = {"--set": typed(args.set), "--against": typed(args.against)}  # (the values as typed, for messages)
    for flag, given in (("--set", base), ("--against", against)):
        check_not_overridden(
            {k: (f"{flag} {k}", shown[flag][k]) for k in given},
            settings,
            runs,
            "; give one of them (compare two values with --set {key}=... --against {key}=... and no {name})",
        )
    model = model_argument(args.model)
    # (both variants checked before the first run: seed_ensemble would find --against's clash only
    # after the first ensemble had run)
    varied = seed_keys(model)
    for flag, given in (("--set", base), ("--against", against)):
        if varied & set(given):
            clash = sorted(varied & set(given))
            raise ModelError(f"{flag} {clash[0]}", given[clash[0]], seeds_varied(clash))  # (the first: fixed, the next)
    # (each ensemble's model checked as the engine sets it up, before the first run of either: a change
    # that no seed can run, a tension above the casing's buckling load, is refused at once, named)
    check = lambda m: check_model_runs(m, args.dt)  # noqa: E731
    sets = {k: ("--set", v, shown["--set"][k]) for k, v in base.items()}
    with_changes(model, sets, check)
    if against:
        with_changes(model, sets | {k: ("--against", v, shown["--against"][k]) for k, v in against.items()}, check)
    names = {"duration": "--duration", "dt": "--dt", "skip": "--skip", "output": "--output", "scheduler": "--scheduler"}
    for key, given in (("scenario.duration", args.duration), ("scenario.dt", args.dt)):
        if given is not None:  # (else the model's value, named by its key)
            names[key] = f"--{key.split('.')[1]}"
    with renamed(names):  # (the settings are checked before the first run)
        ens = seed_ensemble(model, overrides=base, **common)
    _print_ensemble(ens, args.confidence)
    other = d = None
    if against:  # (paired: on the first's samples, the skip it took: its drive's whole periods by default)
        with renamed(names):
            other = seed_ensemble(model, overrides={**base, **against}, **{**common, "skip": ens.settings["skip"]})
    # (both files once both ensembles are done: a run stopped in the second leaves the pair as it
    # was; and before anything is derived from them)
    _save(ens, args.out, "")
    if other is not None:
        _save(other, args.out, "_against")
        d = paired_difference(other, ens)
        _print_change(ens, other, d, against, args.confidence)
    _plot(ens, other, d, args, (", ".join(args.set) or "model", ", ".join(args.against)))
    return 0


def cmd_pool(args):
    """Pool ensemble CSVs run in parts (same model and settings) and print what ``ensemble`` prints."""
    from ..studies import paired_difference, pool_ensembles
    from ..studies.ensemble import unpaired_setting

    _check_confidence(args.confidence)
    outputs = _check_outputs(args)
    _check_not_inputs(args, outputs)
    args.interrupted = kept("stopped", *outputs)
    with renamed({"path": "file"}):  # (a part's error names it as the command line does)
        ens = pool_ensembles(args.files)
    other = d = None
    change = {}
    if args.other_model and not args.against:
        raise ModelError("--other-model", True, "compares the --against files with the files: give --against too")
    if args.against:
        with renamed({"path": "--against"}):
            other = pool_ensembles(args.against)
        change = _changed_overrides(ens, other)
        mine, theirs = (e.settings.get("base_model") for e in (ens, other))
        files = " ".join(map(str, args.against))
        if mine is not None and theirs is not None and mine != theirs and not args.other_model:
            raise ModelError(
                "--against",
                files,
                "must be an ensemble of the model the files it is compared with ran, with other overrides: it is "
                f"of another model (its fingerprint before the overrides {theirs}, theirs {mine}), so the change "
                "would not be its overrides' alone; to compare two model files (a clip moved, say) on the same "
                "seeds and settings, add --other-model",
            )
        if args.other_model and mine != theirs:  # (the change is the two models' whole difference, overrides and all)
            change = _other_model_change(ens, other, change)
        unpaired = unpaired_setting(ens, other)  # (the check paired_difference makes, said with the files)
        if unpaired:
            k, said_mine, said_theirs = unpaired
            raise ModelError(
                "--against",
                files,
                f"must be run with the settings of the files it is compared with: its {k} is {said_theirs!r}, "
                f"theirs {said_mine!r}",
            )
        if not np.array_equal(other.seeds, ens.seeds):
            raise ModelError(
                "--against",
                files,
                f"must pool to the seeds of the files it is compared with, {_seed_list(ens.seeds)}, to pair them; "
                f"they pool to {_seed_list(other.seeds)}",
            )
        d = paired_difference(other, ens)
    _print_ensemble(ens, args.confidence)
    _save(ens, args.out, "")
    if other is not None:
        _print_change(ens, other, d, change, args.confidence)
        _save(other, args.out, "_against")
    said = _as_assignments(change) if isinstance(change, dict) else "--against model"  # (--other-model: a str)
    _plot(ens, other, d, args, (_as_assignments(ens.overrides) or "model", said))
    return 0


def _other_model_change(ens, other, change):
    """What ``pool --other-model`` says the paired change is of: the --against files' model (by its
    fingerprint) against the files' model, the two models' whole difference, with the overrides that
    differ too."""
    fp = other.settings.get("base_model") or other.settings.get("model")
    mine = ens.settings.get("base_model") or ens.settings.get("model")
    said = f"the --against files' model (fingerprint {fp}) instead of the files' ({mine}): the models' whole difference"
    return said + (f", and the overrides {change}" if change else "")


def _changed_overrides(ens, other):
    """The overrides of ``other`` that differ from those of ``ens``, ``(the model's value)`` for one
    that ``other`` does not have."""
    keys = sorted(set(ens.overrides) | set(other.overrides))
    return {
        k: other.overrides.get(k, "(the model's value)") for k in keys if ens.overrides.get(k) != other.overrides.get(k)
    }


def _check_outputs(args):
    """``--out`` (and its ``_against`` twin) and ``--plot`` of ``ensemble`` and ``pool`` checked
    before any run; returns the three paths (None where not asked for), as :func:`kept` takes them."""
    against = _against_path(args.out) if args.against else None
    check_output_path("--out", args.out, (".csv",))
    check_output_path("--out", against, (".csv",))
    check_output_path("--plot", args.plot, PLOT_SUFFIXES)
    check_distinct(("--out", args.out), ("--plot", args.plot))
    return args.out, against, args.plot


def _check_not_inputs(args, outputs):
    """``pool``'s outputs (``--out``, its ``_against`` twin, ``--plot``) must not be one of the parts
    it reads (the files, the ``--against`` files): a part written over would lose its members."""
    parts = [("a file it pools", p) for p in args.files] + [("an --against file", p) for p in args.against]
    for flag, out in zip(("--out", "--out", "--plot"), outputs):
        if out is None:
            continue
        for role, part in parts:
            if Path(out).resolve() != Path(part).resolve():
                continue
            same = role if part == out else f"{part}, {role}"  # (the part as it was spelled, if otherwise)
            said = f"its _against twin {out} is {same}" if flag == "--out" and out != args.out else f"it is {same}"
            raise ModelError(
                flag,
                args.out if flag == "--out" else out,
                f"must not name an input of pool: {said}, which it would write over",
            )


def _seed_list(seeds):
    """Seeds as ``1..4`` when consecutive, else listed (at most ten shown)."""
    seeds = [int(s) for s in seeds]
    if len(seeds) > 2 and seeds == list(range(seeds[0], seeds[-1] + 1)):
        return f"{seeds[0]}..{seeds[-1]}"
    return ", ".join(map(str, seeds[:10])) + (", ..." if len(seeds) > 10 else "")


def _as_assignments(overrides):
    """``{"a.b": 1}`` as ``"a.b=1"``, the form of ``--set``/``--against`` (figure labels)."""
    return ", ".join(f"{k}={v}" for k, v in overrides.items())


def _check_workers(args):
    """--workers: a whole number >= 1, and only where the command starts its workers (a local
    cluster's processes, or the threads of --scheduler threads; the serial runs and a cluster of
    one's own, --scheduler tcp://..., have none of the command's)."""
    if args.workers is None:
        return
    integer("--workers", args.workers, 1)
    if args.scheduler not in (None, "local", "threads"):
        raise ModelError(
            "--workers",
            args.workers,
            f"is the number of workers of a local cluster or of --scheduler threads; with --scheduler "
            f"{args.scheduler} there is none to size (leave --workers out, or give --scheduler threads or local)",
        )


def _check_confidence(confidence):
    number("--confidence", confidence, gt=0, lt=1)


def _print_ensemble(ens, confidence):
    from ..nvh.bands import WINDOW_NAMES

    unit = unit_of(ens.output)
    seeds = f"{ens.seeds[0]}..{ens.seeds[-1]}" if np.all(np.diff(ens.seeds) == 1) else "(see the CSV)"
    print(
        f"# {ens.output} band RMS ({unit}) over {ens.n} seeds {seeds}"
        f"{' with ' + str(ens.overrides) if ens.overrides else ''}; CI {confidence:g} (Student t)"
        + (f"; the records after {ens.settings['skip']:g} s" if "skip" in ens.settings else "")
        + (f", {WINDOW_NAMES[ens.settings['window']]} window" if "window" in ens.settings else "")
    )
    print("band,f_low_hz,f_high_hz,mean,se,ci_low,ci_high,cv")
    for row in ens.as_rows(confidence):
        print(",".join([row["band"]] + [f"{row[k]:.6g}" for k in list(row)[1:]]))
    from ..nvh.bands import NO_RESPONSE_DB, no_response

    if (off := no_response(ens.mean)).any():  # (their levels are the window's leakage, not a response)
        gone = ", ".join(lab for lab, o in zip(ens.labels, off) if o)
        print(
            f"# no response in {gone}: their mean lies more than {NO_RESPONSE_DB:g} dB below the strongest band's, "
            "where Hann's window's leakage from the other bands, not the response, sets a level"
        )
    if ens.warnings:
        print(
            f"cablecasing: warning: {len(ens.warnings)} of {ens.n} members warned (seeds "
            f"{_seed_list(sorted(ens.warnings))}; the ensemble's CSV "
            "keeps what each said)",
            file=sys.stderr,
        )


def _print_change(ens, other, d, change, confidence):
    """The paired change of ``other`` against ``ens`` (``d``): nan in a band where either holds no
    response (``nvh.bands.no_response``: its level is the window's leakage, as the report shows a
    dash), and said when the change made no difference in any member."""
    from ..nvh.bands import no_response

    lo, hi = d.ci(confidence)
    silenced = not np.any(other.levels) and np.any(ens.levels)  # (every level 0: a change of -100 %, no leakage)
    off = no_response(ens.mean) | (False if silenced else no_response(other.mean))
    print(f"# relative change of the mean level with {change} (paired on the same seeds)")
    print(
        "# is there a change: p, the paired t test of no change (two-sided); how large: rel_diff, its se and "
        f"{confidence:.4g} interval (diff_over_se is no test: its se is taken at rel_diff, not at 0)"
    )
    print("band,mean_against,rel_diff,se,ci_low,ci_high,diff_over_se,p")
    for lab, m, r, se, a, b, o, p in zip(d.labels, other.mean, d.r, d.se, lo, hi, off, d.p):
        if o:
            print(f"{lab},{m:.6g},nan,nan,nan,nan,nan,nan")
            continue
        ratio = r / se if se > 0 else (0.0 if r == 0 else math.nan)
        print(f"{lab},{m:.6g},{r:+.4f},{se:.4f},{a:+.4f},{b:+.4f},{ratio:+.1f},{p:.3g}")
    if off.any():
        gone = ", ".join(lab for lab, o in zip(d.labels, off) if o)
        print(f"# no change given in {gone}: no response there in one of the two (the window's leakage sets a level)")
    if silenced:
        print(f"# the change silences {other.output}: every level of every member is 0 N (-100 %)")
    if np.array_equal(ens.levels, other.levels):
        print("# the change made no difference in any member: the two ensembles' levels are the same to the bit")


def _against_path(out, suffix="_against"):
    """``x.csv`` -> ``x_against.csv`` (None for None)."""
    if not out:
        return None
    stem, dot, ext = out.rpartition(".")
    return f"{stem}{suffix}.{ext}" if dot else f"{out}{suffix}"


def _save(ens, out, suffix):
    """Write ``ens`` to ``out`` (``x.csv`` -> ``x<suffix>.csv``), if ``out`` was given."""
    if out:
        path = _against_path(out, suffix) if suffix else out
        ens.save(path)
        print(f"# wrote {path}")


def _plot(ens, other, d, args, labels):
    if args.plot:
        from ..studies import plot_ensemble

        plot_ensemble(ens, args.plot, other, d, args.confidence, labels=labels)
        print(f"# wrote {args.plot}")


def add_parser(sub):
    p = sub.add_parser("study", help="Monte-Carlo study of Section 4.4: correlations and Sobol indices (dask)")
    add_model_argument(p)
    p.add_argument(
        "--vary",
        action="append",
        default=[],
        metavar="KEY=LOW:HIGH",
        help="a parameter and its bounds in SI units, e.g. casing.E=2e9:1e10 (repeatable; default: the paper's "
        "six parameters, docs/studies.md)",
    )
    p.add_argument("--vary-file", default=None, help="TOML file of bounds, one 'casing.E = [2e9, 1e10]' per line")
    p.add_argument(
        "--samples",
        type=int,
        default=300,
        help="runs, rounded up to whole groups of (parameters + 2); a larger number continues a study in --out",
    )
    p.add_argument(
        "--seed",
        type=int,
        default=0,
        help="seed of the scrambled Sobol' sequence (not of the excitation: each sample runs the model's own)",
    )
    p.add_argument(
        "--excitation-seeds",
        type=int,
        default=None,
        metavar="K",
        help="each sample the mean of K runs on the excitation seeds 1..K (K >= 2; default: one run on the "
        "model's own seeds); K times the run time",
    )
    p.add_argument(
        "--scheduler",
        default=None,
        help="where the samples run: 'serial' (this process), 'threads' (this process, one thread per core), "
        "local (default: a dask cluster, one process per core) or a dask scheduler address tcp://host:8786",
    )
    p.add_argument("--workers", type=int, default=None, help="threads or local cluster workers (default: one per core)")
    p.add_argument(
        "--duration", type=float, default=None, help=key_help("scenario.duration", "simulated time per sample")
    )
    add_window_argument(p)
    p.add_argument(
        "--skip",
        type=float,
        default=None,
        help=SKIP_HELP,
    )
    p.add_argument(
        "--output",
        default=STUDY_OUTPUT,
        help="the support, isolator or clip output whose Table 3 band RMS the study records (N or N.m), e.g. "
        "casing.A.Fx, cable.B.Mz, casing.clip0.Fz",
    )
    p.add_argument("--out", default="study", help="folder of study.csv (resumed when it exists) and the figures")
    p.add_argument(
        "--timeout",
        type=float,
        default=PROGRESS_TIMEOUT,
        metavar="S",
        help="on dask: stop (exit status 3, resumable) when no sample finishes for S seconds",
    )
    p.add_argument(
        "--no-progress",
        dest="progress",
        action="store_false",
        help="no progress bar (default: a bar of the samples done on stderr)",
    )
    p.set_defaults(func=cmd_study)

    e = sub.add_parser("ensemble", help="band levels of a support output as means over excitation seeds")
    add_model_argument(e)
    e.add_argument("--seeds", type=int, default=8, help="number of seeds (default 8)")
    e.add_argument("--first-seed", type=int, default=1, help="seeds first..first+n-1 (default 1)")
    e.add_argument("--duration", type=float, default=None, help=key_help("scenario.duration", "simulated time per run"))
    e.add_argument("--dt", type=float, default=None, help=key_help("scenario.dt"))
    add_window_argument(e)
    e.add_argument(
        "--skip",
        type=float,
        default=None,
        help=SKIP_HELP,
    )
    e.add_argument("--output", default=STUDY_OUTPUT, help=f"support output, e.g. {STUDY_OUTPUT}")
    choice_argument(
        e,
        "--kind",
        choices=FromApi("nvh.bands", "BAND_KINDS"),
        default="table3",
        help="band set (docs/studies.md)",
    )
    e.add_argument(
        "--set", action="append", default=[], metavar="KEY=VALUE", help="model change for every run; " + ASSIGNMENT_HELP
    )
    e.add_argument(
        "--against",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="compare with a second ensemble on the same seeds with this change",
    )
    e.add_argument("--confidence", type=float, default=0.95, help="level of the confidence intervals")
    e.add_argument(
        "--scheduler",
        default="serial",
        help="'serial' (default), 'threads' (this process, one thread per core), 'local' (dask, one worker per "
        "core) or tcp://host:8786",
    )
    e.add_argument("--workers", type=int, default=None, help="threads or local cluster workers (default: one per core)")
    e.add_argument("--out", default=None, help="CSV of the per-seed band levels")
    e.add_argument(
        "--plot", default=None, metavar="PNG", help="figure: means with confidence intervals (and the change)"
    )
    e.add_argument(
        "--no-progress",
        dest="progress",
        action="store_false",
        help="no progress bar (default: a bar of the runs done on stderr)",
    )
    e.set_defaults(func=cmd_ensemble)

    q = sub.add_parser("pool", help="pool ensemble CSVs run in parts (ensemble --out) and print their statistics")
    q.add_argument("files", nargs="+", metavar="CSV", help="parts written by 'cablecasing ensemble --out'")
    q.add_argument(
        "--against",
        nargs="+",
        default=[],
        metavar="CSV",
        help="the parts' _against.csv files: print the paired change as 'ensemble --against' does",
    )
    q.add_argument(
        "--other-model",
        action="store_true",
        help="the --against files may be of another model file (a clip moved, say) run on the same seeds and "
        "settings: the change printed is then the two models' whole difference",
    )
    q.add_argument("--confidence", type=float, default=0.95, help="level of the confidence intervals")
    q.add_argument("--out", default=None, help="CSV of the pooled members (and OUT_against.csv)")
    q.add_argument("--plot", default=None, metavar="PNG", help="figure as 'ensemble --plot'")
    q.set_defaults(func=cmd_pool)
