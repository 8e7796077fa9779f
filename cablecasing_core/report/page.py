"""The report's page (report.html): what was run, then every figure and table with the runs it
comes from named beside it."""

from __future__ import annotations

import functools
import html
import math
import re

import numpy as np

from ..errors import ModelError, and_joined
from ..model.schema import lookup
from .runs import NET_OUTPUT, OUTPUT

_CSS = """body{font-family:sans-serif;max-width:70em;margin:1em auto;line-height:1.4}
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #bbb;padding:2px 6px;font-size:90%}
th{background:#eee}td.n{text-align:right;font-family:monospace}img{max-width:100%}
.note{color:#444;font-size:92%}.warn{color:#a40;font-weight:bold}"""


def _e(x):
    return html.escape(str(x))


def _table(head, rows, numeric=()):
    h = "".join(f"<th>{_e(c)}</th>" for c in head)
    body = "".join(
        "<tr>"
        + "".join(f'<td class="n">{c}</td>' if i in numeric else f"<td>{c}</td>" for i, c in enumerate(r))
        + "</tr>"
        for r in rows
    )
    return f"<table><tr>{h}</tr>{body}</table>"


def _g(x, digits=4):
    return "nan" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{float(x) + 0.0:.{digits}g}"


def parameter_rows(model, duration):
    """(key, value, unit, description) of every leaf of the model as text (tables and point lists
    summarised; the model's own duration marked as not the report's): the report's parameter table
    and parameters.csv."""
    from ..model.model import dotted

    leaves = {}
    for key, v in dotted(model.data).items():
        if isinstance(v, list) and v and all(isinstance(x, dict) for x in v):  # (a list of tables: the clips)
            for i, item in enumerate(v):
                for k, x in dotted(item).items():
                    leaves[f"{key}[{i}].{k}"] = x
        else:
            leaves[key] = v
    rows = []
    for key, v in leaves.items():
        unit, desc = "-", ""
        try:
            spec = lookup(re.sub(r"\[\d+\]", "[]", key))  # (casing.clip[0].stiffness: the key casing.clip[].stiffness)
            unit, desc = spec.unit or "-", spec.description
        except ModelError:  # (a segment's number, geometry.segments[1].bend.radius: its validator says)
            m = re.fullmatch(r"([\w.]+)\[\d+\]\.(.+)", key)
            parts = getattr(lookup(m[1]).validator, "leaves", {}) if m else {}
            if m and m[2] in parts:
                unit, desc = parts[m[2]][0] or "-", parts[m[2]][1]
        value = f"table of {len(v)} rows" if isinstance(v, list) and v and isinstance(v[0], list) else v
        if key == "scenario.duration":
            value = f"{v} (the report's runs: {duration:g} s)"
        rows.append((key, str(value), unit, desc))
    return rows


def _excitations(model):
    rows = []
    for name, e in model.scenario["excitation"].items():
        units = {k: lookup(f"scenario.excitation.{name}.{k}").unit for k in e if k not in ("target", "kind")}
        params = ", ".join(f"{k} = {e[k]} {u if u not in ('', '1') else ''}".strip() for k, u in units.items())
        rows.append((_e(name), _e(e["target"]), _e(e["kind"]), _e(params)))
    return rows


#: The alt text of each figure of the report (what it shows, for a reader without the image).
ALT = {
    "trfam_xyz.png": "TRFAM in x, y and z with viscous and structural damping against frequency (Fig. 17)",
    "simulation.png": "support forces of the reference records over time",
    "scalograms.png": "wavelet scalograms of casing.B.Fz of the reference records (Figs. 20-21)",
    "routing_contact.png": "the routing in 3D coloured by the contact time (Fig. 22a)",
    "contact_histogram.png": "contact time per cable node beside the curvature along the arc length (Fig. 22b)",
    "psd.png": "power spectral density of casing.B.Fz (and of net.B.Fz, the force into B) of the reference records",
    "apparent_mass.png": "apparent mass estimated from the record against the TRFAM, with coherence",
    "band_levels.png": "band levels of casing.B.Fz as ensemble means over seeds with confidence intervals",
    "study/correlations.png": "correlation of each parameter with the band RMS (Fig. 23)",
    "study/sobol.png": "first-order and total Sobol indices of each parameter per band",
}


def _with_alt(text: str) -> str:
    """Every ``<img src='X'>`` of the page with its alt text (:data:`ALT`; the file's name for another)."""
    return re.sub(r"<img src='([^']+)'>", lambda m: f"<img src='{m[1]}' alt='{_e(ALT.get(m[1], m[1]))}'>", text)


def specimen_name(source: str) -> str:
    """What a model is called in the report: ``<built-in>`` is the built-in specimen (the paper's,
    ``cablecasing_core/model/specimens/default.toml``), ``<built-in installed>`` the built-in
    installed specimen, a file its name."""
    import os

    if source == "<built-in>":
        return "the built-in specimen (the paper's cable in casing, default.toml)"
    if source.startswith("<built-in ") and source.endswith(">"):
        return f"the built-in specimen '{source[10:-1]}'"
    return os.path.basename(source) or source


def _harmonics_note(harmonics):
    """The scalograms' note on the drive's harmonics (Hz), all of those up to the plotted maximum:
    the lines drawn (:data:`.figures.HARMONICS_DRAWN`), and how many there are when more exist."""
    from .figures import HARMONICS_DRAWN

    shown = ", ".join(f"{f:g}" for f in harmonics[:HARMONICS_DRAWN])
    if len(harmonics) <= HARMONICS_DRAWN:
        return f"; dotted red: the drive and its harmonics ({_e(shown)} Hz)"
    return (
        f"; dotted red: the drive and its first harmonics ({_e(shown)}, ... Hz: {HARMONICS_DRAWN} drawn of the "
        f"{len(harmonics)} up to {harmonics[-1]:g} Hz)"
    )


def _code_rows(info):
    """The header's rows that say what made the report, so that a reader can make it again: the
    code, the libraries, the command line."""
    from .provenance import describe_code

    libs = ", ".join(f"{k} {v}" for k, v in (info.get("libraries") or {}).items())
    rows = []
    if info.get("code"):
        rows.append(("code", _e(describe_code(info["code"]))))
    rows.append(("cablecasing version (installed metadata)", _e(info["version"])))
    if libs:
        rows.append(("Python and libraries", _e(libs)))
    if info.get("command"):
        rows.append(("command", f"<code>{_e(info['command'])}</code>"))
    return rows


def skip_note(info):
    """Why the records' first ``info["skip"]`` s are left out (HTML): the fade-in, and with a harmonic
    drive its start transient as the report computed it (``info["start_transients"]``,
    :func:`~cablecasing_core.report.start_transients`: ln 10 / (zeta omega) of the casing at the drive's
    frequency; docs/nvh.md, "The start transient of a harmonic drive"); a warning when a given skip is
    shorter than that (``info["skip_least"]``), or when the transient does not decay."""
    least = info.get("skip_least")
    items = info.get("start_transients") or []
    text = (
        f"Every record's first {info['skip']:g} s are left out of the levels, spectra and tables (shaded or "
        "marked in the figures): the supports' fade-in and the first response"
    )
    if not items:
        return f"<p class='note'>{text}.</p>"
    said, cable = [], []
    for d in items:
        if d["t"] is None:
            continue
        said.append(
            f"ln 10/(ζω) = {d['t']:.2f} s at {d['frequency']:g} Hz, ζ = {d['zeta']:.2g} (casing.alpha = "
            f"{d['alpha']:g} 1/s, casing.beta = {d['beta']:g} s)"
        )
        if d.get("cable_t") is not None:
            cable.append(f"{d['cable_t']:.2f} s at {d['frequency']:g} Hz (ζ = {d['cable_zeta']:.2g})")
    if said:
        text += (
            ", and the start transient of the harmonic drive: the free vibration its start sets off lies in the "
            "levels until it has decayed to a tenth of its amplitude, which takes ln 10/(ζω) at the damping ratio "
            "ζ = α/(2ω) + βω/2 of the casing's Rayleigh damping at the drive's frequency: "
            + "; ".join(_e(x) for x in said)
            + (
                f"; the cable's own, {_e(', '.join(cable))}, is not counted: it reaches {OUTPUT} through the "
                "contact, and the built-in specimen's shows no such tail"
                if cable
                else ""
            )
            + '. On the built-in specimen (docs/nvh.md, "The start transient of a harmonic drive": 16 seeds, '
            "against the same seeds' level at 1-2 s) the window 0.06-0.5 s read octave 3 +47 ± 18 % and octave 2 "
            "−28 ± 13 %, the window 0.25-1 s is within 2 SE in every band but octave 6 (−4.9 ± 4.5 %). The skip "
            "is that time lengthened so that the rest holds whole periods of the drive."
        )
    else:
        text += "."
    if least and info["skip"] < least:
        text += (
            f"</p><p class='warn'>The skip given, {info['skip']:g} s, is shorter than the drive's start transient, "
            f"{least:.2f} s: the levels with the drive hold part of it."
        )
    lasting = [f"{d['frequency']:g} Hz" for d in items if d["t"] is None]
    if lasting:
        text += (
            f"</p><p class='warn'>The casing has no Rayleigh damping (casing.alpha = casing.beta = 0): the start "
            f"transient of the drive at {_e(', '.join(lasting))} does not decay in the casing, and the levels with "
            "the drive hold it whatever the skip."
        )
    return f"<p class='note'>{text}</p>"


def record_line(info):
    """The records' length after the skip, their FFT resolution and the lines in octave 1: what the
    band levels of octaves 1-2 rest on."""
    from ..nvh.bands import LINES_PER_BAND

    few = info["lines_oct1"] < LINES_PER_BAND
    return (
        f"{info['record_after_skip']:.4g} s after the skip: FFT lines every df = {info['df']:.3g} Hz, "
        f"{info['lines_oct1']:.3g} lines in octave 1 (11-22 Hz; the package warns below {LINES_PER_BAND})"
        + (" <span class='warn'>too few: octave 1 holds much of what lies beside it</span>" if few else "")
    )


def glance_parts(variants, info):
    """The page's first lines (HTML): for each variant with an ensemble, its strongest Table 3 band of
    :data:`OUTPUT` (the ensemble's mean, N, and its 95 % interval, as the band table below gives them),
    and what the levels are: ensemble means over seeds after the skip, at the model's mesh and time
    step (each with its section below)."""
    items = []
    for v in variants:
        e = v.ensemble
        if e is None or not np.any(e.mean > 0):
            continue
        b = int(np.nanargmax(e.mean))
        lo, hi = (x[b] for x in e.ci(0.95))
        items.append(
            f"<li>{_e(v.title)}: {OUTPUT} is strongest in {_e(e.labels[b])} ({e.lower[b]:.3g}-{e.upper[b]:.3g} Hz), "
            f"{_g(e.mean[b], 4)} N (95 % interval {_g(lo, 3)} to {_g(hi, 3)} N, {e.n} seeds)</li>"
        )
    if not items:
        return []
    return [
        "<h2>At a glance</h2><ul>",
        *items,
        f"<li>The levels are means over excitation seeds of records after {info['skip']:g} s: with contact one "
        'record is one draw of a chaotic response ("Band levels" below). They hold for this model\'s mesh and '
        "time step, whose errors the intervals do not cover (the band table's notes say how large).</li></ul>",
    ]


def render(model, info, modes, freq, variants, rms, am, study, fmu, harmonics, out, contact=None):
    """The HTML text of the report (see :func:`cablecasing_core.report.write_report`)."""
    seeds = info["seeds"]
    parts = [
        f"<!doctype html><html lang='en'><head><meta charset='utf-8'><title>cablecasing report: "
        f"{_e(specimen_name(model.source))}</title><style>{_CSS}</style></head><body>",
        f"<h1>Cable in casing: report of {_e(specimen_name(model.source))}</h1>",
        _table(
            ["what", "value"],
            [
                r
                for r in [
                    ("model", f"{_e(model.source)} (fingerprint {info['fingerprint']})"),
                    *_code_rows(info),
                    ("date", _e(info["date"])),
                    (
                        "every run",
                        f"{info['duration']:g} s at dt = {info['dt']:g} s; levels and spectra after {info['skip']:g} s "
                        "(below); band levels through Hann's window",
                    ),
                    ("record for the levels", record_line(info)) if "df" in info else None,
                    (
                        "excitation seeds",
                        f"{seeds[0]}..{seeds[-1]} ({len(seeds)}; the reference records: seed {seeds[0]})",
                    ),
                    ("output", f"{OUTPUT} (N): force the casing exerts on its support B in z"),
                ]
                if r
            ],
        ),
        *glance_parts(variants, info),
        skip_note(info),
        "<h2>Scenario</h2>",
        _table(["excitation", "target", "kind", "parameters"], _excitations(model)),
        "<h2>The runs</h2><p>Every figure and table below comes from these runs (also in runs.json):</p>",
    ]
    rows = []
    for v in variants:
        ens = v.ensemble
        rows.append(
            (
                _e(v.title),
                _e(", ".join(f"{k} = {x}" for k, x in v.seed_overrides.items()) or "-"),
                f"<a href='{v.record.relative_to(out).as_posix()}'>{_e(v.record.relative_to(out).as_posix())}</a>",
                (
                    f"<a href='bands_{v.key}.csv'>bands_{v.key}.csv</a> ({ens.n} seeds)"
                    + (
                        f", <a href='bands_net_B_{v.key}.csv'>bands_net_B_{v.key}.csv</a> ({NET_OUTPUT})"
                        if v.net_ensemble is not None
                        else ""
                    )
                    if ens is not None
                    else "-"
                ),
                _g(v.member_check, 3),
            )
        )
    parts.append(
        _table(
            [
                "variant",
                "reference record's seed",
                "reference record",
                "ensemble",
                "first member vs record (max rel. diff of band levels)",
            ],
            rows,
            numeric=(4,),
        )
    )
    parts.append(
        "<p class='note'>With contact the response is chaotic (docs/time_domain.md): a single record is one draw "
        "of a random process, its band levels scatter from seed to seed, so levels are given as ensemble means with "
        "confidence intervals, and the reference records illustrate.</p>"
    )
    parts += [
        "<h2>Model parameters</h2>",
        _table(
            ["key", "value", "unit", "description"],
            [tuple(map(_e, r)) for r in parameter_rows(model, info["duration"])],
        ),
    ]
    n = max(len(f) for f in modes.values())
    mrows = [[str(i + 1)] + [_g(f[i], 6) if i < len(f) else "" for f in modes.values()] for i in range(n)]
    parts += [
        "<h2>Natural frequencies (Hz)</h2>",
        _table(["mode"] + [f"{b} (Hz)" for b in modes], mrows, numeric=tuple(range(1, len(modes) + 1))),
        "<h2>TRFAM (Eq. 12), structural and viscous damping (Fig. 17)</h2>",
        "<img src='trfam_xyz.png'><p class='note'>Frequency domain; files trfam_x.csv, trfam_y.csv, trfam_z.csv "
        "and trfam.uff (UFF 58, six FRFs, kg). The model's, with its constant moduli and loss factors: the "
        "paper's Fig. 17 uses frequency-dependent ones (its Figs. 9 and 16) and measured data, neither shown "
        "here, so the curves are Fig. 17's kind of plot, not a check against it.</p>",
        "<h2>Support forces of the reference records</h2><img src='simulation.png'>",
        *_rms_parts(rms, info),
        *energy_parts(variants, model),
        "<h2>Wavelet transform of the support force "
        + ("without and with the cable drive" if len(variants) == 2 else f"of {_e(variants[0].title)}")
        + " (Figs. 20-21)</h2>",
        "<img src='scalograms.png'>",
        "<p class='note'>Reference records (seed "
        + f"{seeds[0]}); Morlet wavelet, gamma = 12 (identification.wavelet); dashed: natural frequencies of "
        "the casing"
        + (_harmonics_note(harmonics) if len(harmonics) else "")
        + f"; grey line: the skip ({info['skip']:g} s); grey dash-dot: the cone of influence, within "
        "&radic;2 gamma / (2&pi; f) of the record's ends, where the transform feels the edges.</p>",
        "<h2>Contact: routing and contact time beside the curvature (Fig. 22)</h2>",
        "<img src='routing_contact.png'><img src='contact_histogram.png'>" + contact_note(contact, info)
        if {"casing", "cable"} <= set(model.bodies)
        else "<p>The model has no cable in a casing: no contact.</p>",
    ]
    parts += _bands(variants, model, info)
    parts += net_parts(variants, info)
    parts += ["<h2>Spectra</h2><img src='psd.png'>", psd_note(variants, info)]
    if am is not None:
        parts += ["<img src='apparent_mass.png'>", f"<p class='note'>{apparent_mass_note(am, variants[0].title)}</p>"]
    parts += _study(study, variants)
    if fmu is not None:
        parts += fmu_parts(fmu)
    parts.append("</body></html>")
    return _with_alt("\n".join(parts))


def contact_note(contact, info):
    """Under Fig. 22: what the contact time counts (the whole run, the skip included) and where the
    most contact is against where the curvature is highest."""
    if not contact:
        return ""
    text = (
        f"<p class='note'>Contact time per run of {contact['duration']:g} s, counted from t = 0 over the whole "
        f"run: the first {info['skip']:g} s, which the levels leave out, included ({_e(contact['what'])})."
    )
    if contact["any"]:
        text += (
            f" The most contact is at s = {contact['s_most']:.3g} m (curvature {contact['kappa_most']:.3g} 1/m); "
            f"the curvature is highest at s = {contact['s_curviest']:.3g} m ({contact['kappa_max']:.3g} 1/m)"
            + (
                ": the paper puts the highest contact area at the highest curvature, this run does not."
                if abs(contact["s_most"] - contact["s_curviest"]) > 0.05
                else ", as the paper finds."
            )
        )
    return text + "</p>"


def psd_note(variants, info):
    """Under psd.png: the window, the seed, the range and a curve drawn once for two names."""
    flat = _constant_outputs(variants, info["skip"])
    same = [
        v.title
        for v in variants
        if v.net_bands is not None and _net_is_casing(v) and f"{OUTPUT} ({v.title})" not in flat
    ]
    text = (
        f"Welch's estimate, Hann's window, of the reference records (seed {info['seeds'][0]}) after "
        f"{info['skip']:g} s, over Table 3's bands 11-5680 Hz from 2 df (the legend gives df), where Welch's "
        "lines measure."
    )
    if same:
        text += (
            f" In the variant {and_joined([_e(t) for t in same])} cable.B.Fz is 0 N, so {NET_OUTPUT} is {OUTPUT}: one "
            "curve, named as both."
        )
    if flat:
        text += (
            f" {and_joined([_e(n) for n in flat])} {'is' if len(flat) == 1 else 'are'} constant after the skip (no "
            "power at any frequency: the model's excitation does not reach it), so the log axis has nothing of "
            f"{'it' if len(flat) == 1 else 'them'} to draw."
        )
    return f"<p class='note'>{text}</p>"


def _constant_outputs(variants, skip):
    """The series of psd.png (``OUTPUT`` and, with a cable, ``NET_OUTPUT`` of each reference record,
    '<output> (<variant title>)') that are constant after ``skip`` s (:func:`.figures.constant`)."""
    from ..records import after_skip
    from .figures import constant

    flat = []
    for v in variants:
        rec = v.result.records()
        keep = after_skip(rec.time, skip, rec.time[0])
        for name in (OUTPUT, NET_OUTPUT) if v.net_bands is not None else (OUTPUT,):
            if constant(rec.column(name)[keep]):
                flat.append(f"{name} ({v.title})")
    return flat


def _net_is_casing(v):
    """Whether a variant's reference record has net.B.Fz equal to casing.B.Fz in every band (cable.B.Fz 0)."""
    b = v.net_bands or {}
    return OUTPUT in b and NET_OUTPUT in b and np.array_equal(b[OUTPUT].rms, b[NET_OUTPUT].rms)


def fmu_parts(fmu):
    """The FMU's section: its check as given, the output file linked, and what it is compared with."""
    rows = []
    for k, v in fmu.items():
        cell = f"<a href='{_e(v)}'>{_e(v)}</a>" if k == "FMU outputs" else _e(v)
        rows.append((_e(k), cell))
    return [
        "<h2>The FMU</h2>",
        _table(["what", "value"], rows),
        "<p class='note'>The FMU is checked against the core driven by the same sampled record (the scenario's "
        "support motion sampled every communication step and reconstructed over each step, as a host gives it), "
        "not against the report's records: the core's own runs take the excitation at every time step, and with "
        "contact the response is chaotic, so fmu_outputs.csv need not retrace the reference record with the drive "
        "beyond its first hundredths of a second: it is another draw of the same process.</p>",
    ]


def _band_total(v):
    """sqrt of the sum of the squared Table 3 band levels (N) of the reference record's casing.B.Fz
    (its bands: ``net_bands`` of a model with a cable, else the ensemble's first member, the same
    run), or None."""
    if v.net_bands is not None and OUTPUT in v.net_bands:
        b = v.net_bands[OUTPUT].rms
    elif v.ensemble is not None:
        b = v.ensemble.levels[0]
    else:
        return None
    return float(np.sqrt(np.sum(np.square(b))))


def _rms_parts(rms, info):
    """The RMS table of the reference records' support forces: mean, RMS total (with the mean) and
    RMS dynamic (without it), N, one row per variant and force; and, beside casing.B.Fz's RMS
    dynamic, the root of the sum of its squared Table 3 band levels, with when the two agree."""
    from .figures import RMS_COLUMNS

    rows = [(_e(v.title), _e(v.record.name), _e(n), *(_g(x, 6) for x in t)) for v, d in rms for n, t in d.items()]
    sums = []
    for v, d in rms:
        total = _band_total(v)
        if total is not None and OUTPUT in d:
            dyn = d[OUTPUT][2]
            sums.append(f"{_e(v.title)}: {_g(total, 4)} N against {_g(dyn, 4)} N ({100 * (total / dyn - 1):+.1f} %)")
    compare = (
        f" The Table 3 band levels of {OUTPUT}, root of the sum of their squares: {'; '.join(sums)}." if sums else ""
    )
    return [
        _table(["variant", "record", "output"] + [f"{c} (N)" for c in RMS_COLUMNS], rows, numeric=(3, 4, 5)),
        f"<p class='note'>After {info['skip']:g} s, from the saved records (rms.csv at full precision). RMS total "
        "includes the mean, the force's static part; "
        "RMS dynamic is the RMS with the mean removed (the standard deviation), what vibrates, as in "
        "<code>simulate</code>'s table: the band levels and the PSD remove the mean too, but they weight the "
        "record through Hann's window, most in its middle. So the band levels' root sum of squares equals the RMS "
        "dynamic only for a record whose level is steady along it and whose power lies within Table 3's "
        f"11-5680 Hz; a level that changes along the record (a transient, a burst of contact) makes them differ, "
        f"and the band levels are then the window's weighted average.{compare}</p>",
    ]


def energy_parts(variants, model):
    """The energy ledger (J) of each reference record since t = 0: the supports'
    work, what Rayleigh damping and the contacts dissipated, the normal force's own work
    (``contact_normal_dissipation``: negative where the normal-plane contact on a mesh of a curved
    casing makes energy, a model-quality indicator) and the balance's residual."""
    vs = [v for v in variants if getattr(v.result, "energies", None)]
    if not vs:
        return []
    keys = [
        ("start_energy", "stored at t = 0 (the static state)"),
        ("support_work", "work of the supports"),
        ("load_work", "work of the constant loads (gravity, the tension's pre-stretch)"),
        ("rayleigh_dissipation", "dissipated by Rayleigh damping"),
        ("contact_dissipation", "dissipated in the contacts"),
        ("contact_damping_dissipation", "of which contact damping"),
        ("friction_dissipation", "of which friction"),
        ("contact_normal_dissipation", "of which the normal force's own work"),
        ("mount_dissipation", "dissipated in the mounts' dampers"),
        ("stored_now", "stored at the end (kinetic, strain and contact energy)"),
        ("residual", "residual of the balance"),
    ]
    # (the rows that are zero in every record, the specimen's at rest without loads or mounts, left out)
    optional = {"start_energy", "load_work", "mount_dissipation"}
    keys = [(k, lab) for k, lab in keys if k not in optional or any(v.result.energies.get(k) for v in vs)]
    rows = []
    for key, label in keys:
        row = [_e(label)]
        for v in vs:
            e = v.result.energies
            if key == "stored_now":
                x = float(e["kinetic"] + e["strain"] + e["contact_potential"])
            else:
                x = float(e.get(key, float("nan")))
            w = float(e.get("support_work", float("nan")))
            share = f" ({100 * x / w + 0.0:+.2f} % of the supports' work)" if key != "support_work" and w else ""
            row.append(f"{_g(x, 4)}{share}")
        rows.append(row)
    docs = (
        " docs/time_domain.md (\"The mesh\", the normal force's work) gives −2.38 % of the supports' work at "
        "35 elements on the built-in specimen's 1 s records with the drive, −0.07 % at 140."
        if builtin_specimen(model) == "<built-in>"
        else ""
    )
    return [
        "<h3>Energy ledger of the reference records (J, since t = 0)</h3>",
        _table(["quantity"] + [_e(v.title) for v in vs], rows, numeric=tuple(range(1, len(vs) + 1))),
        "<p class='note'>From the saved records (their <code>energies</code>; <code>cablecasing simulate</code> "
        "prints the same ledger), over the whole run. The normal force's own work is what the contacts "
        "dissipate beyond their damping and friction: zero for a conservative contact law, negative where the "
        "normal-plane contact on the mesh of a curved casing makes energy, falling as the mesh is refined; the "
        f"residual is the ledger's error (stored now − stored at t = 0 − supplied + dissipated).{docs}</p>",
    ]


def _median(medians, lines, key, bare=False):
    """The coherence's median over the range ``key`` ("10-100", Hz) as the page says it: "median 0.54
    over 10-100 Hz (15 lines)", or, over fewer than ``figures.MIN_MEDIAN_LINES`` lines, that it has
    no meaningful median there and how many lines it holds; ``bare``: the median alone ("0.50"), or
    "no figure" (the range's line count is said beside the measured median)."""
    from .figures import MIN_MEDIAN_LINES

    value, count = medians.get(key, float("nan")), lines.get(key)
    few = count is not None and count < MIN_MEDIAN_LINES
    if bare:
        return "no figure" if few else f"{value:.2f}"
    if few:
        return (
            f"no meaningful median over {key} Hz, which holds {count} line{'s' if count != 1 else ''} (a median "
            f"needs at least {MIN_MEDIAN_LINES})"
        )
    return f"median {value:.2f} over {key} Hz" + (f" ({count} lines)" if count is not None else "")


def apparent_mass_note(am, title):
    """The note under apparent_mass.png (HTML): what the estimate is compared with and why its
    coherence drops, from :func:`.figures.apparent_mass_figure`'s summary ``am``."""
    n, ne, df = am["n_averages"], am["n_effective"], am["df"]
    m, x = am["median_coherence"], am["expected_coherence"]
    head = (
        f"H1 from {_e(am['input'])} to {OUTPUT} of the reference record {_e(title)} ({n} averages of {df:.3g} Hz "
        "lines, Hann's window), in the TRFAM's sign convention, against what it estimates: the TRFAM (viscous) "
        "averaged over the window's spectral window (dashed; Bendat &amp; Piersol 11.4, as docs/nvh.md, "
        '"Against the TRFAM", compares them), with the TRFAM as computed for reference (dotted). '
    )
    k = am.get("median_lines", {})
    coh = (
        f"The coherence has {_median(m, k, '10-100')} and {_median(m, k, '10-1000')}; the window's smoothing "
        f"alone leaves {_median(x, k, '10-100', bare=True)} and {_median(x, k, '10-1000', bare=True)} of the "
        f"noise-free TRFAM (dashed, lower panel; with {n} averages, worth {ne:.2g} independent ones as they overlap, "
        f"a low coherence reads higher, by about (1 - &gamma;&sup2;)&sup2;/{ne:.2g}). "
    )
    narrow = am.get("narrow_modes") or []
    why = ""
    if narrow:
        b = [w for _, w in narrow]
        why = (
            f"{len(narrow)} of the casing's modes between 10 and 1000 Hz ({', '.join(f'{f:.1f}' for f, _ in narrow)} "
            f"Hz) are narrower than the lines (half-power bandwidths {min(b):.2g}-{max(b):.2g} Hz, viscous "
            f"damping), and Hann's window spreads each line over &plusmn;{2 * df:.3g} Hz, across which the TRFAM "
            "rises and falls by a factor of several: H1 then reads the window's average, below the TRFAM at its "
            "peaks and above it in its notches, and the coherence drops by as much as the TRFAM varies within "
            "the window. "
        )
    c = am.get("coarser")
    more = ""
    if c:
        cm = c["median_coherence"]
        worse = cm["10-1000"] < m["10-1000"]
        more = (
            ("More averages at coarser lines make it worse, not better: at " if worse else "At ")
            + f"{c['df']:.3g} Hz lines ({c['n_averages']} averages) the coherence has "
            f"{_median(cm, c.get('median_lines', {}), '10-100')} and "
            f"{_median(cm, c.get('median_lines', {}), '10-1000')}. "
        )
        if narrow:
            half = min(b) / 2
            more += (
                f"Only finer lines remove the bias: lines of half the narrowest bandwidth ({half:.2g} Hz) need "
                f"segments of {1 / half:.2g} s, a record of at least {2 / half:.2g} s after the skip for 3 averages. "
            )
    others = am.get("other_inputs") or []
    also = (
        f"The casing is driven at {and_joined([_e(t) for t in others])} too, which the input does not explain: that "
        "lowers the coherence besides the window's bias. "
        if others
        else ""
    )
    if am.get("contact"):
        return (
            head + coh + "The record has contact, so the transmission is not linear: impacts put force into the "
            "casing that the support's motion does not explain, and lower the coherence below what the window "
            "leaves. " + also + why + "The band of &plusmn;2 random errors covers the random error only."
        )
    bands = am.get("input_bands") or []
    spans = and_joined([f"{lo:g}-{hi:g}" for lo, hi in bands])
    flat = f"the input is the scenario's random excitation, flat over {spans} Hz"
    if others:
        cause = (
            "The record has no contact, so the system is linear. "
            + also
            + (f"{flat[0].upper()}{flat[1:]}. " if bands else "")
        )
    else:
        covered = any(lo <= 10.0 and hi >= 1000.0 for lo, hi in bands)
        cause = (
            "The record has no contact, so the system is linear and the record noise-free: the coherence drops "
            "are the resolution's bias, not random error (which cannot lower the coherence of a noise-free "
            "linear record)" + (f" nor a lack of input: {flat}. " if covered else f"; {flat}. " if bands else ". ")
        )
    return (
        head
        + cause
        + why
        + coh
        + more
        + "The band of &plusmn;2 random errors covers the random error, not this bias: compare H1 with the dashed "
        "curve, not with the dotted one."
    )


#: The model's numerical accuracy, quoted from the docs for the report's band levels:
#: {built-in source: [(the docs' section, the sentence quoting it)]}; figures for the specimens at
#: their own mesh (35 elements) and step (1e-5 s), on 1 s records (tests/cli/test_report_bands.py
#: finds each figure in its section).
ACCURACY_QUOTES = {
    "<built-in>": [
        (
            "The mesh",
            "the mesh, with contact (the specimen's scenario, with the cable drive): against 140 elements (within "
            "2 SE of 280 in every band) every band's expected level at 35 elements differs by more than 2 SE: "
            "octave 2 (22–44 Hz) +50.9 ± 9.2 %, octave 9 +21.3 %, octave 5 −11.0 %, the others −5.9 to +6.8 % "
            "(128 seeds, through Hann's window); geometry.n_elements = 140 gives levels converged in the mesh, "
            "at about 4 × the cost",
        ),
        (
            "The mesh",
            "the mesh, without contact (as in the variant without the cable drive): at 35 elements the levels "
            "are within 1.5 % of those at 280 elements up to 355 Hz and −4.1 to −20.4 % off in octaves 6-9 (seed "
            "1, contact off, through the rectangular window)",
        ),
        (
            "The time step on 456 seeds",
            "the time step: at 1e-5 s every band's expected level is within 1.6 % of that at 2.5e-6 s, "
            "bounded below 4 % at two standard errors (456 seeds, through Hann's window)",
        ),
    ],
    "<built-in installed>": [
        (
            "The mesh",
            "the mesh: against 140 elements octave 3 (the drive's line) is within 1.0 % and octaves 1-2 within "
            "2.4 %, but octaves 4, 5 and 7-9 are off by −7.5 to +27.0 % (16 seeds), and octaves 7-9 have no "
            "mesh-converged value up to 280 elements",
        ),
        (
            "A friction law whose limit exists",
            "the time step: 1e-5 s is within 1.0 % of the converged levels in every band of every seed measured",
        ),
    ],
}
#: The mesh and step at which :data:`ACCURACY_QUOTES` were measured (geometry.n_elements, dt in s).
ACCURACY_SETTINGS = (35, 1e-5)


#: The mesh's bias per Table 3 band of the built-in specimens at :data:`ACCURACY_SETTINGS`, quoted
#: from docs/time_domain.md, "The mesh" (tests/cli/test_report_bands.py finds each in its table):
#: {specimen: {variant key: (what it is measured against, on what, [9 figures in %, as printed])}};
#: the records it was measured on are :data:`MESH_BIAS_RECORDS`'.
MESH_BIAS = {
    "<built-in>": {
        "drive": (
            "35 against 140 elements, the specimen's scenario with contact, 128 seeds, Hann's window, 1 s records "
            "after 0.06 s, ± 2 SE",
            ["+6.8 ± 5.3", "+50.9 ± 9.2", "−5.1 ± 2.9", "−5.9 ± 2.2", "−11.0 ± 2.6", "−5.2 ± 1.9", "+6.5 ± 3.2",
             "+6.5 ± 5.0", "+21.3 ± 5.7"],
        ),
        "nodrive": (
            "35 against 280 elements, without contact (as this variant, which has none), seed 1, the rectangular "
            "window, 1 s records after 0.05 s",
            ["+1.5", "+0.3", "−1.5", "−0.6", "−0.6", "−4.1", "−7.4", "−7.0", "−20.4"],
        ),
    },
    "<built-in installed>": {
        "drive": (
            "35 against 140 elements, the specimen's scenario, 16 seeds, Hann's window, 1 s records after 0.06 s "
            "(± 2 SE in octaves 1-2; octaves 3-9, the drive's response, within 0.2)",
            ["+2.4 ± 1.1", "+0.9 ± 2.2", "+1.0", "+10.6", "−7.5", "−0.7", "+16.4", "+7.8", "+27.0"],
        ),
    },
}  # fmt: skip


#: The records :data:`MESH_BIAS` was measured on: {specimen: {variant key: (duration, skip) in s}}
#: (docs/time_domain.md, "The mesh": 1 s runs, band levels after the CLI's skip then, 0.05 s of the
#: default specimen's linear runs, 0.06 s with the drive; benchmarks/mesh_refinement.py --skip).
MESH_BIAS_RECORDS = {
    "<built-in>": {"drive": (1.0, 0.06), "nodrive": (1.0, 0.05)},
    "<built-in installed>": {"drive": (1.0, 0.06)},
}


def builtin_specimen(model):
    """The built-in specimen ``model`` is (``"<built-in>"``, ``"<built-in installed>"``: the keys of
    :data:`MESH_BIAS` and :data:`ACCURACY_QUOTES`), by its content (``Model.fingerprint``, so
    ``cablecasing_core/model/specimens/default.toml`` loaded as a file is the built-in specimen), or
    None for another model."""
    return _specimens().get(model.fingerprint())


@functools.cache
def _specimens():
    """{fingerprint: source} of the built-in specimens (their files do not change while the package runs)."""
    from ..model import load_model, specimen_names

    return {m.fingerprint(): m.source for m in map(load_model, specimen_names())}


def _known_bias(model, info):
    """{variant key: (what, [figures as printed])} of :data:`MESH_BIAS` for a built-in specimen whose
    report's records are those the figures were measured on (:data:`MESH_BIAS_RECORDS`: ``info``'s
    duration and skip, to within half a step), else {} (another model's bias, or another record's, is
    not known)."""
    spec = builtin_specimen(model)
    known = {}
    for key, entry in MESH_BIAS.get(spec, {}).items():
        duration, skip = MESH_BIAS_RECORDS[spec][key]
        half = info["dt"] / 2
        if abs(info["duration"] - duration) < half and abs(info["skip"] - skip) < half:
            known[key] = entry
    return known


def _unknown_bias(model, info):
    """The note (HTML) on the mesh bias :data:`MESH_BIAS` holds for this specimen's variants but the
    report's records are not those it was measured on (:func:`_known_bias`), or ''."""
    spec = builtin_specimen(model)
    known = _known_bias(model, info)
    left = {k: r for k, r in MESH_BIAS_RECORDS.get(spec, {}).items() if k not in known}
    if not left:
        return ""
    on = "; ".join(
        f"{'with' if k == 'drive' else 'without'} the cable drive: {d:g} s runs after {t:g} s"
        for k, (d, t) in left.items()
    )
    return (
        "<p class='note'><b>Mesh bias</b> (docs/time_domain.md, \"The mesh\") is not shown beside these levels: it "
        f"was measured on other records of this specimen ({on}), these are {info['duration']:g} s runs after "
        f"{info['skip']:g} s, whose levels hold another part of the run. <code>--duration</code> and "
        "<code>--skip</code> of those records give it; the note below quotes its largest figures.</p>"
    )


def _percent(text):
    """The figure of a quoted bias ('−11.0 ± 2.6' -> -11.0)."""
    return float(text.split("±")[0].replace("−", "-").strip())


def mesh_bias(model, info):
    """{variant key: [bias in %, ...]} of :data:`MESH_BIAS` for a built-in specimen on the records the
    figures were measured on (:func:`_known_bias`), else {} (another model's bias is not known)."""
    return {k: [_percent(x) for x in figs] for k, (_, figs) in _known_bias(model, info).items()}


def accuracy_note(model, info):
    """What the band levels' intervals cover and what they do not (HTML): the seed scatter of this
    model at its mesh and step, not the model's numerical error, quoted from docs/time_domain.md
    (:data:`ACCURACY_QUOTES`) for a built-in specimen at the mesh and step they were measured at,
    and named with where it is measured for another model."""
    n_el, dt = model.data["geometry"]["n_elements"], info["dt"]
    head = (
        f"<b>What the intervals cover.</b> The 95 % intervals and the CVs are the seed-to-seed scatter of this "
        f"model's records, at its mesh (geometry.n_elements = {n_el}) and time step (dt = {dt:g} s): how well "
        f"{len(info['seeds'])} seeds pin down this model's expected level. They do not cover the model's "
        "numerical error, its distance from the same model converged in the mesh and the step"
    )
    quotes = ACCURACY_QUOTES.get(builtin_specimen(model))
    if quotes and (n_el, dt) == ACCURACY_SETTINGS:
        items = "".join(f'<li>{_e(q)} (docs/time_domain.md, "{_e(sec)}").</li>' for sec, q in quotes)
        return f"{head}, measured on this specimen at these settings on 1 s records:<ul>{items}</ul>"
    return (
        f'{head}: docs/time_domain.md measures it on the built-in specimens only ("The mesh": at 35 '
        'elements octave 2 of the built-in specimen +50.9 ± 9.2 % against 140 elements; "The time step on 456 '
        'seeds": 1e-5 s within 1.6 % of 2.5e-6 s), not on this model or at these settings; <code>cablecasing '
        "ensemble --set geometry.n_elements=N --against ...</code> (docs/studies.md) measures this model's."
    )


def _bands(variants, model, info):
    from ..nvh.bands import NO_RESPONSE_DB, no_response

    ens = [v for v in variants if v.ensemble is not None]
    if not ens:
        return ["<h2>Band levels</h2><p>No random excitation: no ensemble over seeds.</p>"]
    e0 = ens[0].ensemble
    n_el = model.data["geometry"]["n_elements"]
    known = _known_bias(model, info)
    head = ["band", "Hz"]
    for v in ens:
        head += [f"{v.title}: mean (N)", "95 % CI (N)", "mean (dB re 1 N)", "95 % CI (dB)", "CV of one record"]
        if v.key in known:
            head.append(f"{v.title}: mesh bias of {n_el} elements (%)")
    off = {v.key: no_response(v.ensemble.mean) for v in ens}
    rows = []
    for b, lab in enumerate(e0.labels):
        row = [lab, f"{e0.lower[b]:g}-{e0.upper[b]:g}"]
        for v in ens:
            e = v.ensemble
            bias = known.get(v.key, (None, None))[1]
            if off[v.key][b]:
                row += ["–", "–", "–", "–", "no response"] + (["–"] if bias else [])
                continue
            lo, hi = (x[b] for x in e.ci(0.95))  # (cut at 0 below by Ensemble.ci: a level is not negative)
            m = e.mean[b]
            row += [
                _g(m, 4),
                f"{_g(lo, 3)} to {_g(hi, 3)}",
                f"{_db(m)}",
                f"{_db(lo)} to {_db(hi)}",
                f"{100 * e.cv[b]:.0f} %",
            ]
            if bias:
                half = max(hi - m, m - lo) / m if m > 0 else math.inf
                beyond = abs(_percent(bias[b])) / 100.0 > half  # (a bias larger than the interval's half-width)
                row.append(f"<span class='warn'>{_e(bias[b])}</span>" if beyond else _e(bias[b]))
        rows.append(row)
    parts = [
        f"<h2>Band levels of {OUTPUT} (Table 3): ensemble means over excitation seeds</h2>",
        "<img src='band_levels.png'>",
        _table(head, rows, numeric=tuple(range(2, len(head)))),
        "<p class='note'>Means over the seeds of the ensembles (bands_&lt;variant&gt;.csv: one row per seed); "
        "Student-t 95 % intervals (cut at 0); CV: the seed-to-seed scatter of a single record's level.</p>",
    ]
    parts.append(_unknown_bias(model, info))
    if known:
        parts.append(
            "<p class='note'><b>Mesh bias</b> (docs/time_domain.md, \"The mesh\"): how far this model's expected "
            f"level at its {n_el} elements lies from the level converged in the mesh, measured on this specimen "
            + "; ".join(
                f"{_e(next(v.title for v in ens if v.key == k))}: {_e(what)}"
                for k, (what, _) in known.items()
                if any(v.key == k for v in ens)
            )
            + ". <span class='warn'>Bold</span>: a bias larger than the interval's half-width, so the interval "
            "does not hold the converged level; a model file with geometry.n_elements = 140 (about 4 × the cost) "
            "gives levels converged in the mesh.</p>"
        )
    for v in ens:
        gone = [lab for lab, o in zip(e0.labels, off[v.key]) if o]
        if gone:
            top = 20 * np.log10(np.max(v.ensemble.mean))
            parts.append(
                f"<p class='note'>–: no response. In the variant {_e(v.title)}, {and_joined([_e(g) for g in gone])} "
                f"{'lies' if len(gone) == 1 else 'lie'} more than {NO_RESPONSE_DB:g} dB below its strongest band "
                f"({top:.1f} dB re 1 N): below the level that Hann's window leaks from content 32 lines away, so "
                "the window, not a response, sets such a level, and it is neither drawn nor given an interval "
                f"(its values are in bands_{v.key}.csv)."
                + (
                    " Its excitation ends at "
                    + " and ".join(f"{hi:g} Hz" for hi in sorted({e["band"][1] for e in _random(v.model)}))
                    + " and it has no contact."
                    if _random(v.model)
                    and len(_random(v.model)) == len(v.model.scenario["excitation"])
                    and not _touched(v)
                    else ""
                )
                + "</p>"
            )
    parts.append(f"<div class='note'>{accuracy_note(model, info)}</div>")
    return parts


#: What net.B.Fz is, the start of the note under either table of it (:func:`net_parts`).
_NET_SUM_NOTE = (
    "<p class='note'>At end B the casing's abutment and the cable's end attach to one part, the transmission, "
    f'so what it receives is their sum, {NET_OUTPUT} = {OUTPUT} + cable.B.Fz (docs/nvh.md, "Net forces and '
    'paths"; <code>cablecasing bands RECORD --column net.B.Fz</code> gives it from any record). Its band '
    "levels are those of the summed samples, not the sum of the two bodies' levels: where the cable and the "
    "casing carry one loop (the cable's drive pulls the part the casing pushes), their forces cancel in part. "
)


def net_parts(variants, info):
    """The band levels of the force into B, net.B.Fz = casing.B.Fz + cable.B.Fz: the ensemble means
    with their intervals and net.B.Fz against casing.B.Fz paired member by member
    (``Variant.net_ensemble``, of the same runs as ``Variant.ensemble``; bands_net_B_<variant>.csv),
    or, when no variant has an ensemble, the reference records' levels (:func:`_net_single_parts`).
    HTML, or nothing for a model without a cable."""
    from ..nvh.bands import NO_RESPONSE_DB, no_response
    from ..studies.ensemble import paired_difference

    withnet = [v for v in variants if v.net_ensemble is not None]
    if not withnet:
        return _net_single_parts(variants, info)
    # (a variant whose cable.B.Fz is 0, no drive at B, has net.B.Fz = casing.B.Fz in every member: said, not shown)
    vs = [v for v in withnet if not np.array_equal(v.net_ensemble.levels, v.ensemble.levels)]
    same = [_e(v.title) for v in withnet if v not in vs]
    title = f"<h2>The force into the transmission at B: {NET_OUTPUT} beside {OUTPUT} (Table 3, ensemble means)</h2>"
    same_note = (
        f" In the variant {and_joined(same)} cable.B.Fz is 0 N in every member, so {NET_OUTPUT} is {OUTPUT} (above)."
        if same
        else ""
    )
    if not vs:
        return [title, f"<p class='note'>{same_note.strip()}</p>"]
    e0 = vs[0].net_ensemble
    head = ["band", "Hz"]
    for v in vs:
        head += [f"{v.title}: {NET_OUTPUT} mean (N)", "95 % CI (N)", f"re {OUTPUT} (dB)", "95 % CI (dB)"]
    # per variant, once: the paired ratio (r = mean net / mean casing - 1), its interval, net's interval, no response
    per = []
    for v in vs:
        net, casing = v.net_ensemble, v.ensemble
        pd = paired_difference(net.levels, casing.levels)
        per.append((net, pd, pd.ci(0.95), net.ci(0.95), no_response(net.mean) | no_response(casing.mean)))
    rows = []
    for b, lab in enumerate(e0.labels):
        row = [lab, f"{e0.lower[b]:g}-{e0.upper[b]:g}"]
        for net, pd, (lo_r, hi_r), (lo, hi), off in per:
            if off[b]:
                row += ["–", "–", "–", "–"]
                continue
            row += [
                _g(net.mean[b], 4),
                f"{_g(lo[b], 3)} to {_g(hi[b], 3)}",
                f"{20 * np.log10(1 + pd.r[b]):+.1f}",
                f"{_ratio_db(1 + lo_r[b])} to {_ratio_db(1 + hi_r[b])}",
            ]
        rows.append(row)
    n = e0.n
    return [
        title,
        _table(head, rows, numeric=tuple(range(2, len(head)))),
        _NET_SUM_NOTE + f"Means over the same {n} seeds as the ensembles of {OUTPUT} above, from the same runs "
        "(bands_net_B_&lt;variant&gt;.csv: one row per seed), Student-t 95 % intervals; "
        f"re {OUTPUT}: the ratio of the two means in dB, its interval from the members paired seed by seed "
        "(<code>paired_difference</code>, docs/studies.md), which removes the scatter the excitation explains in "
        f"both. –: no response (more than {NO_RESPONSE_DB:g} dB below the column's strongest band, as above). "
        "bands_net_B.csv holds the reference records' casing.B.Fz, cable.B.Fz and net.B.Fz." + same_note + "</p>",
    ]


def _ratio_db(x):
    """A ratio of levels (-) in dB, "-inf" at or below 0 (a paired interval's lower end may reach it)."""
    return f"{20 * np.log10(x):+.1f}" if x > 0 else "-inf"


def _net_single_parts(variants, info):
    """The band levels of the force into B, net.B.Fz = casing.B.Fz + cable.B.Fz, beside casing.B.Fz
    and cable.B.Fz, of each variant's reference record (``Variant.net_bands``; bands_net_B.csv):
    HTML, or nothing for a model without a cable (the page's table when no variant has an ensemble)."""
    from ..nvh.bands import NO_RESPONSE_DB, no_response

    vs = [v for v in variants if v.net_bands is not None]
    if not vs:
        return []
    names = list(vs[0].net_bands)
    b0 = vs[0].net_bands[names[0]]
    head = ["band", "Hz"]
    for v in vs:
        head += [f"{v.title}: {n} (N)" for n in names] + [f"{v.title}: {NET_OUTPUT} re {OUTPUT} (dB)"]
    # (a band more than NO_RESPONSE_DB below its column's strongest holds no response: a dash, as in the
    # ensembles' table; its value is in bands_net_B.csv)
    off = {(v.key, n): no_response(v.net_bands[n].rms) for v in vs for n in names}
    rows = []
    for i, lab in enumerate(b0.labels):
        row = [lab, f"{b0.lower[i]:g}-{b0.upper[i]:g}"]
        for v in vs:
            row += ["–" if off[v.key, n][i] else _g(v.net_bands[n].rms[i], 4) for n in names]
            a, b = v.net_bands[OUTPUT].rms[i], v.net_bands[NET_OUTPUT].rms[i]
            shown = not (off[v.key, OUTPUT][i] or off[v.key, NET_OUTPUT][i])
            row.append(f"{20 * np.log10(b / a):+.1f}" if shown else "–")
        rows.append(row)
    return [
        f"<h2>The force into the transmission at B: {NET_OUTPUT} beside {OUTPUT} (Table 3, reference records)</h2>",
        _table(head, rows, numeric=tuple(range(2, len(head)))),
        _NET_SUM_NOTE
        + f"–: no response (more than {NO_RESPONSE_DB:g} dB below the column's strongest band, as above). "
        f"From the reference records after {info['skip']:g} s, through Hann's window, as the ensembles: one "
        f"record each, one draw of the seeds' scatter (the ensemble means above are of {OUTPUT}); files "
        "bands_net_B.csv at full precision.</p>",
        f"<p class='warn'>One record only: these levels carry a single record's scatter{_cv_span(vs)}, and no "
        f"interval; for a decision take the ensemble of {NET_OUTPUT} itself: <code>cablecasing ensemble "
        f"--output {NET_OUTPUT}</code> (docs/studies.md).</p>",
    ]


def _cv_span(variants):
    """', which for casing.B.Fz with the cable drive is 5-17 % per band (...)': the CV of one record
    over the bands with a response of the model's own scenario (the last variant, which the study
    runs and whose net.B.Fz differs from casing.B.Fz), or ''."""
    v = next((v for v in reversed(list(variants)) if v.ensemble is not None), None)
    if v is None:
        return ""
    cvs = 100 * v.ensemble.cv[~no_response_of(v.ensemble.mean)]
    if not cvs.size:
        return ""
    return (
        f", which for {OUTPUT} {_e(v.title)} is {cvs.min():.0f}-{cvs.max():.0f} % per band (the CV of one record, "
        "above)"
    )


def no_response_of(levels):
    """:func:`~cablecasing_core.nvh.bands.no_response` of ``levels``."""
    from ..nvh.bands import no_response

    return no_response(levels)


def _random(model):
    """The model's random excitations (their scenario tables)."""
    return [e for e in model.scenario["excitation"].values() if e["kind"] == "random"]


def _touched(v):
    """Whether a variant's ensemble or reference record had any contact."""
    ct = getattr(v.ensemble, "contact_time", None)
    rec = getattr(v.result, "contact_time", None)
    return bool((ct is not None and np.any(ct > 0)) or (rec is not None and np.any(np.asarray(rec) > 0)))


def _db(x):
    """A level in dB re 1 N, "-inf" for zero."""
    return f"{20 * np.log10(x):.1f}" if x > 0 else "-inf"


def _study(study, variants=()):
    if study is None:
        return [
            "<h2>Study (Fig. 23)</h2><p>No study: the model has none of the paper's parameters, or it was "
            "not asked for.</p>"
        ]
    bounds = ", ".join(f"{k} {lo:g}..{hi:g}" for k, (lo, hi) in study["bounds"].items())
    seeds = study.get("seeds") or {}
    said = ", ".join(f"{k} = {x}" for k, x in seeds.items())
    parts = [
        "<h2>A small Monte-Carlo study (Fig. 23)</h2>",
        f"<p>{study['runs']} runs ({study['ok']} ok) of Saltelli's design, parameters: {_e(bounds)} "
        f"(<a href='{study['csv']}'>{study['csv']}</a>).</p>",
        "<p class='note'>"
        + (
            f"Every run uses the scenario's excitation seed ({_e(said)}): one record per point, so each output "
            f"carries a single record's chaotic scatter{_cv_span(variants)}, besides the parameters' effect. "
            if said
            else ""
        )
        + "The bounds are the package's (studies.PAPER_BOUNDS: the paper's where it gives them; for the axial "
        "amplitude, which it does not, 0.5-2 × the specimen's). docs/studies.md, \"The paper's conclusions in "
        "this model\", compares a study of this model with the paper's Fig. 23.</p>",
    ]
    parts += [f"<p class='warn'>{_e(w)}</p>" for w in study.get("warnings", [])]
    if "pearson" in study:
        parts.append("<img src='study/correlations.png'>")
        for c in (study["pearson"], study["spearman"]):
            parts.append(f"<p>{c.method.capitalize()} r (-), {c.n} ok runs ({_e(c.legend())}):</p>")
            cells = [[f"{x:+.2f}{'*' if q < 0.05 else ''}" for x, q in zip(r, p)] for r, p in zip(c.r, c.pvalue)]
            parts.append(
                _table(
                    ["parameter"] + list(c.outputs),
                    [[_e(p)] + cells[i] for i, p in enumerate(c.parameters)],
                    numeric=tuple(range(1, len(c.outputs) + 1)),
                )
            )
    sob = study.get("sobol")
    if study.get("sobol_note"):
        parts.append(f"<p class='note'>{_e(study['sobol_note'])}</p>")
    if sob is not None:
        parts.append("<img src='study/sobol.png'>")
        rows = []
        for i, p in enumerate(sob.parameters):
            rows.append([_e(p) + " S1"] + [f"{a:+.2f} ± {c:.2f}" for a, c in zip(sob.S1[i], sob.S1_conf[i])])
            rows.append([_e(p) + " ST"] + [f"{a:+.2f} ± {c:.2f}" for a, c in zip(sob.ST[i], sob.ST_conf[i])])
        parts.append(f"<p>Sobol indices (-), {sob.n_base} complete base points, {sob.conf_level:.0%} intervals:</p>")
        parts.append(_table(["index"] + list(sob.outputs), rows, numeric=tuple(range(1, len(sob.outputs) + 1))))
    return parts
