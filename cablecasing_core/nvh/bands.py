"""Frequency bands and band RMS of a sampled signal (the paper's Section 4.4, Table 3, Fig. 23).

The package's one library of bands: the band sets (:func:`octave_bands`, :class:`Bands`; Table 3
and IEC 61260-1), the band levels' windows (:data:`WINDOWS`, :func:`window_options`), band RMS by
Parseval (:func:`octave_rms`, :class:`BandRMS`), the advice on too few FFT lines per band
(:func:`few_lines`) and the level below which a band holds no response (:func:`no_response`). The
studies, the report, the command line and ``frequency.trfam_band_rms`` take their bands from here;
the sum over a band with its edge bins split (``band_sums``, ``bin_edges``) is in
:mod:`~cablecasing_core.nvh.spectra`, which the PSD's band mean squares share.
(``cablecasing_core.studies.octave``, this module's earlier name, still imports its names.)

The paper tracks "the RMS value of the time response of the force support in the z direction" in
the nine octave bands of Table 3. :func:`octave_rms` computes band RMS values of any sampled signal
by Parseval's theorem over the FFT bins:

1. The record ``x`` (n samples at ``fs`` Hz) is detrended (``scipy.signal.detrend``; default
   ``"constant"``: its mean, which no band holds, removed) and windowed (``scipy.signal.get_window``;
   default Hann's window, ``"hann"``); the spectrum is divided by ``mean(w**2)``, so that the band
   mean squares of stationary noise, and of a tone whose main lobe (its bin and the two beside it)
   lies inside one band, keep their level. Why Hann's: the rectangular window (``"boxcar"``) takes
   the record for one period of a periodic signal, and the jump between its last and first sample
   and its strong bands leak into the weak ones with a tail of power falling as 1/m^2 (m bins away),
   a bias that falls as 1 / the record's length: on the built-in specimen's casing.B.Fz octave 9
   read +59 % at 0.44 s, +33 % at 1 s, +8 % at 4 s and +1.5 % at 16 s against Hann's on the same
   records, Hann's within its scatter of its 16 s levels at every length
   (``benchmarks/band_window.py``, docs/time_domain.md "The window of the band levels"). Hann's
   tail falls as 1/m^6. With ``window="boxcar"`` and ``detrend=None``
   Parseval holds exactly (the band mean squares over 0..fs/2 sum to ``mean(x**2)``): a line of
   whole periods then stays in its bin.
2. One-sided power spectrum (mean square per bin, signal unit squared):
   ``P_0 = |X_0|^2 / n^2``, ``P_k = 2 |X_k|^2 / n^2`` for ``0 < k < n/2``, and ``P_{n/2} = |X_{n/2}|^2 / n^2``
   for even n, so that ``sum(P) = mean(x**2)`` (Parseval, ``numpy.fft.rfft``).
3. Bin k stands for the frequency interval ``[f_k - df/2, f_k + df/2]`` (``df = fs / n``), clipped to
   ``[0, fs/2]``. A bin that straddles a band edge is *split proportionally*: the band receives the
   fraction of the bin's interval that it overlaps. Contiguous bands therefore share the power of an
   edge bin without losing or double-counting any, and a tone on a bin centre at least ``df/2``
   inside a band lands wholly in that band.
4. Band RMS = sqrt(sum of the band's shares of P), in the signal's unit.

Band sets (``octave_bands``):

* ``"table3"`` (default): the paper's Table 3, lower edges 11, 22, 44, 88, 177, 355, 710, 1420,
  2840 Hz, upper edges 22, ..., 5680 Hz, labels ``"oct1"`` .. ``"oct9"`` (the paper's labels 1..9);
  ``nominal``: the nominal octave each stands in for (16, 31.5, 63, ..., 4000 Hz: their centres lie
  within 2 % of those octaves'), for figures.
* ``"octave"`` and ``"third"``: base-10 bands of IEC 61260-1:2014 with exact edges: ratio
  ``G = 10**(3/10)``, reference ``f_r = 1000`` Hz, mid-band ``f_m = f_r G**(x/b)`` (b = 1 or 3, x
  integer), edges ``f_m G**(-1/(2b))`` and ``f_m G**(+1/(2b))``. Labels are the standard's nominal
  mid-band frequencies (IEC 61260-1:2014, Annex E; the R10 series 1, 1.25, 1.6, 2, 2.5, 3.15, 4, 5,
  6.3, 8 in every decade, the octaves every third of them): ``"16Hz"``, ``"31.5Hz"``, ``"125Hz"``,
  ``"1000Hz"``, ``"2000Hz"``; the exact mid-band frequencies stay in ``centre`` (15.85, 31.62, 125.9,
  1000, 1995 Hz).

Nyquist rule: a band whose upper edge exceeds ``fs/2`` cannot be measured completely. By default
(``beyond_nyquist="error"``) this raises :class:`~cablecasing_core.errors.ModelError` naming
``fs``; ``"drop"`` leaves such bands out of the result, ``"nan"`` keeps them with RMS ``nan``.
A band narrower than one bin (``df`` larger than the bandwidth: record too short) also raises.
A decimated record (``Records.passband_hz``) passes ``passband``: the same rule then holds at the
frequency its anti-alias filter keeps flat instead of at fs/2.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy import signal as _signal

from ..errors import ModelError, ModelWarning
from ..model.validators import Choice, array_1d, number
from .spectra import band_sums, bin_edges, level_db, level_reference

#: Table 3 of the paper: lower and upper edges (Hz) of the nine octave bands.
TABLE3_LOWER = (11.0, 22.0, 44.0, 88.0, 177.0, 355.0, 710.0, 1420.0, 2840.0)
TABLE3_UPPER = (22.0, 44.0, 88.0, 177.0, 355.0, 710.0, 1420.0, 2840.0, 5680.0)
#: IEC 61260-1 base-10 octave ratio G = 10^(3/10) and reference frequency (Hz).
IEC_G = 10.0**0.3
IEC_FR = 1000.0
#: The nominal mid-band frequencies of IEC 61260-1 (Annex E) in one decade, from 1000 Hz: the
#: one-third-octave band x (f_m = 1000 G^(x/3)) is named R10[x mod 10] x 10^(3 + x // 10) Hz.
R10 = (1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0)
#: Table 3's nine octaves by the nominal octave whose centre each lies next to (Hz).
TABLE3_NOMINAL = (16.0, 31.5, 63.0, 125.0, 250.0, 500.0, 1000.0, 2000.0, 4000.0)
BAND_KINDS = ("table3", "octave", "third")
#: The nominal mid-band frequencies (Hz) the IEC band sets keep by default (:func:`octave_bands`).
IEC_F_MIN, IEC_F_MAX = 10.0, 20000.0
#: The fewest FFT lines a band holds without a warning. Through Hann's window a tone's content
#: spreads over the lines within 2 of its own (on a line: 1/6 of its power on each neighbour; off a
#: line: a main lobe 4 lines wide, then side lobes below -31 dB), so a band narrower than 4 lines
#: has most of its width within reach of what lies beyond its edges: a 1 N tone 20 Hz beside the
#: 16 Hz third (3.66 Hz wide) puts 0.3 N into it from a 0.44 s record (1.6 lines) and under 0.02 N
#: from a 0.94 s one (3.4 lines).
LINES_PER_BAND = 4
NYQUIST_RULES = ("error", "drop", "nan")


@dataclass(frozen=True)
class Bands:
    """A set of frequency bands (Hz): ``lower``, ``upper``, ``centre`` (geometric mean) and ``labels``
    (Table 3 of the paper, or IEC 61260-1 bands, or any edges).

    Build with :func:`octave_bands` or directly with edge arrays (validated: finite, non-negative,
    ``lower < upper``, labels unique).
    """

    lower: np.ndarray
    upper: np.ndarray
    labels: tuple
    nominal: tuple = ()

    def __post_init__(self):
        lo = np.atleast_1d(np.asarray(self.lower, dtype=float))
        up = np.atleast_1d(np.asarray(self.upper, dtype=float))
        if lo.ndim != 1 or lo.shape != up.shape or lo.size == 0:
            raise ModelError(
                "bands", (self.lower, self.upper), "lower and upper edges must be 1-D arrays of equal, non-zero length"
            )
        if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(up)) and np.all(lo >= 0) and np.all(up > lo)):
            raise ModelError(
                "bands", (lo.tolist(), up.tolist()), "edges must be finite, >= 0 Hz, and lower < upper for every band"
            )
        labels = tuple(str(s) for s in self.labels)
        if len(labels) != lo.size or len(set(labels)) != lo.size:
            raise ModelError("bands.labels", self.labels, f"must be {lo.size} unique names, one per band")
        nominal = tuple(float(v) for v in self.nominal) or tuple(float(f"{c:.3g}") for c in np.sqrt(lo * up))
        if len(nominal) != lo.size:
            raise ModelError("bands.nominal", self.nominal, f"must be {lo.size} frequencies (Hz), one per band")
        object.__setattr__(self, "lower", lo)
        object.__setattr__(self, "upper", up)
        object.__setattr__(self, "labels", labels)
        object.__setattr__(self, "nominal", nominal)

    @property
    def centre(self):
        """Geometric centre frequency sqrt(lower * upper) of each band (Hz)."""
        return np.sqrt(self.lower * self.upper)

    def __len__(self):
        return self.lower.size

    def select(self, keep) -> Bands:
        """The bands where the boolean array ``keep`` is true."""
        keep = np.asarray(keep, bool)
        return Bands(
            self.lower[keep], self.upper[keep], tuple(np.array(self.labels)[keep]), tuple(np.array(self.nominal)[keep])
        )


def nominal_label(f_hz: float) -> str:
    """A band's name by its nominal mid-band frequency (Hz): ``"31.5Hz"``, ``"1000Hz"``."""
    return f"{f_hz:g}Hz"


def nominal_of(label: str, centre: float) -> float:
    """The nominal mid-band frequency (Hz) of a band by its label: ``"31.5Hz"`` -> 31.5, Table 3's
    ``"oct5"`` -> 250 (:data:`TABLE3_NOMINAL`); any other band: its centre (Hz) to 3 digits."""
    if label.endswith("Hz"):
        try:
            return float(label[:-2])
        except ValueError:
            pass
    if label.startswith("oct") and label[3:].isdigit() and 1 <= int(label[3:]) <= len(TABLE3_NOMINAL):
        return TABLE3_NOMINAL[int(label[3:]) - 1]
    return float(f"{centre:.3g}")


def iec_nominal(x, b: int) -> np.ndarray:
    """The nominal mid-band frequencies (Hz, IEC 61260-1 Annex E) of the base-10 bands of index
    ``x`` (integers; f_m = 1000 G^(x/b)) for octaves (b = 1) or one-third octaves (b = 3)."""
    k = np.asarray(x, int) * (3 // b)  # the one-third-octave index
    return np.array([R10[i % 10] * 10.0 ** (3 + i // 10) for i in np.atleast_1d(k)])


@dataclass(frozen=True)
class BandRMS:
    """Result of :func:`octave_rms` (Section 4.4): the bands (Hz) and the RMS in each (signal unit).

    ``lower``, ``upper``, ``centre``: the bands' edges and geometric centres (Hz); ``labels`` their
    names and ``nominal`` their nominal mid-band frequencies (Hz); ``rms``: the RMS in each band, in
    the signal's unit (N for a force; not a level in dB: :meth:`level_db` gives those); ``fs`` the
    sample rate (Hz) and ``n`` the samples of the record; ``unit`` the signal's unit as
    :func:`octave_rms` was told it ("" when it was not), which gives :meth:`level_db` its default
    reference. ``bins`` is the (fractional) number of FFT bins in each band, the number of degrees of freedom
    / 2 of a noise band estimate (relative standard deviation of a band mean square of Gaussian
    noise is about ``1/sqrt(bins)``).
    """

    lower: np.ndarray
    upper: np.ndarray
    centre: np.ndarray
    labels: tuple
    rms: np.ndarray
    bins: np.ndarray
    fs: float
    n: int
    nominal: tuple = ()
    unit: str = ""

    @property
    def mean_square(self):
        """Band mean squares (signal unit squared)."""
        return self.rms**2

    def as_dict(self):
        """``{label: rms}`` (signal unit), the form a study's ``evaluate`` returns (Section 4.4)."""
        return {lab: float(v) for lab, v in zip(self.labels, self.rms)}

    def level_db(self, ref: float | None = None) -> np.ndarray:
        """Band levels ``20 log10(rms / ref)`` in dB re ``ref`` (in the signal's unit). Default: the
        reference of :attr:`unit` (``nvh.spectra.REFERENCES``: 1 N for a force, 1e-6 m/s2 for an
        acceleration), as :meth:`~cablecasing_core.nvh.spectra.PSD.level_db` takes it, so that the
        band levels and the PSD levels of one signal are against one reference; 1 (dB re 1 of the
        signal's unit) when the unit is not known (``unit=""``, :func:`octave_rms` told none). A unit
        without a reference in that table needs ``ref`` (:class:`ModelError` naming ``ref``)."""
        return level_db(self.rms, self.reference(ref))

    def reference(self, ref: float | None = None) -> float:
        """The reference (signal unit) of :meth:`level_db`: ``ref`` when given, else that of
        :attr:`unit`, or 1 when the unit is not known."""
        return level_reference(self.unit, ref)


def octave_bands(kind: str = "table3", f_min: float | None = None, f_max: float | None = None) -> Bands:
    """Band set of the paper's Table 3 or of IEC 61260-1 (base 10), edges in Hz.

    Parameters
    ----------
    kind : {"table3", "octave", "third"}
        ``"table3"``: the nine bands of Table 3 (Section 4.4), 11-22 Hz ... 2840-5680 Hz.
        ``"octave"`` / ``"third"``: exact base-10 octave / one-third-octave bands, G = 10^(3/10),
        reference 1000 Hz.
    f_min, f_max : float, optional
        Hz. Keep the bands whose nominal mid-band frequency (their name) lies in ``[f_min, f_max]``. Defaults: all of
        Table 3; 10 Hz and 20 kHz for the IEC sets (:data:`IEC_F_MIN`, :data:`IEC_F_MAX`: octaves
        16 Hz .. 16 kHz, third-octaves 10 Hz .. 20 kHz by their nominal names).

    Returns
    -------
    Bands
    """
    if kind not in BAND_KINDS:
        raise ModelError("bands", kind, "must be one of " + ", ".join(BAND_KINDS) + " (or a Bands object)")
    if kind == "table3":
        lo, up = np.array(TABLE3_LOWER), np.array(TABLE3_UPPER)
        labels = [f"oct{i + 1}" for i in range(lo.size)]
        nominal = np.array(TABLE3_NOMINAL)
        fmin = 0.0 if f_min is None else f_min
        fmax = np.inf if f_max is None else f_max
    else:
        fmin = IEC_F_MIN if f_min is None else f_min
        fmax = IEC_F_MAX if f_max is None else f_max
    for key, v in (("f_min", fmin), ("f_max", fmax)):
        if v != np.inf:  # (inf: no upper limit)
            number(key, v, ge=0, unit="Hz")
    if fmax < fmin:  # (equal: the one band of that nominal frequency, the range being closed)
        if f_max is None:  # (the default upper limit: the lower one given is what is wrong)
            raise ModelError("f_min", fmin, f"must be at most f_max, by default {fmax:g} Hz (give f_max too)")
        if f_min is None:  # (the default lower limit: the upper one given is what is wrong)
            raise ModelError("f_max", fmax, f"must be at least f_min, by default {fmin:g} Hz (give f_min too)")
        raise ModelError("f_max", fmax, f"must be at least f_min = {fmin} Hz")
    if kind != "table3":
        b = 1 if kind == "octave" else 3
        # x range: f_m = f_r G^(x/b) within [fmin, fmax]; the small slack admits 10 Hz exactly.
        x_lo = int(np.ceil(b * np.log10(max(fmin, 1e-12) / IEC_FR) / 0.3 - 1e-9))
        x_hi = int(np.floor(b * np.log10(fmax / IEC_FR) / 0.3 + 1e-9)) if np.isfinite(fmax) else x_lo + 60
        x = np.arange(x_lo - 1, x_hi + 2)  # (one more each side: the names decide, below)
        fm = IEC_FR * IEC_G ** (x / b)
        lo, up = fm * IEC_G ** (-1.0 / (2 * b)), fm * IEC_G ** (1.0 / (2 * b))
        nominal = iec_nominal(x, b)
        labels = [nominal_label(f) for f in nominal]
    nominal = np.asarray(nominal, float)  # (by the names: --fmin 16 keeps the 16 Hz octave, centre 15.85 Hz)
    keep = (nominal >= fmin * (1 - 1e-12)) & (nominal <= fmax * (1 + 1e-12))
    if not keep.any():  # (named by the limits given: the other is its default)
        key, value = {
            (True, False): ("f_min", fmin),
            (False, True): ("f_max", fmax),
        }.get((f_min is not None, f_max is not None), ("f_min/f_max", (fmin, fmax)))
        raise ModelError(
            key, value, f"leaves no {kind} band whose nominal frequency lies in {fmin:g}..{fmax:g} Hz (f_min..f_max)"
        )
    return Bands(lo, up, tuple(labels), tuple(nominal)).select(keep)


def bands_of(bands: str | Bands) -> Bands:
    """The :class:`Bands` (edges in Hz) that ``bands`` names: a :class:`Bands` as given, or a band
    set's name, one of :data:`BAND_KINDS` (:func:`octave_bands` with its default range); anything
    else raises :class:`ModelError` naming ``bands``."""
    if isinstance(bands, Bands):
        return bands
    if isinstance(bands, str):
        return octave_bands(bands)
    raise ModelError("bands", bands, "must be 'table3', 'octave', 'third' or a Bands object")


#: The windows of the band levels a study, an ensemble and ``bands`` offer: Hann's (``octave_rms``'s
#: default) and the rectangular one, through which Parseval holds exactly and which the docs' tables
#: whose commands name ``--window boxcar`` and the benchmarks' cached rectangular-window references take.
WINDOWS = ("hann", "boxcar")
#: What the commands call them when they say which window their levels took.
WINDOW_NAMES = {"hann": "Hann", "boxcar": "rectangular"}


def window_options(window: str) -> dict:
    """``octave_rms``'s window and detrending for ``window`` (one of :data:`WINDOWS`): Hann's with the
    mean removed, or the rectangular window without detrending (Parseval exact), the window of the docs'
    tables whose commands name ``--window boxcar``."""
    Choice(*WINDOWS)("window", window)
    return {"window": "hann", "detrend": "constant"} if window == "hann" else {"window": "boxcar", "detrend": None}


def few_lines(bands: str | Bands, length: float, fmin_advice: bool = True) -> str | None:
    """Why the bands that a record of ``length`` s puts fewer than :data:`LINES_PER_BAND` FFT lines
    in (df = 1 / length Hz) hold much of what lies beside them, with the record that would give the
    lowest of them its lines, and (``fmin_advice``) the ``f_min`` that leaves them out; None when
    every band has them. The one rule of :func:`octave_rms`'s warning and of the ensembles' and
    studies' check before their runs (whose band sets have no ``f_min``)."""
    sel = bands_of(bands)
    df = 1.0 / length
    few = sel.upper - sel.lower < LINES_PER_BAND * df * (1 - 1e-12)
    if not few.any():
        return None
    i = int(np.argmax(few))
    j = int(np.nonzero(few)[0][-1]) + 1  # the first band with its lines
    width = sel.upper[i] - sel.lower[i]
    return (
        f"its {length:.4g} s put fewer than {LINES_PER_BAND} FFT lines (df = {df:.3g} Hz) in band(s) "
        f"{', '.join(sel.labels[k] for k in np.nonzero(few)[0])}: each line's content spreads over the lines beside "
        "it (a tone one line beyond a band's edge puts up to 1/6 of its power into the band through Hann's window), "
        f"so such a band holds much of what lies beside it; {LINES_PER_BAND} lines in {sel.labels[i]} need a record "
        f"of {LINES_PER_BAND} / {width:.3g} Hz = {LINES_PER_BAND / width:.3g} s"
        + (_leave_out_below(sel, j) if fmin_advice else "")
    )


def _leave_out_below(sel, j) -> str:
    """The advice to leave out the bands of ``sel`` below its ``j``-th (none when there is none)."""
    if j >= len(sel):
        return ""
    return f"; or leave out the bands below {sel.labels[j]} ({FMIN_ADVICE.format(f_min=sel.nominal[j])})"


#: How the advice of :func:`few_lines` and :func:`octave_rms` names the lowest band to keep (the
#: ``f_min`` of :func:`octave_bands`); the command line says ``--fmin`` instead.
FMIN_ADVICE = "octave_bands(kind, f_min={f_min:g})"


def octave_rms(
    x: ArrayLike,
    fs: float,
    bands: str | Bands = "table3",
    *,
    detrend: str | None = "constant",
    window="hann",
    beyond_nyquist: str = "error",
    name: str = "x",
    passband: float | None = None,
    warn_few_lines: bool = True,
    unit: str = "",
) -> BandRMS:
    """RMS of a sampled signal in octave bands by Parseval over FFT bins (Section 4.4, Table 3, Fig. 23).

    Parameters
    ----------
    x : array_like, shape (n,)
        The signal in any unit (e.g. the support force at casing end B in z, N), n >= 2 samples.
    fs : float
        Sample rate in Hz (e.g. ``1 / dt`` of a time-domain run).
    bands : {"table3", "octave", "third"} or Bands
        Band set, see :func:`octave_bands`. Default: the paper's Table 3.
    detrend : {"constant", "linear", None}
        Detrending of the record before the FFT (``scipy.signal.detrend``). Default ``"constant"``:
        the mean removed (no band holds it; Hann's window would spread it to the first bin). None
        keeps it in the 0 Hz bin.
    window : str or tuple
        ``scipy.signal.get_window`` spec, power-normalised by ``mean(w**2)``. Default ``"hann"``
        (module docstring: the rectangular window's leakage biases weak bands upward); ``"boxcar"``,
        the rectangular window, with ``detrend=None`` makes Parseval exact.
    beyond_nyquist : {"error", "drop", "nan"}
        What to do with a band whose upper edge exceeds fs/2 (see module docstring).
    name : str
        What the signal is in messages (a record's column, ``"casing.B.Fz in run.csv"``).
    passband : float, optional
        Hz. The frequency up to which the record holds its content unaltered (default the Nyquist
        frequency fs/2): a record decimated through an anti-alias filter is flat only to 0.7 of its
        Nyquist frequency (``Records.passband_hz``). A band whose upper edge lies above it is treated
        as a band beyond Nyquist, by ``beyond_nyquist``.
    warn_few_lines : bool
        Warn (:class:`~cablecasing_core.errors.ModelWarning`, :func:`few_lines`) when a band holds
        fewer than :data:`LINES_PER_BAND` FFT lines of the record (default True; the ensembles and
        studies warn once before their runs instead).
    unit : str
        The signal's unit (``"N"``, ``"m/s2"``; a record's ``Records.unit(name)``), kept in
        :attr:`BandRMS.unit`: :meth:`BandRMS.level_db` then defaults to its reference
        (``nvh.spectra.REFERENCES``), as the PSD's levels do. Default "": not known, levels re 1.

    Returns
    -------
    BandRMS
        Band edges and centres (Hz), labels, and RMS values in the signal's unit.
    """
    x = array_1d(name, x)
    fs = number("fs", fs, gt=0, unit="Hz")
    Choice(*NYQUIST_RULES)("beyond_nyquist", beyond_nyquist)
    if not isinstance(unit, str):
        raise ModelError("unit", unit, "must be a unit as text ('N', 'm/s2'), or '' when it is not known")
    if detrend not in (None, "constant", "linear"):
        raise ModelError("detrend", detrend, "must be None, 'constant' or 'linear'")
    bands = bands_of(bands)
    n = x.size
    nyq = fs / 2
    top = nyq if passband is None else min(number("passband", passband, gt=0, unit="Hz"), nyq)
    limit = "Nyquist frequency" if top == nyq else f"passband {top:.4g} Hz ({top / nyq:.2g} of the Nyquist frequency)"
    over = bands.upper > top * (1 + 1e-12)
    if over.any() and beyond_nyquist == "error":
        i = int(np.argmax(bands.upper))  # (the highest band: the rate that holds it holds them all)
        j = int(np.argmax(over))
        which = (
            f"band '{bands.labels[i]}' ({bands.lower[i]:g}-{bands.upper[i]:g} Hz) lies"
            if i == j
            else f"bands '{bands.labels[j]}' to '{bands.labels[i]}' (up to {bands.upper[i]:g} Hz) lie"
        )
        raise ModelError(
            "fs",
            fs,
            f"must be at least {2 * nyq / top:.3g} x {bands.upper[i]:g} Hz = {2 * nyq / top * bands.upper[i]:.6g} Hz "
            f"so that {which} below the {limit}; or pass beyond_nyquist='drop' or 'nan'",
        )
    keep = ~over if beyond_nyquist == "drop" else np.ones(len(bands), bool)
    if not keep.any():
        raise ModelError("fs", fs, f"puts every band above the {limit}: {top:g} Hz")
    sel = bands.select(keep)
    df = fs / n
    measurable = sel.upper <= top * (1 + 1e-12)
    narrow = measurable & (sel.upper - sel.lower < df * (1 - 1e-12))
    if narrow.any():
        i = int(np.argmax(narrow))
        j = int(np.nonzero(narrow)[0][-1]) + 1  # the first band the record resolves
        lowest = _leave_out_below(sel, j)
        raise ModelError(
            name,
            f"{n / fs:.4g} s",
            f"is too short for band {sel.labels[i]} ({sel.lower[i]:.4g}-{sel.upper[i]:.4g} Hz, "
            f"{sel.upper[i] - sel.lower[i]:.3g} Hz wide): a band needs at least one FFT line, a record of at least "
            f"1 / {sel.upper[i] - sel.lower[i]:.3g} Hz = {1 / (sel.upper[i] - sel.lower[i]):.3g} s{lowest}",
        )
    if warn_few_lines and (note := few_lines(sel.select(measurable), n / fs)):
        warnings.warn(f"{name}: {note}", ModelWarning, stacklevel=2)

    if detrend is not None:
        x = _signal.detrend(x, type=detrend)
    try:
        w = _signal.get_window(window, n, fftbins=True)
    except (ValueError, TypeError) as exc:
        raise ModelError("window", window, f"must be a scipy.signal.get_window spec ({exc})") from None
    X = np.fft.rfft(x * w)
    P = np.abs(X) ** 2 / (n * n)
    P[1 : (n + 1) // 2] *= 2.0  # one-sided: double every bin except 0 and (even n) Nyquist
    P /= np.mean(w * w)  # power normalisation of the window (1 for boxcar)
    ms, bins = band_sums(P, bin_edges(n, fs), sel.lower, sel.upper)
    rms = np.sqrt(ms)
    if beyond_nyquist == "nan":
        rms = np.where(measurable, rms, np.nan)
    return BandRMS(
        lower=sel.lower,
        upper=sel.upper,
        centre=sel.centre,
        labels=sel.labels,
        rms=rms,
        bins=bins,
        fs=fs,
        n=n,
        nominal=sel.nominal,
        unit=unit,
    )


#: A band whose ensemble-mean level lies more than this many dB below the variant's strongest band
#: holds no response: the report shows a dash in its table and leaves it out of band_levels.png, and
#: `ensemble` names such bands below its table. Why
#: 100 dB (an amplitude ratio of 1e-5): the band levels go through Hann's window, whose spectral
#: window falls off k lines away as its sidelobes' envelope 1 / (pi k^3) of its peak (the first
#: sidelobe -31.5 dB at 2.4 lines, -71 dB at 10.5, -100 dB from 32 on), so a band 100 dB below the
#: strongest reads no more than what the window leaks from content 32 lines away (73 Hz at the
#: report's 0.44 s records, 2.3 Hz lines): at that level the window, not the response, may set
#: it, and a band with nothing in it reads the leakage's far tail. Measured on the built-in
#: specimen without the cable drive (its excitation ends at 1 kHz, no contact; seed 1, 0.5 s after
#: 0.06 s): octaves 8 and 9 read 155.7 and 172.4 dB below its strongest band (octave 4), and 6e5
#: and 3e6 times higher through the rectangular window, whose sidelobes fall only as 1 / (pi k):
#: window artefacts, not levels. The bands that hold a response lie far above the threshold: the
#: same record's octaves 1-7 within 26 dB of the strongest, with the drive within 43 dB, the
#: installed specimen's octave 9 67 dB below its octave 3 (docs/time_domain.md, "The mesh", its
#: mean levels at 140 elements). (tests/cli/test_report_bands.py)
NO_RESPONSE_DB = 100.0


def no_response(mean) -> np.ndarray:
    """The bands of an ensemble's ``mean`` levels (N) that hold no response: more than
    :data:`NO_RESPONSE_DB` below the strongest band (a band of exactly 0 too)."""
    mean = np.asarray(mean, dtype=float)
    top = np.nanmax(mean) if mean.size and np.any(mean > 0) else 0.0
    return ~(mean > top * 10 ** (-NO_RESPONSE_DB / 20.0))
