"""First-order and total Sobol indices of a study's outputs, with bootstrap confidence intervals
(``SALib.analyze.sobol``, Saltelli 2010 / Jansen estimators), and the sample-size checks that say
when a study is too small to mean anything.

The study's runs follow Saltelli's design (:mod:`.sampling`): base point j is the group of d + 2
consecutive runs A_j, AB_j^(1..d), B_j. A group enters the indices only when all its runs are ok
(a failed or infeasible run leaves its group out); SALib gets the complete groups in order.

* ``S1`` (first order): the share of an output's variance that one parameter explains alone;
  ``ST`` (total): its share with all its interactions. Both are dimensionless, 0..1 (estimates may
  stray below 0 or above 1 by their error); ``*_conf`` are the half-widths of the intervals at
  ``conf_level``, SALib's normal interval: z times the standard deviation of the estimate over
  ``num_resamples`` bootstrap resamples of the groups.
* Checked against the Ishigami function's closed forms (tests/studies/test_sensitivity.py;
  benchmarks.md, "Sensitivity analysis").

Too small (:func:`size_warnings`):

* correlations: with n independent samples a coefficient differs from zero at 95 % only beyond
  ``r_crit = tanh(1.96 / sqrt(n - 3))`` (Fisher's z); when ``r_crit > 0.3`` (fewer than 44 samples)
  the table is said to be indicative only. The independent count of Saltelli's design is taken as
  2 n_base (the A and B points); the other runs share coordinates with them;
* Sobol indices: when the widest interval exceeds +-0.1 (an index then says little more than
  "small" or "large").
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from ..model.validators import integer, number
from .results_store import StudyResults, load_results

#: Above this critical correlation (95 %, Fisher z) a correlation table is called indicative only.
R_CRIT_LIMIT = 0.3
#: Above this 95 % half-width a Sobol index is called too uncertain to read.
SOBOL_CONF_LIMIT = 0.1
#: The widest interval (half-width) of a Sobol index that is still shown: beyond it the table would
#: be intervals wider than the indices' range, the figure error bars only (the study command and the
#: report print the count and the widest interval instead; :func:`sobol_shown`).
SOBOL_SHOWN = 0.5


def widest_interval(sobol) -> float:
    """The widest half-width of the intervals of ``sobol`` (:class:`SobolIndices`; NaN where every
    output is constant)."""
    conf = np.concatenate([sobol.S1_conf.ravel(), sobol.ST_conf.ravel()])
    return float(np.nanmax(conf)) if np.isfinite(conf).any() else float("nan")


def sobol_shown(sobol) -> bool:
    """Whether the indices ``sobol`` are shown as a table and a figure: none of their intervals is
    wider than :data:`SOBOL_SHOWN` (the few complete base points of a small study give intervals of
    ±487 and more)."""
    return not widest_interval(sobol) > SOBOL_SHOWN


@dataclass(frozen=True)
class SobolIndices:
    """First-order ``S1`` and total ``ST`` Sobol indices (parameters x outputs, dimensionless) with
    the half-widths ``S1_conf``, ``ST_conf`` of their ``conf_level`` bootstrap intervals, from
    ``n_base`` complete groups of Saltelli's design."""

    parameters: tuple
    outputs: tuple
    S1: np.ndarray
    S1_conf: np.ndarray
    ST: np.ndarray
    ST_conf: np.ndarray
    n_base: int
    conf_level: float


def complete_groups(results: StudyResults) -> np.ndarray:
    """Indices (sorted) of the base points whose d + 2 runs are all ok with finite outputs."""
    g = results.group_size
    if g == 0:
        raise ModelError("results", "no Saltelli design", "Sobol indices need a study run with this version's design")
    good = results.ok & np.all(np.isfinite(results.Y), axis=1)
    groups = {}
    for i, ok in zip(results.index, good):
        groups.setdefault(int(i) // g, []).append(bool(ok))
    return np.array(sorted(j for j, oks in groups.items() if len(oks) == g and all(oks)), int)


def group_rows(results: StudyResults, groups: np.ndarray) -> np.ndarray:
    """Row numbers of the runs of the base points ``groups`` (complete ones: :func:`complete_groups`),
    an int array (len(groups), group_size), each group's runs in the design's order."""
    g = results.group_size
    row_of = {int(i): k for k, i in enumerate(results.index)}
    return np.array([[row_of[j * g + m] for m in range(g)] for j in groups], int).reshape(len(groups), g)


def sobol_indices(
    results: StudyResults | str, conf_level: float = 0.95, num_resamples: int = 200, seed: int = 0
) -> SobolIndices:
    """First-order and total Sobol indices of every output over the complete groups of the study
    (module docstring). ``results``: :class:`StudyResults` or a study CSV path; the bootstrap is
    seeded (``seed``), so the intervals are reproducible. Needs at least 4 complete groups."""
    from .executor import check_packages

    check_packages("serial", name="sobol_indices")
    from SALib.analyze import sobol

    number("conf_level", conf_level, gt=0, lt=1)
    integer("num_resamples", num_resamples, 2)
    integer("seed", seed, 0)
    if not isinstance(results, StudyResults):
        results = load_results(results)
    groups = complete_groups(results)
    if groups.size < 4:
        bad = [
            f"{int(np.sum(results.status == k))} {k}" for k in ("failed", "infeasible") if (results.status == k).any()
        ]
        why = f"; of the {len(results)} runs, {' and '.join(bad)} (their errors say why)" if bad else ""
        raise ModelError(
            "results",
            f"{groups.size} complete groups",
            f"Sobol indices need at least 4 complete groups (base points whose {results.group_size} runs are all "
            f"ok){why}",
        )
    d = len(results.parameters)
    take = group_rows(results, groups).ravel()
    problem = {"num_vars": d, "names": list(results.parameters), "bounds": [[0.0, 1.0]] * d}
    out = {k: np.full((d, len(results.outputs)), np.nan) for k in ("S1", "S1_conf", "ST", "ST_conf")}
    for b in range(len(results.outputs)):
        y = results.Y[take, b]
        if np.ptp(y) == 0:
            continue  # a constant output has no variance to share
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = sobol.analyze(
                problem,
                y,
                calc_second_order=False,
                num_resamples=num_resamples,
                conf_level=conf_level,
                seed=seed + 1,  # SALib takes a seed of 0 for none (np.random's global state, test-order dependent)
            )
        for k in out:
            out[k][:, b] = r[k]
    return SobolIndices(
        tuple(results.parameters), tuple(results.outputs), n_base=int(groups.size), conf_level=conf_level, **out
    )


def critical_correlation(n: int) -> float:
    """The smallest |r| that differs from zero at 95 % with n independent samples (Fisher's z):
    tanh(1.96 / sqrt(n - 3)); 1 for n <= 3, where it is not defined."""
    return 1.0 if n <= 3 else math.tanh(1.96 / math.sqrt(n - 3))


def size_warnings(results: StudyResults, sobol: SobolIndices | None = None) -> list[str]:
    """Plain-language warnings when the study is too small to mean anything (module docstring)."""
    out = []
    n_ok = int(np.sum(results.ok))
    n_ind = min(n_ok, 2 * len(complete_groups(results))) if results.group_size else n_ok
    r_crit = critical_correlation(n_ind)
    if r_crit > R_CRIT_LIMIT:
        out.append(
            f"{n_ok} ok runs ({n_ind} independent points): a correlation differs from zero at 95 % only beyond "
            f"|r| = {r_crit:.2f}, so the tables are indicative only (too small: under 44 independent points, where "
            f"that threshold exceeds {R_CRIT_LIMIT})"
        )
    if sobol is not None:
        conf = np.concatenate([sobol.S1_conf.ravel(), sobol.ST_conf.ravel()])
        worst = float(np.nanmax(conf)) if np.isfinite(conf).any() else 0.0  # (all NaN: constant outputs)
        if worst > SOBOL_CONF_LIMIT:
            out.append(
                f"Sobol indices from {sobol.n_base} base points are uncertain by up to +-{worst:.2g} "
                f"({sobol.conf_level:.0%}); too small: any interval wider than +-{SOBOL_CONF_LIMIT}"
            )
    return out
