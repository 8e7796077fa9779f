"""The buckling load of a body under axial compression: the honest check of a tension that the
casing must carry as compression.

The casing's compression P (the cable's tension) softens it by its geometric stiffness,
K = K_E - P K_G1 (K_G1 the geometric stiffness of a unit tension, element_beam.py). It buckles at
the smallest P that makes K singular on the free DOFs: the generalized eigenproblem
K_G1 phi = mu K_E phi, P_cr = 1 / mu_max (K_E positive definite with a clamped support, K_G1
positive semi-definite). For a straight clamped-clamped body this is Euler's 4 pi^2 EI / L^2
(to the discretisation); for the routed casing it is the linearised buckling load of the curved,
supported casing, which no closed form gives. Below it, and only below it, K is positive definite,
which is what the check tests (a banded Cholesky factorisation); the load itself is computed for
the message of a refusal.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import cholesky_banded, eigh

from ..errors import ModelError


def buckling_load(system) -> float:
    """The compression (N) at which the tangent stiffness of ``system`` (an assembled
    :class:`~cablecasing_core.structure.assembly.BodySystem` with a prestress N0 != 0) turns
    singular on its free DOFs; inf when no compression can."""
    f = system.free
    KE = system.K_E.toarray()[np.ix_(f, f)]
    KG1 = system.K_G.toarray()[np.ix_(f, f)] / system.N0  # K_G1: of a unit tension (K_G is linear in N0)
    mu = eigh(KG1, KE, eigvals_only=True)[-1]  # (all of them: LAPACK's subset driver is slower here)
    return float(1.0 / mu) if mu > 0.0 else float("inf")


def is_positive_definite(system) -> bool:
    """Whether the tangent stiffness of ``system`` on its free DOFs is positive definite (its
    compression below the buckling load): a banded Cholesky factorisation (half-bandwidth 11)
    succeeds, ~0.2 ms instead of an eigenproblem."""
    f = system.free
    A = system.K.toarray()[np.ix_(f, f)]
    n, b = len(f), 11
    ab = np.zeros((b + 1, n))
    for k in range(b + 1):  # upper form: ab[b - k, j] = A[j - k, j]
        j = np.arange(k, n)
        ab[b - k, j] = A[j - k, j]
    try:
        cholesky_banded(ab, check_finite=False)
    except np.linalg.LinAlgError:
        return False
    return True


def check_compression(system) -> None:
    """Refuse (ModelError naming loads.cable_tension) a body whose compression -N0 reaches its
    buckling load; the message gives the load, and for a straight clamped body Euler's too."""
    P = -system.N0
    if P <= 0.0 or is_positive_definite(system):
        return
    P_cr = buckling_load(system)
    EI = system.E * system.section.I
    L = system.centerline.length
    euler = ""
    if all(v == "clamped" for v in system.spec.supports.values()):
        euler = f"; a straight clamped {system.name} of this length ({L:.4g} m) buckles at 4 pi^2 EI / L^2 = " + (
            f"{4 * np.pi**2 * EI / L**2:.4g} N"
        )
    raise ModelError(
        "loads.cable_tension",
        P,
        f"must be below the {system.name}'s buckling load {P_cr:.4g} N (the compression it carries, equal to "
        f"the cable's tension, at which its tangent stiffness K_E + K_G turns singular{euler})",
    )
