"""Studies of Section 4: octave-band RMS (Table 3), the Monte-Carlo correlation study (Section 4.4,
Fig. 23) and band levels as ensemble means over excitation seeds.

>>> from cablecasing_core.studies import octave_rms, run_study, correlations, plot_correlations
>>> octave_rms(force_N, fs_hz).as_dict()                     # {"oct1": N, ..., "oct9": N}
>>> res = run_study("study.csv", "mypkg.mod:evaluate", n_samples=300, seed=1)   # LocalCluster
>>> correlations(res, "pearson").as_dict()
>>> sobol_indices(res).ST                                     # total Sobol indices (parameters x bands)
>>> ens = seed_ensemble(model, seeds=8)                      # band levels over excitation seeds
>>> ens.mean, ens.se, paired_difference(ens_a, ens_b).r
>>> ens.save("part1.csv"); pool_ensembles(["part1.csv", "part2.csv"])   # an ensemble run in parts

Band RMS (``octave_rms``, ``octave_bands``, ``Bands``, ``BandRMS``) is :mod:`cablecasing_core.nvh.bands`'s,
named here too (``studies.octave``, its earlier home, still imports every name of it). Modules: ``sampling``
(bounds, Saltelli's design, constraints), ``evaluators`` (per-sample functions), ``executor`` (serial or
dask), ``results_store`` (the resumable CSV),
``study`` (``run_study``), ``correlation``, ``sensitivity`` (Sobol indices, size checks),
``ensemble`` (the data), ``ensemble_runs`` (``seed_ensemble``), ``plots``. See docs/studies.md.
"""

from ..nvh.bands import TABLE3_LOWER, TABLE3_UPPER, BandRMS, Bands, octave_bands, octave_rms
from .correlation import GAP, Correlation, correlations
from .ensemble import Ensemble, PairedDifference, load_ensemble, paired_difference, pool_ensembles
from .ensemble_runs import random_excitations, seed_ensemble, seed_ensembles, seed_overrides
from .evaluators import DEFAULT_EVALUATE, DEFAULT_OUTPUTS, default_evaluate
from .executor import execute, resolve_evaluate
from .plots import plot_correlations, plot_ensemble, plot_sobol
from .results_store import StudyResults, load_results
from .sampling import (
    AXIAL_AMPLITUDE_KEY,
    DEFAULT_CONSTRAINTS,
    PAPER_BOUNDS,
    check_bounds,
    gap_constraint,
    parse_vary,
    read_vary_file,
    sobol_design,
)
from .sensitivity import SobolIndices, critical_correlation, size_warnings, sobol_indices
from .study import run_study

__all__ = [
    "AXIAL_AMPLITUDE_KEY",
    "DEFAULT_CONSTRAINTS",
    "DEFAULT_EVALUATE",
    "DEFAULT_OUTPUTS",
    "GAP",
    "PAPER_BOUNDS",
    "TABLE3_LOWER",
    "TABLE3_UPPER",
    "BandRMS",
    "Bands",
    "Correlation",
    "Ensemble",
    "PairedDifference",
    "StudyResults",
    "check_bounds",
    "correlations",
    "default_evaluate",
    "execute",
    "gap_constraint",
    "parse_vary",
    "read_vary_file",
    "sobol_design",
    "sobol_indices",
    "size_warnings",
    "critical_correlation",
    "SobolIndices",
    "plot_sobol",
    "load_ensemble",
    "load_results",
    "octave_bands",
    "octave_rms",
    "paired_difference",
    "plot_correlations",
    "plot_ensemble",
    "pool_ensembles",
    "random_excitations",
    "resolve_evaluate",
    "run_study",
    "seed_ensemble",
    "seed_ensembles",
    "seed_overrides",
]
