"""Sampling of the Monte-Carlo study (Section 4.4): the parameters and their bounds (the paper's, or
any numeric keys of any model, from the command line or a file), their check against the model and
the schema, the design, and the feasibility constraint.

Design: Saltelli's scheme for first-order and total Sobol indices (``SALib.sample.sobol.sample``
with ``calc_second_order=False``), on a scrambled Sobol' sequence of dimension 2d
(``scipy.stats.qmc.Sobol(2 d, scramble=True, seed)``) scaled to the bounds: base point j gives the
d + 2 runs A_j, AB_j^(1..d) (A_j with its i-th coordinate from B_j) and B_j, rows j (d + 2) ..
j (d + 2) + d + 1. Every run is a point of the box (each coordinate uniform within its bounds), so
all of them serve the correlations; the groups give the Sobol indices (:mod:`.sensitivity`). The
design is a pure function of (bounds and their order, seed); a larger study is the same sequence
continued (the first N base points of N' > N are those of N), so enlarging a study computes only the
new runs. The Sobol' sequence's balance asks for a power of two of base points (SALib warns
otherwise; the warning is silenced here, the indices stay valid with their bootstrap intervals).

Infeasible samples: the cable must fit in the casing (``cable.d < casing.d_inner``). With the
paper's bounds this always holds (max cable.d 3.3 mm < min casing.d_inner 3.4 mm). For other bounds
the study *rejects* such samples (status ``infeasible``, reason recorded; their groups are left out of
the Sobol indices), also when only one diameter is varied: it is compared with the model's value
of the other (the constraints see the sample's values over the model's).
"""

from __future__ import annotations

import math
import numbers
import warnings
from collections.abc import Iterable, Mapping

import numpy as np

from ..errors import NOT_SHOWN, ModelError, closest
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


_NAMES = "parameter names must be dotted model keys such as 'casing.E'"
_FORM = "must be a dict {key: (low, high)} or a sequence of (key, (low, high))"


def check_bounds(bounds: dict | None = None, model=None, settings=None) -> dict[str, tuple[float, float]]:
    """Validated ``{dotted.key: (low, high)}`` (SI units of the key). Section 4.4.

    ``bounds`` is a dict or a sequence of ``(key, (low, high))`` pairs; ``None`` gives
    :data:`PAPER_BOUNDS`. Every key must be a numeric parameter of ``model`` (a Model, a TOML path,
    or None for the built-in specimen; ``False`` skips the model checks) and a float key of the
    schema whose allowed range holds both bounds. ``settings`` are the run settings of the samples
    that take the place of a model key, ``{setting: (name, value)}`` as
    :func:`~.evaluators.check_not_overridden` takes them (``{"duration": ("duration", 0.2)}``): a key
    a given setting takes the place of (``scenario.duration``) is refused, the samples would not vary
    it. Raises ModelError for an unknown key (listing the keys a study can vary: the model's float
    keys but those), a key given twice, an integer or text key, a key a setting takes the place of,
    bounds that are not two real numbers (text such as ``"2e9"``, True/False), a bound outside the
    allowed range, non-finite bounds or ``low >= high``.
    """
    from ..model.schema import SETTING_KEYS
    from .evaluators import check_not_overridden

    paper = bounds is None
    bounds = _pairs(PAPER_BOUNDS if paper else bounds)
    if not bounds:
        raise ModelError("bounds", bounds, "must name at least one parameter")
    settings = dict(settings or {})
    fixed = {SETTING_KEYS[s] for s, (_, value) in settings.items() if value is not None}
    known = None
    if model is not False:
        from ..model import Model, load_model

        m = model if isinstance(model, Model) else load_model(model)
        known = m.parameters()
    out = {}
    for key, b in bounds.items():
        if not isinstance(key, str):
            raise ModelError("bounds", key, _NAMES)
        check_not_overridden(
            {key: (f"bounds.{key}", b)},
            settings,
            "every sample",
            "; vary {key} without {name} (each sample runs its own)",
        )
        if known is not None and key not in known:
            varied = sorted(k for k in known if _float_key(k) and k not in fixed)  # (what a study can vary)
            hint = " (the paper's six parameters are the default; give others, e.g. --vary casing.E=2e9:1e10)"
            close = closest(key, varied)
            mean = f" (did you mean {close[0]}?)" if close else ""
            raise ModelError(
                f"bounds.{key}",
                NOT_SHOWN,  # (the value of an unknown key, maybe of a file that is no study's, is not shown)
                f"is not a numeric parameter of the model {m.source}{hint if paper else ''}{mean}; those a study "
                "can vary: " + ", ".join(varied),
            )
        try:
            pair = tuple(b)
        except TypeError:
            pair = ()
        if len(pair) != 2 or not all(isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_)) for v in pair):
            raise ModelError(f"bounds.{key}", b, "must be a pair (low, high) of numbers (not text or True/False)")
        lo, hi = (float(v) for v in pair)
        if not (math.isfinite(lo) and math.isfinite(hi)):
            raise ModelError(f"bounds.{key}", b, "must be finite numbers")
        if lo >= hi:
            raise ModelError(f"bounds.{key}", b, "lower bound must be below the upper bound")
        out[key] = (lo, hi)
    if known is not None:
        _check_schema(m, out)
    return out


def _pairs(bounds):
    """``bounds`` as a dict: a mapping, or a sequence of (key, (low, high)) pairs that names each
    key once (a key given twice is refused: a dict would keep only its last bounds)."""
    if isinstance(bounds, Mapping):
        return dict(bounds)
    if isinstance(bounds, (str, bytes)) or not isinstance(bounds, Iterable):
        raise ModelError("bounds", bounds, _FORM)
    out = {}
    for item in bounds:
        if not (isinstance(item, (tuple, list)) and len(item) == 2):
            raise ModelError("bounds", item, _FORM)
        key, b = item
        if not isinstance(key, str):
            raise ModelError("bounds", key, _NAMES)
        if key in out:
            raise ModelError(f"bounds.{key}", b, f"names {key!r} again (first {out[key]!r}); give each key once")
        out[key] = b
    return out


def _float_key(key):
    """Whether the model key ``key`` takes a continuous value (a float key of the schema), as a study
    samples it (:func:`_check_schema`)."""
    from ..model.schema import lookup

    return lookup(key).type in _FLOAT_TYPES


_FLOAT_TYPES = ("float", "float or table")


def _check_schema(model, bounds):
    """Every parameter must be a float key of the schema whose allowed range holds both bounds.
    (Cross-checks between keys, such as the gap, are the constraints' and the model's at each run.)"""
    from ..model.schema import lookup

    for key, (lo, hi) in bounds.items():
        spec = lookup(key)
        if spec.type not in _FLOAT_TYPES:
            raise ModelError(
                f"bounds.{key}", [lo, hi], f"is a key of type {spec.type}; a study samples continuous (float) keys only"
            )
        for v in (lo, hi):
            try:
                spec.check(v, key)
            except ModelError as exc:
                raise ModelError(f"bounds.{key}", [lo, hi], f"must lie in the key's allowed range ({exc})") from None


def group_size(bounds: dict) -> int:
    """Runs per base point of the design: d + 2 for d parameters (A, AB^(1..d), B)."""
    return len(bounds) + 2


def base_points(bounds: dict, n_samples: int) -> int:
    """Base points of a design of at least ``n_samples`` runs: ceil(n_samples / (d + 2)), at least 2."""
    return max(2, math.ceil(integer("n_samples", n_samples, 2) / group_size(bounds)))


def sobol_design(bounds: dict | None = None, n_base: int = 8, seed: int = 0) -> np.ndarray:
    """Saltelli's design (n_base (d + 2), d) in the bounds' SI units (module docstring): runs of
    ``n_base`` base points of a scrambled Sobol' sequence with ``seed``. Deterministic in (bounds,
    seed); the design of a larger n_base starts with this one. Keys are not checked against a model
    here (see :func:`check_bounds`)."""
    bounds = check_bounds(bounds, model=False)
    n = integer("n_base", n_base, 2)
    seed = integer("seed", seed, 0)
    from SALib.sample import sobol

    problem = {"num_vars": len(bounds), "names": list(bounds), "bounds": [list(b) for b in bounds.values()]}
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*balance properties of Sobol.*")
        return sobol.sample(problem, n, calc_second_order=False, scramble=True, seed=seed)


def parse_vary(text: str) -> tuple[str, tuple[float, float]]:
    """``"casing.E=2e9:1e10"`` -> ``("casing.E", (2e9, 1e10))`` (``--vary KEY=LOW:HIGH``, SI units)."""
    key, sep, rng = str(text).partition("=")
    lo, sep2, hi = rng.partition(":")
    try:
        if not (sep and sep2 and key.strip()):
            raise ValueError
        return key.strip(), (float(lo), float(hi))
    except ValueError:
        raise ModelError(
            "--vary", text, "must be KEY=LOW:HIGH with a dotted model key, e.g. casing.E=2e9:1e10"
        ) from None


def read_vary_file(path) -> dict[str, tuple[float, float]]:
    """The bounds in a TOML file, one ``key = [low, high]`` per parameter (dotted keys, SI units)::

    casing.E = [2e9, 1e10]
    contact.friction = [0.05, 0.2]
    """
    from ..model.load import MAX_MODEL_BYTES, toml_file
    from ..model.model import dotted

    out = dotted(toml_file(path, "--vary-file", MAX_MODEL_BYTES))
    if not out:
        raise ModelError("--vary-file", str(path), "names no parameter; write lines such as casing.E = [2e9, 1e10]")
    return out


def gap_constraint(params):
    """Feasibility of a sample (Section 4.4; the radial gap of Eqs. 30-31 must be positive):
    ``None`` if ``cable.d < casing.d_inner`` (both in m), else the reason. ``params`` are the
    sample's values over the model's (:func:`~.study.run_study`), so that a diameter varied alone is
    compared with the model's value of the other; checked when ``params`` hold both."""
    if "cable.d" in params and "casing.d_inner" in params and params["cable.d"] >= params["casing.d_inner"]:
        return (
            f"infeasible: cable.d = {params['cable.d']!r} m is not below casing.d_inner = "
            f"{params['casing.d_inner']!r} m"
        )
    return None


DEFAULT_CONSTRAINTS = (gap_constraint,)
