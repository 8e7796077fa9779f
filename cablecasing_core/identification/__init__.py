"""Parameter identification (the paper's Section 3): damping and dynamic modulus from measurements.

* :mod:`.wavelet` - Morlet wavelet transform (:func:`cwt_morlet`) and damping ratios from its
  ridges (:func:`wavelet_damping`, Section 3.2.1, Figs. 10-11).
* :mod:`.rayleigh` - Rayleigh factors alpha, beta by least squares (:func:`rayleigh_fit`, Eqs. 40-44).
* :mod:`.circlefit` - loss factors from Nyquist circles, loss-factor plane and diagonal ridge
  (:func:`loss_factor_circle`, Section 3.2.2, Eq. 45, Figs. 12-13).
* :mod:`.modulus` - frequency-dependent dynamic modulus (:func:`identify_modulus`, Section 3.1, Figs. 8-9).
* :mod:`.frf` - H1/H2 FRF estimates, coherence (:func:`frf_estimate`).
* :mod:`.uff_io` - a time record's column (any record file, :func:`~cablecasing_core.records.read_records`)
  and FRFs from CSV or UFF dataset 58 (the format: :mod:`cablecasing_core.uff`).
* :mod:`.params_toml` - identified parameters in the model file's TOML keys.
* :mod:`.plots` - figures like the paper's Figs. 9, 11 and 13 (matplotlib, Agg).

See docs/identification.md. SI units throughout; frequencies in Hz where named ``*_hz``.
"""

from .circlefit import (
    FRF_KINDS,
    CircleFitResult,
    find_resonances,
    fit_circle,
    loss_factor_circle,
    spectrum_peaks,
    to_displacement_form,
)
from .frf import FRFEstimate, frf_estimate
from .modulus import ModulusResult, identify_modulus, identify_modulus_model
from .params_toml import loss_factor_table, parameters_toml
from .rayleigh import RayleighFit, rayleigh_fit, rayleigh_matrix, rayleigh_zeta
from .uff_io import (
    MeasuredFRF,
    Record,
    frf_kind,
    read_csv_frf,
    read_csv_time,
    read_frf,
    read_frf_function,
    read_frf_kind,
    read_time_record,
    read_time_record_from,
    read_uff,
    write_csv_frf,
    write_csv_time,
    write_uff,
    write_uff_frf,
    write_uff_time,
)
from .wavelet import DEFAULT_GAMMA, RidgeResult, cwt_morlet, edge_length, wavelet_damping, wavelet_time_spread

__all__ = [
    "DEFAULT_GAMMA",
    "FRF_KINDS",
    "CircleFitResult",
    "FRFEstimate",
    "MeasuredFRF",
    "ModulusResult",
    "RayleighFit",
    "Record",
    "RidgeResult",
    "cwt_morlet",
    "edge_length",
    "find_resonances",
    "fit_circle",
    "frf_estimate",
    "identify_modulus",
    "identify_modulus_model",
    "loss_factor_circle",
    "loss_factor_table",
    "parameters_toml",
    "rayleigh_fit",
    "rayleigh_matrix",
    "rayleigh_zeta",
    "spectrum_peaks",
    "read_csv_frf",
    "read_csv_time",
    "frf_kind",
    "read_frf",
    "read_frf_function",
    "read_frf_kind",
    "read_time_record",
    "read_time_record_from",
    "read_uff",
    "to_displacement_form",
    "wavelet_damping",
    "wavelet_time_spread",
    "write_csv_frf",
    "write_csv_time",
    "write_uff",
    "write_uff_frf",
    "write_uff_time",
]
