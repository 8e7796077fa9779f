"""Correlation of the study's parameters with its outputs (Section 4.4, Fig. 23): Pearson and
Spearman coefficients over the ok samples, with the derived gap, and their p-values. The gap
(``GAP``, m) is the diametral clearance casing.d_inner − cable.d, twice the model's radial gap;
it is added when both diameters are varied.

The p-value of a study run in Saltelli's design is a permutation test over its base points, not
the t distribution of independent samples: the d + 2 runs of a base point share coordinates (d of
them carry A_j's value of a parameter, two B_j's: :mod:`.sampling`), so the runs are not independent
draws and ``scipy.stats.pearsonr``'s p-value, which counts every run, is anti-conservative (a 5 %
test rejected 11-14 % of the time for an output independent of the parameter, 304 runs of the
installed specimen's bounds). Under the null hypothesis "the output does not depend on this
parameter" the blocks of the parameter's values can be exchanged between base points while each
keeps its outputs; ``scipy.stats.permutation_test`` permutes them (exactly when there are few base
points) and the statistic is the coefficient over all the blocks' runs, which is the r reported:
with failed or infeasible runs, r is taken over the runs of the complete base points only."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from ..model.validators import integer
from .results_store import StudyResults, load_results
from .sensitivity import complete_groups, group_rows

#: The derived parameter: the diametral clearance casing.d_inner − cable.d (m), twice the radial gap.
GAP = "gap"


@dataclass
class Correlation:
    """Correlation coefficients (dimensionless, -1..1) of parameters (rows) with outputs (columns).

    ``method`` is "pearson" or "spearman"; ``r`` and ``pvalue`` are (len(parameters), len(outputs));
    ``n`` is the number of runs r uses, the same the p-values test; ``pvalue_from`` says how the
    p-values were found (a permutation test over the complete base points of Saltelli's design, or
    the t distribution of independent samples) and over which runs. Section 4.4, Fig. 23.
    """

    method: str
    parameters: tuple
    outputs: tuple
    r: np.ndarray
    pvalue: np.ndarray
    n: int
    pvalue_from: str = ""

    def legend(self, mark="*"):
        """What marks the coefficients with p < 0.05 and by which test, e.g. ``"* p < 0.05, two-sided,
        by a permutation test over 38 complete base points"`` (or that there are no p-values)."""
        if np.isfinite(self.pvalue).any():
            if not np.nanmin(self.pvalue) < 0.05:  # (nothing is marked: say so, not what a mark would mean)
                return f"none with p < 0.05, two-sided, by {self.pvalue_from}"
            return f"{mark} p < 0.05, two-sided, by {self.pvalue_from}"
        return f"p-values {self.pvalue_from}"

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


def correlations(
    results: StudyResults | str,
    method: str = "pearson",
    include_gap: bool = True,
    n_resamples: int = 9999,
    seed: int = 0,
) -> Correlation:
    """Pearson or Spearman correlation of every parameter with every output over the ok samples
    (in Saltelli's design those of its complete base points, which the p-values test).

    ``results`` is a :class:`StudyResults` or a CSV path. With ``include_gap`` and both diameters
    sampled, the derived ``gap = casing.d_inner - cable.d`` (m; Fig. 23(c)) is added as a parameter.
    The coefficients are ``scipy.stats.pearsonr`` / ``spearmanr``'s; a constant column gives NaN.
    The p-values (two-sided) of a study in Saltelli's design come from a permutation test over its
    complete base points (module docstring; ``n_resamples`` random permutations seeded by ``seed``,
    all of them when there are fewer), and r is taken over the same runs, those of the complete
    base points (an ok run of a base point with a failed or infeasible run is left out; the result's
    ``n`` and ``pvalue_from`` say how many runs r uses); below 3 complete base points the p-values
    are NaN and r is over all ok runs. Those of other results come from the t distribution of their
    independent samples. Section 4.4, Fig. 23.
    """
    from scipy import stats

    if not isinstance(results, StudyResults):
        results = load_results(results)
    if method not in ("pearson", "spearman"):
        raise ModelError("method", method, "must be 'pearson' or 'spearman'")
    integer("n_resamples", n_resamples, 99)
    integer("seed", seed, 0)
    names, X = _columns(results, include_gap)
    ok = np.flatnonzero(results.ok & np.all(np.isfinite(results.Y), axis=1))
    n_ok = int(ok.size)
    if n_ok < 3:
        raise ModelError("results", f"{n_ok} ok samples", "need at least 3 successful samples for a correlation")
    groups = complete_groups(results) if results.group_size else None
    blocks = None  # (the runs of the complete base points, (groups, runs per group): the permutation test's)
    if groups is None:
        pvalue_from = f"the t distribution of {n_ok} independent samples"
    elif len(groups) < 3:
        pvalue_from = f"none: {len(groups)} complete base points, a permutation test needs 3 (r over {n_ok} ok runs)"
    else:
        blocks = group_rows(results, groups)
        ok = blocks.ravel()
        left = n_ok - ok.size
        pvalue_from = f"a permutation test over {len(groups)} complete base points, r over their {ok.size} runs" + (
            f" ({left} ok runs of incomplete base points left out)" if left else ""
        )
        if len(groups) <= 4:  # (all n! orders are enumerated: the smallest two-sided p is 2 / n!)
            n = len(groups)
            pvalue_from += f" (its smallest p-value is 2/{n}! = {2 / math.factorial(n):.2g}: none can reach 0.05)"
    fn = stats.pearsonr if method == "pearson" else stats.spearmanr
    r = np.full((len(names), len(results.outputs)), np.nan)
    pv = np.full_like(r, np.nan)
    rng = np.random.default_rng(seed)
    for a in range(len(names)):
        for b in range(len(results.outputs)):
            x, y = X[ok, a], results.Y[ok, b]
            if np.ptp(x) == 0 or np.ptp(y) == 0:
                continue
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                res = fn(x, y)
            r[a, b] = float(res.statistic)
            if groups is None:
                pv[a, b] = float(res.pvalue)
            elif blocks is not None:
                pv[a, b] = _block_permutation_pvalue(X[blocks, a], results.Y[blocks, b], method, n_resamples, rng)
    return Correlation(
        method=method,
        parameters=names,
        outputs=tuple(results.outputs),
        r=r,
        pvalue=pv,
        n=int(ok.size),
        pvalue_from=pvalue_from,
    )


def _block_permutation_pvalue(x, y, method, n_resamples, rng):
    """Two-sided p-value of the correlation of x with y, both (groups, runs per group), when the rows
    of x are exchangeable between groups under the null hypothesis (module docstring). Spearman's
    coefficient is Pearson's of the ranks over all runs, which a permutation of whole rows keeps."""
    from scipy import stats

    if method == "spearman":
        x = stats.rankdata(x, axis=None).reshape(x.shape)
        y = stats.rankdata(y, axis=None).reshape(y.shape)
    # the permutations keep the set of x values, so their mean and spread: r is proportional to the
    # sum of x times the centred y
    yc = (y - y.mean()).ravel()
    scale = np.sqrt(np.sum((x - x.mean()) ** 2) * np.sum(yc**2))

    def statistic(order, axis):
        return (x[order].reshape(*order.shape[:-1], -1) @ yc) / scale

    batch = max(1, int(2e6 // x.size))  # (about 16 MB of permuted x at a time)
    res = stats.permutation_test(
        (np.arange(len(x)),),
        statistic,
        permutation_type="pairings",
        vectorized=True,
        n_resamples=n_resamples,
        batch=batch,
        random_state=rng,
    )
    return float(res.pvalue)
