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

A prestressed body (an installed model's cable in tension and casing in compression,
docs/installed.md) has the tangent stiffness K = K_E + K_G, of which only the elastic part K_E
carries the material's modulus and loss: the dynamic stiffness is then

* viscous: D = (1 + i omega beta) (s K_E + K_G) - (omega^2 - i omega alpha) M (Rayleigh on the
  tangent stiffness, as in the time domain),
* structural: D = s (1 + i eta(omega)) K_E + K_G - omega^2 M (the complex modulus, Eq. 11, acts
  on the elastic stiffness only; the geometric stiffness of the prestress has no loss),

which the undamped modes no longer diagonalise (K_G and K_E are not proportional); it is solved
directly at each frequency on the free DOFs, whose matrices are banded (half-bandwidth 11,
scipy.linalg.solve_banded), exact like the modal sum.

With isolators or clips (``structure/mount_element.py``) each mount's support is a node of its own
whose six DOFs are prescribed (the augmented system of ``structure/assembly.py``), and the mount
adds its complex dynamic stiffness Z = K6 + i omega C6, or K6 k_scale(f) (1 + i loss(f)) when it
has a table (K6, times k_scale(f), with damping "none") as [[Z, -Z], [-Z, Z]] between the body's
node and its support's. Z is not proportional to K or M, so such a body is solved directly too
(Z sits on a node block of D_ff, which stays banded); f_p at an isolator's support DOFs is the
force through the isolator. The Rayleigh and loss factors of the body do not act on the mounts,
which have their own damping.

Sign convention: f_p is the force the support applies to the body (the reaction of Eq. 13), so a
rigid mass m has a driving-point apparent mass of +m.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike
from scipy.linalg import solve_banded

from ..errors import ModelError, plain
from ..model.limits import MAX_FREQUENCIES
from ..model.schema import DIRECTIONS, SUPPORT_NAMES
from ..model.validators import Choice, check_model, frequencies
from ..structure.assembly import assemble_body
from .modal import _modes_up_to, modal_basis

if TYPE_CHECKING:
    from ..model import Model

DAMPING_MODELS = ("viscous", "structural", "none")

#: The frequencies (Hz) a TRFAM is computed at: the lowest, below which nothing vibrates (a period of
#: 12 days; a transfer between two held ends is there the static stiffness over omega^2, 1e12 kg and
#: more, and below about 1e-150 Hz omega^2 underflows to nan and inf; a driving point that carries its
#: body rigidly, a cantilever's, loses its digits to round-off below about 1e-3 Hz: docs/api.md), and
#: the highest (the ``trfam`` command's --fmin/--fmax limit: the model's modes and records lie far below).
MIN_FREQUENCY_HZ = 1e-6
MAX_FREQUENCY_HZ = 1e6


def trfam_frequencies(key: str, freqs_hz: ArrayLike) -> np.ndarray:
    """``freqs_hz`` checked for :func:`trfam`: a non-empty 1-D array of at most
    :data:`~cablecasing_core.model.limits.MAX_FREQUENCIES` real numbers (not bools, not complex:
    :func:`~cablecasing_core.model.validators.frequencies`) from :data:`MIN_FREQUENCY_HZ` to
    :data:`MAX_FREQUENCY_HZ` Hz; a :class:`ModelError` naming ``key``."""
    f = frequencies(key, freqs_hz, at_most=MAX_FREQUENCIES)
    bad = (f < MIN_FREQUENCY_HZ) | (f > MAX_FREQUENCY_HZ)
    if np.any(bad):
        raise ModelError(
            key,
            float(f[bad][0]),
            f"every frequency must lie from {MIN_FREQUENCY_HZ:g} to {MAX_FREQUENCY_HZ:g} Hz (a TRFAM outside "
            "is no vibration, or overflows)",
        )
    return f


def half_power_bandwidths(model: Model, body: str, damping: str, f_lo: float, f_hi: float):
    """(natural frequencies f_n in Hz, their half-power bandwidths in Hz) of the modes of ``body``
    from ``f_lo`` to ``f_hi`` Hz under ``damping``: the width of a resonance peak of the TRFAM where
    |H| is at least 1/sqrt(2) of its height.

    * structural: eta(f_n) r_E f_n, eta the loss factor at f_n,
    * viscous: 2 zeta_n f_n = (alpha + beta omega_n^2 r_T) / (2 pi), i.e. zeta = alpha / (2 omega) +
      beta omega / 2 (Rayleigh damping's modal ratio, the paper's Eq. 41, which
      :func:`~cablecasing_core.identification.rayleigh.rayleigh_zeta` computes; this is it for r_T = 1),
    * none: 0 (the peak is infinite),

    with r_E = s(f_n) phi^T K_E phi / omega_n^2 and r_T = phi^T (s K_E + K_G) phi / omega_n^2 the
    shares of the mode's stiffness that carry the body's loss (phi the mass-normalised mode; both 1
    for a body without prestress or mounts, where the bandwidths are exact for separated modes). A
    mount's own damping is not counted: it widens the peaks further."""
    Choice(*DAMPING_MODELS)("damping", damping)
    f, shapes, system = _modes_up_to(model, body, f_hi)
    keep = f >= f_lo
    f, shapes = f[keep], shapes[:, keep]
    if damping == "none" or not len(f):
        return f, np.zeros_like(f)
    spec = system.spec
    w2 = (2.0 * np.pi * f) ** 2
    s = np.asarray(spec.modulus(f), dtype=float) / system.E
    e_part = s * np.einsum("im,im->m", shapes, system.K_E @ shapes) / w2
    if damping == "structural":
        return f, np.asarray(spec.loss(f), dtype=float) * e_part * f
    g_part = np.einsum("im,im->m", shapes, system.K_G @ shapes) / w2 if system.prestressed else 0.0
    # Eq. 41 (2 zeta omega = alpha + beta omega^2, beta's share r_T), in Hz
    return f, (spec.alpha + spec.beta * w2 * (e_part + g_part)) / (2.0 * np.pi)


#: The largest frequency step, as a share of a mode's half-power bandwidth, that the command line's
#: ``trfam`` takes without a warning: it shows every peak within 11 % of its height
#: (:func:`grid_peak_height` = 0.894).
PEAK_GRID_SHARE = 0.5


def grid_peak_height(df, bandwidth):
    """The least fraction (-) of a resonance peak's |TRFAM| that a frequency grid of step ``df`` (Hz)
    shows, on a mode of half-power ``bandwidth`` (Hz, :func:`half_power_bandwidths`): near a
    separated mode |H| / |H|max = 1 / sqrt(1 + (2 (f - f_n) / bandwidth)^2) (the half-power
    bandwidth of Eq. 41 being where it is 1/sqrt(2)), and a grid point may lie df/2 from f_n, so
    1 / sqrt(1 + (df / bandwidth)^2): 0.894 (within 11 %) at df = bandwidth / 2. Arrays broadcast;
    a bandwidth of 0 (an undamped, infinite peak) gives 0."""
    df, bw = np.asarray(df, dtype=float), np.asarray(bandwidth, dtype=float)
    with np.errstate(divide="ignore"):
        return 1.0 / np.sqrt(1.0 + (df / bw) ** 2)


def parse_port(key, value, model):
    """Split ``"casing.A.x"`` into (body, support, component index 0..2), checking it exists. A
    clip's support is a port too: ``"casing.clip0.x"`` (clips by index) or, for a clip with an
    excitation, ``"<excitation>.x"`` -> ("casing", "clip<i>", 0)."""
    parts = value.split(".") if isinstance(value, str) else []
    clips = model.data.get("casing", {}).get("clip", [])
    if len(parts) == 2 and parts[1] in DIRECTIONS:
        names = [c.get("excitation") for c in clips]
        if parts[0] in names:
            return "casing", f"clip{names.index(parts[0])}", DIRECTIONS.index(parts[1])
    if len(parts) == 3 and parts[0] == "casing" and parts[1] in [f"clip{i}" for i in range(len(clips))]:
        if parts[2] in DIRECTIONS:
            return "casing", parts[1], DIRECTIONS.index(parts[2])
    if len(parts) != 3 or parts[1] not in SUPPORT_NAMES or parts[2] not in DIRECTIONS or parts[0] not in model.bodies:
        ports = [f"{b}.{s}" for b, spec in model.bodies.items() for s in SUPPORT_NAMES if spec.supports[s] != "free"]
        ports += [f"casing.clip{i}" for i in range(len(clips))]
        ports += [c["excitation"] for c in clips if c.get("excitation")]
        raise ModelError(
            key,
            value,
            f"must be '<port>.<x|y|z>' with a port of the model {model.source}: " + ", ".join(ports),
        )
    body, support, d = parts
    if model.bodies[body].supports[support] == "free":
        raise ModelError(key, value, f"support {body}.{support} is free; TRFAM needs clamped or isolator supports")
    return body, support, DIRECTIONS.index(d)


class FrequencyResponse:
    """Reusable modal data of one body for repeated TRFAM evaluation.

    Build once per body, then call :meth:`support_forces` for any frequency vector.
    """

    def __init__(self, system):
        self.system = system
        if system.prestressed or system.mounts:
            self._direct_setup(system)
            return
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
        # viscous: C = alpha M + beta K (Eq. 40, Eq. 5 assembled), K + i w C - w^2 M = kappa K - mu M
        if damping == "viscous":
            kappa, alpha = s * (1.0 + 1j * w * spec.beta), spec.alpha
            kappa_g = 1.0 + 1j * w * spec.beta
        elif damping == "structural":  # K (1 + i eta), Eq. 11
            kappa, alpha = s * (1.0 + 1j * spec.loss(f)), 0.0
            kappa_g = np.ones_like(w, dtype=complex)
        else:
            kappa, alpha = s.astype(complex), 0.0
            kappa_g = np.ones_like(w, dtype=complex)
        mu = w**2 - 1j * w * alpha
        rows = slice(None) if rows is None else rows
        cols = slice(None) if cols is None else cols
        if self.system.prestressed or self.system.mounts:
            Z = [m.dynamic_stiffness(f, damped=damping != "none") for m in self.system.mounts]
            return self._direct_forces(kappa, kappa_g, mu, rows, cols, Z)
        Kin, Min = self.Kin[:, cols], self.Min[:, cols]
        Kout, Mout = self.Kout[rows], self.Mout[rows]
        k, m = kappa[:, None], mu[:, None]
        d = k * self.lam[None, :] - m  # (nf, nm)
        on_resonance = d == 0.0  # only undamped: a frequency exactly at a natural frequency
        inv_d = 1.0 / np.where(on_resonance, 1.0, d)
        inv_d[on_resonance] = 0.0
        load = k[:, :, None] * Kin[None] - m[:, :, None] * Min[None]  # (nf, nm, nj)
        out = k[:, None, :] * Kout[None] - m[:, None, :] * Mout[None]  # (nf, nq, nm)
        F = -np.einsum("fqm,fm,fmj->fqj", out, inv_d, load, optimize=True)
        F += kappa[:, None, None] * self.Kpp[rows][:, cols][None] - mu[:, None, None] * self.Mpp[rows][:, cols][None]
        for kf in np.nonzero(on_resonance.any(axis=1))[0]:
            # undamped modes at their own frequency: the force is unbounded where their residue, summed
            # over them (a degenerate pair's shapes are any rotation of each other, so only their sum
            # means anything), couples the two supports, and they add nothing where it does not: there
            # it is round-off of its terms' cancellation, below 1e-8 of their largest coupling to any
            # support (of all the prescribed DOFs, whichever rows and columns are asked for)
            modes = np.nonzero(on_resonance[kf])[0]
            residue = out[kf][:, modes] @ load[kf][modes, :]
            reach = kappa[kf] * self.Kout[:, modes] - mu[kf] * self.Mout[:, modes]
            drive = kappa[kf] * self.Kin[modes, :] - mu[kf] * self.Min[modes, :]
            F[kf][np.abs(residue) > 1e-8 * np.abs(reach).max() * np.abs(drive).max()] = np.inf
        return F

    BAND = 11  # half-bandwidth of a body's matrices (six DOFs per node, two nodes per element)

    def _direct_setup(self, system):
        """The blocks of K_E, K_G and M of a prestressed body or one with mounts (on the augmented
        DOFs), the free-free ones in banded storage; each mount's node (its first position among
        the free DOFs) and its support's six positions among the prescribed DOFs."""
        self.blocks = [system.blocks(A) for A in (system.K_E, system.K_G, system.M)]
        self.mount_at = []
        for m in range(len(system.mounts)):
            node, base = system.mount_dofs(m)
            self.mount_at.append((int(np.searchsorted(system.free, node[0])), np.searchsorted(system.prescribed, base)))
        b = self.BAND
        n = len(system.free)
        self.banded = []
        for ff, _, _, _ in self.blocks:
            ab = np.zeros((2 * b + 1, n))
            for k in range(-b, b + 1):  # ab[b + i - j, j] = A[i, j] (scipy's banded storage)
                i = np.arange(max(0, k), min(n, n + k))
                ab[b + k, i - k] = ff[i, i - k]
            self.banded.append(ab)

    def _direct_forces(self, kappa, kappa_g, mu, rows, cols, Z=()):
        """Support forces of a prestressed body or one with mounts: D(omega) = kappa K_E + kappa_g K_G
        - mu M + the mounts' Z[m][k] (6 x 6, N/m) solved on the free DOFs at each frequency (banded),
        x_f = -D_ff^-1 D_fp e_j, f_p = D_pf x_f + D_pp e_j."""
        (_, Efp, Epf, Epp), (_, Gfp, Gpf, Gpp), (_, Mfp, Mpf, Mpp) = self.blocks
        Ebd, Gbd, Mbd = self.banded
        b = self.BAND
        r6 = np.arange(6)
        ii, jj = np.meshgrid(r6, r6, indexing="ij")
        F = np.empty((len(mu), len(Epf[rows]), Efp[:, cols].shape[1]), dtype=complex)
        for k, (ke, kg, m) in enumerate(zip(kappa, kappa_g, mu)):
            D_fp = ke * Efp + kg * Gfp - m * Mfp
            D_pf = ke * Epf + kg * Gpf - m * Mpf
            D_pp = ke * Epp + kg * Gpp - m * Mpp
            ab = ke * Ebd + kg * Gbd - m * Mbd
            for (f0, pb), z in zip(self.mount_at, Z):
                zk = z[k]
                node = r6 + f0
                ab[b + ii - jj, f0 + jj] += zk  # (node, node) block, in banded storage
                D_fp[np.ix_(node, pb)] -= zk
                D_pf[np.ix_(pb, node)] -= zk
                D_pp[np.ix_(pb, pb)] += zk
            x = solve_banded((b, b), ab, -D_fp[:, cols], check_finite=False)
            F[k] = D_pf[rows] @ x + D_pp[rows][:, cols]
        return F


def trfam(model: Model, input: str, output: str, freqs_hz: ArrayLike, damping: str = "viscous") -> np.ndarray:
    """Apparent-mass transfer function TRFAM (Eq. 12) in kg: complex, one value per frequency.

    Of one body alone on its supports and mounts: no contact with the other body (the time
    domain's); an installed model's body with the axial prestress of ``loads.cable_tension`` (K_G)
    about its route, not its static state (no sag, no contact forces;
    :func:`~cablecasing_core.frequency.modal.frequency_domain_scope`).

    Parameters
    ----------
    model : Model (a :class:`~cablecasing_core.Model`; anything else raises a ModelError naming ``model``)
    input : str, the driven support DOF, e.g. ``"casing.A.x"`` (its acceleration is the input).
    output : str, the support DOF whose force is the output, e.g. ``"casing.B.x"`` (same body).
    freqs_hz : array of frequencies in Hz, from :data:`MIN_FREQUENCY_HZ` (1e-6) to
        :data:`MAX_FREQUENCY_HZ` (1e6), real (a ModelError otherwise; True and False, and complex
        numbers, whose imaginary part would be lost, are refused).
    damping : "viscous" (Eq. 10, Rayleigh alpha/beta), "structural" (Eq. 11, loss factor) or "none".
    """
    check_model(model)
    f = trfam_frequencies("freqs_hz", freqs_hz)
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
    return apparent_mass_of(fr.support_forces(f, damping, rows=[q], cols=[j])[:, 0, 0], f)


def trfam_matrix(
    model: Model, body: str, input_support: str, output_support: str, freqs_hz: ArrayLike, damping: str = "viscous"
) -> np.ndarray:
    """The 3x3 TRFAM block (kg, Eq. 12), shape (nf, 3 outputs x/y/z, 3 inputs x/y/z), between two
    supports of one body at ``freqs_hz`` (Hz): the force at ``output_support`` over the acceleration
    of ``input_support`` ("A" or "B"); ``freqs_hz`` and ``damping`` as :func:`trfam`'s (the body
    alone, as there)."""
    check_model(model)
    f = trfam_frequencies("freqs_hz", freqs_hz)
    if body not in model.bodies:
        raise ModelError("body", body, "must be one of " + ", ".join(repr(b) for b in model.bodies))
    for key, support in (("input_support", input_support), ("output_support", output_support)):
        if support not in SUPPORT_NAMES:
            raise ModelError(key, support, "must be 'A' or 'B'")
    parse_port("input_support", f"{body}.{input_support}.x", model)
    parse_port("output_support", f"{body}.{output_support}.x", model)
    system = assemble_body(model, body)
    fr = FrequencyResponse(system)
    cols = [system.prescribed_index(input_support, d) for d in range(3)]
    rows = [system.prescribed_index(output_support, d) for d in range(3)]
    return apparent_mass_of(fr.support_forces(f, damping, rows=rows, cols=cols), f)


def apparent_mass_of(forces, f):
    """Eq. 12's last step, the one place of it: the TRFAM (kg) from the support forces (N) of a unit
    displacement of the driven support, ``forces`` with the frequency ``f`` (Hz) along its first
    axis, over that displacement's acceleration -(2 pi f)^2 (m/s2)."""
    f = np.asarray(f, dtype=float)
    return forces / (-((2.0 * np.pi * f) ** 2)).reshape((-1,) + (1,) * (np.ndim(forces) - 1))


#: What :func:`trfam_band_rms` does with a band that reaches beyond the grid's frequencies.
OUTSIDE_RULES = ("drop", "nan", "error")


def trfam_band_rms(freqs_hz: ArrayLike, H: ArrayLike, bands="table3", *, unit: str = "kg", outside: str = "drop"):
    """Band values of a transfer function ``H`` sampled at ``freqs_hz`` (Hz; the TRFAM of
    :func:`trfam`, kg, or any other): in each band [f_low, f_high] (Hz) of ``bands`` (Table 3's
    octaves by default, the bands of the report's and the studies' levels; ``"octave"``,
    ``"third"`` or a :class:`~cablecasing_core.nvh.bands.Bands`) the RMS of |H| over the band,

        sqrt( 1 / (f_high - f_low) * integral from f_low to f_high of |H(f)|^2 df )      (H's unit),

    what relates the band RMS of the output to that of an input flat in the band: a white
    acceleration of band RMS a through the apparent mass gives a force of band RMS this times a.

    The integral takes each frequency of the grid as standing for the interval halfway to its
    neighbours (the first and the last frequency for the half towards the grid), a frequency
    whose interval straddles a band's edge split in proportion, as the band levels split their FFT
    bins (:func:`~cablecasing_core.nvh.spectra.band_sums`): within a band of an even grid whose
    edges fall on the grid, the trapezoidal rule. A peak narrower than the grid's step is not
    resolved: the step that keeps a peak's height within 11 % (``cablecasing trfam`` warns of a
    coarser one, at most half the narrowest half-power bandwidth) integrates its area within about 1 %.

    ``freqs_hz``: increasing, positive, finite (Hz), at least two; ``H``: as many finite values,
    complex or real. ``unit``: H's unit (kept in the result; kg for a TRFAM). ``outside``: a band
    that reaches beyond the grid [freqs_hz[0], freqs_hz[-1]] is left out (``"drop"``, the default),
    kept with a nan (``"nan"``) or refused (``"error"``, a :class:`ModelError` naming ``freqs_hz``);
    no band within the grid is refused whatever the rule.

    Returns a :class:`~cablecasing_core.nvh.bands.BandRMS`: ``rms`` in H's unit per band,
    ``bins`` the grid's frequencies in each band (fractional), ``n`` the grid's length and ``fs``
    nan (no record)."""
    from ..model.validators import array_1d
    from ..nvh.bands import BandRMS, bands_of
    from ..nvh.spectra import band_sums

    f = frequencies("freqs_hz", freqs_hz)
    if f.size < 2 or not np.all(np.diff(f) > 0):
        raise ModelError(
            "freqs_hz", freqs_hz, "must be two or more frequencies in Hz in increasing order (the grid of H)"
        )
    h = array_1d("H", H, min_len=2, complex_ok=True)
    if h.shape != f.shape:
        raise ModelError("H", plain(f"{h.size} values"), f"must hold one value per frequency: {f.size}")
    Choice(*OUTSIDE_RULES)("outside", outside)
    if not isinstance(unit, str):
        raise ModelError("unit", unit, "must be a unit as text ('kg', '1'), or '' when it is not known")
    b = bands_of(bands)
    edges = np.concatenate([[f[0]], 0.5 * (f[1:] + f[:-1]), [f[-1]]])  # (each frequency's interval)
    inside = (b.lower >= f[0] * (1 - 1e-12)) & (b.upper <= f[-1] * (1 + 1e-12))
    if not inside.all() and outside == "error" or not inside.any():
        beyond = ", ".join(
            f"{lab} ({lo:g}-{hi:g} Hz)" for lab, lo, hi, i in zip(b.labels, b.lower, b.upper, inside) if not i
        )
        raise ModelError(
            "freqs_hz",
            plain(f"{f[0]:g}..{f[-1]:g} Hz"),
            f"must reach from a band's lower edge to its upper one: the grid leaves out {beyond}"
            + ("" if inside.any() else ", every band asked for"),
        )
    sel = b if outside == "nan" else b.select(inside)
    power, cells = band_sums(np.abs(h) ** 2 * np.diff(edges), edges, sel.lower, sel.upper)
    rms = np.sqrt(power / (sel.upper - sel.lower))
    if outside == "nan":
        rms = np.where(inside, rms, np.nan)
    return BandRMS(
        lower=sel.lower,
        upper=sel.upper,
        centre=sel.centre,
        labels=sel.labels,
        rms=rms,
        bins=cells,
        fs=float("nan"),
        n=int(f.size),
        nominal=sel.nominal,
        unit=unit,
    )
