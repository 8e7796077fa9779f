"""Identified parameters as TOML in the model file's own keys.

Keys of a ``[casing]`` or ``[cable]`` section (the model schema, ``model/schema.py``): ``alpha`` (1/s) and ``beta``
(s) of Rayleigh damping, Eq. (40); ``loss_factor`` (dimensionless) of Eq. (11), a number or a
table ``[[f_Hz, eta], ...]``; ``E`` (Pa), a number or a table ``[[f_Hz, E_Pa], ...]`` (Section 3.1).
Tables are sorted by strictly increasing frequency, as the model file requires. The values are
written by the model file's own writer (:func:`~cablecasing_core.model.model.toml_text`).
"""

from __future__ import annotations

import numpy as np

from ..errors import ModelError
from ..model.model import toml_text
from ..model.schema import BODY_NAMES as BODIES
from ..model.schema import lookup
from ..model.validators import Choice

#: Significant digits of the numbers written: rounding by at most 5e-10 relative, below the tolerance to which
#: `identify modulus` iterates a modulus (1e-9 of a frequency at least, 2e-9 in E) and far below what a
#: measurement resolves (a circle fit's frequency to 1e-6 at best), so the model gives back what was
#: identified; repr's 17 digits only showed the solvers' last bits (``100.22999999999767``). A table whose
#: frequencies these digits would make equal keeps repr's.
DIGITS = 10


#: The units of the keys written, as the comment line of a section states them (the model file's, model/schema.py):
#: key -> (of a number, of a table).
UNITS = {
    "alpha": ("alpha 1/s",) * 2,
    "beta": ("beta s",) * 2,
    "loss_factor": ("loss_factor dimensionless", "loss_factor [[f_Hz, eta]], eta dimensionless"),
    "E": ("E Pa", "E [[f_Hz, Pa]]"),
}


def _rounded(x, digits=DIGITS):
    """``x`` rounded to ``digits`` significant digits, a float (None: every bit); written by
    ``repr`` (:func:`toml_text`), it has at most that many digits."""
    return float(x) if digits is None else float(f"{float(x):.{digits}g}")


def _checked(body, key, value):
    """``value`` checked by the model file's own rule for ``<body>.<key>`` (the schema), rounded to
    :data:`DIGITS`; a table (rows [f_Hz, value] of any sequence type) is sorted by frequency first."""
    if np.ndim(value) > 0:
        try:
            value = sorted(([float(a), float(b)] for a, b in value), key=lambda r: r[0])
        except (TypeError, ValueError):
            raise ModelError(key, value, "a table must be rows [f_Hz, value]") from None
        lookup(f"{body}.{key}").check(value, key)
        short = [_rounded(a) for a, _ in value]
        digits = DIGITS if all(p < q for p, q in zip(short, short[1:])) else None
        return [[_rounded(a, digits), _rounded(b, digits)] for a, b in value]
    return _rounded(lookup(f"{body}.{key}").check(float(value), key))


def _negative(v):
    """Whether ``v`` is a number below 0 (a fit without the nonnegative bound)."""
    try:
        return float(v) < 0.0
    except (TypeError, ValueError):
        return False


def loss_factor_table(circle_results):
    """``[[f_Hz, eta], ...]`` rows from :class:`~.circlefit.CircleFitResult` objects, sorted by frequency."""
    return sorted([[float(r.f_r_hz), float(r.eta)] for r in circle_results])


def parameters_toml(
    body: str | None = None, alpha=None, beta=None, loss_factor=None, E=None, comment: str | None = None
) -> str:
    """TOML lines with the given identified parameters, in the model file's keys: Rayleigh
    ``alpha``, ``beta`` (Eqs. 40-44), ``loss_factor`` (Eq. 11, Eq. 45), ``E`` (Section 3.1).

    ``body`` ("casing"/"cable") adds the section header ``[body]``; None gives lines to paste under
    an existing header. ``loss_factor`` and ``E`` are numbers or tables ``[[f_Hz, value], ...]``
    (``loss_factor`` may also be a list of circle-fit results). Values are checked against what
    the model file accepts (alpha, beta, loss factor >= 0; E > 0; sorted tables) and written
    with :data:`DIGITS` (10) significant digits. Units: alpha 1/s, beta s, E Pa, frequencies Hz; a section
    (``body`` given) states those of its keys in a comment line before its header (:data:`UNITS`,
    ``# units: alpha 1/s, beta s``).
    """
    lines = []
    if comment:
        lines += [f"# {c}" for c in str(comment).splitlines()]
    if body is not None:
        Choice(*BODIES)("body", body)
        given = {"alpha": alpha, "beta": beta, "loss_factor": loss_factor, "E": E}
        units = "; ".join(
            ", ".join(
                UNITS[k][np.ndim(given[k]) > 0 or isinstance(given[k], (list, tuple))]
                for k in keys
                if given[k] is not None
            )
            for keys in (("alpha", "beta"), ("loss_factor",), ("E",))
            if any(given[k] is not None for k in keys)
        )
        if units:
            lines.append(f"# units: {units}")
        lines.append(f"[{body}]")
    rules = body or BODIES[0]  # (both bodies take the same values)
    for key, v in (("alpha", alpha), ("beta", beta)):
        if v is None:
            continue
        try:
            lines.append(f"{key} = {toml_text(_checked(rules, key, v))}")
        except ModelError as exc:
            if not _negative(v):  # (above the bound, not finite, not a number: the schema's own rule)
                raise
            raise ModelError(
                key, v, f"the model file needs a Rayleigh factor >= 0 ({exc.allowed}); refit with nonnegative=True"
            ) from None
    if loss_factor is not None:
        lf = loss_factor
        if isinstance(lf, (list, tuple)) and lf and hasattr(lf[0], "eta"):
            lf = loss_factor_table(lf)
        lines.append(f"loss_factor = {toml_text(_checked(rules, 'loss_factor', lf))}")
    if E is not None:
        lines.append(f"E = {toml_text(_checked(rules, 'E', E))}")
    return "\n".join(lines) + "\n"
