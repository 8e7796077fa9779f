"""Figures of the studies (matplotlib, Agg backend): correlations like Fig. 23, ensemble levels."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ..errors import ModelError
from ..plotting import save_figure  # (also selects the Agg backend)
from ..records import unit_of
from .correlation import GAP, correlations
from .results_store import StudyResults, load_results
from .sampling import AXIAL_AMPLITUDE_KEY

#: Panels of Fig. 23: (a) E_jv, (b) E_op, (c) gap, (d) axial amplitude, (e) friction.
FIG23_PARAMETERS = ("cable.E", "casing.E", GAP, AXIAL_AMPLITUDE_KEY, "contact.friction")
_LABELS = {
    "cable.E": "$E_{jv}$ (cable.E)",
    "casing.E": "$E_{op}$ (casing.E)",
    GAP: "gap = $d_5 - D_{z0}$",
    AXIAL_AMPLITUDE_KEY: r"$\bar X_{jv}$ (axial amplitude)",
    "contact.friction": r"$\eta$ (contact.friction)",
    "cable.d": "$D_{z0}$ (cable.d)",
    "casing.d_inner": "$d_5$ (casing.d_inner)",
}


def plot_correlations(results, path, parameters=None, methods=("pearson", "spearman"), title=None, cors=None):
    """Write a figure like Fig. 23 (Section 4.4): one panel per parameter, bars of the correlation
    coefficient (-1..1) per output band, one bar colour per method; a bar whose p-value
    (:func:`.correlations`) is 0.05 or more is faded. Returns ``path``.

    ``parameters`` defaults to Fig. 23's five panels (E_jv, E_op, gap, axial amplitude, friction)
    when they were sampled, else every sampled parameter. ``cors``: the :class:`Correlation` of
    ``results`` per method when the caller has them (their permutation tests are not cheap).
    Matplotlib, Agg backend.
    """
    if not isinstance(results, StudyResults):
        results = load_results(results)
    cors = list(cors) if cors is not None else [correlations(results, m) for m in methods]
    names = cors[0].parameters
    if parameters is None:
        parameters = [p for p in FIG23_PARAMETERS if p in names]
        if len(parameters) < len(FIG23_PARAMETERS):
            parameters = list(names)
    bad = [p for p in parameters if p not in names]
    if bad:
        raise ModelError("parameters", bad, "must be sampled parameters (or 'gap'): " + ", ".join(names))
    nb = len(results.outputs)
    fig, axes = plt.subplots(len(parameters), 1, figsize=(7, 1.9 * len(parameters) + 0.6), sharex=True, squeeze=False)
    width = 0.8 / len(cors)
    x = np.arange(nb)
    for k, (ax, p) in enumerate(zip(axes[:, 0], parameters)):
        row = names.index(p)
        for m, c in enumerate(cors):
            bars = ax.bar(x + (m - (len(cors) - 1) / 2) * width, c.r[row], width, label=c.method)
            for bar, q in zip(bars, c.pvalue[row]):
                if q >= 0.05:  # (faded: not different from zero at 95 %; NaN, untested, not)
                    bar.set_alpha(0.3)
        _panel(ax, k, p, (-1, 1), "r (-)")
    _band_axis(axes, results.outputs)
    _suptitle(
        fig,
        title
        or f"Correlation with the band RMS{_of(results)}, {cors[0].n} runs used (Fig. 23)\n"
        + (
            f"faded: p >= 0.05 (two-sided, by {cors[0].pvalue_from})"
            if np.isfinite(cors[0].pvalue).any()
            else cors[0].legend()  # (no p-values: it says why)
        ),
        9,
    )
    save_figure(fig, path)
    return path


def _suptitle(fig, text, fontsize):
    """The figure's title, each line wrapped to the figure's width (a character taken as 0.6 of the
    font size: wider than the average of its font), so that no part of it is cut off."""
    import textwrap

    width = int(fig.get_figwidth() * 72 / (0.6 * fontsize))
    fig.suptitle("\n".join(textwrap.fill(line, width) for line in text.split("\n")), fontsize=fontsize)


def _of(results):
    """`` of casing.B.Fz (N)``: the quantity a study's outputs are values of, when it says."""
    q = getattr(results, "quantity", None)
    return f" of {q['name']} ({q['unit']})" if q else ""


def _panel(ax, k, parameter, ylim, ylabel):
    """One parameter's panel of Fig. 23 and of the Sobol figure: title (a), (b), ..., limits, grid."""
    ax.axhline(0.0, color="k", lw=0.6)
    ax.set_ylim(*ylim)
    ax.set_ylabel(ylabel)
    ax.set_title(f"({chr(97 + k)}) {_LABELS.get(parameter, parameter)}", fontsize=9, loc="left")
    ax.grid(True, axis="y", alpha=0.3)


def _band_axis(axes, outputs):
    """The shared band axis of a column of panels (Table 3's number over its edges in Hz, else the
    output's name) and the legend in the first panel."""
    from ..nvh.bands import octave_bands
    from ..nvh.plots import band_ticks

    t3 = octave_bands("table3")
    edges = dict(zip(t3.labels, band_ticks(t3)))
    ticks = [edges.get(o, o) for o in outputs]
    axes[-1, 0].set_xticks(np.arange(len(outputs)), ticks, rotation=0 if len(outputs) <= 12 else 90, fontsize=7)
    axes[-1, 0].set_xlabel(
        "octave band of Table 3 over the nominal octave it stands for (Hz)" if outputs[0] == "oct1" else "band"
    )
    axes[0, 0].legend(fontsize=7, loc="best", framealpha=0.85)


def _percent(level):
    """A confidence level in per cent as given (0.995: ``99.5%``; ``.0%`` would print 100%)."""
    return f"{100 * level:.10g}%"


def _sobol_limits(sob, k):
    """The y limits of parameter ``k``'s Sobol panel: the indices' range (-0.2 to 1.1) widened to hold
    every bar and interval (an estimate from few base points reaches beyond [0, 1], and a bar or an
    interval cut at the panel's edge would hide by how much)."""
    lo = np.nanmin(np.concatenate([sob.S1[k] - sob.S1_conf[k], sob.ST[k] - sob.ST_conf[k], [-0.2]]))
    hi = np.nanmax(np.concatenate([sob.S1[k] + sob.S1_conf[k], sob.ST[k] + sob.ST_conf[k], [1.1]]))
    pad = 0.05 * (hi - lo)
    return (lo - pad if lo < -0.2 else lo, hi + pad if hi > 1.1 else hi)


def plot_sobol(results, path, title=None, conf_level=0.95, sob=None):
    """First-order (S1) and total (ST) Sobol indices per output band with their confidence intervals
    (``sensitivity.sobol_indices``), one panel per parameter. ``sob``: the :class:`SobolIndices` of
    ``results`` when the caller has them (then ``conf_level`` is theirs). Returns ``path``."""
    from .sensitivity import sobol_indices

    if not isinstance(results, StudyResults):
        results = load_results(results)
    sob = sob if sob is not None else sobol_indices(results, conf_level=conf_level)
    d, nb = len(sob.parameters), len(sob.outputs)
    fig, axes = plt.subplots(d, 1, figsize=(7, 1.8 * d + 0.8), sharex=True, squeeze=False)
    x = np.arange(nb)
    for k, (ax, p) in enumerate(zip(axes[:, 0], sob.parameters)):
        ax.bar(x - 0.2, sob.S1[k], 0.4, yerr=sob.S1_conf[k], capsize=2, label="first order S1")
        ax.bar(x + 0.2, sob.ST[k], 0.4, yerr=sob.ST_conf[k], capsize=2, label="total ST")
        _panel(ax, k, p, _sobol_limits(sob, k), "index (-)")
    _band_axis(axes, sob.outputs)
    _suptitle(
        fig,
        title
        or f"Sobol indices of the band RMS{_of(results)}, {sob.n_base} base points ({_percent(sob.conf_level)} "
        "intervals)",
        10,
    )
    save_figure(fig, path)
    return path


def plot_ensemble(ens, path, other=None, diff=None, confidence=0.95, labels=("base", "against"), title=None):
    """Band levels over excitation seeds (``studies.seed_ensemble``): the ensemble mean per band with
    its Student-t confidence interval (N, or N.m for a moment output; log axis, with the level in dB
    re 1 N or 1 N.m on the right), a second ensemble beside it, and, with ``diff``
    (``studies.paired_difference(other, ens)``), the relative change r (%) per band with its interval."""
    from ..nvh.plots import db_axis, set_band_ticks

    unit = unit_of(ens.output)
    x = np.arange(1, len(ens.labels) + 1)
    rows = 2 if diff is not None else 1
    fig, axes = plt.subplots(rows, 1, figsize=(7, 3.2 * rows + 0.6), sharex=True, squeeze=False)
    ax = axes[0, 0]
    sets = [(ens, labels[0], -0.12)] + ([(other, labels[1], 0.12)] if other is not None else [])
    for e, lab, dx in sets:
        lo, hi = e.ci(confidence)
        ax.errorbar(
            x + dx,
            e.mean,
            yerr=[e.mean - lo, hi - e.mean],
            fmt="o",
            capsize=3,
            label=f"{lab}: mean of {e.n} seeds, {_percent(confidence)} CI",
        )
    ax.set_yscale("log")
    ax.set_ylabel(f"RMS {ens.output} ({unit})")
    db_axis(ax, 1.0, unit, power=False)
    if title:
        ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    if diff is not None:
        a2 = axes[1, 0]
        lo, hi = diff.ci(confidence)
        a2.errorbar(x, 100 * diff.r, yerr=[100 * (diff.r - lo), 100 * (hi - diff.r)], fmt="s", capsize=3)
        a2.axhline(0.0, color="k", lw=0.8)
        a2.set_ylabel(f"{labels[1]} vs {labels[0]} (%)")
        a2.grid(True, alpha=0.3)
    last = axes[-1, 0]
    set_band_ticks(last, x, ens)
    last.set_xlabel("band: nominal mid-band frequency (Hz)")
    save_figure(fig, path)
