"""Transfer functions estimated from the support signals of a time record: the apparent mass
(TRFAM, Eq. 12, kg) and the force transmissibility (dimensionless), with their coherence.

Both go through the identification module's estimators (:func:`~cablecasing_core.identification.frf.frf_estimate`:
Welch densities, H1 = G_xy / G_xx, H2 = G_yy / G_yx, coherence gamma^2 = H1 / H2) and carry the
normalized random error of H1 from the coherence (:func:`~cablecasing_core.identification.frf.random_error`).

* **Apparent mass** ``M(f) = F / a``: the acceleration of the driven support (input, e.g.
  ``casing.A.az``, m/s2) to a support force (output, e.g. ``casing.B.Fz``, N), in kg. The time
  domain records the force each body exerts *on* its support; the TRFAM of Eq. 13 (``cc.trfam``) uses
  the force the support applies to the body, the negative. :func:`apparent_mass` uses the TRFAM's
  convention (it negates the recorded force), so its estimate is comparable with ``cc.trfam`` as it is.
* **Force transmissibility** ``T(f) = F_out / F_in``: a support force at the receiving end over the
  force at the driven end (both as recorded, so the sign convention cancels), dimensionless. The
  supports are clamped, so a motion transmissibility (the motion at B over the motion at A) is zero by
  construction and not offered.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ModelError, renamed
from ..identification.frf import frf_estimate, random_error, welch_averages
from ..model.schema import STUDY_OUTPUT
from ..model.validators import Choice, array_1d, integer, number, seconds
from ..records import Records, after_skip
from ..units import unit_key
from .spectra import finest_segment_resolution, segment_for_resolution

#: The fewest Welch averages a transfer estimate takes: with one, the coherence is 1 by construction.
MIN_AVERAGES = 3
#: The shortest default segment (samples; 8 lines): the default takes at most an eighth of the record
#: (at least 15 averages), so it needs at least 8 * MIN_SEGMENT samples.
MIN_SEGMENT = 16


@dataclass(frozen=True)
class Transfer:
    """An estimated transfer function: ``f_hz`` (Hz), ``H`` (the chosen estimator), ``H1``, ``H2``,
    ``coherence`` (0..1), ``error`` (normalized random error of |H1|, Bendat & Piersol Eq. 9.90),
    ``n_averages`` (Welch segments) and ``n_effective`` (the independent averages they are worth, as
    they overlap: the n of the error and of the coherence's bias), ``kind`` ("apparent mass" or
    "transmissibility"), ``unit`` ("kg" or "1"),
    ``input`` and ``output`` (record columns), ``estimator`` ("H1" or "H2")."""

    f_hz: np.ndarray
    H: np.ndarray
    H1: np.ndarray
    H2: np.ndarray
    coherence: np.ndarray
    error: np.ndarray
    n_averages: int
    n_effective: float
    kind: str
    unit: str
    input: str
    output: str
    estimator: str

    @property
    def ratio(self) -> str:
        """What ``H`` is the ratio of, by the record's columns: ``casing.B.Fz/casing.A.Fz`` for a
        transmissibility (the recorded forces), ``(-casing.B.Fz)/casing.A.az`` for an apparent mass,
        which takes the recorded force negated (the TRFAM's convention): ``spectrum --kind``'s column
        names and the plot's title, so that a file read without the docs says the sign."""
        out = f"(-{self.output})" if self.kind == "apparent mass" else self.output
        return f"{out}/{self.input}"


def _units(units):
    """The units read of a transfer function's input and output, for a message: 'g' and 'N'."""
    return " and ".join(f"'{u}'" for u in units)


def finest_resolution(rec: Records, skip: float | None = None) -> float:
    """The finest ``resolution_hz`` (Hz) that :func:`apparent_mass` and :func:`transmissibility` take
    of the record ``rec`` after ``skip`` s (None: ``rec.default_skip()``): fs / the longest power of two
    of samples that leaves :data:`MIN_AVERAGES` averages (at most half of the samples after the skip)."""
    seconds("skip", skip, zero_ok=True, none_ok=True)
    skip = rec.default_skip() if skip is None else skip
    return finest_segment_resolution(rec.fs, int(after_skip(rec.time, skip, rec.time[0]).sum()), MIN_AVERAGES)


def _estimate(rec, x_name, y_name, sign, kind, unit, estimator, skip, nperseg, resolution_hz):
    Choice("H1", "H2")("estimator", estimator)
    seconds("skip", skip, zero_ok=True, none_ok=True)
    if nperseg is not None:
        nperseg = integer("nperseg", nperseg, 8)
    if resolution_hz is not None:
        resolution_hz = number("resolution_hz", resolution_hz, gt=0, unit="Hz")
    x = array_1d(rec.resolve(x_name, "input"), rec.column(x_name, "input"))
    y = sign * array_1d(rec.resolve(y_name, "output"), rec.column(y_name, "output"))
    if x.size != rec.time.size or y.size != rec.time.size:
        raise ModelError(
            "rec", f"{x.size}, {y.size} and {rec.time.size} samples", "columns must be as long as the time"
        )
    fs = rec.fs
    if skip is None:  # (the record's default, as spectrum and bands take it)
        skip = rec.default_skip()
    keep = after_skip(rec.time, skip, rec.time[0])
    if keep.sum() < 64:
        raise ModelError(
            "skip", skip, f"must leave at least 64 samples of the {rec.time[-1] - rec.time[0]:.6g} s record"
        )
    n = int(keep.sum())
    if nperseg is None:  # 1 Hz with >= 15 averages at most; a resolution asked for with >= 3 of them
        share = 8 if resolution_hz is None else 2  # (segments of at most n / share: >= 15 or >= 3 averages)
        if n < share * MIN_SEGMENT:
            raise ModelError(
                "record",
                f"{n} samples after skip ({n / fs:.4g} s)",
                f"must hold at least {share * MIN_SEGMENT} samples for the default segment (at most 1/{share} of "
                f"the record, at least {MIN_SEGMENT} samples); give nperseg for a shorter one, with fewer averages",
            )
        if resolution_hz is None:
            seg = int(2 ** np.round(np.log2(fs / 1.0)))
        else:  # (refused as spectrum --resolution: one rule)
            seg = segment_for_resolution("resolution_hz", resolution_hz, fs, n, MIN_AVERAGES, MIN_SEGMENT)
        nperseg = max(MIN_SEGMENT, min(seg, 2 ** int(np.log2(n // share))))
    if welch_averages(n, nperseg, nperseg // 2) < MIN_AVERAGES:  # (counted at 50 %: frf_estimate's span more)
        raise ModelError(
            "nperseg",
            nperseg,
            f"must leave at least {MIN_AVERAGES} Welch averages (50 % overlap) of the {n} samples after skip, so "
            f"at most {n // 2}: from one average the coherence is 1 whatever the signals, and the random error "
            "that follows from it means nothing",
        )
    with renamed({"x": rec.resolve(x_name), "y": rec.resolve(y_name)}):  # (frf_estimate's checks, by column)
        est = frf_estimate(x[keep], y[keep], fs, nperseg=nperseg)
    H = est.H1 if estimator == "H1" else est.H2
    return Transfer(
        est.f_hz,
        H,
        est.H1,
        est.H2,
        est.coherence,
        random_error(est.coherence, est.n_effective),
        est.n_averages,
        est.n_effective,
        kind,
        unit,
        rec.resolve(x_name),
        rec.resolve(y_name),
        estimator,
    )


def apparent_mass(
    rec: Records,
    input: str = "casing.A.az",
    output: str = STUDY_OUTPUT,
    estimator: str = "H1",
    skip: float | None = None,
    nperseg: int | None = None,
    resolution_hz: float | None = None,
) -> Transfer:
    """The apparent mass (kg) from a support acceleration ``input`` (m/s2) to a support force
    ``output`` (N) of the record ``rec``, in the TRFAM's sign convention (module docstring).

    skip (s): the start of the record left out (fade-in and transient); None (the default) takes the
    record's :meth:`~cablecasing_core.records.Records.default_skip`, as ``spectrum`` and ``bands`` do
    (0.05 s, or the fade-in the record states if longer, lengthened so that the rest holds whole
    periods of the lines it states). nperseg: samples per Welch segment, or ``resolution_hz`` (the
    nearest power of two of samples; at most half the record after the skip, so at least 3 averages: a
    finer one is refused naming ``resolution_hz`` and the finest the record allows,
    :func:`finest_resolution`, as ``spectrum --resolution`` is); default 1 Hz but at most an eighth of
    the record, so at least 15 averages; the default segment is at least 16 samples, so a record of
    fewer than 128 samples after skip is refused naming its length."""
    units = rec.unit(input, "input"), rec.unit(output, "output")
    if (unit_key(units[0], False), unit_key(units[1], False)) != ("m/s2", "N"):  # (spellings: units.unit_key)
        raise ModelError(
            "input/output",
            (input, output),
            "the apparent mass needs an acceleration in m/s2 (m/s^2, m/s**2, m/s² alike) and a force in N; their "
            f"units read: {_units(units)}",
        )
    return _estimate(rec, input, output, -1.0, "apparent mass", "kg", estimator, skip, nperseg, resolution_hz)


def transmissibility(
    rec: Records,
    input: str = "casing.A.Fz",
    output: str = STUDY_OUTPUT,
    estimator: str = "H1",
    skip: float | None = None,
    nperseg: int | None = None,
    resolution_hz: float | None = None,
) -> Transfer:
    """The force transmissibility (dimensionless) from the support force ``input`` (N, the driven
    end) to the support force ``output`` (N) of the record ``rec`` (arguments as :func:`apparent_mass`)."""
    units = rec.unit(input, "input"), rec.unit(output, "output")
    if unit_key(units[0], False) != unit_key(units[1], False):  # (m/s^2 and m/s2 are one unit: units.unit_key)
        raise ModelError(
            "input/output",
            (input, output),
            f"a transmissibility needs two signals of one unit (spelled alike but for spaces, brackets around "
            f"it, ^ and **; case counts: mN is not MN); their units read: {_units(units)}",
        )
    return _estimate(rec, input, output, 1.0, "transmissibility", "1", estimator, skip, nperseg, resolution_hz)


def window_expectation(H_of, fs, nperseg, f_low, f_high, input_psd=None, oversample=16, half_width=8):
    """What a Welch H1 estimate (Hann's window, segments of ``nperseg`` samples at ``fs`` Hz) of a
    noise-free linear system of frequency response ``H_of(f)`` (f in Hz, > 0) tends to with many
    averages, where the lines are coarser than its resonances: the densities averaged over the
    window's spectral window |W(f' - f)|^2 (Bendat & Piersol, *Random Data*, 11.4: E[G_xy(f)] =
    integral |W(f' - f)|^2 H(f') G_xx(f') df', and E[G_xx], E[G_yy] with 1 and |H|^2), under the input
    spectrum ``input_psd(f)`` (flat if None). Returns ``(f, E_H1, coherence)`` on a grid of df /
    ``oversample`` (df = fs / nperseg; every line k df lies on it) over [f_low, f_high] Hz:
    ``E_H1 = E[G_xy] / E[G_xx]`` (the TRFAM averaged over the window, H1's expectation; docs/nvh.md,
    "Against the TRFAM") and the coherence of those expectations, |E[G_xy]|^2 / (E[G_xx] E[G_yy]) (<=
    1 by Cauchy-Schwarz): what the window's smoothing alone leaves of a coherence of 1, with no noise
    and no random error. A finite number of averages n_d reads a coherence higher by about (1 -
    gamma^2)^2 / n_d (Bendat & Piersol's bias of the coherence estimate). The window's |W|^2 is taken
    over +-``half_width`` lines (beyond 8 lines it is below 3e-7 of its peak); components below 0 Hz
    (their images) are left out. The report draws it beside the H1 of its record."""
    from scipy.signal import get_window

    df = fs / nperseg
    step = df / oversample
    j0 = max(1, int(np.floor((f_low - half_width * df) / step)))
    j1 = int(np.ceil((f_high + half_width * df) / step))
    g = np.arange(j0, j1 + 1) * step
    G = np.ones_like(g) if input_psd is None else np.asarray(input_psd(g), dtype=float)
    H = np.zeros(g.size, dtype=complex)
    H[G > 0] = H_of(g[G > 0])
    w2 = np.abs(np.fft.fft(get_window("hann", nperseg), oversample * nperseg)) ** 2
    m = half_width * oversample
    kernel = np.concatenate([w2[-m:], w2[: m + 1]])  # (offsets -m..m steps: symmetric, as np.convolve wants it)

    def smooth(a):
        return np.convolve(a, kernel, mode="same")

    gxy, gxx, gyy = smooth(H * G), smooth(G), smooth(np.abs(H) ** 2 * G)
    keep = (g >= f_low - 1e-9 * step) & (g <= f_high + 1e-9 * step) & (gxx > 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        return g[keep], (gxy / gxx)[keep], (np.abs(gxy) ** 2 / (gxx * gyy))[keep]
