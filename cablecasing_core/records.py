"""Time records in and out, by file suffix: ``.csv``, ``.npz`` and ``.uff`` (UFF dataset 58).

A record is a time axis (s, evenly spaced) and named columns: the outputs of the time domain
(``casing.B.Fz``, N; ``model.schema.OUTPUTS``), the support inputs of the driven channels
(``casing.A.az``, m/s2; ``model.schema.INPUTS``) or any other name. Every command that reads records
(``bands``, ``spectrum``, ``identify damping``) reads all three formats with :func:`read_records`;
``cablecasing simulate --out`` and :meth:`SimulationResult.save` write them with
:func:`write_records`.

* **CSV**: one header line ``time [s],casing.A.Fx [N],...,contact.active [1],...``: each column is
  named by its output or input name with its unit in brackets; 9 significant digits (the time
  15, so that steps such as 1/30000 s stay equal). Read, the time column (the first) may be in
  any unit of :data:`~cablecasing_core.files.TIME_UNITS` (s, sec, ms, msec, us, µs, ...), in the
  header's brackets or as ``time_ms``: it is converted to s; a unit that is not one of time is
  refused. A column is
  found by its name alone (``casing.B.Fz``), by the whole header (``casing.B.Fz [N]``), or by the
  ``<name>_<unit>`` form of earlier versions (``casing.B.Fz_N``); a file with bare names (the FMU's
  outputs written by fmpy) takes the units from the schema. Two columns of one name (in either
  form) are refused; a header in quotes (``"time [s]"``, as spreadsheets write it) is read without them.
  A record that states its passband (:attr:`Records.passband_hz`: a run's record at every step, its
  Nyquist frequency, or decimated with the anti-alias filter) has a comment line after the header,
  ``# passband_hz = 3500 (...)``, Hz; read, such a line before the first row of numbers
  (:func:`~cablecasing_core.files.csv_statements`) gives the record its passband. A run's record
  states the lines of its scenario's harmonic excitations the same way, ``# lines_hz = 50 (...)``
  (Hz, separated by spaces; :attr:`Records.lines_hz`), from which :meth:`Records.default_skip`
  keeps whole periods of them, and the supports' fade-in, ``# ramp_s = 0.01 (...)`` (s,
  ``scenario.ramp``; :attr:`Records.ramp_s`), before which that skip does not start. Every reader of these
  files skips lines starting with ``#`` (:func:`~cablecasing_core.files.read_csv_table`;
  ``numpy.loadtxt(path, delimiter=",", skiprows=1)``, ``numpy.genfromtxt(path, delimiter=",",
  names=True)``; ``pandas.read_csv(path, comment="#")``).
* **NPZ**: ``time`` (n,), ``table`` (n, m), ``names`` and ``units`` (m,), full double precision, and
  any further arrays of the writer (a run's per-node contact histories; :meth:`SimulationResult.load`).
* **UFF 58** (binary, through pyuff, :mod:`.uff`): one
  function of type 1 (time response) per column, ``id1`` the column's name, the ordinate's unit label and data type (9
  reaction force for forces and moments, 8 displacement, 11 velocity, 12 acceleration), the
  response node the support (casing A 1, casing B 2, cable A 3, cable B 4; 0 for the contact
  summary) and direction 1-3 for x, y, z, 4-6 for moments about them. Read, an ``id1`` that several
  functions share (an analyser's ``Response``) names each of them ``<id1>@<node><direction>``
  (``Response@2z``; :func:`~.uff.function_names`). What a run's record states
  (passband, lines, fade-in, as the CSV's comment lines) every function states in its ID lines
  (80 characters each): ID line 5 ``cablecasing passband_hz=3500 ramp_s=0.01``, ID line 3
  ``cablecasing lines_hz=50 100`` (:data:`~.uff.STATEMENTS`; a file of other
  tools, whose ID lines do not start with ``cablecasing``, states none). So a run's ``.uff`` file
  gives the same :meth:`Records.default_skip` and passband as its ``.csv`` and ``.npz``.

A record is evenly sampled by one rule, :attr:`Records.fs`, for every command and function that reads
one: its times on the uniform grid through the first and the last within 1e-6 of a step, or within
the rounding its file kept them to (a CSV's time printed with few digits, :attr:`Records.time_rounding`);
the rate is 1 / the least-squares slope of the times against their index.

Files are written atomically (:mod:`.files`): an interrupted write leaves an earlier file intact. A
record is written only if a reader takes it back (:func:`write_records`): a column that holds NaN, an
infinity or a magnitude beyond :data:`~cablecasing_core.files.MAX_MAGNITUDE` (a run that diverged) is
refused naming the column and the time of its first such value, and nothing is written.

**Net forces and paths** (:func:`derived_terms`; docs/nvh.md, "Net forces and paths"). Every column
a record's support and clip outputs add up to is a column of the record by its name:
``net.A.Fz``, ``net.B.Fz`` (``casing.<end>.<c>`` + ``cable.<end>.<c>``: at each end the casing's
abutment and the cable's end attach to one part, the shifter housing at A, the transmission at B),
``paths.Fz`` (both ends of both bodies and every clip: the whole force the cable and casing pass to
their mounts), and any sum of columns, ``net.A.Fz+casing.clip0.Fz``. Every output is the force the
body exerts on its support, in global axes, so the sum of the samples is the force on the part they
share; its spectrum and band levels are those of the summed samples (the spectrum of a sum is not
the sum of the spectra: the casing's and the cable's forces at an end cancel in part).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from .errors import ModelError, closest, plain, renamed
from .files import (
    MAX_MAGNITUDE,
    atomic_path,
    check_values,
    csv_statements,
    read_csv_table,
    runs_to_keep,
    time_column,
    unreadable,
)
from .model.schema import (
    BODY_NAMES,
    FORCE_NAMES,
    INPUTS,
    OUTPUTS,
    SUPPORT_NAMES,
    channels_of,
    input_spec,
    inputs_of,
    output_spec,
)
from .timedomain.start_skip import LEAST_SKIP, least_skip, skip_for_whole_periods  # noqa: F401 (also records' names)
from .uff import STATEMENTS, UFF_EXTENSIONS, Record, data_type, function_names, read_uff, write_uff
from .units import unit_key

SUFFIXES = (".csv", ".npz", ".uff")
_NODES = {"casing.A": 1, "casing.B": 2, "cable.A": 3, "cable.B": 4}


#: How far (of a step) an exact time may lie from the uniform grid through a record's first and last
#: (:attr:`Records.fs`), beside what summing the steps adds (:func:`_exact_allowance`): times computed
#: as k dt lie on it to rounding (1e-16 of t), a CSV's of 15 digits (:func:`write_records`) within
#: 1.3e-11 of a step at 1/30000 s; a sample missing or late is off it by half a step or more.
EXACT_DEPARTURE = 1e-6


def _grid_departures(time) -> tuple:
    """``(step, departures)`` of increasing times ``time`` (s): the step (s) of the uniform grid
    through the first and the last, and each time's distance from it (s)."""
    t = np.asarray(time, dtype=float)
    step = (t[-1] - t[0]) / (t.size - 1) if t.size > 1 else 0.0
    return step, np.abs(t - (t[0] + step * np.arange(t.size)))


def _exact_allowance(time) -> float:
    """How far (s) exact times ``time`` (s) may lie from the uniform grid through the first and the
    last (:attr:`Records.fs`): :data:`EXACT_DEPARTURE` of a step, plus n eps max|t|, what summing the
    steps in double precision may add (a host's ``t += h``; each sum rounds by at most eps/2 of
    itself, so the k-th time by k eps/2 max|t| and the grid through the ends by as much again):
    1e6 steps of 1/30000 s summed so lie up to 3.4e-10 s off (1e-5 of a step), within the 7.4e-9 s this
    allows, 2.2e-4 of a step."""
    t = np.asarray(time, dtype=float)
    step = (t[-1] - t[0]) / (t.size - 1) if t.size > 1 else 0.0
    return EXACT_DEPARTURE * step + t.size * np.finfo(float).eps * float(np.abs(t).max(initial=0.0))


def unit_of(name: str) -> str:
    """Unit of a record column: an output's or input's unit from the schema, "s" for time, else ""."""
    if name in ("time", "time_s"):
        return "s"
    for spec in (output_spec, input_spec):  # (also a clip's outputs and inputs)
        try:
            return spec(name)[0]
        except ModelError:
            pass
    try:  # a derived column (net.B.Fz, paths.Fz, a+b): its terms' unit when they share one
        terms = derived_terms(name, ())
    except ModelError:
        terms = None
    units = {unit_of(t) for t in terms or ()}
    return units.pop() if len(units) == 1 else ""


def check_column_name(name, names, key: str) -> None:
    """Refuse, as :meth:`Records.resolve` would on a record of the columns ``names``, a ``name``
    that is neither one of them nor a derived column of them (:func:`derived_terms`: ``net.B.Fz``,
    ``paths.Fz``, ``a+b`` of one unit): a :class:`ModelError` naming ``key`` (a run's output, checked
    before the run), with the closest name (``casing.b.fz``: ``casing.B.Fz``; ``net.B.Fq``: ``net.B.Fz``)
    and the sums it also takes."""
    if name in names:
        return
    with renamed({"name": key}):
        derived = isinstance(name, str) and derived_terms(name, names) is not None
    if not derived:
        sums = [f"net.{s}.{c}" for s in SUPPORT_NAMES for c in FORCE_NAMES] + [f"paths.{c}" for c in PATH_FORCES]
        close = closest(name, list(names) + sums)
        mean = f" (did you mean {close[0]}?)" if close else ""
        raise ModelError(
            key,
            name,
            f"must be one of the outputs{mean}: "
            + ", ".join(repr(n) for n in names)
            + ", or a sum of them: net.<A|B>.<Fx..Mz> (casing + cable at that end), paths.<Fx|Fy|Fz> (every end and "
            "clip), a+b (outputs of one unit joined by '+'; docs/nvh.md, \"Net forces and paths\")",
        )
    Records(time=np.zeros(2), columns={n: np.zeros(2) for n in names}, units={n: unit_of(n) for n in names}).resolve(
        name, key
    )


def after_skip(time: np.ndarray, skip: float, start: float = 0.0) -> np.ndarray:
    """Which samples of an evenly spaced time axis ``time`` (s) lie after the first ``skip`` s from
    ``start`` (s): the mask of t - start > skip, a sample within 1e-6 of a step of start + skip
    counting as at it (left out); ``skip`` = 0 keeps every sample (a measured record of n samples
    keeps its n). So a record of N steps of dt after ``skip`` > 0 keeps exactly N samples: t = k dt
    computed in floating point lands a hair above or below skip (6000 * 1e-5 > 0.06), and the
    sample at skip kept as well makes N + 1, whose periodic extension is one step
    longer than the whole periods of a line on the record's bins: through the rectangular window
    the installed specimen's 50 Hz line (27 N in octave 3) then leaks into octaves 1-2 in proportion
    to dt (docs/time_domain.md, "The record's length"). ``start``: 0 for a run's
    :class:`~cablecasing_core.timedomain.simulation.SimulationResult` (its ``time`` holds the ends of
    the steps, dt .. T), ``time[0]`` for a record read from a file (whose first row is its start)."""
    time = np.asarray(time, dtype=float)
    if skip == 0:
        return np.ones(time.shape, dtype=bool)
    step = (time[-1] - time[0]) / (time.size - 1) if time.size > 1 else 0.0
    return time - start > skip + 1e-6 * step


#: The force components a sum over paths adds: the moments of the paths are about their own points
#: (the ends' and the clips' nodes) and do not add to a moment about one.
PATH_FORCES = ("Fx", "Fy", "Fz")


def derived_terms(name: str, names) -> tuple | None:
    """The columns whose samples add up to the derived column ``name`` of a record whose columns
    are ``names``, or None when ``name`` is no derived column's name (docs/nvh.md, "Net forces and
    paths"). Every support and clip output is the force (N) or moment (N.m) the body exerts on its
    support, in global axes, so a sum of them is the force on what those supports hold:

    * ``net.<A|B>.<Fx..Mz>``: ``casing.<end>.<c>`` + ``cable.<end>.<c>``. At each end the casing's
      abutment and the cable's end attach to one part (the shifter housing at A, the transmission
      at B), and this is what that part receives: with a cable tension the casing pushes the part
      with about T and the cable pulls it with T, which cancel. The moments are about the end's node,
      where both bodies' end nodes lie (one centreline).
    * ``paths.<Fx|Fy|Fz>``: every end of both bodies and every clip of the casing in ``names``
      (``casing.clip0.Fz``, ...): the force the cable and casing pass to all their mounts together,
      their weight less the rate of change of their momentum (and of the Rayleigh damping's force
      against absolute motion, alpha M v). A moment is refused: those of the paths are about
      different points.
    * ``<a>+<b>+...``: the columns named, each a column or one of the above (the paths into a
      vehicle's body of a shifter mounted on it: ``net.A.Fz+casing.clip0.Fz+casing.clip1.Fz``).

    Raises :class:`ModelError` naming ``name`` for a ``paths`` moment, a sum with an empty term, or
    clips in ``names`` that skip an index (``casing.clip0`` and ``clip2`` without ``clip1``)."""
    if not isinstance(name, str):
        return None
    if "+" in name:
        terms = tuple(t.strip() for t in name.split("+"))
        if not all(terms):
            raise ModelError("name", name, "must be columns joined by '+', each named (no empty term)")
        return terms
    parts = name.split(".")
    if len(parts) == 3 and parts[0] == "net" and parts[1] in SUPPORT_NAMES and parts[2] in FORCE_NAMES:
        return tuple(f"{b}.{parts[1]}.{parts[2]}" for b in BODY_NAMES)
    if len(parts) == 2 and parts[0] == "paths" and parts[1] in FORCE_NAMES:
        c = parts[1]
        if c not in PATH_FORCES:
            raise ModelError(
                "name",
                name,
                "must be a force, paths.Fx, paths.Fy or paths.Fz: the paths' moments are about their own points (the "
                "ends' and the clips' nodes) and do not add; net.A.Mx and net.B.Mx are about one point",
            )
        clips = sorted(int(n[11:].split(".")[0]) for n in names if _is_clip_column(n, c))
        if clips != list(range(len(clips))):
            gap = min(set(range(len(clips) + 1)) - set(clips))
            raise ModelError(
                "name",
                name,
                f"must sum every clip: the record holds casing.clip{clips[-1]}.{c} but not casing.clip{gap}.{c}",
            )
        ends = tuple(f"{b}.{s}.{c}" for b in BODY_NAMES for s in SUPPORT_NAMES)
        return ends + tuple(f"casing.clip{i}.{c}" for i in clips)
    return None


def _is_clip_column(name, component) -> bool:
    """Whether ``name`` is the output ``casing.clip<i>.<component>`` of a clip."""
    parts = str(name).split(".")
    clip = len(parts) == 3 and parts[0] == "casing" and parts[1][:4] == "clip" and parts[1][4:].isdigit()
    return clip and parts[2] == component


@dataclass
class Records:
    """A time record: ``time`` (s, n), ``columns`` {name: (n,) array}, ``units`` {name: unit},
    ``source`` (file or run), ``extra`` (further arrays of an NPZ file; ``passband_hz``, of an NPZ
    file, a CSV file's comment line or a UFF file's ID line, see :attr:`passband_hz`).

    Checked when made: ``time`` a 1-D array (or list) of finite real numbers (s), ``columns`` a
    mapping of names to 1-D arrays (or lists) of as many samples as ``time``; a
    :class:`ModelError` names ``time``, or the column and both lengths, otherwise. The columns are
    kept as numpy arrays in a new dict (the caller's is not changed); their values are not checked
    (a column may hold NaN where a measurement has gaps: :func:`~.nvh.transfer.apparent_mass` and
    the band levels refuse it naming the column, :func:`read_records` refuses it in a file, and
    :func:`write_records` refuses to write it).

    A derived column (:func:`derived_terms`: ``net.B.Fz``, ``paths.Fz``, ``casing.B.Fz+cable.B.Fz``)
    is found by :meth:`resolve`, :meth:`column` and :meth:`unit` as any column: the first time it is
    asked for, the sum of its terms' samples is added to ``columns`` (so a file written afterwards
    holds it), its unit to ``units`` and its terms to ``derived`` ({name: terms}).

    ``time_rounding`` (s, one per sample or one for all): how far each time may lie from the time it
    stands for, as its file kept it: half the last digit a CSV printed it with
    (:func:`~cablecasing_core.files.printed_rounding`), the rounding of a UFF abscissa stored point by
    point; 0 (the default) for exact times (a run's, an NPZ file's). :attr:`fs` allows it;
    a time stored as a float narrower than float64 (float32) is allowed half its spacing at each time
    besides (``time_rounding`` is then that, or the one given where larger).
    ``time_label``: how a message names the time (``its time column 'time [s]' (the first)``)."""

    time: np.ndarray
    columns: dict
    units: dict = field(default_factory=dict)
    source: str = ""
    extra: dict = field(default_factory=dict)
    time_rounding: object = field(default=0.0, repr=False, compare=False)
    time_label: str = field(default="its time", repr=False, compare=False)
    derived: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self):
        time = np.asarray(self.time)
        if time.dtype.kind not in "iuf" or time.ndim != 1:
            raise ModelError(
                "time",
                self.time,
                f"must be a 1-D array of real numbers (s), one per sample; got {time.ndim}-D of dtype {time.dtype}",
            )
        stored_as = time.dtype
        narrow = stored_as.kind == "f" and stored_as.itemsize < 8  # (float32: MATLAB single, many DAQ exports)
        # the rounding of a narrower float (half its spacing at each time), allowed as a file's rounding is
        stored = 0.5 * np.abs(np.spacing(time)).astype(float) if narrow else 0.0
        time = time.astype(float, copy=False)
        if not np.all(np.isfinite(time)):
            k = int(np.argmax(~np.isfinite(time)))
            raise ModelError("time", plain(f"{float(time[k])} at sample {k}"), "must hold finite numbers (s) only")
        if not isinstance(self.columns, Mapping):
            raise ModelError("columns", self.columns, "must be a dict of column names and 1-D arrays of samples")
        columns = {}
        for name, values in self.columns.items():
            a = np.asarray(values)
            if a.ndim != 1 or a.size != time.size:
                shape = f"{a.size} samples" if a.ndim == 1 else f"an array of shape {a.shape}"
                raise ModelError(
                    f"columns[{name!r}]",
                    plain(shape),
                    f"must be a 1-D array as long as the time: {time.size} samples (one value per time)",
                )
            columns[name] = a
        rounding = np.asarray(self.time_rounding)
        if rounding.dtype.kind not in "iuf" or rounding.ndim > 1 or rounding.size not in (1, time.size):
            raise ModelError(
                "time_rounding",
                self.time_rounding,
                f"must be a number of s or one per sample ({time.size}): how far each time may lie from the time it "
                "stands for",
            )
        if not np.all(np.isfinite(rounding) & (rounding >= 0)):
            raise ModelError("time_rounding", self.time_rounding, "must hold finite numbers of s, 0 or more")
        if narrow:
            self.time_rounding = np.maximum(rounding.astype(float), stored)
            self.time_label = f"{self.time_label} (stored as {stored_as})"
        self.time, self.columns = time, columns
        self.units = dict(self.units or {})  # (a copy: a derived column's unit is added to it)

    @property
    def names(self) -> tuple:
        return tuple(self.columns)

    @property
    def fs(self) -> float:
        """Sampling rate (Hz) of the evenly sampled record; the one rule of every command and function
        that reads a record (``bands``, ``spectrum``, ``identify damping``, ``read_time_record``).

        The times must increase and lie on the uniform grid through the first and the last to within
        :data:`EXACT_DEPARTURE` of a step and what summing the steps may add (:func:`_exact_allowance`;
        exact times: a run's, an NPZ file's, a CSV's of 15 digits, a UFF abscissa given by its start
        and step, a host's summed times), or, where the file kept fewer digits
        (:attr:`time_rounding`: an analyser's ``%.6g`` CSV, whose steps at 2048 Hz differ by up to
        1 % of themselves; a UFF abscissa stored point by point in E13.5), to within that rounding
        (each time's, plus the first's and the last's, which place the grid) when it resolves the
        step to 10 % (a coarser one could hide a missing sample, which moves the times by half a
        step from that grid). A :class:`ModelError` naming the file, the time column, the sample
        that departs most and what is allowed otherwise.

        fs is 1 / the least-squares slope of the times against their index, not (n - 1) / (t[-1] -
        t[0]): on exact times the two agree to rounding (1e-15), but on rounded times the latter
        takes the error of its two ends alone (up to a digit over the record's length), the slope
        averages every time's. Over 300 records of ``%.6g`` times (0.3-5 s, 2-51 kHz, random
        starts) its error was 9e-8 of fs (median; the ends' 9e-7); 1.2 s at 2048 Hz: 6e-10 against
        2.5e-6, whose last time prints 1.19971 for 1.1997070."""
        t = self.time
        where = self.source or "record"
        if t.size < 2:
            raise ModelError(
                "file", where, f"holds {t.size} row(s): a record needs at least two samples for its time step"
            )
        d = np.diff(t)
        if not np.all(d > 0):
            k = int(np.argmax(d <= 0))
            raise ModelError(
                "file",
                where,
                f"must be evenly sampled: {self.time_label} must increase in equal steps, rows in time order; "
                f"sample {k + 2} of {t.size} (t = {t[k + 1]:.9g} s) does not come after sample {k + 1} "
                f"(t = {t[k]:.9g} s)",
            )
        step, departure = _grid_departures(t)
        rounding = np.broadcast_to(np.asarray(self.time_rounding, dtype=float), t.shape)
        resolved = 2.0 * float(rounding.max()) <= 0.1 * step
        exact = _exact_allowance(t)
        allowed = exact + (rounding + rounding[0] + rounding[-1] if resolved else 0.0)
        if np.any(departure > allowed):
            j = int(np.argmax(departure - allowed))
            within = f"{EXACT_DEPARTURE:g} of a step ({exact:.3g} s with what summing the steps may add)"
            if rounding.any() and resolved:
                within += (
                    f" plus the rounding the file kept each time to ({rounding[j]:.3g} s there, and that of the first "
                    f"and the last: +-{allowed[j]:.3g} s in all)"
                )
            elif rounding.any():
                within += f" (its digits, up to {2 * rounding.max():.3g} s, are too coarse to resolve its step to 10 %)"
            raise ModelError(
                "file",
                where,
                f"must be evenly sampled: {self.time_label} must increase in equal steps, rows in time order, no "
                f"sample missing, every time on the uniform grid through the first and the last to within {within}; "
                f"sample {j + 1} of {t.size} (t = {t[j]:.9g} s) departs from that grid of step {step:.6g} s by "
                f"{departure[j]:.3g} s ({departure[j] / step:.2g} of a step)",
            )
        k = np.arange(t.size) - 0.5 * (t.size - 1)  # (centred: the slope's sums without cancellation)
        return float(np.dot(k, k) / np.dot(k, t - t.mean()))

    @property
    def passband_hz(self) -> float:
        """The frequency (Hz) up to which the record holds its content unaltered: ``extra["passband_hz"]``
        where the record says so (a run's record decimated by its anti-alias filter,
        :func:`~cablecasing_core.timedomain.simulation.decimate`: flat within 0.01 dB up to 0.7 of
        its Nyquist frequency, less above; kept in ``.npz``, ``.csv`` and ``.uff`` files), else
        the Nyquist frequency fs/2. A record that states none may hold content of its source above
        the Nyquist frequency aliased below it (an FMU's outputs sampled at its communication points)."""
        nyquist = self.fs / 2
        if "passband_hz" not in self.extra:
            return nyquist
        return min(float(np.asarray(self.extra["passband_hz"])), nyquist)

    @property
    def lines_hz(self) -> tuple:
        """The frequencies (Hz) of the harmonic excitations the record states (``extra["lines_hz"]``:
        a run's record, in ``.npz``, ``.csv`` and ``.uff`` files), or () when it states none."""
        return tuple(float(f) for f in np.atleast_1d(self.extra.get("lines_hz", ())))

    @property
    def ramp_s(self) -> float:
        """The supports' fade-in (s) the record states (``extra["ramp_s"]``: a run of a scenario
        whose ``scenario.ramp`` is not 0, in ``.npz``, ``.csv`` and ``.uff`` files), or 0."""
        return float(np.asarray(self.extra.get("ramp_s", 0.0)))

    def default_skip(self) -> float:
        """The start of the record (s) the band levels and spectra leave out by default: the longer
        of :data:`LEAST_SKIP` and :attr:`ramp_s` (:func:`least_skip`), lengthened so that the rest
        holds whole periods of :attr:`lines_hz` (:func:`skip_for_whole_periods`); as ``ensemble``
        and ``study`` take for a run of the same scenario (``timedomain.scenario.whole_period_skip``)."""
        length = float(self.time[-1] - self.time[0])
        return skip_for_whole_periods(self.lines_hz, length, 1.0 / self.fs, least_skip(self.ramp_s))

    def run_step(self) -> tuple | None:
        """What the record says of the time step (s) of the run it holds: ``(dt, "every step")`` for a
        run's record of every step, which states its Nyquist frequency as its passband (a run's
        :meth:`~cablecasing_core.timedomain.simulation.SimulationResult.records`), so that its sample
        interval 1 / fs is the step; ``(dt_max, "decimated")`` for a decimated one, which states less
        (0.7 of its Nyquist frequency, after the anti-alias filter; a record of a result loaded from
        such a file keeps it) and holds at least two steps per sample without saying how many, so that
        the step is at most half its sample interval; None for a record that states no passband (picked
        samples, a CSV of an FMU's outputs written by its host, a measurement), whose samples say
        nothing of a step."""
        if "passband_hz" not in self.extra:
            return None
        nyquist = self.fs / 2
        if abs(float(np.asarray(self.extra["passband_hz"])) - nyquist) <= 1e-6 * nyquist:
            return 1.0 / self.fs, "every step"
        return 0.5 / self.fs, "decimated"

    def resolve(self, name: str, key: str = "name") -> str:
        """The column called ``name``, its header form ``name [unit]`` or ``name_unit``, or a derived
        column (:func:`derived_terms`, added to the record when first asked for; a name with ``+``
        is a sum unless a column of the record has that name); a :class:`ModelError` naming ``key``
        (the argument that gave the name: ``name`` by default; the command line passes its option,
        ``--column``, ``--input``) lists the columns when there is none, and names a derived
        column's term that the record lacks, or terms of different units."""
        if name in self.columns:
            return name
        bare = name.split(" [")[0]
        for col in self.columns:
            u = self.units.get(col, "")
            if bare == col or name in (f"{col} [{u}]", f"{col}_{u}", f"{col}_{u.replace('.', '')}"):
                if "+" not in name or "+" in col:  # (casing.B.Fz [N]+cable.B.Fz [N] is a sum)
                    return col
        derived = self._derive(name, key)
        if derived is not None:
            return derived
        raise ModelError(key, name, f"must be a column of {self.source or 'the record'}: " + ", ".join(self.columns))

    def _derive(self, name, key):
        """The derived column ``name`` (:func:`derived_terms`) added to the record; None when
        ``name`` names none."""
        with renamed({"name": key}):  # (named as the caller's argument or option: --column)
            terms = derived_terms(name, self.columns)
        if terms is None:
            return None
        cols = []
        for t in terms:
            try:
                cols.append(self.resolve(t, key))
            except ModelError:
                raise ModelError(
                    key,
                    name,
                    f"is the sum {' + '.join(terms)}, but {t} is not a column of {self.source or 'the record'} "
                    "(its columns: " + ", ".join(self.columns) + ")",
                ) from None
        twice = [c for c in cols if cols.count(c) > 1]
        if twice:
            raise ModelError(key, name, f"names {twice[0]} twice: give each term of a sum once")
        units = [self.units.get(c, "") for c in cols]
        if len({unit_key(u, False) for u in units}) > 1:  # (m/s^2 and m/s2 are one unit: units.unit_key)
            shown = ", ".join(f"{c} [{u or 'no unit'}]" for c, u in zip(cols, units))
            raise ModelError(key, name, f"adds columns of different units ({shown}): the terms of a sum need one unit")
        canon = "+".join(cols) if "+" in name else name
        if canon not in self.columns:
            self.columns[canon] = np.sum([np.asarray(self.columns[c], dtype=float) for c in cols], axis=0)
            self.units[canon] = units[0]
            self.derived[canon] = tuple(cols)
        return canon

    def terms(self, name: str, key: str = "name") -> tuple:
        """The columns whose sum the column ``name`` is (a derived one's terms, :func:`derived_terms`;
        a column's own name, as a 1-tuple, otherwise)."""
        col = self.resolve(name, key)
        return self.derived.get(col, (col,))

    def column(self, name: str, key: str = "name") -> np.ndarray:
        """The values of a column (see :meth:`resolve`), in its unit."""
        return self.columns[self.resolve(name, key)]

    def unit(self, name: str, key: str = "name") -> str:
        """The unit of a column (see :meth:`resolve`), "" where none is known."""
        return self.units.get(self.resolve(name, key), "")


def write_records(path: str | os.PathLike, rec: Records) -> str:
    """Write ``rec`` to ``path`` by its suffix (``.csv``, ``.npz``, ``.uff``; atomically). Returns the
    path. A suffix it does not write raises :class:`ModelError` naming ``path`` (the CLI renames it
    to its option, ``errors.renamed``); a folder that does not exist, or a failed write,
    :class:`~cablecasing_core.files.WriteError`. Nothing is written that :func:`read_records` would
    refuse to read back: a column that is not real, or holds NaN, an infinity or a magnitude beyond
    :data:`~cablecasing_core.files.MAX_MAGNITUDE` (a run that diverged), raises :class:`ModelError`
    naming the column and the time of its first such value (:func:`check_record_values`), and an earlier
    file of that name is left as it was."""
    path = str(path)
    suffix = os.path.splitext(path)[1].lower()
    if suffix not in SUFFIXES:
        raise ModelError("path", path, "must end in " + ", ".join(SUFFIXES))
    names = list(rec.columns)
    check_record_values(path, rec)
    table = np.column_stack([rec.time] + [np.asarray(rec.columns[n], float) for n in names])
    units = [rec.units.get(n, "") for n in names]
    if suffix == ".csv":
        header = csv_header(["time [s]"] + [_csv_field(n, u) for n, u in zip(names, units)])
        if "passband_hz" in rec.extra:  # (comment lines after the header: _read_csv reads them back)
            header += "\n" + passband_line(float(np.asarray(rec.extra["passband_hz"])))
        if rec.lines_hz:
            header += "\n" + lines_line(rec.lines_hz)
        if rec.ramp_s > 0:
            header += "\n" + ramp_line(rec.ramp_s)
        with atomic_path(path) as tmp:
            # (the time with 15 digits: with 9, the steps of 1/30000 s would differ by 3e-5 of themselves)
            fmt = ["%.15g"] + ["%.9g"] * len(names)
            np.savetxt(tmp, table, delimiter=",", header=header, comments="", fmt=fmt)
    elif suffix == ".npz":
        # (to an open file: numpy appends .npz to a name that does not end in it, such as "r.NPZ")
        with atomic_path(path) as tmp, open(tmp, "wb") as fh:
            np.savez_compressed(
                fh, time=rec.time, table=table[:, 1:], names=np.array(names), units=np.array(units), **rec.extra
            )
    else:
        # (what the CSV's comment lines state, to the same 15 digits: the ID lines 3 and 5 of every function)
        stated = {}
        if "passband_hz" in rec.extra:
            stated["passband_hz"] = f"{float(np.asarray(rec.extra['passband_hz'])):.15g}"
        if rec.lines_hz:
            stated["lines_hz"] = " ".join(f"{f:.15g}" for f in rec.lines_hz)
        if rec.ramp_s > 0:
            stated["ramp_s"] = f"{rec.ramp_s:.15g}"
        funcs = [
            Record(
                "time",
                rec.time,
                table[:, 1 + i],
                n,
                *uff_dof(n),
                unit=u,
                data_type=data_type(u),
                stated=stated,
            )
            for i, (n, u) in enumerate(zip(names, units))
        ]
        write_uff(path, funcs)
    return path


def check_record_values(path, rec: Records) -> None:
    """Refuse (:class:`ModelError` naming the column, ``time`` for the time) a record that a file
    written from it would not give back (:func:`read_records` reads real, finite numbers of magnitude
    at most :data:`~cablecasing_core.files.MAX_MAGNITUDE` only): a column of complex or non-numeric
    values, or one that holds NaN, an infinity or a larger magnitude, named with the time (s) and
    the row of its first such value, and with ``path``, to which nothing is written."""
    n = rec.time.size
    for key, shown, values in [("time", plain("the time axis"), rec.time)] + [
        ("column", name, v) for name, v in rec.columns.items()
    ]:
        a = np.asarray(values)
        if a.dtype.kind not in "biuf":
            raise ModelError(
                key,
                shown,
                f"holds values of type {a.dtype}: a record's file holds real numbers only; nothing was written to "
                f"{path}",
            )
        a = a.astype(float, copy=False)
        bad = unreadable(a)
        if bad.any():
            k = int(np.argmax(bad))
            what = str(a[k]) if not np.isfinite(a[k]) else f"{a[k]:.3g}"
            raise ModelError(
                key,
                shown,
                f"holds {what} at t = {rec.time[k]:.9g} s (row {k + 1} of {n}), its first value a record's file "
                f"cannot hold (read_records reads finite numbers of magnitude at most {MAX_MAGNITUDE:g} only): nothing "
                f"was written to {path}. Values not finite or this large come from a run that diverged (a time "
                "step too long for the model, or a motion or load beyond it); a gap in a measurement can be written "
                "by the part before it",
            )


def passband_line(passband_hz: float) -> str:
    """The comment line by which a CSV record states its passband (Hz): ``# passband_hz = 3500
    (...)``, the frequency to 15 significant digits and what it means (no comma: a reader that
    splits the line at commas still finds a single field starting with ``#``)."""
    return (
        f"# passband_hz = {passband_hz:.15g} (Hz: the columns hold the run's content unaltered up to this frequency "
        "and nothing aliased from above it: a run's every step or its record low-pass filtered against aliasing)"
    )


def lines_line(lines_hz) -> str:
    """The comment line by which a CSV record states the lines of its harmonic excitations (Hz):
    ``# lines_hz = 50 (...)``, several separated by spaces (no comma, as :func:`passband_line`)."""
    return (
        "# lines_hz = "
        + " ".join(f"{f:.15g}" for f in lines_hz)
        + (
            " (Hz: the harmonic excitations of the run; band levels leave out by default the start that keeps "
            "whole periods of them after it)"
        )
    )


def ramp_line(ramp_s: float) -> str:
    """The comment line by which a CSV record states the supports' fade-in (s): ``# ramp_s = 0.01
    (...)``, to 15 significant digits (no comma, as :func:`passband_line`)."""
    return (
        f"# ramp_s = {ramp_s:.15g} (s: the supports' motion fades in over this time, scenario.ramp; band levels "
        "leave out by default at least this start)"
    )


def uff_dof(name: str) -> tuple:
    """(rsp_node, rsp_dir, ref_node, ref_dir) of a record column or a support DOF such as
    ``casing.B.x`` in UFF 58 (module docstring)."""
    parts = name.split(".")
    node = _NODES.get(".".join(parts[:2]), 0)
    last = parts[-1] if len(parts) == 3 else ""
    direction = {"x": 1, "y": 2, "z": 3}.get(last[-1:], 0) if node else 0
    if last[:1] == "M":
        direction += 3
    return node, direction, 0, 0


def read_records(path: str | os.PathLike, channel: str | int | None = None) -> Records:
    """The record in ``path`` (``.csv``, ``.npz`` or ``.uff``/``.unv``, by suffix; see the module
    docstring). Raises :class:`ModelError` naming the file and what is wrong. ``channel`` (a column's
    name or place, as the caller's ``--channel``) changes no value read: a UFF file's refusal for
    another time function says that the one asked for is not concerned (the file is read, and
    refused, as a whole: its functions are one record)."""
    path = str(path)
    suffix = os.path.splitext(path)[1].lower()
    if not os.path.exists(path):
        raise ModelError("file", path, "does not exist")
    if not os.path.isfile(path):
        raise ModelError("file", path, "must be a regular file (not a folder or a device)")
    if suffix == ".npz":
        rec = _read_npz(path)
    elif suffix in UFF_EXTENSIONS:
        rec = _read_uff(path, channel)
    elif suffix not in (".csv", ".txt"):
        raise ModelError("file", path, "must end in .csv, .npz or .uff (the record's format goes by its suffix)")
    else:
        rec = _read_csv(path)
    return rec


def _file_record(path, time, columns, units, extra=None, time_label="its time", time_rounding=0.0) -> Records:
    """The :class:`Records` of a file's time and columns, checked first as a file's (a
    :class:`ModelError` naming the file, the column and what is wrong): real, finite numbers, every
    column as long as the time; ``time_label`` and ``time_rounding`` as :class:`Records`'."""
    for name, values in [("time", time), *columns.items()]:
        if np.iscomplexobj(values):
            raise ModelError("file", path, f"column {name} holds complex numbers: a time record must be real")
    check_values("file", path, time)
    if np.ndim(time) != 1:
        raise ModelError("file", path, f"its time must be one column of samples, not of shape {np.shape(time)}")
    for j, values in enumerate(columns.values()):
        if np.shape(values) != np.shape(time):
            raise ModelError(
                "file", path, f"column {j + 2} has {np.size(values)} samples, the time axis {np.size(time)}"
            )
        check_values("file", path, np.column_stack([time, values]))
    return Records(time, columns, units, path, {} if extra is None else extra, time_rounding, time_label)


def _read_csv(path):
    header, data = read_csv_table(path, "file")
    names, units = [], {}
    to_s = time_column("file", path, header[0])  # (time [ms], time_ms: converted to s)
    time = data[:, 0] if to_s == 1.0 else data[:, 0] * to_s
    for h in header[1:]:
        name, unit = _csv_name(h)
        names.append(name)
        units[name] = unit or unit_of(name)
    _unique(path, [header[0], *names])  # (with the earlier '<name>_<unit>' forms mapped to their names)
    cols = {n: data[:, i + 1] for i, n in enumerate(names)}
    passband, lines, ramp = _csv_stated(path)
    extra = {} if passband is None else {"passband_hz": np.array(passband)}
    if lines is not None:
        extra["lines_hz"] = np.array(lines)
    if ramp is not None:
        extra["ramp_s"] = np.array(ramp)
    rec = _file_record(path, time, cols, units, extra, f"its time column {header[0]!r} (the first)")
    departure = _grid_departures(rec.time)[1]
    if rec.time.size > 2 and np.any(departure > _exact_allowance(rec.time)):
        # (the printed digits widen what Records.fs allows, so they matter only for times off the grid:
        # read then, by the one reader again; parsing every row's digits costs as much as the table)
        rec.time_rounding = read_csv_table(path, "file", rounding=True)[2] * to_s
    return rec


def _csv_name(h: str) -> tuple:
    """``(name, unit)`` of a CSV header's field (as the csv module gives it, quotes removed):
    ``name [unit]``, or ``<name>_<unit>`` of an output or input (earlier versions), or a bare name
    (unit "")."""
    h = h.strip()
    name, _, unit = h.partition(" [")
    name, unit = name.strip(), unit.rstrip("]")
    for known in OUTPUTS + INPUTS:  # the '<name>_<unit>' form of earlier versions
        if h in (f"{known}_{unit_of(known)}", f"{known}_{unit_of(known).replace('.', '')}"):
            name = known
    return name, unit


def _csv_field(name: str, unit: str) -> str:
    """A column's field of a CSV header, ``name [unit]`` (or ``name`` without a unit), checked to be
    read back as that name and unit (:func:`_csv_name`): a name or unit with a line break (the reader
    takes a line for a row), a name with `` [`` (the reader's start of the unit), with spaces around
    it (the reader strips them), or in the earlier ``<name>_<unit>`` form of another column raises
    :class:`ModelError` naming the column. A comma or a double quote is fine: the header quotes
    such a field (:func:`csv_header`)."""
    field_ = f"{name} [{unit}]" if unit else str(name)
    back = _csv_name(field_)
    why = None
    if len(f"{field_}x".splitlines()) > 1:  # (\n, \r and what else str.splitlines, the reader's, splits at)
        why = "a line break, which a CSV header cannot hold (its reader takes it for a row)"
    elif back[0] != name or (unit and back[1] != unit):
        why = (
            "what a CSV header cannot give back: it would be read as "
            + (f"'{back[0]}' [{back[1]}]" if back[1] else f"'{back[0]}'")
            + " (a name has no ' [', which starts its unit, no spaces around it, and is not an output's or input's "
            "earlier form <name>_<unit>)"
        )
    if why:
        raise ModelError(
            "column", name, f"holds {why}; rename the column, or write the record as .npz or .uff, which keep any name"
        )
    return field_


def csv_header(fields) -> str:
    """The header line of ``fields``, separated by commas; a field with a comma or a double quote in
    double quotes (its quotes doubled), as the csv module writes it and :func:`read_records` reads it
    (``files.read_csv_table``)."""
    import csv
    import io

    out = io.StringIO()
    csv.writer(out, lineterminator="").writerow(fields)
    return out.getvalue()


def _csv_stated(path):
    """The passband (Hz), the lines (Hz, a tuple) and the fade-in (s) a CSV record states in comment
    lines before its first row of numbers (:func:`passband_line`, :func:`lines_line`,
    :func:`ramp_line`, read by :func:`~cablecasing_core.files.csv_statements`), each None when not
    stated. One stated other than as positive numbers (one passband, one fade-in), or stated twice,
    raises :class:`ModelError` naming the file and the line."""
    stated = csv_statements(path, ("passband_hz", "lines_hz", "ramp_s"))
    out = []
    for name, example in (("passband_hz", "3500"), ("lines_hz", "50"), ("ramp_s", "0.01")):
        if name not in stated:
            out.append(None)
            continue
        lineno, text = stated[name]
        try:
            values = tuple(float(v) for v in text.split())
        except ValueError:
            values = ()
        if not _stated_well(name, values):
            raise ModelError(
                "file",
                path,
                f"line {lineno} states {name}, but not as {_STATED[name]} ('# {name} = {example}', as "
                "'cablecasing simulate --out' writes it)",
            )
        out.append(values if name == "lines_hz" else values[0])
    return tuple(out)


#: What a record may state beside its columns, and how (CSV comment lines, NPZ arrays).
_STATED = {
    "passband_hz": "a positive number of Hz",
    "lines_hz": "positive numbers of Hz separated by spaces",
    "ramp_s": "a number of s, 0 or more",
}


def _stated_well(name, values) -> bool:
    """Whether ``values`` (a sequence of floats) is what a record may state as ``name`` (:data:`_STATED`)."""
    values = tuple(values)
    if not values or not all(np.isfinite(v) for v in values) or (name != "lines_hz" and len(values) > 1):
        return False
    return all(v >= 0 for v in values) if name == "ramp_s" else all(v > 0 for v in values)


def _check_npz_stated(path, arrays):
    """The statements of an NPZ record (``passband_hz``, ``lines_hz``, ``ramp_s`` arrays) checked as a
    CSV's are (:func:`_csv_stated`): a :class:`ModelError` naming the file and the array otherwise."""
    for name, what in _STATED.items():
        if name not in arrays:
            continue
        a = np.asarray(arrays[name])
        ok = a.dtype.kind in "iuf" and a.ndim <= 1 and _stated_well(name, np.atleast_1d(a).astype(float).tolist())
        if not ok:
            raise ModelError("file", path, f"its array {name} must be {what.replace(' separated by spaces', '')}")


def _unique(path, names):
    """Column names must be unique (a second column of a name would be ignored silently); a
    column's name is its header without the unit (``casing.B.Fz [N]`` and the earlier form
    ``casing.B.Fz_N``, mapped to its name before this check, are the same)."""
    seen = {}
    for j, n in enumerate(names):
        bare = str(n).split(" [")[0].strip()
        if bare in seen:
            raise ModelError(
                "file",
                path,
                f"column {j + 1} repeats the name of column {seen[bare] + 1} (names must be unique; "
                "'<name> [<unit>]' and '<name>_<unit>' are the same name)",
            )
        seen[bare] = j


def _read_npz(path):
    import zipfile

    try:
        with np.load(path, allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files}
        for k in ("time", "table"):  # integer or boolean samples are numbers, as in a CSV table
            if k in arrays and arrays[k].dtype.kind in "iub":
                arrays[k] = arrays[k].astype(float)
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile) as exc:
        raise ModelError("file", path, f"is not a readable .npz file ({type(exc).__name__})") from None
    if "table" in arrays and "names" in arrays and "time" in arrays:
        names = [str(n) for n in np.atleast_1d(arrays.pop("names"))]
        units = [str(u) for u in np.atleast_1d(arrays.pop("units", np.array([unit_of(n) for n in names])))]
        table, time = np.asarray(arrays.pop("table")), np.asarray(arrays.pop("time"))
        if time.ndim != 1 or table.ndim != 2 or table.shape != (time.size, len(names)) or len(units) != len(names):
            raise ModelError(
                "file",
                path,
                f"must hold time (n,), table (n, m), names and units (m,); it holds time {time.shape}, table "
                f"{table.shape}, {len(names)} names and {len(units)} units",
            )
        _unique(path, names)
        _check_npz_stated(path, arrays)
        return _file_record(path, time, {n: table[:, i] for i, n in enumerate(names)}, dict(zip(names, units)), arrays)
    if "time" in arrays:  # any npz of 1-D arrays beside a time axis
        time = arrays.pop("time")
        cols = {k: v.astype(float) if v.dtype.kind in "iub" else v for k, v in arrays.items() if v.shape == time.shape}
        if cols:
            return _file_record(path, time, cols, {k: unit_of(k) for k in cols})
    raise ModelError("file", path, "must hold the arrays time, table, names (as 'cablecasing simulate --out' writes)")


def _axis_text(t) -> str:
    """A time axis for a message: its samples, start and (mean) step, ``3000 samples from 0 s every 0.001 s``."""
    step = (t[-1] - t[0]) / (t.size - 1) if t.size > 1 else float("nan")
    return f"{t.size} samples from {t[0]:.6g} s every {step:.6g} s"


def _asked(names, channel):
    """The name among ``names`` (a UFF file's time functions) that ``channel`` gives (a name, its header form
    ``Response [m/s2]``, or a place), or None when it gives none of them (a derived column) or is None."""
    if channel is None:
        return None
    if isinstance(channel, str) and not channel.strip().isdigit():
        bare = channel.split(" [")[0].strip()
        return bare if bare in names else None
    j = int(channel)
    return names[j] if 0 <= j < len(names) else None


def _read_uff(path, channel=None):
    every = read_uff(path)
    funcs = [r for r in every if r.kind == "time"]
    if not funcs:
        held = ", ".join(str(n) for n in sorted({r.func_type for r in every}))
        raise ModelError(
            "file",
            path,
            f"contains no time record (UFF 58, function type 1); it holds UFF 58 function type(s) {held} (1 time "
            "response, 4 FRF, 6 coherence, ...)",
        )
    t = funcs[0].x
    cols, units = {}, {}
    # (each column its id1; an id1 that repeats, as an analyser's "Response", <id1>@<node><direction>)
    names = function_names(funcs, [r.name or f"x{i + 1}" for i, r in enumerate(funcs)])
    asked = _asked(names, channel)

    def as_a_whole(name):  # (why another function's fault refuses the file: said when a channel was asked)
        fine = f"the channel asked for, {asked}, is not concerned, but " if asked not in (None, name) else ""
        return (
            f"{fine}a file's time functions are read as one record (spectrum, bands and the derived columns use them "
            "together), so the file is refused as a whole"
        )

    for i, (r, name) in enumerate(zip(funcs, names)):
        if r.x.shape != t.shape or not np.allclose(r.x, t, rtol=0, atol=1e-9 * max(1.0, abs(t[-1]))):
            raise ModelError(
                "file",
                path,
                f"time function {i} ({name}) has another time axis than the first ({names[0]}): "
                f"{_axis_text(r.x)}, against {_axis_text(t)}; the time functions of one file must share one time "
                f"axis (the same start, step and number of samples): {as_a_whole(name)}; export them on one axis "
                f"(cut to the shorter), or {name} to a file of its own",
            )
        if name in cols:
            raise ModelError(
                "file",
                path,
                f"time function {i} repeats the name of an earlier one, {name} (its id1, and its node and "
                "direction where the id1 repeats, and its reference where those do): names must be unique",
            )
        if r.stated != funcs[0].stated:  # (one record: every function states the same)
            raise ModelError(
                "file",
                path,
                f"time function {i} ({r.name}) states {r.stated or 'nothing'} in its ID lines 3 and 5, time function "
                f"0 ({funcs[0].name}) {funcs[0].stated or 'nothing'}: the functions of one record state the same",
            )
        bad = unreadable(np.asarray(r.data, float))
        if bad.any():  # (named by the function and its time, as the file's reader knows them)
            at = np.flatnonzero(bad)
            k, n = int(at[0]), t.size
            keep = runs_to_keep(
                bad, lambda i: f"the record up to {t[i - 1]:.6g} s", lambda j: f"the record from {t[j]:.6g} s"
            )
            if len(funcs) > 1:
                keep.append(f"the other functions without {name}")
            raise ModelError(
                "file",
                f"{path} ({name})",
                f"holds a value that is not a finite number of magnitude at most {MAX_MAGNITUDE:g} at {t[k]:.6g} s "
                f"(point {k + 1} of {n}{f', and {at.size - 1} more' if at.size > 1 else ''}): an overloaded or "
                f"missing measurement"
                + (f"; {as_a_whole(name)}" if len(funcs) > 1 else "")
                + "; measure again"
                + (f", or export only {' or '.join(keep)}" if keep else ""),
            )
        cols[name] = np.asarray(r.data, float)
        units[name] = r.unit or unit_of(name)
    extra = {}
    for name, text in funcs[0].stated.items():  # (as a CSV's comment lines, _csv_stated)
        try:
            values = tuple(float(v) for v in text.split())
        except ValueError:
            values = ()
        if not _stated_well(name, values):
            example = {"passband_hz": "3500", "lines_hz": "50", "ramp_s": "0.01"}[name]
            raise ModelError(
                "file",
                path,
                f"its ID line {STATEMENTS[name]} states {name}, but not as {_STATED[name]} ('cablecasing "
                f"{name}={example}', as 'cablecasing simulate --out' writes it)",
            )
        extra[name] = np.array(values if name == "lines_hz" else values[0])
    label = f"the abscissa of its time function{'s' if len(funcs) > 1 else ''} ({', '.join(names[:3])}"
    label += (", ..." if len(funcs) > 3 else "") + (", stored point by point)" if funcs[0].abscissa_rounding else ")")
    return _file_record(path, t, cols, units, extra, label, funcs[0].abscissa_rounding * np.abs(t))


def driven_inputs(model) -> tuple:
    """The support inputs (names of ``inputs_of(model)``: :data:`INPUTS` and an excited clip's
    ``<excitation>.z``, ``.vz``, ``.az``) of the channels the model's scenario drives: for each
    excitation target its three inputs (displacement, velocity, acceleration); an ``axial`` target
    drives x, y and z of its support."""
    channels, names = channels_of(model), inputs_of(model)
    chans = []
    for e in model.scenario["excitation"].values():
        *where, d = e["target"].split(".")
        for c in ("x", "y", "z") if d == "axial" else (d,):
            ch = ".".join([*where, c])
            if ch not in chans:
                chans.append(ch)
    chans.sort(key=channels.index)
    return tuple(names[k * len(channels) + channels.index(c)] for k in range(3) for c in chans)
