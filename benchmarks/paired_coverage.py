"""Coverage of the paired change's interval and size of its p-value, on simulated ensembles.

A check for docs/studies.md, "Statistics": ``studies.paired_difference(a, b)`` gives the relative
change r of the mean band level with its standard error at the estimated r (ratio-estimator
linearisation) and Student's t interval (how large the change is), and ``p``, the paired t test
of no change (is there a change). Band levels of a chaotic record are skewed where they scatter
most (lognormal of CV 0.5-0.7 in the outer octaves), and neither is exact there.

Each case draws ``--draws`` ensembles of n seeds whose members a_i, b_i are lognormal of the given
CV, correlated ``rho`` per seed on the log scale (the pairing), and a_i scaled by 1 + r_true (the
true relative change of the mean level). Every ensemble is one column of the (n, draws) arrays
handed to the package's ``paired_difference``, so its own formulas are measured. It prints
``name: value`` lines, per case ``n<n>_cv<cv>_rho<rho>_r<r_true>``:

* ``coverage_...``: the share of 95 % intervals ``ci(0.95)`` that hold r_true (nominal 0.95; the
  binomial SE over 100 000 draws is 0.0007);
* ``reject_p_...`` (r_true = 0 only): the share with p < 0.05, the paired t test's size (nominal
  0.05; exact for normal differences);
* ``reject_ci_...`` (r_true = 0 only): the share of intervals that exclude 0, what reading the
  interval (or |r| / SE > t) as the test would reject.

Run (2026-12-08, 100 000 draws per case, about 10 s):
  .venv/bin/python benchmarks/paired_coverage.py
"""

import numpy as np
from _options import checked, integer, parser

from cablecasing_core.studies import paired_difference

SEEDS = (4, 6, 8, 16)
CVS = (0.5, 0.7)
RHOS = (0.0, 0.5)
CHANGES = (0.0, 0.2)


def case(rng, n, cv, rho, r_true, draws, confidence=0.95):
    """(coverage of r_true, rejection rate of p < 1 - confidence, rate of intervals without 0)."""
    s = np.sqrt(np.log1p(cv**2))  # (lognormal of this CV: sd of its log)
    z1 = rng.standard_normal((n, draws))
    z2 = rho * z1 + np.sqrt(1 - rho**2) * rng.standard_normal((n, draws))
    a = (1 + r_true) * np.exp(s * z1)
    b = np.exp(s * z2)
    d = paired_difference(a, b)
    lo, hi = d.ci(confidence)
    covered = np.mean((lo <= r_true) & (r_true <= hi))
    return covered, np.mean(d.p < 1 - confidence), np.mean((lo > 0) | (hi < 0))


def main():
    p = parser(__doc__)
    p.add_argument("--draws", type=int, default=100_000, help="simulated ensembles per case")
    p.add_argument("--seed", type=int, default=2026, help="random generator's seed")
    args = p.parse_args()
    with checked(p):
        integer("--draws", args.draws, 100)
        integer("--seed", args.seed, 0)
    rng = np.random.default_rng(args.seed)
    for n in SEEDS:
        for cv in CVS:
            for rho in RHOS:
                for r_true in CHANGES:
                    cov, rej_p, rej_ci = case(rng, n, cv, rho, r_true, args.draws)
                    name = f"n{n}_cv{cv}_rho{rho}_r{r_true}"
                    print(f"coverage_{name}: {cov:.4f}")
                    if r_true == 0:
                        print(f"reject_p_{name}: {rej_p:.4f}")
                        print(f"reject_ci_{name}: {rej_ci:.4f}")


if __name__ == "__main__":
    main()
