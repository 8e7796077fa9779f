"""Sampling of the Monte-Carlo study (Section 4.4): the parameters and bounds of the paper, their
check against a model, the Latin hypercube and the feasibility constraint.

``scipy.stats.qmc.LatinHypercube(d, rng=seed)`` with ``scramble=True`` (a random point inside each
stratum), scaled to the bounds. The design is a pure function of ``(bounds, n_samples, seed)``;
sample ``i`` is row ``i`` of it, so it is the same in serial and in parallel runs and after a restart.

Infeasible samples: the cable must fit in the casing (``cable.d < casing.d_inner``). With the
paper's bounds this always holds (max cable.d 3.3 mm < min casing.d_inner 3.4 mm). For other bounds
the study *rejects* such samples (status ``infeasible``, reason recorded) rather than sampling the
gap, so that the six named parameters keep their Latin-hypercube stratification.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import ModelError
from ..model.validators import integer

#: Model key of the amplitude (m) of the cable's longitudinal (axial) excitation, \bar X_jv of Section 4.4.
AXIAL_AMPLITUDE_KEY = "scenario.excitation.cable_axial.amplitude"

#: The six parameters of Section 4.4 with their bounds (SI). The paper gives no bounds for the
#: axial amplitude; 0.5x-2x the built-in 5e-4 m (displacement amplitude along the cable tangent,
#: the unit of the scenario's harmonic excitation) is used.
PAPER_BOUNDS = {
    "cable.E": (3.0e10, 8.5e10),  # Pa, E_jv
    "casing.E": (0.2e10, 1.0e10),  # Pa, E_op
    "cable.d": (0.003, 0.0033),  # m, D_z0
    "casing.d_inner": (0.0034, 0.0046),  # m, d_5
    AXIAL_AMPLITUDE_KEY: (2.5e-4, 1.0e-3),  # m, \bar X_jv
    "contact.friction": (0.05, 0.2),  # -, eta
}


def check_bounds(bounds: dict | None = None, model=None) -> dict[str, tuple[float, float]]:
    """Validated ``{dotted.key: (low, high)}`` (SI units of the key). Section 4.4.

    ``None`` gives :data:`PAPER_BOUNDS`. Every key must be a numeric parameter of ``model`` (a Model,
    a TOML path, or None for the built-in specimen; ``False`` skips the key check). Raises
    ModelError for an unknown key, non-finite bounds or ``low >= high``.
    """
    bounds = dict(PAPER_BOUNDS if bounds is None else bounds)
    if not bounds:
        raise ModelError("bounds", bounds, "must name at least one parameter")
    known = None
    if model is not False:
        from ..model import Model, load_model

        m = model if isinstance(model, Model) else load_model(model)
        known = m.parameters()
    out = {}
    for key, b in bounds.items():
        if not isinstance(key, str):
            raise ModelError("bounds", key, "parameter names must be dotted model keys such as 'casing.E'")
        if known is not None and key not in known:
            raise ModelError(
                f"bounds.{key}", b, "is not a numeric parameter of the model; known: " + ", ".join(sorted(known))
            )
        try:
            lo, hi = (float(v) for v in b)
        except (TypeError, ValueError):
            raise ModelError(f"bounds.{key}", b, "must be a pair (low, high) of numbers") from None
        if not (math.isfinite(lo) and math.isfinite(hi)):
            raise ModelError(f"bounds.{key}", b, "must be finite numbers")
        if lo >= hi:
            raise ModelError(f"bounds.{key}", b, "lower bound must be below the upper bound")
        out[key] = (lo, hi)
    return out


def latin_hypercube(bounds: dict | None = None, n_samples: int = 300, seed: int = 0) -> np.ndarray:
    """Latin-hypercube design (n_samples, d) in the bounds' SI units (Section 4.4, "Monte Carlo").

    Columns follow the order of ``bounds`` (default :data:`PAPER_BOUNDS`). Each column has exactly
    one point in each of the ``n_samples`` equal strata of its interval
    (``scipy.stats.qmc.LatinHypercube(d, scramble=True, rng=seed)``). Deterministic in
    (bounds, n_samples, seed). Keys are not checked against a model here (see :func:`check_bounds`).
    """
    bounds = check_bounds(bounds, model=False)
    n = integer("n_samples", n_samples, 2)
    seed = integer("seed", seed, 0)
    from scipy.stats import qmc

    try:
        sampler = qmc.LatinHypercube(len(bounds), scramble=True, rng=seed)
    except TypeError:  # scipy < 1.15 names it seed (same default_rng stream)
        sampler = qmc.LatinHypercube(len(bounds), scramble=True, seed=seed)
    unit = sampler.random(n)
    lo = np.array([b[0] for b in bounds.values()])
    hi = np.array([b[1] for b in bounds.values()])
    return qmc.scale(unit, lo, hi)


def gap_constraint(params):
    """Feasibility of a sample (Section 4.4; the radial gap of Eqs. 30-31 must be positive):
    ``None`` if ``cable.d < casing.d_inner`` (both in m), else the reason. Only checked when both
    diameters are sampled; the model's own validation catches the rest at evaluation."""
    if "cable.d" in params and "casing.d_inner" in params and params["cable.d"] >= params["casing.d_inner"]:
        return (
            f"infeasible: cable.d = {params['cable.d']!r} m is not below casing.d_inner = "
            f"{params['casing.d_inner']!r} m"
        )
    return None


DEFAULT_CONSTRAINTS = (gap_constraint,)
