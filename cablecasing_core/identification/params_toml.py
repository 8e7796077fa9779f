"""Identified parameters as TOML in the model file's own keys.

Keys of a ``[casing]`` or ``[cable]`` section (the model schema, ``model/schema.py``): ``alpha`` (1/s) and ``beta``
(s) of Rayleigh damping, Eq. (40); ``loss_factor`` (dimensionless) of Eq. (11), a number or a
table ``[[f_Hz, eta], ...]``; ``E`` (Pa), a number or a table ``[[f_Hz, E_Pa], ...]`` (Section 3.1).
Tables are sorted by strictly increasing frequency, as the model file requires.
"""
from __future__ import annotations

import numpy as np

from ..errors import ModelError

BODIES = ("casing", "cable")


def _num(x):
    return repr(float(x))


def _table(key, rows, positive):
    try:
        t = [[float(a), float(b)] for a, b in rows]
    except (TypeError, ValueError):
        raise ModelError(key, rows, "a table must be rows [f_Hz, value]") from None
    t.sort(key=lambda r: r[0])
    f = [r[0] for r in t]
    if not t or any(b <= a for a, b in zip(f, f[1:])) or f[0] < 0:
        raise ModelError(key, rows, "table frequencies must be >= 0 Hz and distinct")
    for r in t:
        if not np.isfinite(r[1]) or (r[1] <= 0 if positive else r[1] < 0):
            raise ModelError(key, r, "values must be " + ("positive" if positive else "zero or positive"))
    return "[" + ", ".join(f"[{_num(a)}, {_num(b)}]" for a, b in t) + "]"


def loss_factor_table(circle_results):
    """``[[f_Hz, eta], ...]`` rows from :class:`~.circlefit.CircleFitResult` objects, sorted by frequency."""
    return sorted([[float(r.f_r_hz), float(r.eta)] for r in circle_results])


def parameters_toml(body=None, alpha=None, beta=None, loss_factor=None, E=None, comment=None):
    """TOML lines with the given identified parameters, in the model file's keys: Rayleigh
    ``alpha``, ``beta`` (Eqs. 40-44), ``loss_factor`` (Eq. 11, Eq. 45), ``E`` (Section 3.1).

    ``body`` ("casing"/"cable") adds the section header ``[body]``; None gives lines to paste under
    an existing header. ``loss_factor`` and ``E`` are numbers or tables ``[[f_Hz, value], ...]``
    (``loss_factor`` may also be a list of circle-fit results). Values are checked against what
    the model file accepts (alpha, beta, loss factor >= 0; E > 0; sorted tables) and written
    with full precision. Units: alpha 1/s, beta s, E Pa, frequencies Hz.
    """
    lines = []
    if comment:
        lines += [f"# {c}" for c in str(comment).splitlines()]
    if body is not None:
        if body not in BODIES:
            raise ModelError("body", body, "must be 'casing' or 'cable'")
        lines.append(f"[{body}]")
    for key, v in (("alpha", alpha), ("beta", beta)):
        if v is None:
            continue
        if not np.isfinite(float(v)) or float(v) < 0:
            raise ModelError(key, v, "the model file needs a Rayleigh factor >= 0; refit with nonnegative=True")
        lines.append(f"{key} = {_num(v)}")
    if loss_factor is not None:
        lf = loss_factor
        if isinstance(lf, (list, tuple)) and lf and hasattr(lf[0], "eta"):
            lf = loss_factor_table(lf)
        if np.ndim(lf) == 0:
            if not np.isfinite(float(lf)) or float(lf) < 0:
                raise ModelError("loss_factor", lf, "must be a number >= 0")
            lines.append(f"loss_factor = {_num(lf)}")
        else:
            lines.append(f"loss_factor = {_table('loss_factor', lf, positive=False)}")
    if E is not None:
        if np.ndim(E) == 0:
            if not np.isfinite(float(E)) or float(E) <= 0:
                raise ModelError("E", E, "must be a positive number (Pa)")
            lines.append(f"E = {_num(E)}")
        else:
            lines.append(f"E = {_table('E', E, positive=True)}")
    return "\n".join(lines) + "\n"
