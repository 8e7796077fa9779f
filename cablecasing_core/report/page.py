"""The report's page (report.html): what was run, then every figure and table with the runs it
comes from named beside it."""

from __future__ import annotations

import html
import math
import re

import numpy as np

from ..errors import ModelError
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


def render(model, info, modes, freq, variants, rms, am, study, fmu, harmonics, out):
    """The HTML text of the report (see :func:`cablecasing_core.report.write_report`)."""
    seeds = info["seeds"]
    parts = [
        f"<!doctype html><html lang='en'><head><meta charset='utf-8'><title>cablecasing report: "
        f"{_e(specimen_name(model.source))}</title><style>{_CSS}</style></head><body>",
        f"<h1>Cable in casing: report of {_e(specimen_name(model.source))}</h1>",
        _table(
            ["what", "value"],
            [
                ("model", f"{_e(model.source)} (fingerprint {info['fingerprint']})"),
                ("cablecasing version", _e(info["version"])),
                ("date", _e(info["date"])),
                (
                    "every run",
                    f"{info['duration']:g} s at dt = {info['dt']:g} s; levels and spectra after {info['skip']:g} s "
                    "(whole periods of the harmonic drive after it); band levels through Hann's window",
                ),
                ("excitation seeds", f"{seeds[0]}..{seeds[-1]} ({len(seeds)}; the reference records: seed {seeds[0]})"),
                ("output", f"{OUTPUT} (N): force the casing exerts on its support B in z"),
            ],
        ),
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
                f"<a href='{v.record.relative_to(out)}'>{_e(v.record.relative_to(out))}</a>",
                f"<a href='bands_{v.key}.csv'>bands_{v.key}.csv</a> ({ens.n} seeds)" if ens is not None else "-",
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
        "and trfam.uff (UFF 58, six FRFs, kg).</p>",
        "<h2>Support forces of the reference records</h2><img src='simulation.png'>",
        *_rms_parts(rms, info),
        "<h2>Wavelet transform of the support force "
        + ("without and with the cable drive" if len(variants) == 2 else f"of {_e(variants[0].title)}")
        + " (Figs. 20-21)</h2>",
        "<img src='scalograms.png'>",
        "<p class='note'>Reference records; dashed: natural frequencies of the casing"
        + (_harmonics_note(harmonics) if len(harmonics) else "")
        + ".</p>",
        "<h2>Contact: routing and contact time beside the curvature (Fig. 22)</h2>",
        "<img src='routing_contact.png'><img src='contact_histogram.png'>"
        if {"casing", "cable"} <= set(model.bodies)
        else "<p>The model has no cable in a casing: no contact.</p>",
    ]
    parts += _bands(variants, model, info)
    parts += net_parts(variants, info)
    parts += [
        "<h2>Spectra</h2><img src='psd.png'>",
    ]
    if am is not None:
        parts += ["<img src='apparent_mass.png'>", f"<p class='note'>{apparent_mass_note(am, variants[0].title)}</p>"]
    parts += _study(study)
    if fmu is not None:
        parts += [
            "<h2>The FMU</h2>",
            _table(["what", "value"], [(_e(k), _e(v)) for k, v in fmu.items()]),
        ]
    parts.append("</body></html>")
    return _with_alt("\n".join(parts))


def _rms_parts(rms, info):
    """The RMS table of the reference records' support forces: mean, RMS total (with the mean) and
    RMS dynamic (without it), N, one row per variant and force."""
    from .figures import RMS_COLUMNS

    rows = [(_e(v.title), _e(v.record.name), _e(n), *(_g(x, 6) for x in t)) for v, d in rms for n, t in d.items()]
    return [
        _table(["variant", "record", "output"] + [f"{c} (N)" for c in RMS_COLUMNS], rows, numeric=(3, 4, 5)),
        f"<p class='note'>After {info['skip']:g} s, from the saved records (rms.csv at full precision). RMS total "
        "includes the mean, the force's static part; "
        "RMS dynamic is the RMS with the mean removed (the standard deviation), what vibrates, as in "
        "<code>simulate</code>'s table: the band levels and the PSD remove the mean too, so compare them with "
        "it.</p>",
    ]


def apparent_mass_note(am, title):
    """The note under apparent_mass.png (HTML): what the estimate is compared with and why its
    coherence drops, from :func:`.figures.apparent_mass_figure`'s summary ``am``."""
    n, df = am["n_averages"], am["df"]
    m, x = am["median_coherence"], am["expected_coherence"]
    head = (
        f"H1 from {_e(am['input'])} to {OUTPUT} of the reference record {_e(title)} ({n} averages of {df:.3g} Hz "
        "lines, Hann's window), in the TRFAM's sign convention, against what it estimates: the TRFAM (viscous) "
        "averaged over the window's spectral window (dashed; Bendat &amp; Piersol 11.4, as docs/nvh.md, "
        '"Against the TRFAM", compares them), with the TRFAM as computed for reference (dotted). '
    )
    coh = (
        f"The coherence has median {m.get('10-100', float('nan')):.2f} over 10-100 Hz and {m['10-1000']:.2f} over "
        f"10-1000 Hz; the window's smoothing alone leaves {x.get('10-100', float('nan')):.2f} and "
        f"{x['10-1000']:.2f} of the noise-free TRFAM (dashed, lower panel; with {n} averages a low coherence "
        f"reads higher, by about (1 - &gamma;&sup2;)&sup2;/{n}). "
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
            + f"{c['df']:.3g} Hz lines ({c['n_averages']} averages) the median coherence is "
            f"{cm.get('10-100', float('nan')):.2f} over 10-100 Hz and {cm['10-1000']:.2f} over 10-1000 Hz. "
        )
        if narrow:
            half = min(b) / 2
            more += (
                f"Only finer lines remove the bias: lines of half the narrowest bandwidth ({half:.2g} Hz) need "
                f"segments of {1 / half:.2g} s, a record of at least {2 / half:.2g} s after the skip for 3 averages. "
            )
    others = am.get("other_inputs") or []
    also = (
        f"The casing is driven at {_and([_e(t) for t in others])} too, which the input does not explain: that "
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
    flat = f"the input is the scenario's random excitation, flat over {_and([f'{lo:g}-{hi:g}' for lo, hi in bands])} Hz"
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
    quotes = ACCURACY_QUOTES.get(model.source)
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
    from ..studies.octave import NO_RESPONSE_DB, no_response

    ens = [v for v in variants if v.ensemble is not None]
    if not ens:
        return ["<h2>Band levels</h2><p>No random excitation: no ensemble over seeds.</p>"]
    e0 = ens[0].ensemble
    head = ["band", "Hz"]
    for v in ens:
        head += [f"{v.title}: mean (N)", "95 % CI (N)", "mean (dB re 1 N)", "95 % CI (dB)", "CV of one record"]
    off = {v.key: no_response(v.ensemble.mean) for v in ens}
    rows = []
    for b, lab in enumerate(e0.labels):
        row = [lab, f"{e0.lower[b]:g}-{e0.upper[b]:g}"]
        for v in ens:
            e = v.ensemble
            if off[v.key][b]:
                row += ["–", "–", "–", "–", "no response"]
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
        rows.append(row)
    parts = [
        f"<h2>Band levels of {OUTPUT} (Table 3): ensemble means over excitation seeds</h2>",
        "<img src='band_levels.png'>",
        _table(head, rows, numeric=tuple(range(2, len(head)))),
        "<p class='note'>Means over the seeds of the ensembles (bands_&lt;variant&gt;.csv: one row per seed); "
        "Student-t 95 % intervals (cut at 0); CV: the seed-to-seed scatter of a single record's level.</p>",
    ]
    for v in ens:
        gone = [lab for lab, o in zip(e0.labels, off[v.key]) if o]
        if gone:
            top = 20 * np.log10(np.max(v.ensemble.mean))
            parts.append(
                f"<p class='note'>–: no response. In the variant {_e(v.title)}, {_and([_e(g) for g in gone])} "
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


def net_parts(variants, info):
    """The band levels of the force into B, net.B.Fz = casing.B.Fz + cable.B.Fz, beside casing.B.Fz
    and cable.B.Fz, of each variant's reference record (``Variant.net_bands``; bands_net_B.csv):
    HTML, or nothing for a model without a cable."""
    from ..studies.octave import NO_RESPONSE_DB, no_response

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
        f"<p class='note'>At end B the casing's abutment and the cable's end attach to one part, the transmission, "
        f'so what it receives is their sum, {NET_OUTPUT} = {OUTPUT} + cable.B.Fz (docs/nvh.md, "Net forces and '
        'paths"; <code>cablecasing bands RECORD --column net.B.Fz</code> gives it from any record). Its band '
        "levels are those of the summed samples, not the sum of the two bodies' levels: where the cable and the "
        "casing carry one loop (the cable's drive pulls the part the casing pushes), their forces cancel in part. "
        f"–: no response (more than {NO_RESPONSE_DB:g} dB below the column's strongest band, as above). "
        f"From the reference records after {info['skip']:g} s, through Hann's window, as the ensembles: one "
        f"record each, one draw of the seeds' scatter (the ensemble means above are of {OUTPUT}); files "
        "bands_net_B.csv at full precision.</p>",
    ]


def _and(items):
    """'a', 'a and b', 'a, b and c'."""
    return " and ".join([", ".join(items[:-1]), items[-1]] if len(items) > 1 else items)


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


def _study(study):
    if study is None:
        return [
            "<h2>Study (Fig. 23)</h2><p>No study: the model has none of the paper's parameters, or it was "
            "not asked for.</p>"
        ]
    bounds = ", ".join(f"{k} {lo:g}..{hi:g}" for k, (lo, hi) in study["bounds"].items())
    parts = [
        "<h2>A small Monte-Carlo study (Fig. 23)</h2>",
        f"<p>{study['runs']} runs ({study['ok']} ok) of Saltelli's design, parameters: {_e(bounds)} "
        f"(<a href='{study['csv']}'>{study['csv']}</a>).</p>",
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
