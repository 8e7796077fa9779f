"""Measured data for the identification: a time record's column and FRFs, from CSV, NPZ or UFF files.

A time record is a column of a record file (:func:`read_time_record`: CSV, NPZ or UFF dataset 58 through
:func:`cablecasing_core.records.read_records`, the one reader of record files, whose ``Records.fs`` is
the one rule of an evenly sampled time). An FRF is read from CSV or from UFF dataset 58 (type 4).
The UFF 58 format itself (:class:`Record`, :func:`read_uff`, :func:`write_uff`, the data types) is
:mod:`cablecasing_core.uff`, and the units of frequency are :mod:`cablecasing_core.units`; their names
are importable from here as well.

CSV time records have one header line, ``time_s,<channel>,...`` (:func:`write_csv_time`). CSV FRFs:
``frequency_hz,re_<name>,im_<name>[,...]`` (the first ``re_``/``im_`` pair, or the one ``channel`` names; the ``trfam``
CLI's ``frequency_hz,re_kg,im_kg,magnitude_kg,phase_deg`` files are accepted as they are), after an
optional line ``# kind = <kind>`` (displacement, velocity, acceleration, apparent_mass) that
:func:`write_csv_frf` writes when given the kind and :func:`read_frf_kind` reads back.
Units are SI: s, Hz, and the unit of the quantity.
"""

from __future__ import annotations

import re
import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError, ModelWarning, and_joined, excerpt
from ..files import atomic_path, csv_statements, read_csv_table, runs_to_keep
from ..model.validators import Choice, array_1d, number
from ..records import derived_terms, read_records
from ..uff import (
    DATA_TYPES,
    FRF_KIND_TYPES,
    PYUFF_MISSING,
    STATEMENTS,
    UFF_EXTENSIONS,
    Record,
    check_function,
    dof_name,
    frf_kind,
    function_names,
    is_uff,
    read_uff,
    write_uff,
    write_uff_frf,
    write_uff_time,
)
from ..units import FREQUENCY_UNITS, frequency_factor, frequency_units_text

__all__ = [
    "DATA_TYPES",
    "FREQUENCY_NAMES",
    "FREQUENCY_UNITS",
    "FRF_KIND_TYPES",
    "PYUFF_MISSING",
    "STATEMENTS",
    "UFF_EXTENSIONS",
    "MeasuredFRF",
    "Record",
    "frequency_column",
    "frequency_factor",
    "frequency_units_text",
    "frf_kind",
    "function_names",
    "is_frequency_header",
    "is_uff",
    "read_csv_frf",
    "read_csv_time",
    "read_frf",
    "read_frf_function",
    "read_frf_kind",
    "read_time_record",
    "read_time_record_from",
    "read_uff",
    "write_csv_frf",
    "write_csv_time",
    "write_uff",
    "write_uff_frf",
    "write_uff_time",
]


def write_csv_time(path, x, fs, names=None, t0=0.0):
    """Time record(s) to CSV: columns ``time_s`` and one per channel (``x`` of shape (n,) or (n, k),
    real and finite, in the channels' own units: checked before anything is written); ``fs`` the
    sampling rate (Hz), ``t0`` the first sample's time (s), ``names`` the channels' column names."""
    a = np.asarray(x)
    if a.ndim not in (1, 2):
        raise ModelError("x", f"array of shape {a.shape}", "must be samples (n,) or channels of samples (n, k)")
    x2 = array_1d("x", a.reshape(a.shape[0], -1).ravel(), min_len=1).reshape(a.shape[0], -1)
    names = list(names) if names else (["x"] if x2.shape[1] == 1 else [f"x{i + 1}" for i in range(x2.shape[1])])
    if len(names) != x2.shape[1]:
        raise ModelError("names", names, f"must give one name per channel ({x2.shape[1]})")
    t = number("t0", t0, unit="s") + np.arange(x2.shape[0]) / number("fs", fs, gt=0, unit="Hz")
    with atomic_path(path) as tmp:
        np.savetxt(
            tmp, np.column_stack([t, x2]), delimiter=",", header=",".join(["time_s", *names]), comments="", fmt="%.17g"
        )


def write_csv_frf(path, freqs_hz, H, name="H", kind=None):
    """A complex FRF to CSV: ``frequency_hz,re_<name>,im_<name>`` (finite values, one per frequency,
    the frequencies strictly increasing: checked before anything is written). ``kind`` (one of
    ``circlefit.FRF_KINDS``: "displacement", "velocity", "acceleration", "apparent_mass") is written
    as a first line ``# kind = <kind>``, which :func:`read_frf_kind` reads back; None writes no such
    line (the reader's caller then takes its default)."""
    if kind is not None:
        from .circlefit import FRF_KINDS

        kind = Choice(*FRF_KINDS)("kind", kind)
    f, H = check_function(freqs_hz, H, "freqs_hz", "H", real=False, min_len=1)
    table = np.column_stack([f, H.real, H.imag])
    head = f"frequency_hz,re_{name},im_{name}"
    if kind is not None:
        head = f"# kind = {kind}\n{head}"
    with atomic_path(path) as tmp:
        np.savetxt(tmp, table, delimiter=",", header=head, comments="", fmt="%.17g")


def _csv_frf_kind(path, strict=True):
    """The FRF kind a CSV's comment line ``# kind = <kind>`` states before its first row of numbers
    (:func:`~cablecasing_core.files.csv_statements`; :func:`write_csv_frf` writes it before the
    header), None without one (a file of other tools, or written without a kind); for a kind the
    circle fit does not take a ModelError naming ``file`` (None when not ``strict``)."""
    stated = csv_statements(path, ("kind",)).get("kind")
    if stated is None:
        return None
    lineno, kind = stated[0], stated[1].lower()
    from .circlefit import FRF_KINDS

    if kind in FRF_KINDS:
        return kind
    if not strict:
        return None
    raise ModelError(
        "file",
        str(path),
        f"its line {lineno}, '# kind = {stated[1]}', names no FRF kind the circle fit takes: one of "
        + ", ".join(repr(k) for k in FRF_KINDS),
    )


def read_time_record(path, channel=None):
    """``(x, fs, name)``: the column ``channel`` of the record file ``path`` (CSV, NPZ or UFF: any file
    :func:`~cablecasing_core.records.read_records` reads), its sampling rate (Hz,
    ``Records.fs``: the rule of every command that reads records) and its name. ``channel`` is a
    column's name (``casing.B.Fz``, its header form ``casing.B.Fz [N]``, a UFF function's ``id1`` or
    ``<id1>@<node><direction>``, a derived column such as ``net.B.Fz``) or its place among the
    columns (0 the first after the time; default 0)."""
    return read_time_record_from(path, channel)[:3]


def read_csv_time(path, channel=None):
    """:func:`read_time_record` (which reads CSV, NPZ and UFF files alike): ``(x, fs, name)``."""
    return read_time_record_from(path, channel)[:3]


def read_time_record_from(path, channel=None):
    """``(x, fs, name, t0)``: :func:`read_time_record` and the time of its first sample (s), which
    the wavelet analysis counts its times from."""
    rec = read_records(path, 0 if channel is None else channel)  # (named in a refusal for another function)
    name = _channel(rec, channel)
    return np.asarray(rec.columns[name], dtype=float), rec.fs, name, float(rec.time[0])


def _channel(rec, channel):
    """The column of the record ``rec`` that ``channel`` names (see :func:`read_time_record`); a
    ModelError naming ``channel`` and listing the columns for one it does not."""
    cols = list(rec.columns)
    allowed = f"must be 0..{len(cols) - 1} or a name in the file: " + ", ".join(cols)
    if channel is None:
        return cols[0]
    if isinstance(channel, str) and not channel.strip().isdigit():
        try:
            return rec.resolve(channel, "channel")
        except ModelError:
            try:  # (a sum the record cannot make says why; any other name lists the columns)
                derived = derived_terms(channel, cols) is not None
            except ModelError:
                derived = False
            if derived:
                raise
            raise ModelError("channel", channel, allowed) from None
    j = int(channel)
    if not 0 <= j < len(cols):
        raise ModelError("channel", channel, allowed)
    return cols[j]


#: The names of a CSV FRF's frequency column (its first), before its unit (``frequency [rad/s]``,
#: ``f_hz``); :func:`frequency_column`.
FREQUENCY_NAMES = ("frequency", "freq", "f")
_UNIT_IN_BRACKETS = re.compile(r"(.*?)\s*[\[(]\s*([^\])]*?)\s*[\])]")


def _frequency_header(header):
    """``(is a frequency, unit text)`` of a CSV column header: ``frequency [rad/s]``, ``Frequency (Hz)``,
    ``frequency_hz``, ``f_khz``, ``freq`` (no unit: Hz) or a bare unit, ``Hz``, ``rpm``."""
    text = header.strip()
    found = _UNIT_IN_BRACKETS.fullmatch(text)
    if found:
        name, unit = found.group(1), found.group(2)
    else:
        name, _, unit = text.partition("_")
        if frequency_factor(text) is not None and text:  # (the header a unit alone: Hz, rpm)
            return True, text
    if name.strip().lower() not in FREQUENCY_NAMES:
        return False, ""
    return True, unit


def is_frequency_header(header) -> bool:
    """Whether a CSV column header names a frequency (:func:`frequency_column`'s forms, whatever its unit)."""
    return _frequency_header(header)[0]


def frequency_column(path, names, key="file"):
    """The factor (to Hz) of a CSV FRF's frequency column, the first of the header's column names
    ``names``: :data:`FREQUENCY_NAMES` with a unit of :data:`FREQUENCY_UNITS` in brackets,
    ``frequency [rad/s]``, or after an underscore, ``frequency_khz`` (no unit: Hz), or a unit alone,
    ``Hz``. A :class:`ModelError` naming ``key`` and the file, quoting the header, for a first column
    that is no frequency (naming the column that is, if one is) or a unit that is not one of frequency."""
    header = names[0]
    is_frequency, unit = _frequency_header(header)
    shown = excerpt(header.strip(), 40)
    if not is_frequency:
        other = next((j for j, n in enumerate(names) if j and _frequency_header(n)[0]), None)
        where = "" if other is None else f" (its column {other + 1}, {excerpt(names[other].strip(), 40)}, is one)"
        raise ModelError(
            key,
            str(path),
            f"its first column, headed {shown}, is not a frequency{where}: an FRF CSV has the frequency first, "
            "headed frequency_hz (or frequency [Hz]; frequency [rad/s], frequency [kHz], ... are converted to Hz), "
            "then re_<name>,im_<name>",
        )
    factor = frequency_factor(unit)
    if factor is None and "_" in unit:  # (frequency_rad_s: the slash written as an underscore)
        factor = frequency_factor(unit.replace("_", "/"))
    if factor is None:
        raise ModelError(
            key,
            str(path),
            f"the header of its frequency column, {shown}, gives the frequency in {excerpt(unit, 20)}, a unit "
            f"this reader does not convert: one of {frequency_units_text()} (frequency [rad/s] or frequency_rpm; "
            "no unit: Hz)",
        )
    return factor


def _csv_pairs(names):
    """The ``re_``/``im_`` column pairs of a CSV FRF's header ``names``: ``[(name, re column, im column)]``,
    ``name`` what follows ``re``/``im`` (and ``_``), ``re_H21``/``im_H21`` -> ``H21``, matched in any case, in
    the order of their ``re`` columns; without a matched pair, the first column starting ``re`` with the first
    starting ``im`` (another tool's ``Real``, ``Imag``), named by the first."""

    def suffix(name):
        return name[2:].lstrip("_ ").lower()

    re_cols = [i for i, n in enumerate(names) if i and n.lower().startswith("re")]
    im_cols = [i for i, n in enumerate(names) if i and n.lower().startswith("im")]
    pairs = []
    for i in re_cols:
        j = next((j for j in im_cols if suffix(names[j]) == suffix(names[i])), None)
        if j is not None:
            pairs.append((names[i][2:].lstrip("_ ") or names[i], i, j))
    if not pairs and re_cols and im_cols:
        pairs.append((names[re_cols[0]], re_cols[0], im_cols[0]))
    return pairs


def read_csv_frf(path, channel=None):
    """A complex FRF from CSV: returns ``(freqs_hz, H)`` from the first column, the frequency (its unit
    from its header, :func:`frequency_column`: ``frequency [rad/s]``, ``frequency_khz`` converted to Hz),
    and a ``re_*``/``im_*`` column pair: ``channel`` None the first, else the pair of that name (``H21``,
    or either column's, ``re_H21``, ``im_H21``) or place among the pairs (0 the first); another is a
    ModelError naming ``channel`` and listing the pairs."""
    return _read_csv_frf(path, channel)[:2]


def _read_csv_frf(path, channel=None):
    """``(freqs_hz, H, pair name, text naming its columns)`` of :func:`read_csv_frf`."""
    names, data = read_csv_table(path, "file", min_rows=3, min_columns=3, zero_row_free=True)
    to_hz = frequency_column(path, names)
    pairs = _csv_pairs(names)
    if not pairs:
        raise ModelError("file", str(path), "an FRF CSV needs columns frequency_hz,re_<name>,im_<name>")
    if channel is None:
        k = 0
    elif isinstance(channel, str) and not channel.strip().isdigit():
        given = channel.strip().lower()
        k = next(
            (k for k, (n, i, j) in enumerate(pairs) if given in (n.lower(), names[i].lower(), names[j].lower())), -1
        )
    else:
        k = int(channel)
    if not 0 <= k < len(pairs):
        listed = ", ".join(f"{n} ({names[i]}, {names[j]})" for n, i, j in pairs)
        raise ModelError(
            "channel",
            channel,
            f"must be 0..{len(pairs) - 1} or the name of a re_/im_ column pair of {path}: {listed}",
        )
    name, i, j = pairs[k]
    f = data[:, 0] if to_hz == 1.0 else data[:, 0] * to_hz
    with np.errstate(invalid="ignore"):  # (inf on a 0 Hz line, which is read as it is: 1j * inf is nan + inf j)
        H = data[:, i] + 1j * data[:, j]
    warn_zero_lines(f"{path} ({names[i]}, {names[j]})", f, H)
    return f, H, name, f"columns {names[i]}, {names[j]}"


def refuse_nonfinite_lines(where, f, H):
    """A ModelError naming ``where`` (the file and function) when a measured FRF (``f`` Hz, ``H``) holds a value
    that is not a finite number (nan or inf: an overloaded or missing measurement) at a line other than 0 Hz:
    the first such line's frequency and point, how many more, and which whole lines around them could be kept.
    On a 0 Hz line (the first, ``f[0] == 0``) it is allowed and returned as read: the fits leave that line out
    (``circlefit._without_dc``), and an apparent mass is infinite there (review AY2)."""
    bad = ~(np.isfinite(f) & np.isfinite(H))
    if f.size and f[0] == 0.0:
        bad[0] = False
    if not bad.any():
        return
    at = np.flatnonzero(bad)
    first, last, n = int(at[0]), int(at[-1]), f.size
    keep = runs_to_keep(
        bad, lambda k: "the lines before it", lambda j: f"the lines after {'it' if first == last else 'the last'}"
    )
    raise ModelError(
        "file",
        where,
        f"holds a value that is not a finite number (nan or inf) at {f[first]:.6g} Hz (point {first + 1} of {n}"
        f"{f', and {at.size - 1} more, the last at point {last + 1}' if at.size > 1 else ''}): an overloaded or "
        "missing measurement; only a 0 Hz line, which the fits leave out, may hold one; measure again"
        + (f", or export only {' or '.join(keep)}" if keep else ""),
    )


def warn_zero_lines(where, f, H):
    """A ModelWarning naming the lines above 0 Hz of a measured FRF (``f`` Hz, ``H``) where ``H`` is exactly 0
    (``where``: the file and function): a dropout or a line the exporter masked, which the fits leave out as
    missing (``circlefit.without_zero_lines``). A nan line is refused instead (an invalid value: an overload)
    and a 0 Hz line of 0 (the DC line an export zeroes) is not named: no resonance uses it."""
    zero = (H == 0) & (f > 0)
    if not zero.any():
        return
    k, more = int(np.argmax(zero)), int(zero.sum()) - 1
    warnings.warn(
        f"{where}: H is exactly 0 at {f[k]:.6g} Hz (point {k + 1} of {f.size}"
        f"{f', and {more} more' if more else ''}): a dropout or a line the exporter masked (noise alone never "
        "gives an exact 0); the peak search and the circle fits leave these lines out, as missing",
        ModelWarning,
        stacklevel=3,
    )


# ------------------------------------------------------------------------------------------- UFF FRFs


def _uff_frf(path, channel):
    """``(record, name, described)``: the ``channel``-th FRF (UFF 58 function type 4; default the first) of a UFF
    file, or the one of that name (:func:`function_names`: its ``id1``, ``<id1>@<node><direction>`` where the
    id1 repeats, ``<id1>@<response>/<reference>`` where that does too), its name, and a text naming it
    (:attr:`MeasuredFRF.described`). A name of two functions (one id1, response and reference twice) is a
    ModelError naming both; the default, the first, with a ModelWarning when another has its name."""
    every = read_uff(path)
    recs = [r for r in every if r.kind == "frf"]
    if not recs:
        held = sorted({r.func_type for r in every})
        raise ModelError(
            "file",
            str(path),
            f"contains no FRF (UFF 58, function type 4); it holds UFF 58 function type(s) "
            f"{', '.join(map(str, held))} (1 time response, 4 FRF, 6 coherence, ...)",
        )
    names = function_names(recs)
    if channel is None:
        j = 0
    elif isinstance(channel, str) and not channel.strip().isdigit():  # a function's name (its id1)
        bare = channel.split(" [")[0]
        matches = [i for i, n in enumerate(names) if n == bare]
        if len(matches) > 1:
            raise ModelError(
                "channel",
                channel,
                f"names {len(matches)} FRFs of {path}, {_places(matches)} (the same id1, response and reference: "
                f"an export that repeats a function); give the place of one instead ({', '.join(map(str, matches))})",
            )
        j = matches[0] if matches else -1
    else:
        j = int(channel)
    if not 0 <= j < len(recs):
        raise ModelError("channel", channel, f"must be 0..{len(recs) - 1} or a name in the file: " + ", ".join(names))
    same = [i for i, n in enumerate(names) if n == names[j]]
    if channel is None and len(same) > 1:
        warnings.warn(
            f"{path}: {_places(same)} have the same name, {names[j]} (the same id1, response and reference: an "
            f"export that repeats a function); FRF {j}, the first, is read; give the place of another "
            f"({', '.join(map(str, same[1:]))}) as the channel to read it",
            ModelWarning,
            stacklevel=4,
        )
    r = recs[j]
    refuse_nonfinite_lines(f"{path} ({names[j]})", r.x, r.data)
    warn_zero_lines(f"{path} ({names[j]})", r.x, r.data)
    reference = dof_name(r.ref_node, r.ref_dir) if r.ref_node else "none"
    dofs = f"response {dof_name(r.rsp_node, r.rsp_dir)}, reference {reference}"
    dofs = dofs if names[j] == r.name else f"id1 {r.name!r}, {dofs}"  # (the id1 where the name is not it)
    described = f"{names[j]} ({dofs})" if len(recs) == 1 else f"FRF {j} of 0..{len(recs) - 1}, {names[j]} ({dofs})"
    return r, names[j], described


def _places(found):
    """``FRF 0 and FRF 3``, ``FRF 0, FRF 2 and FRF 5``: FRFs by their places among a file's FRFs."""
    return and_joined(f"FRF {i}" for i in found)


@dataclass(frozen=True)
class MeasuredFRF:
    """An FRF read from a file (:func:`read_frf_function`): ``freqs_hz`` (Hz), ``H`` (complex, in the file's
    unit), ``kind`` (the kind the file declares, or None), ``name`` (a UFF function's name,
    :func:`function_names`, or a CSV's ``re_``/``im_`` pair's) and ``described``, a text naming it for a
    table's header: a UFF function's place among the file's FRFs, name, id1, response and reference DOF
    (``FRF 4 of 0..5, FRF@12-x/2z (id1 'FRF', response 12-x, reference 2z)``), a CSV's columns; ``kind_from``
    says what declared ``kind`` ("" when None): a UFF header's data types or, when they are 0, its unit
    labels (:func:`~cablecasing_core.uff.frf_kind_of_labels`), a CSV's line ``# kind = ...``; ``kind_by_labels``
    is True when the unit labels (a heuristic on free text, which a user's stated kind overrides) said it."""

    freqs_hz: np.ndarray
    H: np.ndarray
    kind: str | None
    name: str
    described: str
    kind_from: str = ""
    kind_by_labels: bool = False


def read_frf(path, channel=None):
    """``(freqs_hz, H)`` from a CSV or UFF file (the n-th FRF of a UFF file, default the first; only
    function type 4 counts: a coherence or spectrum stored with it is skipped; an abscissa in rad/s,
    rpm, kHz is converted to Hz). A value that is not finite is refused but on a 0 Hz line, which is
    returned as read (the fits leave that line out: :func:`refuse_nonfinite_lines`)."""
    return read_frf_kind(path, channel, strict=False)[:2]


def read_frf_kind(path, channel=None, strict=True):
    """``(freqs_hz, H, kind)``: :func:`read_frf` and the FRF kind the file declares: a UFF header's
    (:func:`frf_kind`; None when it does not say; a ratio the circle fit does not take is a ModelError
    naming the file, or None when not ``strict``), a CSV's line ``# kind = <kind>`` before its first
    row of numbers (:func:`write_csv_frf` writes it; None without one; an unknown kind as a UFF's)."""
    m = read_frf_function(path, channel, strict)
    return m.freqs_hz, m.H, m.kind


def read_frf_function(path, channel=None, strict=True) -> MeasuredFRF:
    """:func:`read_frf_kind` as a :class:`MeasuredFRF`, with the name of the function read and a text naming it
    (its place, id1, response and reference: what a table's header says it was fitted to)."""
    if not is_uff(path):
        f, H, name, described = _read_csv_frf(path, channel)
        kind = _csv_frf_kind(path, strict)
        return MeasuredFRF(f, H, kind, name, described, "the line '# kind = ...' of the file" if kind else "")
    r, name, described = _uff_frf(path, channel)
    try:
        kind = frf_kind(r, strict)
    except ModelError as exc:
        raise ModelError(exc.key, f"{path}: {exc.value}", exc.allowed) from None
    if kind is None:
        kind_from = ""
    elif r.data_type and r.denominator_type:
        kind_from = "the header of the file"
    else:
        kind_from = (
            f"the unit labels {r.unit} / {r.denominator_unit or '-'} of the header of the file, its data types being 0"
        )
    by_labels = kind is not None and not (r.data_type and r.denominator_type)
    return MeasuredFRF(r.x, np.asarray(r.data, dtype=complex), kind, name, described, kind_from, by_labels)
