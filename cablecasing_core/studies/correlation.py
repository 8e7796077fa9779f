"""Correlation of the study's parameters with its outputs (Section 4.4, Fig. 23): Pearson and
Spearman coefficients over the ok samples, with the derived radial gap."""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from .results_store import StudyResults, load_results

GAP = "gap"


@dataclass
class Correlation:
    """Correlation coefficients (dimensionless, -1..1) of parameters (rows) with outputs (columns).

    ``method`` is "pearson" or "spearman"; ``r`` and ``pvalue`` are (len(parameters), len(outputs));
    ``n`` is the number of ok samples used. Section 4.4, Fig. 23.
    """

    method: str
    parameters: tuple
    outputs: tuple
    r: np.ndarray
    pvalue: np.ndarray
    n: int

    def as_dict(self):
        """``{parameter: {output: r}}``."""
        return {p: {o: float(self.r[i, j]) for j, o in enumerate(self.outputs)} for i, p in enumerate(self.parameters)}


def _columns(results, include_gap):
    names = list(results.parameters)
    X = results.X
    if include_gap and "cable.d" in names and "casing.d_inner" in names:
        gap = X[:, names.index("casing.d_inner")] - X[:, names.index("cable.d")]
        names.append(GAP)
        X = np.column_stack([X, gap])
    return tuple(names), X


def correlations(results: StudyResults | str, method: str = "pearson", include_gap: bool = True) -> Correlation:
    """Pearson or Spearman correlation of every parameter with every output over the ok samples.

    ``results`` is a :class:`StudyResults` or a CSV path. With ``include_gap`` and both diameters
    sampled, the derived ``gap = casing.d_inner - cable.d`` (m; Fig. 23(c)) is added as a parameter.
    Uses ``scipy.stats.pearsonr`` / ``spearmanr``; a constant column gives NaN. Section 4.4, Fig. 23.
    """
    from scipy import stats

    if not isinstance(results, StudyResults):
        results = load_results(results)
    if method not in ("pearson", "spearman"):
        raise ModelError("method", method, "must be 'pearson' or 'spearman'")
    names, X = _columns(results, include_gap)
    ok = results.ok & np.all(np.isfinite(results.Y), axis=1)
    n_ok = int(ok.sum())
    if n_ok < 3:
        raise ModelError("results", f"{n_ok} ok samples", "need at least 3 successful samples for a correlation")
    fn = stats.pearsonr if method == "pearson" else stats.spearmanr
    r = np.full((len(names), len(results.outputs)), np.nan)
    pv = np.full_like(r, np.nan)
    for a in range(len(names)):
        for b in range(len(results.outputs)):
            x, y = X[ok, a], results.Y[ok, b]
            if np.ptp(x) == 0 or np.ptp(y) == 0:
                continue
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                res = fn(x, y)
            r[a, b], pv[a, b] = float(res.statistic), float(res.pvalue)
    return Correlation(method=method, parameters=names, outputs=tuple(results.outputs), r=r, pvalue=pv, n=n_ok)
