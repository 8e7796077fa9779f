"""Studies of Section 4: octave-band RMS (Table 3) and the Monte-Carlo correlation study (Section 4.4, Fig. 23).

>>> from cablecasing_core.studies import octave_rms, run_study, correlations, plot_correlations
>>> octave_rms(force_N, fs_hz).as_dict()                     # {"oct1": N, ..., "oct9": N}
>>> res = run_study("study.csv", "mypkg.mod:evaluate", n_samples=300, seed=1)   # LocalCluster
>>> correlations(res, "pearson").as_dict()

See docs/studies.md.
"""
from .montecarlo import (AXIAL_AMPLITUDE_KEY, DEFAULT_CONSTRAINTS, DEFAULT_EVALUATE, DEFAULT_OUTPUTS,
                         PAPER_BOUNDS, Correlation, StudyResults, check_bounds, correlations,
                         default_evaluate, gap_constraint, latin_hypercube, load_results,
                         plot_correlations, resolve_evaluate, run_study)
from .octave import TABLE3_LOWER, TABLE3_UPPER, BandRMS, Bands, octave_bands, octave_rms

__all__ = ["AXIAL_AMPLITUDE_KEY", "DEFAULT_CONSTRAINTS", "DEFAULT_EVALUATE", "DEFAULT_OUTPUTS", "PAPER_BOUNDS",
           "TABLE3_LOWER", "TABLE3_UPPER", "BandRMS", "Bands", "Correlation", "StudyResults",
           "check_bounds", "correlations", "default_evaluate", "gap_constraint",
           "latin_hypercube", "load_results", "octave_bands", "octave_rms", "plot_correlations",
           "resolve_evaluate", "run_study"]
