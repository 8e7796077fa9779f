"""Measured data in and out: time records and FRFs as Universal File Format dataset 58, or CSV.

UFF 58 ("function at nodal DOF") goes through ``pyuff`` (an optional dependency, imported when
needed). Function type 1 is a time response, type 4 a frequency response function; data are
written in binary (58b) double precision, so values round-trip exactly. The dataset's header
stores an even abscissa's start and increment in E13.5 format (six significant digits); the exact
values are also written, as text, into the ID line 4 (``cablecasing x0=... dx=...``) and used on
reading when they agree with the header's to its rounding (5e-6 relative); otherwise (a file
another tool re-saved in rad/s or shifted, keeping the ID lines) the header's are used, with a
ModelWarning. Unevenly spaced abscissae are stored point by point (exact in binary). Writers check
their input before anything is written: finite values, one per abscissa value, a strictly
increasing abscissa, real time records (a ModelError naming the argument otherwise).

CSV files have one header line. Time records: ``time_s,<channel>,...``. FRFs:
``frequency_hz,re_<name>,im_<name>[,...]`` (the first ``re_``/``im_`` pair is read; the ``trfam``
CLI's ``frequency_hz,re_kg,im_kg,magnitude_kg,phase_deg`` files are accepted as they are), after an
optional line ``# kind = <kind>`` (displacement, velocity, acceleration, apparent_mass) that
:func:`write_csv_frf` writes when given the kind and :func:`read_frf_kind` reads back. A UFF 58 time
record stored point by point (another tool's, with the uneven-abscissa flag) is accepted when its
times lie on an even grid to the rounding of its abscissa (ASCII: E13.5).
Units are SI: s, Hz, and the unit of the quantity.
"""

from __future__ import annotations

import csv
import os
import re
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..errors import ModelError, ModelWarning, excerpt, renamed
from ..files import TIME_UNITS, csv_statements, time_column, time_factor
from ..model.validators import Choice, array_1d, number

_TAG = re.compile(r"cablecasing x0=(\S+) dx=(\S+)")
UFF_EXTENSIONS = (".uff", ".unv", ".uf")


@dataclass(frozen=True)
class Record:
    """One function read from a file: ``kind`` ("time" for UFF function type 1, "frf" for type 4,
    "other" for the rest: coherence, spectra, ...), abscissa ``x`` (s or Hz, converted from the
    header's abscissa unit, whose label is kept in ``abscissa_unit``), ``data`` (real for time,
    complex for an FRF), ``name``, the UFF node/direction fields, the ordinate's unit label and UFF
    data type (0 unknown, 8 displacement, 9 reaction force, 11 velocity, 12 acceleration, 13
    excitation force; for an FRF also those of its denominator), the UFF function type, whether the
    dataset was binary (58b) and what it states beside its values in its ID lines, ``stated``
    ({name: text}, :data:`STATEMENTS`: a run's record's passband, harmonic lines and fade-in)."""

    kind: str
    x: np.ndarray
    data: np.ndarray
    name: str = ""
    rsp_node: int = 1
    rsp_dir: int = 1
    ref_node: int = 0
    ref_dir: int = 0
    unit: str = ""
    data_type: int = 0
    denominator_unit: str = ""
    denominator_type: int = 0
    func_type: int = 0
    abscissa_unit: str = ""
    binary: bool = False
    stated: dict = field(default_factory=dict)

    @property
    def fs(self):
        """Sampling rate (Hz) of an evenly sampled time record."""
        return 1.0 / float(self.x[1] - self.x[0])


#: What reading or writing a UFF file needs when pyuff is missing (the command line checks an output's
#: suffix with it before a run, cli/paths.py).
PYUFF_MISSING = "needs the optional package pyuff, which is not installed: pip install 'cablecasing[identify]'"


def _pyuff(path=None, doing="reading/writing"):
    """The module pyuff, or a ModelError naming the file ``path`` that needs it (``doing`` it)."""
    try:
        import pyuff
    except ImportError as exc:  # (pyuff is installed with the 'identify' extra)
        raise ModelError("file", "UFF" if path is None else str(path), f"{doing} UFF {PYUFF_MISSING}") from exc
    return pyuff


def _even(x):
    d = np.diff(x)
    return d.size > 0 and np.all(d > 0) and np.allclose(d, d[0], rtol=1e-9, atol=0.0)


#: What a run's record states beside its columns (``records.Records``: ``passband_hz``, Hz; ``lines_hz``, Hz
#: separated by spaces; ``ramp_s``, s), by the UFF 58 ID line that carries it in every function of the
#: record: ID line 5 ``cablecasing passband_hz=3500 ramp_s=0.01``, ID line 3 ``cablecasing lines_hz=50 100``
#: (ID lines are 80 characters; ID line 4 holds the abscissa's tag, ID line 1 the name). A line without
#: the leading ``cablecasing`` (another tool's, a date) states nothing.
STATEMENTS = {"passband_hz": 5, "ramp_s": 5, "lines_hz": 3}
_ID_LINE = 80
_STATED = re.compile(r"(\w+)=(.*?)(?=\s+\w+=|\s*$)")


def _statement_lines(rec):
    """``({3: ID line 3, 5: ID line 5}, [names left out])`` of a function that states ``rec.stated``
    (:data:`STATEMENTS`), "NONE" for a line that states nothing; a statement the 80 characters of its
    line cannot hold (many harmonic lines) is left out (:func:`write_uff` warns)."""
    lines = {3: [], 5: []}
    for name, text in rec.stated.items():
        if name not in STATEMENTS:
            raise ModelError("stated", name, "must be one of " + ", ".join(STATEMENTS))
        lines[STATEMENTS[name]].append(f"{name}={' '.join(str(text).split())}")
    out, left = {}, []
    for line, parts in lines.items():
        kept = []
        for part in parts:
            if len(" ".join(["cablecasing", *kept, part])) <= _ID_LINE:
                kept.append(part)
            else:
                left.append(part.partition("=")[0])
        out[line] = " ".join(["cablecasing", *kept]) if kept else "NONE"
    return out, left


def _statements(dataset):
    """What a dataset states in its ID lines 3 and 5 (:data:`STATEMENTS`): {name: text}."""
    found = {}
    for name, line in STATEMENTS.items():
        text = str(dataset.get(f"id{line}", "")).strip()
        if not text.startswith("cablecasing "):
            continue
        for key, value in _STATED.findall(text[len("cablecasing ") :]):
            if key == name:
                found[name] = value.strip()
    return found


def _function(x, data, x_key, data_key, real, min_len=2):
    """The abscissa ``x`` and ordinate ``data`` of one function to write, checked before anything is
    written (the one check of every writer): finite numbers, one value per abscissa value, the
    abscissa strictly increasing, ``data`` real where the function is (a time record). A ModelError
    names the argument (``x_key``, ``data_key``)."""
    x = array_1d(x_key, x, min_len=min_len)
    data = array_1d(data_key, data, min_len=min_len, complex_ok=not real)
    if data.size != x.size:
        raise ModelError(data_key, f"{data.size} values", f"must have one value per abscissa value ({x.size})")
    if np.any(np.diff(x) <= 0.0):
        k = int(np.argmax(np.diff(x) <= 0.0))
        raise ModelError(
            x_key,
            f"{float(x[k])!r} then {float(x[k + 1])!r} at index {k + 1}",
            "the abscissa must increase strictly (no repeats)",
        )
    return x, data


def _dataset(rec, binary, x_key="x", data_key="data", id_lines=None):
    pyuff = _pyuff()
    is_time = rec.kind == "time"
    if np.size(rec.x) < 2:  # (pyuff cannot write one abscissa value; nor could a reader tell its spacing)
        what = "time record" if is_time else "FRF"
        raise ModelError(x_key, f"{np.size(rec.x)} value", f"a UFF 58 {what} needs at least 2 abscissa values")
    x, data = _function(rec.x, rec.data, x_key, data_key, real=is_time)
    even = _even(x)
    dx = float(x[1] - x[0]) if even else 0.0
    stated = _statement_lines(rec)[0] if id_lines is None else id_lines
    return pyuff.prepare_58(
        binary=1 if binary else 0,
        func_type=1 if is_time else 4,
        id1=(rec.name or ("time record" if is_time else "FRF"))[:80],
        id2="cablecasing",
        id3=stated[3],
        id4=f"cablecasing x0={float(x[0])!r} dx={dx!r}" if even else "NONE",
        id5=stated[5],
        rsp_node=int(rec.rsp_node),
        rsp_dir=int(rec.rsp_dir),
        ref_node=int(rec.ref_node),
        ref_dir=int(rec.ref_dir),
        rsp_ent_name="NONE",
        ref_ent_name="NONE",  # 10-character fields
        data=data if is_time else data.astype(complex),
        x=x,
        abscissa_spacing=1 if even else 0,
        abscissa_spec_data_type=17 if is_time else 18,
        abscissa_axis_units_lab="s" if is_time else "Hz",
        ordinate_spec_data_type=int(rec.data_type),
        ordinate_axis_units_lab=rec.unit or "NONE",
        orddenom_spec_data_type=int(rec.denominator_type),
        orddenom_axis_units_lab=rec.denominator_unit or "NONE",
        z_axis_spec_data_type=0,
    )


def write_uff(path, records, binary=True):
    """Write :class:`Record` objects to ``path`` as UFF dataset 58, atomically (a file that was
    there is replaced only when the new one is complete). Every record is checked first (finite
    values, one per abscissa value, a strictly increasing abscissa, a real time record): a
    ModelError naming ``records[i].x`` or ``records[i].data`` leaves ``path`` as it was. What a
    record states (``Record.stated``, :data:`STATEMENTS`) goes into its ID lines 3 and 5; a
    statement longer than the line's 80 characters is left out with a ModelWarning."""
    from ..files import atomic_path

    pyuff = _pyuff(path, "writing")
    lines = [_statement_lines(r) for r in records]
    sets = [
        _dataset(r, binary, f"records[{i}].x", f"records[{i}].data", id_lines)
        for i, (r, (id_lines, _)) in enumerate(zip(records, lines))
    ]
    left = sorted({name for _, names in lines for name in names})
    if left:
        warnings.warn(
            f"{path}: the 80 characters of a UFF 58 ID line cannot hold the record's {', '.join(left)} (too many "
            "harmonic lines): the file leaves it out, and a reader takes the default (no lines, no fade-in, the "
            "Nyquist frequency); a .csv or .npz file keeps it",
            ModelWarning,
            stacklevel=2,
        )
    with atomic_path(path) as tmp:
        if binary:  # (by hand, to one handle: _write_58b)
            with open(tmp, "wb") as fh:
                for d in sets:
                    _write_58b(fh, d)
            return
        try:
            pyuff.UFF(str(tmp)).write_sets(sets, mode="add")
        except Exception as exc:
            cause = _write_failure(exc)
            if cause is exc:
                raise
            raise cause from None


def _write_58b(fh, d):
    """Write the dataset ``d`` (a dict of ``pyuff.prepare_58``, checked by :func:`_dataset`) as UFF 58b
    (binary, double precision) to the open binary file ``fh``: byte for byte what pyuff 2.5's
    ``UFF.write_sets`` writes (``tests/identification/test_review_i_uff.py`` compares them), the header
    lines as in its ``_write58``, then the values in the machine's byte order, then the end line.

    Written by hand because pyuff's writer of a binary dataset 58 leaves a file open per dataset:
    ``_write58`` closes the handle it is given, opens the file again in binary to append the values,
    closes that, and opens it a third time in text mode for the end line, a handle it never closes
    (its caller closes the first one). A record of 38 columns left 38 handles to the garbage
    collector: a ``ResourceWarning`` each (an error under ``-W error``), the file open until
    collected (on Windows the atomic write's rename of a file still open fails). Its ``write_sets``
    also re-reads the whole file after each dataset. The ASCII form (``binary=False``) goes through
    pyuff: it writes to the one handle it opens."""
    import sys

    data, x = np.asarray(d["data"]), np.asarray(d["x"], float)
    real = not np.iscomplexobj(data)
    n = data.size
    even = int(bool(d.get("abscissa_spacing", 0)))
    little = sys.byteorder == "little"

    def g(key, default=0):
        return d.get(key, default)

    def i(key):
        return int(g(key))

    dx = even * (x[1] - x[0])
    lines = [
        f"{-1:6d}",
        f"{58:6d}b{1 if little else 2:6d}{2:6d}{11:12d}{n * 8:12d}{0:6d}{0:6d}{0:12d}{0:12d}",
        *(f"{g(f'id{k}', 'NONE'):<80}" for k in range(1, 6)),
        f"{i('func_type'):5d}{i('func_id'):10d}{i('ver_num'):5d}{i('load_case_id'):10d} "
        f"{g('rsp_ent_name', 'NONE'):>10}{i('rsp_node'):10d}{i('rsp_dir'):4d} "
        f"{g('ref_ent_name', 'NONE'):>10}{i('ref_node'):10d}{i('ref_dir'):4d}",
        f"{4 if real else 6:10d}{n:10d}{even:10d}{even * x[0]:13.5e}{dx:13.5e}{float(g('z_axis_value')):13.5e}",
        *(
            f"{i(f'{a}_spec_data_type'):10d}{i(f'{a}_len_unit_exp'):5d}{i(f'{a}_force_unit_exp'):5d}"
            f"{i(f'{a}_temp_unit_exp'):5d} {g(f'{a}_axis_lab', 'NONE'):<20} {g(f'{a}_axis_units_lab', 'NONE'):<20}"
            for a in ("abscissa", "ordinate", "orddenom", "z_axis")
        ),
    ]
    columns = [data] if real else [data.real, data.imag]
    if not even:  # (an uneven abscissa is stored point by point beside the values)
        columns.insert(0, x)
    values = np.column_stack(columns).ravel()  # (x0, y0, x1, y1, ... or re0, im0, ...)
    fh.write(("\n".join(lines) + "\n").encode("utf-8"))
    fh.write(values.astype("<f8" if little else ">f8").tobytes())
    fh.write(f"{-1:6d}\n".encode())


def _write_failure(exc):
    """What stopped pyuff's write: pyuff turns every exception of its writing, an ``OSError`` (a full
    disk) and a ``KeyboardInterrupt`` (Ctrl-C) too, into a bare ``Exception("Error writing data-set
    #58")`` whose context holds it; that is returned (the caller raises it: an interrupt stays one,
    a failed write an ``OSError``), else ``exc``."""
    seen, cause = set(), exc
    while cause is not None and id(cause) not in seen:
        if isinstance(cause, (KeyboardInterrupt, OSError)):
            return cause
        seen.add(id(cause))
        cause = cause.__cause__ or cause.__context__
    return exc


def write_uff_time(path, x, fs, name="x", t0=0.0, binary=True, **dof):
    """Write one time record (real samples ``x`` at ``fs`` Hz from ``t0`` s) as UFF 58, function type 1."""
    x = array_1d("x", x)  # (real: a complex record is refused, not cut to its real part)
    t = number("t0", t0, unit="s") + np.arange(x.size) / number("fs", fs, gt=0, unit="Hz")
    with renamed({"records[0].data": "x"}):
        write_uff(path, [Record("time", t, x, name, **dof)], binary=binary)


def write_uff_frf(path, freqs_hz, H, name="H", binary=True, kind=None, **dof):
    """Write one complex FRF (at ``freqs_hz`` Hz) as UFF 58, function type 4. ``kind`` (``circlefit.FRF_KINDS``)
    sets the header's ordinate and denominator data types and unit labels (:data:`FRF_KIND_TYPES`), which
    :func:`frf_kind` reads back; None leaves them 0 (unknown) unless ``dof`` gives them."""
    if kind is not None:
        from .circlefit import FRF_KINDS

        num, den, unit, den_unit = FRF_KIND_TYPES[Choice(*FRF_KINDS)("kind", kind)]
        dof = {"data_type": num, "denominator_type": den, "unit": unit, "denominator_unit": den_unit, **dof}
    with renamed({"records[0].x": "freqs_hz", "records[0].data": "H"}):
        write_uff(path, [Record("frf", freqs_hz, H, name, **dof)], binary=binary)


def read_uff(path):
    """All dataset-58 functions of a UFF file as a list of :class:`Record` (type 1 -> "time", else "frf")."""
    pyuff = _pyuff(path, "reading")
    if not os.path.exists(path):
        raise ModelError("file", str(path), "does not exist")
    if not os.path.isfile(path):
        what = "a folder" if os.path.isdir(path) else "a device or another special file"
        raise ModelError("file", str(path), f"is {what}, not a UFF file: a UFF file is a regular file")
    try:
        u = pyuff.UFF(str(path))
        types = list(u.get_set_types())
        idx = [i for i, ty in enumerate(types) if int(ty) == 58]
        if not idx:
            raise ModelError("file", str(path), "contains no UFF dataset 58 (function at nodal DOF)")
        sets = u.read_sets(idx)
    except ModelError:
        raise
    except Exception as exc:
        # (the reader's message may quote the file's lines: only its kind is shown)
        raise ModelError("file", str(path), f"is not a readable UFF file ({type(exc).__name__})") from None
    if isinstance(sets, dict):
        sets = [sets]
    out = []
    for s in sets:
        x = _abscissa(path, s)
        func_type = int(s.get("func_type", 0))
        kind = {1: "time", 4: "frf"}.get(func_type, "other")
        abscissa_unit = _label(s, "abscissa_axis_units_lab")
        if kind != "other":
            x = x * _abscissa_scale(path, str(s.get("id1", "")).strip(), kind, abscissa_unit)
        data = np.asarray(s["data"])
        data = data.real.astype(float) if kind == "time" and not np.iscomplexobj(data) else data
        out.append(
            Record(
                kind,
                x,
                data,
                str(s.get("id1", "")).strip(),
                int(s.get("rsp_node", 1)),
                int(s.get("rsp_dir", 1)),
                int(s.get("ref_node", 0)),
                int(s.get("ref_dir", 0)),
                _label(s, "ordinate_axis_units_lab"),
                int(s.get("ordinate_spec_data_type", 0)),
                _label(s, "orddenom_axis_units_lab"),
                int(s.get("orddenom_spec_data_type", 0)),
                func_type,
                abscissa_unit,
                bool(int(s.get("binary", 0))),
                _statements(s),
            )
        )
    return out


#: Relative rounding of the header's abscissa start and increment, E13.5 (six significant digits):
#: at most half a unit of the sixth digit, 5e-6 of the value (a mantissa of at least 1).
_E13_5 = 5e-6


def _abscissa(path, dataset):
    """A dataset's abscissa (in the header's unit): an even one from the exact start and increment of
    the ID line 4 tag (``cablecasing x0=... dx=...``) when they agree with the header's (E13.5) to
    its rounding, else from the header (another tool re-saved the file, in rad/s or shifted, keeping
    the ID lines: a ModelWarning says so)."""
    x = np.asarray(dataset["x"], dtype=float)
    m = _TAG.search(str(dataset.get("id4", "")))
    if not m or int(dataset.get("abscissa_spacing", 0)) != 1:
        return x
    x0, dx = float(m.group(1)), float(m.group(2))
    h0, hdx = float(dataset.get("abscissa_min", np.nan)), float(dataset.get("abscissa_inc", np.nan))
    if abs(h0 - x0) <= _E13_5 * abs(x0) and abs(hdx - dx) <= _E13_5 * abs(dx):
        return x0 + np.arange(x.size) * dx
    warnings.warn(
        f"file {path} ({str(dataset.get('id1', '')).strip() or 'function'}): the ID line 4 tag "
        f"'cablecasing x0={x0!r} dx={dx!r}' disagrees with the header's abscissa (start {h0:g}, increment "
        f"{hdx:g} {_label(dataset, 'abscissa_axis_units_lab') or 'in its unit'}) beyond the header's "
        "6-digit rounding: the file was changed after it was written (re-saved in another unit, shifted); "
        "the header's abscissa is used",
        ModelWarning,
        stacklevel=3,
    )
    return x


#: Units of a frequency (an FRF's abscissa: a UFF 58 header's label, a CSV FRF's first column) and
#: their factor to Hz; looked up in lower case with spaces removed (:func:`frequency_factor`). A time
#: record's are those of a CSV record's time column, :data:`cablecasing_core.files.TIME_UNITS`.
FREQUENCY_UNITS = {
    "Hz": 1.0,
    "1/s": 1.0,
    "cps": 1.0,
    "kHz": 1e3,
    "rad/s": 1.0 / (2.0 * np.pi),
    "rad/sec": 1.0 / (2.0 * np.pi),
    "rads/s": 1.0 / (2.0 * np.pi),
    "r/s": 1.0 / (2.0 * np.pi),
    "rpm": 1.0 / 60.0,
    "cpm": 1.0 / 60.0,
    "1/min": 1.0 / 60.0,
}
_FREQUENCY_KEYS = {k.lower(): v for k, v in FREQUENCY_UNITS.items()}


def frequency_factor(unit: str) -> float | None:
    """The factor from the frequency unit ``unit`` to Hz (:data:`FREQUENCY_UNITS`, in any case, spaces
    ignored: ``kHz``, ``KHZ``, ``rad / s``); 1.0 for no unit (""), None for a unit that is not one of
    frequency."""
    key = unit.lower().replace(" ", "")
    return 1.0 if not key else _FREQUENCY_KEYS.get(key)


def frequency_units_text() -> str:
    """The units :func:`frequency_factor` converts, for a message: ``'Hz', '1/s', ...``."""
    return ", ".join(repr(k) for k in FREQUENCY_UNITS)


#: FRF kind (circlefit.FRF_KINDS) from the UFF 58 data types of ordinate (numerator) and denominator:
#: 8 displacement, 9 reaction force, 11 velocity, 12 acceleration, 13 excitation force.
_FORCE = (9, 13)
#: What :func:`write_uff_frf` writes for a kind: (ordinate data type, denominator data type, their unit labels);
#: :func:`frf_kind` reads each back as that kind (apparent mass as the ``trfam`` command writes it, reaction
#: force over acceleration).
FRF_KIND_TYPES = {
    "displacement": (8, 13, "m", "N"),
    "velocity": (11, 13, "m/s", "N"),
    "acceleration": (12, 13, "m/s2", "N"),
    "apparent_mass": (9, 12, "N", "m/s2"),
}


def _abscissa_scale(path, name, kind, label):
    """Factor from the header's abscissa unit to s (time) or Hz (FRF); a ModelError for a unit it does not know."""
    key = label.lower().replace(" ", "")
    factor = (time_factor(key) if key else 1.0) if kind == "time" else frequency_factor(key)
    if factor is None:
        allowed = ", ".join(repr(k) for k in TIME_UNITS) if kind == "time" else frequency_units_text()
        raise ModelError(
            "file",
            f"{path} ({name or kind})",
            f"its abscissa unit {label!r} is not one this reader converts; a "
            f"{'time record' if kind == 'time' else 'FRF'} needs one of {allowed} "
            f"(or none: {'s' if kind == 'time' else 'Hz'})",
        )
    return factor


def frf_kind(record, strict=True):
    """The FRF kind (see ``circlefit.FRF_KINDS``) a UFF record's header declares, from its ordinate
    and denominator data types; None when they do not say (a type 0); for a ratio the circle fit
    does not take (F/v, a/a, ...) a ModelError, or None when not ``strict`` (the caller then says
    which kind to fit it as)."""
    num, den = int(record.data_type), int(record.denominator_type)
    if num == 0 or den == 0:
        return None
    if den in _FORCE:
        kind = {8: "displacement", 11: "velocity", 12: "acceleration"}.get(num)
    elif num in _FORCE:
        kind = {12: "apparent_mass", 8: "displacement"}.get(den)  # (F/x, dynamic stiffness: as it is)
    else:
        kind = None
    if kind is None and not strict:
        return None
    if kind is None:
        names = {8: "displacement", 9: "reaction force", 11: "velocity", 12: "acceleration", 13: "excitation force"}
        raise ModelError(
            "file",
            f"{record.name or 'FRF'}: {names.get(num, f'type {num}')} / {names.get(den, f'type {den}')}",
            "the header declares an FRF the circle fit does not take; it needs x/F (receptance), v/F "
            "(mobility), a/F (accelerance), F/a (apparent mass) or F/x (dynamic stiffness); to fit it as one "
            "of them anyway, give its kind (--kind)",
        )
    return kind


def _label(dataset, key):
    """A text field of a UFF dataset, "" for pyuff's "NONE"."""
    text = str(dataset.get(key, "")).strip()
    return "" if text == "NONE" else text


# ------------------------------------------------------------------------------------------- CSV


def write_csv_time(path, x, fs, names=None, t0=0.0):
    """Time record(s) to CSV: columns ``time_s`` and one per channel (``x`` of shape (n,) or (n, k),
    real and finite: checked before anything is written)."""
    from ..files import atomic_path

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
    from ..files import atomic_path

    if kind is not None:
        from .circlefit import FRF_KINDS

        kind = Choice(*FRF_KINDS)("kind", kind)
    f, H = _function(freqs_hz, H, "freqs_hz", "H", real=False, min_len=1)
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


def read_csv_time(path, channel=None):
    """A time record from CSV or NPZ (:func:`cablecasing_core.records.read_records`, the one reader of
    record files): returns ``(x, fs, name)``; ``channel`` is a column name (``casing.B.Fz``, its header
    form ``casing.B.Fz [N]``) or an index among the signal columns (default the first). The first
    column is the time (s), evenly spaced."""
    return _csv_time_from(path, channel)[:3]


def _csv_time_from(path, channel=None):
    """:func:`read_csv_time` and the time of the record's first sample (s): ``(x, fs, name, t0)``."""
    from ..records import read_records

    rec = read_records(path)
    cols = list(rec.columns)
    if channel is None:
        j = 0
    elif isinstance(channel, str) and not channel.isdigit():
        try:
            j = cols.index(rec.resolve(channel))
        except ModelError:
            raise ModelError("channel", channel, "must be one of " + ", ".join(cols)) from None
    else:
        j = int(channel)
        if not 0 <= j < len(cols):
            raise ModelError("channel", channel, f"must be 0..{len(cols) - 1} or a column name")
    return rec.columns[cols[j]], _record_fs(path, rec), cols[j], float(rec.time[0])


_NUMBER = re.compile(r"^[+-]?(\d*)(?:\.(\d*))?(?:[eE]([+-]?\d+))?$")


def _record_fs(path, rec):
    """Sampling rate (Hz) of a record; a text file's time column printed with few digits (an
    analyser's ``%.6g``: at 2048 Hz the steps then differ by up to 1e-2 of themselves) is accepted
    when every time lies on the uniform grid through the first and last time to within half its last
    printed digit (plus the rounding of those two), and that digit resolves the step to 10 % (median
    over the rows); the rate is then the least-squares slope's. The digits are those of the column's
    unit (``time [ms]``: a digit of 1e-2 is 1e-5 s), scaled to s as the record's time is."""
    try:
        return rec.fs
    except ModelError:
        if os.path.splitext(str(path))[1].lower() not in (".csv", ".txt"):
            raise
    t = np.asarray(rec.time, dtype=float)  # (s: converted from the header's unit)
    q = []  # the last printed digit of each time (s)
    lead = []  # the decimal exponent of each time's leading digit (in the column's unit; nan for 0)
    to_s = None  # the factor of the header's time unit to s (time [ms]: 1e-3), found on its line
    with open(path, encoding="utf-8-sig", errors="replace") as fh:  # (-sig: as read_csv_table reads it)
        for line in fh:
            if to_s is None and line.strip() and not line.lstrip().startswith("#"):  # the header line
                head = next(csv.reader([line], skipinitialspace=True))[0]
                to_s = time_column("file", path, head)
                continue
            cells = next(csv.reader([line], skipinitialspace=True), [""])  # (a quoted time too: "0.001")
            m = _NUMBER.match(cells[0].strip() if cells else "")
            if m and (m.group(1) or m.group(2)):
                # (a whole number, "0" or "2", says nothing of the digits kept: the column's median is taken)
                whole = m.group(2) is None and m.group(3) is None
                q.append(np.nan if whole else 10.0 ** (int(m.group(3) or 0) - len(m.group(2) or "")) * to_s)
                v = abs(float(m.group(0)))
                lead.append(np.floor(np.log10(v)) if v > 0 else np.nan)
    ok = len(q) == t.size > 2 and not np.all(np.isnan(q))
    q = np.asarray(q) if ok else np.ones(t.size)
    quantum = float(np.nanmedian(q))
    if ok:
        q = np.minimum(q, _digit_cap(q, np.asarray(lead), to_s, quantum))
    q = np.where(np.isnan(q), quantum, q)
    # each time within half its last digit (and the conversion's rounding, 1e-12 of the largest)
    fs, step, resid = _fs_on_grid(t, 0.5 * q + 1e-12 / 3 * np.abs(t).max(), quantum)
    if ok and fs is not None:
        return fs
    worst = float(resid.max()) if t.size else np.inf
    raise ModelError(
        "file",
        str(path),
        f"must be evenly sampled: its times depart from a uniform grid of step {step:.6g} s by up to {worst:.3g} s "
        f"({worst / step:.2g} of a step), more than the rounding of their printed digits allows (typically "
        f"+-{0.5 * quantum:.3g} s); "
        "the time (the first column) must increase in equal steps, rows in time order, no sample missing",
    ) from None


def _fs_on_grid(t, half_digit, quantum):
    """``(fs, step, departures)`` of the times ``t`` (s, increasing) against the uniform grid through
    the first and the last: ``fs`` (Hz), the least-squares slope's (the rounding averages out), when
    each time lies on the grid within ``half_digit`` (s per time: its printing's rounding) plus that
    of the two ends and ``quantum`` (s, the printing's digit) resolves the step to 10 %, else None;
    the grid's ``step`` (s) and each time's departure from it (s)."""
    k = np.arange(t.size)
    step = (t[-1] - t[0]) / (t.size - 1) if t.size > 1 else 0.0
    resid = np.abs(t - (t[0] + step * k))
    allowed = (half_digit + half_digit[0] + half_digit[-1]) * (1 + 1e-6)
    on = step > 0 and quantum <= 0.1 * step and bool(np.all(np.diff(t) > 0)) and bool(np.all(resid <= allowed))
    return (1.0 / float(np.polyfit(k, t, 1)[0]) if on else None), step, resid


def _digit_cap(q, lead, to_s, quantum):
    """The coarsest last digit (s) each printed time may be credited with: a time printed short ("0.5",
    "-0.02": ``%g`` strips trailing zeros) is no evidence of a coarse resolution, and its own digit would
    widen the allowance of every row (a CSV with a sample missing was read at 2045.5 Hz). The cap is
    the larger of the column's median digit (``%.9f``: fixed decimals) and the digit its median number of
    significant digits gives at the time's own magnitude (``%.6g``: 1e-6 s from 0.1 s, 1e-5 s from 1 s,
    so a record that crosses 1 s keeps its coarser rows past it)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        sig = np.round(lead - np.log10(q / to_s)) + 1.0  # significant digits printed
    if np.all(np.isnan(sig)):
        return np.full(q.shape, quantum)
    by_magnitude = 10.0 ** (lead - float(np.nanmedian(sig)) + 1.0) * to_s
    return np.fmax(quantum, by_magnitude)  # (fmax: a 0's nan magnitude gives the median)


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


def read_csv_frf(path):
    """A complex FRF from CSV: returns ``(freqs_hz, H)`` from the first column, the frequency (its unit
    from its header, :func:`frequency_column`: ``frequency [rad/s]``, ``frequency_khz`` converted to Hz),
    and the first ``re_*``/``im_*`` column pair."""
    from ..files import read_csv_table

    names, data = read_csv_table(path, "file", min_rows=3, min_columns=3)
    to_hz = frequency_column(path, names)
    re_i = next((i for i, n in enumerate(names) if i and n.lower().startswith("re")), None)
    im_i = next((i for i, n in enumerate(names) if i and n.lower().startswith("im")), None)
    if re_i is None or im_i is None:
        raise ModelError("file", str(path), "an FRF CSV needs columns frequency_hz,re_<name>,im_<name>")
    f = data[:, 0] if to_hz == 1.0 else data[:, 0] * to_hz
    return f, data[:, re_i] + 1j * data[:, im_i]


# ------------------------------------------------------------------------------ by file extension


def is_uff(path):
    return os.path.splitext(str(path))[1].lower() in UFF_EXTENSIONS


#: A UFF 58 response direction's letters in a function's name (:func:`function_names`); 0 (a scalar) none.
_DIRECTIONS = {0: "", 1: "x", 2: "y", 3: "z", 4: "rx", 5: "ry", 6: "rz"}


def function_names(records, names=None):
    """The names a reader gives the UFF functions ``records``: each its ``id1`` (or ``names``, one
    per record), except where that repeats among them (an analyser's export names every function
    "Response" and tells them apart by node and direction): those are named
    ``<id1>@<node><direction>``, the response node and direction (x, y, z; rx, ry, rz for the
    rotations 4-6; a minus for a negative direction), ``Response@2z``. A name may still repeat (two
    functions of one node and direction); the caller refuses it."""
    names = [r.name for r in records] if names is None else list(names)
    out = []
    for r, name in zip(records, names):
        if names.count(name) > 1:
            d = int(r.rsp_dir)
            name = f"{name}@{int(r.rsp_node)}{'-' if d < 0 else ''}{_DIRECTIONS.get(abs(d), str(abs(d)))}"
        out.append(name)
    return out


def _uff_record(path, kind, channel, missing):
    """The ``channel``-th record (default the first) of ``kind`` in a UFF file; ``missing`` says
    what the file lacks when it has none."""
    every = read_uff(path)
    recs = [r for r in every if r.kind == kind]
    if not recs:
        held = sorted({r.func_type for r in every})
        raise ModelError(
            "file",
            str(path),
            f"contains no {missing}; it holds UFF 58 function type(s) {', '.join(map(str, held))} "
            "(1 time response, 4 FRF, 6 coherence, ...)",
        )
    names = function_names(recs)
    if channel is None:
        j = 0
    elif isinstance(channel, str) and not channel.strip().isdigit():  # a function's name (its id1)
        bare = channel.split(" [")[0]
        j = names.index(bare) if bare in names else -1
    else:
        j = int(channel)
    if not 0 <= j < len(recs):
        raise ModelError("channel", channel, f"must be 0..{len(recs) - 1} or a name in the file: " + ", ".join(names))
    r = recs[j]
    bad = ~(np.isfinite(r.x) & np.isfinite(r.data))
    if bad.any():
        k = int(np.argmax(bad))
        unit = "s" if kind == "time" else "Hz"
        raise ModelError(
            "file",
            f"{path} ({names[j]})",
            f"holds a value that is not a finite number (nan or inf) at {r.x[k]:.6g} {unit} (point {k + 1} of "
            f"{r.x.size}{', and ' + str(int(bad.sum()) - 1) + ' more' if bad.sum() > 1 else ''}): an overloaded or "
            "missing measurement; measure again, or cut the function before it",
        )
    return r


def read_time_record(path, channel=None):
    """``(x, fs, name)`` from a CSV, NPZ or UFF (.uff/.unv) file; ``channel`` selects a column (by
    name or index) or a time function of a UFF file (by its name, id1, or its place among them)."""
    return read_time_record_from(path, channel)[:3]


def read_time_record_from(path, channel=None):
    """``(x, fs, name, t0)``: :func:`read_time_record` and the time of its first sample (s), which
    the wavelet analysis counts its times from."""
    if not is_uff(path):
        return _csv_time_from(path, channel)
    r = _uff_record(path, "time", channel, "time record (UFF 58, function type 1)")
    fs = r.fs if _even(r.x) else _uneven_abscissa_fs(path, r)
    return np.asarray(r.data, dtype=float), fs, r.name, float(r.x[0])


def _uneven_abscissa_fs(path, r):
    """Sampling rate (Hz) of a UFF 58 time record stored point by point (the uneven-abscissa flag, as
    another tool writes an even record): accepted when every time lies on the uniform grid through the
    first and last time to within the rounding of the file's abscissa (ASCII: E13.5, six significant
    digits, at most 5e-6 of the value; binary: single precision at worst, 6e-8), plus the rounding of
    those two, and that rounding resolves the step to 10 %; the rate is then the least-squares slope's
    (the rounding averages out). A ModelError naming ``file`` and the largest departure otherwise."""
    t = np.asarray(r.x, dtype=float)
    rel = 2.0**-24 if r.binary else _E13_5
    quantum = 2.0 * rel * float(np.abs(t).max())  # (a digit of the largest time)
    fs, step, resid = _fs_on_grid(t, rel * np.abs(t), quantum)
    if fs is not None:
        return fs
    worst = float(resid.max())
    j = int(np.argmax(resid))
    what = (
        f"its times depart from a uniform grid of step {step:.6g} s by up to {worst:.3g} s ({worst / step:.2g} "
        f"of a step, at point {j + 1} of {t.size}, t = {t[j]:.6g} s), more than the rounding of its abscissa "
        f"({'E13.5, six digits' if rel == _E13_5 else 'binary'}: +-{rel * abs(t[j]):.3g} s there) allows"
        if quantum <= 0.1 * step
        else f"its abscissa's rounding ({'E13.5, six digits' if rel == _E13_5 else 'binary'}: up to "
        f"+-{0.5 * quantum:.3g} s) does not resolve its step of {step:.6g} s"
    )
    raise ModelError(
        "file",
        f"{path} ({r.name or 'time record'}, stored with an uneven abscissa)",
        f"must be evenly sampled: {what}; the time must increase in equal steps, no sample missing",
    )


def read_frf(path, channel=None):
    """``(freqs_hz, H)`` from a CSV or UFF file (the n-th FRF of a UFF file, default the first; only
    function type 4 counts: a coherence or spectrum stored with it is skipped; an abscissa in rad/s,
    rpm, kHz is converted to Hz)."""
    return read_frf_kind(path, channel, strict=False)[:2]


def read_frf_kind(path, channel=None, strict=True):
    """``(freqs_hz, H, kind)``: :func:`read_frf` and the FRF kind the file declares: a UFF header's
    (:func:`frf_kind`; None when it does not say; a ratio the circle fit does not take is a ModelError
    naming the file, or None when not ``strict``), a CSV's line ``# kind = <kind>`` before its first
    row of numbers (:func:`write_csv_frf` writes it; None without one; an unknown kind as a UFF's)."""
    if not is_uff(path):
        f, H = read_csv_frf(path)
        return f, H, _csv_frf_kind(path, strict)
    r = _uff_record(path, "frf", channel, "FRF (UFF 58, function type 4)")
    try:
        kind = frf_kind(r, strict)
    except ModelError as exc:
        raise ModelError(exc.key, f"{path}: {exc.value}", exc.allowed) from None
    return r.x, np.asarray(r.data, dtype=complex), kind
