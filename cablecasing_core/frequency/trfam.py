"""Steady-state frequency response: the apparent-mass transfer function TRFAM (Eqs. 10-13).

With the DOFs partitioned into free (f) and prescribed support DOFs (p), Eq. (13), the harmonic
response to a unit support displacement x_p = e_j exp(i omega t) is

    x_f = -D_ff^-1 D_fp e_j,        f_p = D_pf x_f + D_pp e_j,

with the dynamic stiffness D(omega) = kappa(omega) K - (omega^2 - i omega alpha) M:

* viscous (Eq. 10, Rayleigh C = alpha M + beta K(omega)): kappa = s (1 + i omega beta),
* structural (Eq. 11, complex modulus E_d (1 + i eta)): kappa = s (1 + i eta(omega)), alpha = 0,

where s(omega) = E_d(omega) / E_ref applies the frequency-dependent modulus at each frequency.
D_ff is diagonalised exactly by the undamped modes of (K, M) because both damping models are
proportional; the solve is then a modal sum over all modes (no truncation), vectorised over
frequency. TRFAM (Eq. 12) = f_p,out / (acceleration of the input DOF) = f_p / (-omega^2), in kg.

With isolators or clips (``structure/mount_element.py``) the supports' own nodes are prescribed
DOFs of the augmented system and each mount adds its complex dynamic stiffness
K6 k_scale(f) (1 + i loss(f)) + i omega C6 between body node and support node. That damping is not
proportional, so D_ff is then solved directly at each frequency (dense LU, in blocks of
frequencies); f_p at an isolator's support node is the force through the isolator.

Sign convention: f_p is the force the support applies to the body (the reaction of Eq. 13), so a
rigid mass m has a driving-point apparent mass of +m.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ModelError
from ..model.schema import DIRECTIONS, SUPPORT_NAMES
from ..model.validators import Choice, frequencies
from ..structure.assembly import assemble_body
from .modal import modal_basis

if TYPE_CHECKING:
    from ..model import Model

DAMPING_MODELS = ("viscous", "structural", "none")


def parse_port(key, value, model):
    """Split ``"casing.A.x"`` into (body, support, component index 0..2), checking it exists."""
    parts = value.split(".") if isinstance(value, str) else []
    if len(parts) != 3 or parts[1] not in SUPPORT_NAMES or parts[2] not in DIRECTIONS:
        raise ModelError(key, value, "must be '<body>.<A|B>.<x|y|z>', e.g. 'casing.A.x'")
    body, support, d = parts
    if body not in model.bodies:
        raise ModelError(key, value, "body must be one of " + ", ".join(repr(b) for b in model.bodies))
    if model.bodies[body].supports[support] == "free":
        raise ModelError(key, value, f"support {body}.{support} is free; TRFAM needs clamped or isolator supports")
    return body, support, DIRECTIONS.index(d)


class FrequencyResponse:
    """Reusable modal data of one body for repeated TRFAM evaluation.

    Build once per body, then call :meth:`support_forces` for any frequency vector.
    """

    def __init__(self, system):
        self.system = system
        if system.mounts:
            return  # solved directly (support_forces)
        basis = modal_basis(system)
        self.lam = basis.lam
        Kff, Kfp, Kpf, Kpp = system.K_blocks
        Mff, Mfp, Mpf, Mpp = system.M_blocks
        phi = basis.phi
        self.Kin, self.Min = phi.T @ Kfp, phi.T @ Mfp  # modal loads of unit support motion
        self.Kout, self.Mout = Kpf @ phi, Mpf @ phi  # support forces of unit modal motion
        self.Kpp, self.Mpp = Kpp, Mpp

    def support_forces(self, freqs_hz: ArrayLike, damping: str = "viscous", rows=None, cols=None) -> np.ndarray:
        """Support-force matrix F[k, q, j] (N per m) at freqs_hz[k]: force on prescribed DOF q for a
        unit harmonic displacement of prescribed DOF j. ``rows``/``cols`` select q and j."""
        Choice(*DAMPING_MODELS)("damping", damping)
        spec = self.system.spec
        f = np.asarray(freqs_hz, dtype=float)
        w = 2.0 * np.pi * f
        s = spec.modulus(f) / self.system.E
        if damping == "viscous":
            kappa, alpha = s * (1.0 + 1j * w * spec.beta), spec.alpha
        elif damping == "structural":
            kappa, alpha = s * (1.0 + 1j * spec.loss(f)), 0.0
        else:
            kappa, alpha = s.astype(complex), 0.0
        mu = w**2 - 1j * w * alpha
        rows = slice(None) if rows is None else rows
        cols = slice(None) if cols is None else cols
        if self.system.mounts:
            return self._direct(f, kappa, mu, damping != "none", rows, cols)
        Kin, Min = self.Kin[:, cols], self.Min[:, cols]
        Kout, Mout = self.Kout[rows], self.Mout[rows]
        k, m = kappa[:, None], mu[:, None]
        inv_d = 1.0 / (k * self.lam[None, :] - m)  # (nf, nm)
        load = k[:, :, None] * Kin[None] - m[:, :, None] * Min[None]  # (nf, nm, nj)
        out = k[:, None, :] * Kout[None] - m[:, None, :] * Mout[None]  # (nf, nq, nm)
        F = -np.einsum("fqm,fm,fmj->fqj", out, inv_d, load, optimize=True)
        F += kappa[:, None, None] * self.Kpp[rows][:, cols][None] - mu[:, None, None] * self.Mpp[rows][:, cols][None]
        return F

    BLOCK = 64  # frequencies per batched dense solve (64 x 216^2 complex: 48 MB)

    def _direct(self, f, kappa, mu, damped, rows, cols):
        """support_forces with mounts: D(omega) = kappa K - mu M + the mounts' dynamic stiffness on
        the augmented DOFs, x_f = -D_ff^-1 D_fp e_j and f_p = D_pf x_f + D_pp e_j at each frequency."""
        sysm = self.system
        K, M = sysm.augmented(sysm.K), sysm.augmented(sysm.M)
        fr, pr = sysm.free, sysm.prescribed
        pr_rows, pr_cols = pr[rows], pr[cols]
        Z = [m.dynamic_stiffness(f, damped) for m in sysm.mounts]
        G = [np.concatenate(sysm.mount_dofs(i)) for i in range(len(sysm.mounts))]
        out = np.empty((len(f), len(pr_rows), len(pr_cols)), complex)
        for k0 in range(0, len(f), self.BLOCK):
            k1 = min(len(f), k0 + self.BLOCK)
            D = kappa[k0:k1, None, None] * K[None] - mu[k0:k1, None, None] * M[None]
            for idx, z in zip(G, Z):
                zz = z[k0:k1]
                D[np.ix_(np.arange(k1 - k0), idx, idx)] += np.block([[zz, -zz], [-zz, zz]])
            Dff = D[:, fr][:, :, fr]
            x = -np.linalg.solve(Dff, D[:, fr][:, :, pr_cols])
            out[k0:k1] = D[:, pr_rows][:, :, fr] @ x + D[:, pr_rows][:, :, pr_cols]
        return out


def trfam(model: Model, input: str, output: str, freqs_hz: ArrayLike, damping: str = "viscous") -> np.ndarray:
    """Apparent-mass transfer function TRFAM (Eq. 12) in kg: complex, one value per frequency.

    Parameters
    ----------
    model : Model
    input : str, the driven support DOF, e.g. ``"casing.A.x"`` (its acceleration is the input).
    output : str, the support DOF whose force is the output, e.g. ``"casing.B.x"`` (same body).
    freqs_hz : array of positive frequencies in Hz.
    damping : "viscous" (Eq. 10, Rayleigh alpha/beta), "structural" (Eq. 11, loss factor) or "none".
    """
    f = frequencies("freqs_hz", freqs_hz)
    bi, si, di = parse_port("input", input, model)
    bo, so, do = parse_port("output", output, model)
    if bi != bo:
        raise ModelError(
            "output",
            output,
            f"must be on the input's body '{bi}' (the bodies are independent "
            "in the frequency domain; contact belongs to the time domain)",
        )
    system = assemble_body(model, bi)
    fr = FrequencyResponse(system)
    j = system.prescribed_index(si, di)
    q = system.prescribed_index(so, do)
    F = fr.support_forces(f, damping, rows=[q], cols=[j])[:, 0, 0]
    return F / (-((2.0 * np.pi * f) ** 2))


def trfam_matrix(
    model: Model, body: str, input_support: str, output_support: str, freqs_hz: ArrayLike, damping: str = "viscous"
) -> np.ndarray:
    """The 3x3 TRFAM block (kg), shape (nf, 3 outputs x/y/z, 3 inputs x/y/z), between two supports
    of one body: the force at ``output_support`` over the acceleration of ``input_support``."""
    f = frequencies("freqs_hz", freqs_hz)
    parse_port("input", f"{body}.{input_support}.x", model)
    parse_port("output", f"{body}.{output_support}.x", model)
    system = assemble_body(model, body)
    fr = FrequencyResponse(system)
    cols = [system.prescribed_index(input_support, d) for d in range(3)]
    rows = [system.prescribed_index(output_support, d) for d in range(3)]
    return fr.support_forces(f, damping, rows=rows, cols=cols) / (-((2.0 * np.pi * f) ** 2))[:, None, None]
