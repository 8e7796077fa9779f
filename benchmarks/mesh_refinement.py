"""The mesh: do the natural frequencies and the expected band levels converge in geometry.n_elements?

Both built-in specimens use the paper's 35 elements per body. This script refines the mesh of the
``default`` and the ``installed`` specimen (``--specimen``), or of one model (``--model MODEL``: a
model file or a built-in specimen's name, as the CLI's MODEL argument and ``installed_time_step.py``'s
``--model``; a file's label in the printed names is its name without ``.toml``), and prints
``name: value`` lines (docs/time_domain.md, "The mesh", holds the tables of the cached run). A model
file's defaults: ``--seeds 16``, ``--skip`` the CLI's (``whole_period_skip``: 0.05 s or the ramp,
lengthened to whole periods of its drives), ``--json`` beside the file (``NAME_mesh_refinement.json``).

Clips (a model with casing clips): each clip's node offset on every mesh of both parts (the node it
acts at minus its ``at``, mm: ``clip_node_offset_mm_SPEC_i``) and ``clips_stay_across_meshes_SPEC``,
false when the clips move between the meshes (``geometry.nodes_at_clips = false``: each clip at its
nearest node, which a finer mesh moves by up to half an element). The study runs either way: the
model as written is the one its user runs, and ``nodes_at_clips = true`` would change it at its own
mesh too; the lines say when a difference between meshes holds the clips' movement as well.

Modal part (``--modal-elements``, default 35 70 140 280): the natural frequencies of each body
(``cc.natural_frequencies``, all modes) matched by their index in ascending order. The reference is
the finest mesh; every mode of the reference below 5680 Hz (the top edge of Table 3) is compared.
Per Table 3 band (of the reference's frequency; "<11 Hz" below it): the number of modes, the
largest |f_n - f_ref| / f_ref at each coarser mesh n (as many modes as the coarsest mesh has in all, when fewer:
``modes_compared_SPEC_BODY``), and the median observed order of the modes in
the band from the three coarsest meshes, p = log2(|f_35 - f_70| / |f_70 - f_140|), and from the
three finest ones (each independent of the reference). Also the number of modes below 5680 Hz at
each mesh.

Band part (``--elements``, default 35 70 140): per mesh, the Table 3 band levels (N) of casing.B.Fz
over seeds 1..N of the casing's random excitation (``--seeds``: one count for all specimens, or
``SPEC=N`` each; default default=128 installed=32), each member the specimen's own scenario at its
own Δt (scenario.dt, 1e-5 s) for ``--duration`` s, the levels of the samples after ``--skip`` s
(``records.after_skip``; default 0.05 s for ``default`` and 0.06 s for ``installed``, whose 0.94 s
then hold whole periods of its 50 Hz drive, docs/time_domain.md "The record's length"). A member
is the run of the ensemble member of ``cablecasing ensemble SPEC --set geometry.n_elements=N`` (the
same overrides, ``simulate``, ``after_skip`` and ``octave_rms`` as ``default_evaluate`` (with the rectangular
window of its cached tables, ``default_evaluate(..., window="boxcar")``); checked on
0.2 s: the same levels bitwise on the default specimen, within 2e-10 on the installed one), run
here to read its energies too. With contact the response is chaotic, so meshes are compared on ensemble
means: per band the mean level and its standard error (sd / sqrt(n), ddof 1), and the relative
difference r = (mean L(n) - mean L(m)) / mean L(m) from every finer mesh m (``vs_m``, on the seeds
the two share), with two standard errors: ``se_indep`` as of independent ensembles
(sqrt(SE_n^2 + (1 + r)^2 SE_m^2) / mean L(m)) and ``se_paired`` from the paired seeds
(``studies.paired_difference``: the seed drives the same excitation record at every mesh). Also
``max |r| + 2 SE``, the r of each half of the seeds, the members' cost, the contacts per step (the
sum of ``contact_time`` over the cable nodes / duration; the contact is a law per cable node, so
they grow with the nodes) and the contact's normal work share
``energies["contact_normal_dissipation"] / energies["contact_dissipation"]`` (mean over seeds and
its SE; docs/time_domain.md "The normal force's work on a mesh"), and its share of the supports'
work.

Linear part (``--linear``): seed 1 with the contact off on every mesh of ``--modal-elements``, the
band levels relative to the finest: the bodies' own error in the forced response (not chaotic, so
one record shows it).

Options: ``--specimen`` or ``--model``, ``--elements``, ``--modal-elements``, ``--seeds``, ``--skip``, ``--duration``,
``--workers`` (processes, default 2), ``--window boxcar|hann`` (of the band members' levels; default
boxcar, the window of the cached tables of ``mesh_refinement.json`` and ``mesh_refinement_per_length.json``;
``mesh_refinement_hann.json`` holds a run through Hann's window, the package's default);
``--mesh-seeds N=K`` runs mesh N on seeds 1..K only (a costly
finest mesh: its differences are then taken on those seeds); ``--dt-check N DT K`` also runs mesh N
at the time step DT on seeds 1..K and prints its paired difference from mesh N at the specimen's own
step (is that step still converged on a fine mesh?); ``--law-length M|paper`` runs the band part's
members with ``contact.law_length`` = M m (``paper``: the cable's length / 35, the law per unit
length with the paper's wall at 35 elements; docs/time_domain.md "A contact law per unit length",
whose cache is ``benchmarks/mesh_refinement_per_length.json``); ``--no-modal``, ``--no-bands``.

Cache: every member is written to ``--json`` (default benchmarks/mesh_refinement.json, atomically,
every 20 s and at the end) with its conditions: the date, the duration, Δt, the skip, a hash of the
package's sources (no git here) and the model's fingerprint; each specimen's summary holds the
seeds, the command and the wall time. A second run reuses the members whose specimen, mesh, Δt,
seed, settings, model fingerprint and source hash match (``--fresh``: none), so a study stopped by
Ctrl-C goes on where it stopped, and ``--seeds 4`` (the cost probe) counts toward a larger run;
``--reuse-other-sources`` also reuses members run by other sources of the package (when others edit
it during a study; the summary lists the sources' hashes, and one member per mesh, Δt and seed is
kept: this source's, else the latest). ``--report`` prints the summaries of the cache without
running anything.

Run (the cached run, docs/time_domain.md "The mesh"; 27.6 min of runs on the shared 2-core machine):
  .venv/bin/python benchmarks/mesh_refinement.py --specimen default --seeds 128 --elements 35 70 140 280 \
      --mesh-seeds 280=32 --dt-check 140 5e-6 32 --linear
  .venv/bin/python benchmarks/mesh_refinement.py --specimen installed --seeds 16 --elements 35 70 140 280 \
      --mesh-seeds 280=2 --dt-check 140 5e-6 2
(``--seeds 4`` first measures the members' cost: ``wall_s_per_member_*``)
"""

import datetime
import hashlib
import json
import math
import os
import sys
import time
from multiprocessing import get_context
from pathlib import Path

import numpy as np
from _options import checked, output_file, parser
from _record_length import require_band_record

HERE = Path(__file__).resolve().parent
SPECIMENS = ("default", "installed")
DEFAULT_SEEDS = {"default": 128, "installed": 32}
DEFAULT_SKIP = {"default": 0.05, "installed": 0.06}
MODEL_SEEDS = 16  # a model file's default --seeds (docs/model_file.md: 16 or more with impacts)
FMAX = 5680.0  # Hz: the top edge of Table 3
OUTPUT = "casing.B.Fz"


def source_hash():
    """sha256 (16 hex digits) of the package's Python sources: the code the members ran."""
    import cablecasing_core

    root = Path(cablecasing_core.__file__).resolve().parent
    h = hashlib.sha256()
    for f in sorted(root.rglob("*.py")):
        h.update(str(f.relative_to(root)).encode())
        h.update(f.read_bytes())
    return h.hexdigest()[:16]


def mesh_model(source, n, law_length=0.0):
    """The model ``source`` (a built-in specimen's name or a model file's path, ``cc.load_model``'s
    argument) at ``n`` elements, its contact law per node (``law_length`` 0 m, the paper's) or per
    unit length (``contact.law_length``, m)."""
    import cablecasing_core as cc

    over = {"geometry.n_elements": int(n)}
    if law_length:
        over["contact.law_length"] = float(law_length)
    return cc.load_model(source).with_overrides(over)


def paper_law_length(source):
    """The cable's length over the paper's 35 elements (m): the law per unit length that gives the
    model's nodes at 35 elements the wall of the law per node (``--law-length paper``)."""
    import cablecasing_core as cc
    from cablecasing_core.structure.geometry import centerline_of

    return float(centerline_of(cc.load_model(source)).lengths.sum() / 35)


def clip_offsets(source, meshes):
    """Where the casing's clips act on each mesh: ``geometry.nodes_at_clips`` of the model
    ``source`` and, per clip in file order, its ``at`` (m) and {n: the arc length of the node it acts
    at minus its at (m)} for n in ``meshes`` (``structure.mount_element.clip_positions``); None
    without clips."""
    import warnings

    import cablecasing_core as cc
    from cablecasing_core.structure.mount_element import clip_positions

    base = cc.load_model(source)
    clips = base.data.get("casing", {}).get("clip", [])
    if not clips:
        return None
    with warnings.catch_warnings():  # (the loader's clip warning, once per mesh: the lines printed say it)
        warnings.simplefilter("ignore")
        at_nodes = {n: clip_positions(mesh_model(source, n)) for n in meshes}
    return {
        "nodes_at_clips": bool(base.geometry["nodes_at_clips"]),
        "clips": [
            {"at_m": float(c["at"]), "offset_m": {str(n): at_nodes[n][i] - float(c["at"]) for n in meshes}}
            for i, c in enumerate(clips)
        ],
    }


def print_clips(spec, d):
    """The lines of :func:`clip_offsets`: each clip's node offset per mesh, and whether the clips
    stay in place across the meshes (a movement above 1e-9 m, round-off of the arc lengths, is one)."""
    print(f"clips_{spec}: {len(d['clips'])} (geometry.nodes_at_clips = {str(d['nodes_at_clips']).lower()})")
    move = 0.0
    for i, c in enumerate(d["clips"]):
        off = c["offset_m"]
        print(
            f"clip_node_offset_mm_{spec}_{i}: "
            + " ".join(f"{n}:{1e3 * v:+.3f}" for n, v in off.items())
            + f" (the node it acts at minus its at = {c['at_m']:g} m, per mesh)"
        )
        move = max(move, max(off.values()) - min(off.values()))
    if move > 1e-9:
        print(
            f"clips_stay_across_meshes_{spec}: false (the clips move by up to {1e3 * move:.3f} mm between the "
            "meshes, so a difference between meshes mixes the clips' movement with the mesh's error; "
            "geometry.nodes_at_clips = true keeps each clip at its at on every mesh)"
        )
    else:
        print(f"clips_stay_across_meshes_{spec}: true (each clip acts at one place on every mesh)")


# ---------------------------------------------------------------- the members (in worker processes)
def _warm():
    import cablecasing_core as cc

    cc.simulate(cc.load_model(), duration=0.002)  # load the compiled kernels once per worker


def linear_member(job):
    """(spec, source, n, seed, duration, skip) with the contact off: the band levels of the linear response
    (deterministic: one seed shows the mesh's own error), and the wall time."""
    import cablecasing_core as cc
    from cablecasing_core.nvh.bands import octave_rms, window_options  # (boxcar: the cached tables')
    from cablecasing_core.records import after_skip
    from cablecasing_core.studies.ensemble_runs import seed_overrides

    spec, source, n, seed, duration, skip = job
    base = mesh_model(source, n)
    t0 = time.perf_counter()
    res = cc.simulate(base.with_overrides(seed_overrides(base, seed)), duration=duration, contact=False)
    wall = time.perf_counter() - t0
    keep = after_skip(res.time, skip)
    levels = octave_rms(
        res.support_force(OUTPUT)[keep], 1.0 / (res.time[1] - res.time[0]), "table3", **window_options("boxcar")
    ).rms
    return spec, int(n), [float(x) for x in levels], wall


def member(job):
    """One ensemble member: (spec, source, n, seed, duration, skip, dt, law_length, window) -> its
    record of levels and energies (spec: the label of the model ``source``, :func:`mesh_model`; dt
    None: the scenario's; law_length m, 0: the law per node; window of the band levels, "boxcar" for
    the cached tables of benchmarks/mesh_refinement.json)."""
    import cablecasing_core as cc
    from cablecasing_core.nvh.bands import octave_rms, window_options
    from cablecasing_core.records import after_skip
    from cablecasing_core.studies.ensemble_runs import seed_overrides

    spec, source, n, seed, duration, skip, dt, law_length, window = job
    base = mesh_model(source, n, law_length)
    model = base.with_overrides(seed_overrides(base, seed))
    t0 = time.perf_counter()
    res = cc.simulate(model, duration=duration, dt=dt)
    wall = time.perf_counter() - t0
    keep = after_skip(res.time, skip)
    fs = 1.0 / (res.time[1] - res.time[0])
    levels = octave_rms(res.support_force(OUTPUT)[keep], fs, "table3", **window_options(window)).rms
    e = res.energies
    return {
        "specimen": spec,
        "n_elements": int(n),
        "seed": int(seed),
        "dt_s": float(model.scenario["dt"] if dt is None else dt),
        "law_length_m": float(law_length),
        "levels_N": [float(x) for x in levels],
        "contact_dissipation_J": float(e["contact_dissipation"]),
        "contact_normal_dissipation_J": float(e["contact_normal_dissipation"]),
        "support_work_J": float(e["support_work"]),
        "contacts_per_step": float(np.sum(res.contact_time) / duration),
        "wall_s": wall,
    }


# ---------------------------------------------------------------- the modal part
def modal_part(sources, meshes):
    """The modal part of the models ``sources`` (label -> a built-in specimen's name or a model
    file's path) on ``meshes``."""
    import warnings

    import cablecasing_core as cc
    from cablecasing_core.studies import octave_bands

    bands = octave_bands("table3")
    edges = [0.0, *bands.lower.tolist(), float(bands.upper[-1])]
    labels = ["<11 Hz", *bands.labels]
    meshes = sorted(meshes)
    ref_n = meshes[-1]
    out = {}
    for spec, source in sources.items():
        out[spec] = {}
        for body in [b for b in ("casing", "cable") if b in cc.load_model(source).data]:  # (a model may lack one)
            t0 = time.perf_counter()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                f = {n: np.asarray(cc.natural_frequencies(mesh_model(source, n), body)) for n in meshes}
            ref = f[ref_n]
            below = int(np.count_nonzero(ref <= FMAX))
            k = min(below, *(len(f[n]) for n in meshes))  # (a coarse mesh of a model may have fewer modes in all)
            rel = {n: (f[n][:k] - ref[:k]) / ref[:k] for n in meshes[:-1]}
            band_of = np.searchsorted(edges, ref[:k], side="right") - 1
            rows = []
            for b, lab in enumerate(labels):
                sel = band_of == b
                row = {"band": lab, "modes": int(sel.sum())}
                if sel.any():
                    for n in meshes[:-1]:
                        row[f"max_abs_rel_change_{n}"] = float(np.max(np.abs(rel[n][sel])))
                    for trio in zip(meshes, meshes[1:], meshes[2:]):
                        a, bb, c = (f[m][:k][sel] for m in trio)
                        with np.errstate(divide="ignore", invalid="ignore"):
                            p = np.log2(np.abs(a - bb) / np.abs(bb - c))
                        p = p[np.isfinite(p)]
                        row[f"order_{trio[0]}_{trio[1]}_{trio[2]}"] = float(np.median(p)) if len(p) else None
                rows.append(row)
            out[spec][body] = {
                "reference_elements": ref_n,
                "modes_compared": k,
                "reference_modes_below_fmax": below,
                "modes_below_fmax": {str(n): int(np.count_nonzero(f[n] <= FMAX)) for n in meshes},
                "frequencies_hz": {str(n): f[n][: k + 8].tolist() for n in meshes},
                "rel_change_vs_reference": {str(n): rel[n].tolist() for n in meshes[:-1]},
                "by_band": rows,
                "wall_s": time.perf_counter() - t0,
            }
    return out


def print_modal(modal):
    for spec, bodies in modal.items():
        for body, d in bodies.items():
            key = f"{spec}_{body}"
            print(f"modes_below_5680hz_{key}: " + " ".join(f"{n}:{c}" for n, c in d["modes_below_fmax"].items()))
            meshes = [int(n) for n in d["modes_below_fmax"]][:-1]
            if d.get("modes_compared", 0) < d.get("reference_modes_below_fmax", 0):
                print(
                    f"modes_compared_{key}: {d['modes_compared']} (of the reference's "
                    f"{d['reference_modes_below_fmax']} below 5680 Hz: the coarsest mesh has {d['modes_compared']} "
                    "modes in all)"
                )
            for n in meshes:
                r = np.abs(d["rel_change_vs_reference"][str(n)])
                print(f"freq_max_abs_rel_change_{key}_{n}: {r.max():.5f} (median {np.median(r):.5f})")
            for row in d["by_band"]:
                if not row["modes"]:
                    continue
                ch = " ".join(f"{n}:{row[f'max_abs_rel_change_{n}']:.2e}" for n in meshes)
                orders = " ".join(
                    f"{k[6:]}:{v:.2f}" if v is not None else f"{k[6:]}:-"
                    for k, v in row.items()
                    if k.startswith("order_")
                )
                band = row["band"].replace(" ", "")
                # (the observed order needs three meshes: none with two)
                print(
                    f"freq_change_{key}_{band}: modes {row['modes']} max |df/f| {ch}"
                    + (f" order {orders}" * bool(orders))
                )


# ---------------------------------------------------------------- the band part
def paired(members_a, members_b):
    """Paired relative difference of the mean levels of ``members_a`` against ``members_b`` (dicts
    seed -> member) on their common seeds: (seeds, r, se_paired, se_indep) or None."""
    from cablecasing_core.studies import paired_difference

    common = sorted(set(members_a) & set(members_b))
    if len(common) < 2:
        return None
    a = np.array([members_a[s]["levels_N"] for s in common])
    b = np.array([members_b[s]["levels_N"] for s in common])
    d = paired_difference(a, b)
    sa, sb = (x.std(axis=0, ddof=1) / math.sqrt(len(common)) for x in (a, b))
    se_indep = np.sqrt(sa**2 + ((1 + d.r) * sb) ** 2) / b.mean(axis=0)
    h = len(common) // 2
    halves = (
        [paired_difference(a[:h], b[:h]).r.tolist(), paired_difference(a[h:], b[h:]).r.tolist()] if h >= 2 else None
    )
    return {
        "seeds": len(common),
        "rel_diff": d.r.tolist(),
        "se_paired": d.se.tolist(),
        "se_indep": se_indep.tolist(),
        "max_abs_plus_2se_paired": float(np.max(np.abs(d.r) + 2 * d.se)),
        "max_abs_plus_2se_indep": float(np.max(np.abs(d.r) + 2 * se_indep)),
        "rel_diff_seed_halves": halves,
    }


def _ratio(a, b):
    """a / b, nan when b is 0 (a model without contact: no contact work)."""
    return a / b if b else math.nan


def summarise(members, spec, variants, dt0):
    """Per variant (n_elements, dt): mean, SE, CV of the band levels on its own seeds, the normal
    work share, contacts, cost; the paired differences of every mesh at ``dt0`` from every finer
    mesh (on their common seeds), and of a variant at another dt from the same mesh at dt0."""
    by = {}
    for m in members:
        if m["specimen"] == spec and (m["n_elements"], m["dt_s"]) in variants:
            by.setdefault((m["n_elements"], m["dt_s"]), {})[m["seed"]] = m
    meshes = sorted(n for n, dt in variants if dt == dt0 and len(by.get((n, dt), {})) >= 2)
    if not meshes:
        return None
    out = {"reference_elements": meshes[-1], "dt_s": dt0, "variants": {}}
    for (n, dt), rows in sorted(by.items()):
        if len(rows) < 2:
            continue
        L = np.array([m["levels_N"] for m in rows.values()])
        mean = L.mean(axis=0)
        share = np.array([_ratio(m["contact_normal_dissipation_J"], m["contact_dissipation_J"]) for m in rows.values()])
        of_work = np.array([_ratio(m["contact_normal_dissipation_J"], m["support_work_J"]) for m in rows.values()])
        d = {
            "n_elements": n,
            "dt_s": dt,
            "seeds": sorted(rows),
            "mean_N": mean.tolist(),
            "se_N": (L.std(axis=0, ddof=1) / math.sqrt(len(L))).tolist(),
            "cv": (L.std(axis=0, ddof=1) / mean).tolist(),
            "normal_work_share_mean": float(share.mean()),
            "normal_work_share_se": float(share.std(ddof=1) / math.sqrt(len(share))),
            "normal_work_of_support_work_mean": float(of_work.mean()),
            "contacts_per_step_mean": float(np.mean([m["contacts_per_step"] for m in rows.values()])),
            "wall_s_per_member_median": float(np.median([m["wall_s"] for m in rows.values()])),
        }
        if dt == dt0 and n in meshes:
            for finer in reversed(meshes[meshes.index(n) + 1 :]):  # every finer mesh, the finest first
                d[f"vs_{finer}"] = paired(rows, by[(finer, dt0)])
        elif dt != dt0 and (n, dt0) in by:
            d[f"vs_dt_{dt0:g}"] = paired(rows, by[(n, dt0)])
        out["variants"][f"{n}@{dt:g}"] = d
    return out


def print_bands(spec, s):
    for d in s["variants"].values():
        k = f"{spec}_{d['n_elements']}" + ("" if d["dt_s"] == s["dt_s"] else f"_dt{d['dt_s']:g}")
        print(f"band_seeds_{k}: {len(d['seeds'])}")
        print(f"band_mean_N_{k}: " + " ".join(f"{x:.4g}" for x in d["mean_N"]))
        print(f"band_se_rel_{k}: " + " ".join(f"{se / m:.4f}" for se, m in zip(d["se_N"], d["mean_N"])))
        print(f"band_cv_{k}: " + " ".join(f"{x:.3f}" for x in d["cv"]))
        for vs, p in d.items():
            if not vs.startswith("vs_") or p is None:
                continue
            r, sp, si = (np.array(p[x]) for x in ("rel_diff", "se_paired", "se_indep"))
            print(f"band_rel_diff_{k}_{vs}: " + " ".join(f"{x:+.4f}" for x in r))
            print(f"band_rel_diff_seeds_{k}_{vs}: {p['seeds']}")
            print(f"band_rel_diff_se_paired_{k}_{vs}: " + " ".join(f"{x:.4f}" for x in sp))
            print(f"band_rel_diff_se_indep_{k}_{vs}: " + " ".join(f"{x:.4f}" for x in si))
            with np.errstate(divide="ignore"):
                print(f"band_diff_over_se_paired_{k}_{vs}: " + " ".join(f"{x:+.1f}" for x in r / sp))
                print(f"band_diff_over_se_indep_{k}_{vs}: " + " ".join(f"{x:+.1f}" for x in r / si))
            print(f"band_max_abs_plus_2se_paired_{k}_{vs}: {p['max_abs_plus_2se_paired']:.4f}")
            print(f"band_max_abs_plus_2se_indep_{k}_{vs}: {p['max_abs_plus_2se_indep']:.4f}")
            if p["rel_diff_seed_halves"]:
                a, b = p["rel_diff_seed_halves"]
                print(f"band_rel_diff_seed_halves_{k}_{vs}: " + " ".join(f"{x:+.3f}/{y:+.3f}" for x, y in zip(a, b)))
        print(
            f"normal_work_share_{k}: {d['normal_work_share_mean']:+.4f} ± {d['normal_work_share_se']:.4f} "
            f"(of the supports' work {d['normal_work_of_support_work_mean']:+.5f})"
        )
        print(f"contacts_per_step_{k}: {d['contacts_per_step_mean']:.2f}")
        print(f"wall_s_per_member_{k}: {d['wall_s_per_member_median']:.2f}")


# ---------------------------------------------------------------- main
def parse_per_spec(values, kind, defaults, specs):
    """``N`` (every model) or ``SPEC=N`` values of ``kind`` over ``defaults`` (label -> value), for the
    labels ``specs``."""
    out = dict(defaults)
    for v in values or []:
        if "=" in v:
            k, _, x = v.partition("=")
            if k not in defaults:
                raise SystemExit(f"{kind} {v!r}: the specimen must be one of {', '.join(defaults)}")
            out[k] = x
        else:
            out = {k: v for k in defaults}
    return {k: out[k] for k in specs}


def model_label(arg):
    """(label, source) of ``--model``'s ``arg``: a built-in specimen's name is its own label and
    source; a model file's label is its name without the suffix (``_file`` added when that is a
    built-in's name), its source the absolute path (the workers load it)."""
    from cablecasing_core.model import specimen_names

    if arg in specimen_names():
        return arg, arg
    path = Path(arg)
    label = path.stem + ("_file" if path.stem in specimen_names() else "")
    return label, str(path.resolve())


def main():
    p = parser(__doc__)
    which = p.add_mutually_exclusive_group()
    which.add_argument("--specimen", nargs="+", choices=SPECIMENS, help="built-in specimens (default: both)")
    which.add_argument(
        "--model",
        metavar="MODEL",
        help="a model file (TOML) or a built-in specimen's name, as the CLI's MODEL: its own scenario on the meshes "
        f"(default --seeds {MODEL_SEEDS}, --skip: the CLI's, --json: FILE's name + _mesh_refinement.json beside it)",
    )
    p.add_argument("--elements", nargs="+", type=int, default=[35, 70, 140], help="meshes of the band part")
    p.add_argument(
        "--mesh-seeds",
        nargs="+",
        default=[],
        metavar="N=K",
        help="run mesh N on seeds 1..K only (fewer than --seeds: a costly finest mesh)",
    )
    p.add_argument("--modal-elements", nargs="+", type=int, default=[35, 70, 140, 280], help="meshes of the modal part")
    p.add_argument("--seeds", nargs="+", metavar="N|SPEC=N", help="seeds 1..N (default default=128 installed=32)")
    p.add_argument("--skip", nargs="+", metavar="S|SPEC=S", help="s (default default=0.05 installed=0.06)")
    p.add_argument("--duration", type=float, default=1.0)
    p.add_argument(
        "--window",
        choices=("boxcar", "hann"),
        default="boxcar",
        help="window of the band members' levels (default boxcar: the cached tables'; the package's default "
        "is hann, docs/time_domain.md 'The window of the band levels')",
    )
    p.add_argument(
        "--dt-check",
        nargs=3,
        metavar=("N", "DT", "K"),
        help="also run mesh N at time step DT (s) on seeds 1..K, compared with mesh N at the specimen's "
        "own step on the same seeds (is that step still converged on a fine mesh?)",
    )
    p.add_argument(
        "--linear",
        action="store_true",
        help="also the band levels with the contact off, seed 1, on every mesh of --modal-elements "
        "(the linear response, not chaotic: the mesh's error without the contact)",
    )
    p.add_argument(
        "--law-length",
        default="0",
        metavar="M|paper",
        help="contact.law_length of the band part's members (m; 0, the default: the law per node, as the "
        "specimens; paper: the cable's length / 35, the law per unit length with the paper's wall at 35 "
        "elements). Give each its own --json",
    )
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--json", help="the cache (default benchmarks/mesh_refinement.json; see --model)")
    p.add_argument("--fresh", action="store_true", help="reuse no cached member")
    p.add_argument(
        "--reuse-other-sources",
        action="store_true",
        help="reuse cached members run by other sources of the package too (the summary lists their "
        "source hashes; for edits elsewhere in the package while a study runs)",
    )
    p.add_argument("--no-modal", action="store_true")
    p.add_argument("--no-bands", action="store_true")
    p.add_argument("--report", action="store_true", help="print the tables of the cache; run nothing")
    args = p.parse_args()

    import cablecasing_core as cc
    from cablecasing_core.errors import ModelError
    from cablecasing_core.files import write_text
    from cablecasing_core.timedomain.scenario import whole_period_skip

    default_seeds, default_skip = dict(DEFAULT_SEEDS), dict(DEFAULT_SKIP)
    if args.model is None:
        sources = {sp: sp for sp in dict.fromkeys(args.specimen or SPECIMENS)}
    else:
        label, source = model_label(args.model)
        sources = {label: source}
        try:
            own = cc.load_model(source)
        except ModelError as e:
            p.error(f"--model {args.model!r}: {e}")
        if label not in SPECIMENS:  # (a built-in keeps its own defaults and its cache)
            default_seeds[label] = MODEL_SEEDS
            default_skip[label] = whole_period_skip(own, args.duration)
            if args.json is None:
                args.json = str(Path(source).with_name(Path(source).stem + "_mesh_refinement.json"))
    if args.json is None:
        args.json = str(HERE / "mesh_refinement.json")
    specs = list(sources)
    try:
        seeds = {k: int(v) for k, v in parse_per_spec(args.seeds, "--seeds", default_seeds, specs).items()}
    except ValueError:
        p.error(f"--seeds = {' '.join(args.seeds)}: must be N or SPEC=N, N a whole number")
    try:
        skips = {k: float(v) for k, v in parse_per_spec(args.skip, "--skip", default_skip, specs).items()}
    except ValueError:
        p.error(f"--skip = {' '.join(args.skip)}: must be S or SPEC=S, S in s")
    if any(v < 2 for v in seeds.values()):
        p.error("--seeds: at least 2 per specimen")
    if args.workers < 1:
        p.error("--workers: at least 1")
    for s in skips.values():
        require_band_record(p, args.duration, s)
    meshes = sorted(set(args.elements))
    if len(meshes) < 2:
        p.error("--elements: at least two meshes")
    cap = {}
    for v in args.mesh_seeds:
        n, _, k = v.partition("=")
        try:
            cap[int(n)] = int(k)
        except ValueError:
            p.error(f"--mesh-seeds {v!r}: N=K, two integers")
    if not args.report:  # (the cache written during the runs: its folder checked before them)
        with checked(p):
            output_file("--json", args.json, (".json",))
    path = Path(args.json)

    code = source_hash()
    dt0 = {sp: float(cc.load_model(sources[sp]).scenario["dt"]) for sp in specs}
    try:
        law_length = {
            sp: paper_law_length(sources[sp]) if args.law_length == "paper" else float(args.law_length) for sp in specs
        }
    except ValueError:
        p.error(f"--law-length {args.law_length!r}: a length in m or 'paper'")
    variants = {sp: {(n, dt0[sp]): min(seeds[sp], cap.get(n, seeds[sp])) for n in meshes} for sp in specs}
    if args.dt_check:
        n, dt, k = args.dt_check
        if int(n) not in meshes:
            p.error(f"--dt-check {n}: must be one of --elements")
        for sp in specs:
            variants[sp][(int(n), float(dt))] = int(k)
    for sp in specs:  # (a mesh the model refuses, e.g. fewer elements than its clips' spans: before any run)
        for n in sorted(set(meshes) | set(args.modal_elements)):
            try:
                mesh_model(sources[sp], n, law_length[sp])
            except ModelError as e:
                p.error(f"{sp} at geometry.n_elements = {n}: {e}")
    fingerprints = {
        f"{sp}/{n}": mesh_model(sources[sp], n, law_length[sp]).fingerprint() for sp in specs for n in meshes
    }
    cache = json.loads(path.read_text()) if path.exists() else {}
    cached = cache.get("members", [])

    def matches(m):
        sp, n = m["specimen"], m["n_elements"]
        cond = m.get("conditions", {})
        return (
            sp in specs
            and (n, m["dt_s"]) in variants[sp]
            and cond.get("duration_s") == args.duration
            and cond.get("skip_s") == skips[sp]
            and cond.get("window", "boxcar") == args.window  # (members before the option: boxcar)
            and (args.reuse_other_sources or cond.get("source_hash") == code)
            and cond.get("model_fingerprint") == fingerprints[f"{sp}/{n}"]
        )

    members = [] if args.fresh else [m for m in cached if matches(m)]
    # (--fresh drops the cached members; otherwise those of other conditions stay in the file)
    others = [] if args.fresh else [m for m in cached if not matches(m)]
    # one member per (specimen, mesh, Δt, seed): this source's, else the latest; the others are dropped
    pick = {}
    for m in members:
        key = (m["specimen"], m["n_elements"], m["dt_s"], m["seed"])
        rank = (m["conditions"]["source_hash"] == code, m["conditions"]["date"])
        if key not in pick or rank > pick[key][0]:
            pick[key] = (rank, m)
    members = [m for _, m in pick.values()]
    state = {
        "what": "benchmarks/mesh_refinement.py: natural frequencies and expected Table 3 band levels of "
        f"{OUTPUT} against geometry.n_elements (docs/time_domain.md, 'The mesh')",
        "source_hash": code,
        "modal": cache.get("modal", {}),
        "bands": cache.get("bands", {}),
        "linear": cache.get("linear", {}),
        "clips": cache.get("clips", {}),
        "members": members + others,
    }

    def save():
        write_text(path, json.dumps(state, indent=1) + "\n")

    t_start = time.perf_counter()
    date = datetime.datetime.now().isoformat(timespec="seconds")
    print(f"source_hash: {code}")
    print(f"date: {date}")
    for sp in specs:  # where the clips act on the meshes compared (both parts')
        clips = clip_offsets(sources[sp], sorted(set(args.elements) | set(args.modal_elements)))
        if clips is not None:
            state["clips"][sp] = clips
            print_clips(sp, clips)
    if not args.no_modal and not args.report:
        t0 = time.perf_counter()
        state["modal"] = {**state["modal"], **modal_part(sources, args.modal_elements)}  # (other specimens kept)
        state["modal"]["conditions"] = {
            "date": date,
            "source_hash": code,
            "modal_elements": sorted(set(args.modal_elements)),
            "fmax_hz": FMAX,
            "wall_s": time.perf_counter() - t0,
        }
        save()
    for sp, d in state["modal"].items():
        if sp in specs:
            print_modal({sp: d})
    if args.linear and not args.report:
        os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
        lin_meshes = sorted(set(args.modal_elements))
        jobs = [(sp, sources[sp], n, 1, args.duration, skips[sp]) for sp in specs for n in reversed(lin_meshes)]
        with get_context("spawn").Pool(args.workers, initializer=_warm) as pool:
            got = pool.map(linear_member, jobs, chunksize=1)
        lin = state.setdefault("linear", {})
        for sp in specs:
            L = {n: (lv, w) for s_, n, lv, w in got if s_ == sp}
            ref = np.array(L[lin_meshes[-1]][0])
            lin[sp] = {
                "conditions": {
                    "date": date,
                    "source_hash": code,
                    "seed": 1,
                    "duration_s": args.duration,
                    "skip_s": skips[sp],
                    "dt_s": dt0[sp],
                    "contact": False,
                },
                "levels_N": {str(n): L[n][0] for n in lin_meshes},
                "rel_diff_vs_finest": {str(n): ((np.array(L[n][0]) - ref) / ref).tolist() for n in lin_meshes[:-1]},
                "wall_s": {str(n): L[n][1] for n in lin_meshes},
            }
        save()
    for sp, d in state.get("linear", {}).items():
        if sp in specs:
            for n, r in d["rel_diff_vs_finest"].items():
                print(f"linear_rel_diff_vs_finest_{sp}_{n}: " + " ".join(f"{x:+.4f}" for x in r))
    if args.report:  # the summaries as the runs left them (their own conditions, seeds and sources)
        for sp in specs:
            if sp in state["bands"]:
                print(f"band_conditions_{sp}: {json.dumps(state['bands'][sp]['conditions'])}")
                print_bands(sp, state["bands"][sp])
        return
    if args.no_bands:
        return

    have = {(m["specimen"], m["n_elements"], m["dt_s"], m["seed"]) for m in members}
    jobs = [
        (sp, sources[sp], n, s, args.duration, skips[sp], None if dt == dt0[sp] else dt, law_length[sp], args.window)
        for s in range(1, max(seeds.values()) + 1)
        for sp in sorted(specs, key=lambda x: x != "installed")  # the costlier specimen first
        for (n, dt), k in sorted(variants[sp].items(), key=lambda v: (-v[0][0], v[0][1]))  # costlier first
        if s <= k and (sp, n, dt, s) not in have
    ]
    print(f"members_cached: {len(members)}")
    print(f"members_to_run: {len(jobs)}")
    if jobs:
        walls = {}
        for m in members:
            walls.setdefault((m["specimen"], m["n_elements"], m["dt_s"]), []).append(m["wall_s"])
        keys = [(j[0], j[2], j[6] or dt0[j[0]]) for j in jobs]
        est = [np.median(walls[k]) for k in keys if k in walls]
        if est:
            print(
                f"estimated_wall_min: {sum(est) / args.workers / 60:.1f} (the cached members' median cost, "
                f"{len(est)} of {len(jobs)} members)"
            )
        for v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
            os.environ.setdefault(v, "1")
        t0 = time.perf_counter()
        done = 0
        last = 0.0
        with get_context("spawn").Pool(args.workers, initializer=_warm) as pool:
            for rec in pool.imap_unordered(member, jobs, chunksize=1):
                sp, n = rec["specimen"], rec["n_elements"]
                rec["conditions"] = {
                    "duration_s": args.duration,
                    "skip_s": skips[sp],
                    "window": args.window,
                    "source_hash": code,
                    "model_fingerprint": fingerprints[f"{sp}/{n}"],
                    "date": datetime.datetime.now().isoformat(timespec="seconds"),
                }
                state["members"].append(rec)
                members.append(rec)
                done += 1
                if time.perf_counter() - last > 20 or done == len(jobs):
                    save()
                    last = time.perf_counter()
                    el = time.perf_counter() - t0
                    print(f"progress: {done}/{len(jobs)} members in {el / 60:.1f} min", file=sys.stderr, flush=True)
        print(f"band_members_wall_min: {(time.perf_counter() - t0) / 60:.1f}")
    for sp in specs:
        s = summarise(members, sp, set(variants[sp]), dt0[sp])
        if s is None:
            print(f"band_{sp}: fewer than 2 seeds on every mesh")
            continue
        s["conditions"] = {
            "date": date,
            "source_hash": code,
            "duration_s": args.duration,
            "dt_s": dt0[sp],
            "skip_s": skips[sp],
            "window": args.window,
            "law_length_m": law_length[sp],
            "seeds": {f"{n}@{dt:g}": f"1..{k}" for (n, dt), k in variants[sp].items()},
            "workers": args.workers,
            "member_source_hashes": sorted({m["conditions"]["source_hash"] for m in members if m["specimen"] == sp}),
            "member_dates": [
                min(m["conditions"]["date"] for m in members if m["specimen"] == sp),
                max(m["conditions"]["date"] for m in members if m["specimen"] == sp),
            ],
            "command": " ".join([".venv/bin/python benchmarks/mesh_refinement.py", *sys.argv[1:]]),
        }
        state["bands"][sp] = s
        print_bands(sp, s)
    end = source_hash()
    for sp in specs:
        if sp in state["bands"]:
            state["bands"][sp]["conditions"]["source_hash_at_end"] = end
            state["bands"][sp]["conditions"]["wall_min_this_invocation"] = (time.perf_counter() - t_start) / 60
            state["bands"][sp]["conditions"]["members_wall_s_sum"] = sum(
                m["wall_s"] for m in members if m["specimen"] == sp
            )
    save()
    if end != code:
        print("warning: the package's sources changed during the run (source_hash_at_end)")
    print(f"total_wall_min: {(time.perf_counter() - t_start) / 60:.1f}")


if __name__ == "__main__":
    main()
