"""Frequency-dependent dynamic modulus of elasticity from measured natural frequencies.

The paper's Section 3.1 (Figs. 8-9, after its Ref. [20]): for every measured natural frequency
``f_i`` of a known mode (its index in the ascending list of computed frequencies), the model's
modulus is adapted until the computed frequency of that mode is within half the frequency
resolution of the measurement (0.25 Hz in the paper), tested after one update at least (the start
is the model's guess, not a measurement). The first adaptive step uses that a body's stiffness
matrix is proportional to ``E`` while the mass matrix is not, so ``f ~ sqrt(E)``:

    E_1 = E_0 (f_measured / f_computed(E_0))^2          (Fig. 8)

(exact in one step for a homogeneous body). Where part of the stiffness does not scale with ``E``
(isolators, clips, cable tension, the other body), ``f^2 = a E + b`` with ``b > 0`` for a linear
model, and repeating that step converges only linearly, at a rate equal to the share ``b / f^2``
(0.7-0.8 took 40 steps and more). The following steps are therefore secant steps in ``f^2``
against ``E``,

    E_{k+1} = E_k - (f_k^2 - f_measured^2) (E_k - E_{k-1}) / (f_k^2 - f_{k-1}^2),

exact (up to rounding) on the affine ``f^2 = a E + b``, so one or two steps after the first; a
secant step that does not give a positive modulus within a factor 10 of ``E_k`` (``f^2`` not
rising with ``E``, or nearly flat) falls back to the first step's rule. The pairs ``(f_i, E_i)``
(Fig. 9, circles) are then approximated by a smooth curve, a least-squares polynomial in
``ln(f / f_ref)`` (degree 2 by default, lower when there are fewer modes, ``f_ref`` the geometric mean
of the measured frequencies) and tabulated as ``[[f_Hz, E_Pa], ...]`` rows, the form the model
file accepts for ``E`` (linear interpolation between rows, held constant outside).

The identification is written against a callable ``compute_frequencies(E_Pa) -> Hz (ascending)``
so it does not depend on the FE model; :func:`identify_modulus_model` wraps the package's own
``natural_frequencies`` for a model and a body.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from ..model.validators import array_1d, integer, number


@dataclass(frozen=True)
class ModulusResult:
    """Result of :func:`identify_modulus` (SI: Hz, Pa).

    ``E_mode[i]`` is the modulus that reproduces ``f_measured_hz[i]`` for mode ``modes[i]``
    (1-based), ``f_computed_hz[i]`` the frequency it gives, ``history[i]`` the list of
    ``(E, f_computed)`` steps of the adaptive process (Fig. 8). ``coefficients`` of the smooth fit
    ``E(f) = sum_k c_k ln(f / f_ref)^k``; ``table`` its tabulation ``[[f_Hz, E_Pa], ...]``.
    """

    f_measured_hz: np.ndarray
    modes: np.ndarray
    E_mode: np.ndarray
    f_computed_hz: np.ndarray
    history: list
    f_ref_hz: float
    coefficients: np.ndarray
    table: list
    tolerance_hz: float

    def E_fit(self, f_hz):
        """The smooth fit E(f) (Pa) at ``f_hz`` (Hz)."""
        u = np.log(np.asarray(f_hz, dtype=float) / self.f_ref_hz)
        return np.polynomial.polynomial.polyval(u, self.coefficients)

    def E_uncertainty(self, f_uncertainty_hz):
        """Uncertainty (Pa) of each mode's modulus ``E_mode`` caused by an uncertainty ``f_uncertainty_hz``
        (Hz; one per mode, or one for all) of its measured frequency, to first order:
        ``dE = 2 f df / s`` with ``s`` the slope of ``f^2`` against ``E`` through the adaptive process's
        last two steps (exact on ``f^2 = a E + b``); ``2 E df / f`` (a homogeneous body, ``f ~ sqrt(E)``)
        where the steps give no slope."""
        df = np.broadcast_to(np.asarray(f_uncertainty_hz, dtype=float), self.E_mode.shape)
        out = np.empty(self.E_mode.size)
        for i, (steps, f, E) in enumerate(zip(self.history, self.f_measured_hz, self.E_mode)):
            (E0, f0), (E1, f1) = steps[-2:] if len(steps) > 1 else steps * 2
            slope = (f1**2 - f0**2) / (E1 - E0) if E1 != E0 else 0.0
            out[i] = 2.0 * f * df[i] / slope if slope > 0.0 else 2.0 * E * df[i] / f
        return out


#: Default degree of the smooth curve in ln(f / f_ref) through the identified moduli (``degree``).
DEGREE = 2
#: Default number of rows of the E(f) table (``n_table``).
N_TABLE = 12


def identify_modulus(
    compute_frequencies,
    f_measured_hz,
    modes,
    E_start,
    freq_resolution_hz=None,
    degree=DEGREE,
    table_freqs_hz=None,
    n_table=N_TABLE,
    max_iter=50,
) -> ModulusResult:
    """Dynamic modulus per measured mode and a smooth E(f) table (Section 3.1, Figs. 8-9).

    Parameters
    ----------
    compute_frequencies : callable
        ``compute_frequencies(E_Pa: float) -> array of natural frequencies (Hz), ascending``.
    f_measured_hz : array (m,)
        Measured natural frequencies (Hz).
    modes : array of int (m,)
        Mode number of each measured frequency: 1-based index into the computed list.
    E_start : float
        Starting modulus (Pa).
    freq_resolution_hz : float or None
        Frequency resolution of the measurement (Hz); the iteration stops when the computed
        frequency is within half of it (the paper: 0.5 Hz resolution, 0.25 Hz), after one update
        ``E (f_measured / f_computed)^2`` at least (exact for a homogeneous body: a start already
        within the tolerance is not kept). None: to a relative 1e-10.
    degree : int or None
        Degree of the smooth fit in ``ln f`` (reduced to m - 1 when fewer modes); None tabulates
        the per-mode moduli themselves (interpolating table).
    table_freqs_hz : array or None
        Frequencies (Hz) of the table rows; default ``n_table`` points spaced geometrically
        between the lowest and highest measured frequency.
    max_iter : int
        Limit of adaptive steps per mode.

    Returns
    -------
    :class:`ModulusResult`.

    Raises
    ------
    ModelError
        Mismatched lengths, non-positive frequencies or moduli, a mode number given twice or beyond
        the computed list, no convergence (the frequency cannot be reached by changing E).
    """
    f_m = array_1d("f_measured_hz", f_measured_hz, min_len=1)
    if np.any(f_m <= 0):
        raise ModelError("f_measured_hz", float(f_m[f_m <= 0][0]), "measured frequencies must be positive (Hz)")
    md = np.atleast_1d(np.asarray(modes))
    if md.shape != f_m.shape:
        raise ModelError("modes", md.tolist(), f"must give one mode number per measured frequency ({f_m.size})")
    if not np.all(np.equal(np.mod(md, 1), 0)) or np.any(md < 1):
        raise ModelError("modes", md.tolist(), "mode numbers are whole numbers >= 1 (1 = lowest mode)")
    md = md.astype(int)
    values, counts = np.unique(md, return_counts=True)
    if np.any(counts > 1):
        raise ModelError(
            "modes",
            md.tolist(),
            f"must name each mode once: mode {int(values[counts > 1][0])} is given {int(counts.max())} times "
            "(one measured frequency per mode; a circular section's near-equal pair is two modes, 1 and 2)",
        )
    E0 = number("E_start", E_start, gt=0, unit="Pa")
    if freq_resolution_hz is not None:
        number("freq_resolution_hz", freq_resolution_hz, gt=0, unit="Hz")

    def freqs(E):
        f = np.asarray(compute_frequencies(float(E)), dtype=float)
        if f.ndim != 1 or f.size < md.max():
            raise ModelError(
                "modes",
                int(md.max()),
                f"compute_frequencies returned {f.size} frequencies; mode numbers must not exceed that",
            )
        return f

    f_start = freqs(E0)
    E_mode = np.empty(f_m.size)
    f_comp = np.empty(f_m.size)
    history = []
    for i, (fi, mi) in enumerate(zip(f_m, md)):
        tol = 0.5 * float(freq_resolution_hz) if freq_resolution_hz is not None else 1e-10 * fi
        E, fc = E0, f_start[mi - 1]
        steps = [(E, fc)]
        for k in range(int(max_iter)):
            # (one update at least: a start already within the tolerance was returned as it was, so the
            # modulus leaned towards the model's guess: 5e9 Pa for a mode of 5.2e9 Pa 0.2 Hz away at 0.5 Hz)
            if k and abs(fc - fi) <= tol:
                break
            if fc <= 0:
                raise ModelError("f_measured_hz", float(fi), f"mode {mi} has a non-positive computed frequency")
            E = _next_modulus(steps, fi)
            fc = freqs(E)[mi - 1]
            steps.append((E, fc))
        else:
            if abs(fc - fi) > tol:
                raise ModelError(
                    "f_measured_hz",
                    float(fi),
                    f"mode {mi}: no modulus reproduces this frequency within {tol:g} Hz "
                    f"after {max_iter} steps (last E = {E:g} Pa gives {fc:g} Hz)",
                )
        E_mode[i], f_comp[i] = E, fc
        history.append(steps)
    f_ref = float(np.exp(np.mean(np.log(f_m))))
    u = np.log(f_m / f_ref)
    if degree is None:
        order = np.argsort(f_m)
        fu, idx = np.unique(f_m[order], return_index=True)
        coeffs = (
            np.polynomial.polynomial.polyfit(u, E_mode, min(f_m.size - 1, 2)) if f_m.size > 1 else np.array([E_mode[0]])
        )
        table = [[float(a), float(b)] for a, b in zip(fu, E_mode[order][idx])]
    else:
        if int(degree) < 0:
            raise ModelError("degree", degree, "must be a whole number >= 0 or None")
        deg = min(int(degree), np.unique(f_m).size - 1)
        coeffs = np.polynomial.polynomial.polyfit(u, E_mode, deg) if deg > 0 else np.array([np.mean(E_mode)])
        if table_freqs_hz is None:
            if f_m.min() == f_m.max():
                tf = np.array([f_m.min()])
            else:
                tf = np.geomspace(f_m.min(), f_m.max(), integer("n_table", n_table, 2))
        else:
            tf = np.unique(array_1d("table_freqs_hz", table_freqs_hz, min_len=1))
            if np.any(tf < 0):
                raise ModelError("table_freqs_hz", float(tf[0]), "must be frequencies >= 0 Hz")
        with np.errstate(divide="ignore"):
            Et = np.polynomial.polynomial.polyval(np.log(np.maximum(tf, 1e-300) / f_ref), coeffs)
        if np.any(Et <= 0):
            raise ModelError(
                "degree", degree, "the smooth fit gives a non-positive modulus in the table's range; use a lower degree"
            )
        table = [[float(a), float(b)] for a, b in zip(tf, Et)]
    return ModulusResult(
        f_measured_hz=f_m,
        modes=md,
        E_mode=E_mode,
        f_computed_hz=f_comp,
        history=history,
        f_ref_hz=f_ref,
        coefficients=np.asarray(coeffs, dtype=float),
        table=table,
        tolerance_hz=0.5 * float(freq_resolution_hz) if freq_resolution_hz is not None else 0.0,
    )


#: Largest factor by which a secant step may change the modulus; beyond it (f^2 nearly flat in E)
#: the fixed-point step is taken instead.
_MAX_SECANT_FACTOR = 10.0


def _next_modulus(steps, f_target):
    """The next modulus (Pa) from the steps ``[(E, f_computed), ...]`` so far: the fixed-point step
    ``E (f_target / f)^2`` first, then the secant in ``f^2`` against ``E`` through the last two steps
    (module docstring), or the fixed-point step when the secant does not give a positive modulus
    within a factor :data:`_MAX_SECANT_FACTOR` of the last."""
    E1, f1 = steps[-1]
    fixed_point = E1 * (f_target / f1) ** 2
    if len(steps) < 2:
        return fixed_point
    E0, f0 = steps[-2]
    slope = (f1**2 - f0**2) / (E1 - E0) if E1 != E0 else 0.0
    if not slope > 0.0:
        return fixed_point
    E = E1 - (f1**2 - f_target**2) / slope
    if not E1 / _MAX_SECANT_FACTOR <= E <= E1 * _MAX_SECANT_FACTOR:
        return fixed_point
    return E


def identify_modulus_model(
    model, body: str, f_measured_hz, modes, freq_resolution_hz=None, degree=DEGREE, count=None, **kw
) -> ModulusResult:
    """:func:`identify_modulus` on the package's FE model of ``body`` ("casing" or "cable").

    ``compute_frequencies(E) = cablecasing_core.natural_frequencies(model.with_overrides({f"{body}.E": E}),
    body, count)`` with ``count`` defaulting to the highest mode number; the start is the model's
    reference modulus. The identified table is put into a model by
    ``model.with_overrides({f"{body}.E": result.table})``. ``f_measured_hz`` and
    ``freq_resolution_hz`` in Hz, as :func:`identify_modulus`'s; the result's table is
    ``[[f_Hz, E_Pa], ...]`` (Hz, Pa: :class:`ModulusResult`).
    """
    from ..frequency.modal import natural_frequencies

    if body not in model.bodies:
        raise ModelError(
            "body", body, f"must be a body of the model {model.source}: " + ", ".join(repr(b) for b in model.bodies)
        )
    md = np.atleast_1d(np.asarray(modes))
    n = int(count) if count is not None else int(np.max(md))

    def compute(E):
        return natural_frequencies(model.with_overrides({f"{body}.E": float(E)}), body, n)

    return identify_modulus(
        compute,
        f_measured_hz,
        modes,
        model.bodies[body].E_ref,
        freq_resolution_hz=freq_resolution_hz,
        degree=degree,
        **kw,
    )
