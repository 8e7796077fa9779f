"""UFF dataset 58 ("function at nodal DOF") in and out: the file format of time records and FRFs.

Below the records (:mod:`.records` reads and writes a record's ``.uff`` file through this module) and
below the identification (``identification.uff_io`` reads measured FRFs and time records through it);
it imports neither. The format goes through ``pyuff`` (an optional dependency, imported when needed).
Function type 1 is a time response, type 4 a frequency response function; data are written in binary
(58b) double precision, so values round-trip exactly. The dataset's header stores an even abscissa's
start and increment in E13.5 format (six significant digits); the exact values are also written, as
text, into the ID line 4 (``cablecasing x0=... dx=...``) and used on reading when they agree with the
header's to its rounding (5e-6 relative); otherwise (a file another tool re-saved in rad/s or shifted,
keeping the ID lines) the header's are used, with a ModelWarning. Unevenly spaced abscissae are stored
point by point (exact in binary); a time record stored so (another tool's, with the uneven-abscissa
flag) keeps the rounding of its abscissa in :attr:`Record.abscissa_rounding`, which
``records.Records.fs`` allows. Writers check their input before anything is written: finite values,
one per abscissa value, a strictly increasing abscissa, real time records (a ModelError naming the
argument otherwise). The header's data types (what the ordinate and the denominator are) are those of
:data:`DATA_TYPES`, the one table of them. Units are SI: s, Hz, and the unit of the quantity.
"""

from __future__ import annotations

import os
import re
import warnings
from dataclasses import dataclass, field

import numpy as np

from .errors import ModelError, ModelWarning, renamed
from .extras import install_hint
from .files import atomic_path, memory_available
from .model.validators import Choice, array_1d, number
from .units import frequency_factor, frequency_units_text, time_factor, time_units_text, unit_key

_TAG = re.compile(r"cablecasing x0=(\S+) dx=(\S+)")
UFF_EXTENSIONS = (".uff", ".unv", ".uf")


@dataclass(frozen=True)
class Record:
    """One function read from a file: ``kind`` ("time" for UFF function type 1, "frf" for type 4,
    "other" for the rest: coherence, spectra, ...), abscissa ``x`` (s or Hz, converted from the
    header's abscissa unit, whose label is kept in ``abscissa_unit``), ``data`` (real for time,
    complex for an FRF), ``name``, the UFF node/direction fields, the ordinate's unit label and UFF
    data type (:data:`DATA_TYPES`: 0 unknown, 8 displacement, 9 reaction force, 11 velocity, 12
    acceleration, 13 excitation force; for an FRF also those of its denominator), the UFF function
    type, whether the dataset was binary (58b), what it states beside its values in its ID lines,
    ``stated`` ({name: text}, :data:`STATEMENTS`: a run's record's passband, harmonic lines and
    fade-in), and ``abscissa_rounding``, how far each abscissa value may lie from the one it stands
    for, relative to it: 0 for an even abscissa (from its start and increment), :data:`_E13_5` for
    one stored point by point in ASCII, 2**-24 in binary (single precision at worst). Writing
    ignores ``func_type``, ``binary`` and ``abscissa_rounding``."""

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
    abscissa_rounding: float = 0.0

    @property
    def fs(self):
        """1 / the abscissa's first step (Hz): the sampling rate of a time function written evenly (its
        start and increment); a record's rate by the rule of every reader is ``records.Records.fs``."""
        return 1.0 / float(self.x[1] - self.x[0])


#: What reading or writing a UFF file needs when pyuff is missing (the command line checks an output's
#: suffix with it before a run, cli/paths.py).
PYUFF_MISSING = "needs the optional package pyuff, which is not installed: " + install_hint("identify", ["pyuff"])


def _pyuff(path=None, doing="reading/writing"):
    """The module pyuff, or a ModelError naming the file ``path`` that needs it (``doing`` it)."""
    try:
        import pyuff
    except ImportError as exc:  # (pyuff is installed with the 'identify' extra)
        raise ModelError("file", "UFF" if path is None else str(path), f"{doing} UFF {PYUFF_MISSING}") from exc
    return pyuff


def _even(x):
    """Whether the writer stores the abscissa ``x`` by its start and increment (the header's even
    flag, the ID line 4 tag), the reader computing ``x[0] + k (x[1] - x[0])``: when that gives every
    value back to 1e-9 of a step; else point by point, exact. How a file keeps an abscissa, not
    whether a record is evenly sampled (``records.Records.fs``, read back the same either way)."""
    x = np.asarray(x, dtype=float)
    dx = float(x[1] - x[0]) if x.size > 1 else 0.0
    return dx > 0 and bool(np.all(np.abs(x - (x[0] + dx * np.arange(x.size))) <= 1e-9 * dx))


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


def check_function(x, data, x_key, data_key, real, min_len=2):
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
    x, data = check_function(rec.x, rec.data, x_key, data_key, real=is_time)
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
    (binary, double precision) to the open binary file ``fh``: what pyuff 2.5's ``UFF.write_sets``
    writes (``tests/identification/test_review_i_uff.py`` compares them), the header lines as in its
    ``_write58``, then the values in the machine's byte order, then the end line, but for the ID line's
    byte count (field 6, "number of bytes following ASCII lines" in the 58b definition): the bytes of
    all the values, 8 x the numbers per point (1 real, 2 complex, one more for an uneven abscissa) x
    the points, where pyuff writes 8 x the points whatever the numbers per point (half the true
    count for a complex FRF; pyuff and this package's reader count the values from the point count
    and read both).

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
    columns = [data] if real else [data.real, data.imag]
    if not even:  # (an uneven abscissa is stored point by point beside the values)
        columns.insert(0, x)
    values = np.column_stack(columns).ravel()  # (x0, y0, x1, y1, ... or re0, im0, ...)
    lines = [
        f"{-1:6d}",
        f"{58:6d}b{1 if little else 2:6d}{2:6d}{11:12d}{values.size * 8:12d}{0:6d}{0:6d}{0:12d}{0:12d}",
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
        dof = {**frf_fields(kind), **dof}
    with renamed({"records[0].x": "freqs_hz", "records[0].data": "H"}):
        write_uff(path, [Record("frf", freqs_hz, H, name, **dof)], binary=binary)


def read_uff(path):
    """All dataset-58 functions of a UFF file as a list of :class:`Record` (type 1 -> "time", 4 -> "frf", else
    "other"). A dataset whose values are not as many as its header's point count (cut and closed, stray bytes,
    a 58b whose line ends became CRLF), or a dataset 58 without its end line (a cut file), is a ModelError
    naming the file and the dataset (:func:`_check_count`, :func:`_refuse_truncated`)."""
    pyuff = _pyuff(path, "reading")
    if not os.path.exists(path):
        raise ModelError("file", str(path), "does not exist")
    if not os.path.isfile(path):
        what = "a folder" if os.path.isdir(path) else "a device or another special file"
        raise ModelError("file", str(path), f"is {what}, not a UFF file: a UFF file is a regular file")
    _check_memory(path)
    try:
        u = pyuff.UFF(str(path))
        types = list(u.get_set_types())
        idx = [i for i, ty in enumerate(types) if int(ty) == 58]
        _refuse_truncated(path, len(idx))
        if not idx:
            raise ModelError("file", str(path), "contains no UFF dataset 58 (function at nodal DOF)")
    except ModelError:
        raise
    except Exception as exc:
        # (the reader's message may quote the file's lines: only its kind is shown)
        raise ModelError("file", str(path), f"is not a readable UFF file ({type(exc).__name__})") from None
    sets = []
    for k, i in enumerate(idx):  # (one by one: a malformed one is named)
        try:
            with np.errstate(all="ignore"):  # (a corrupted binary's garbage values: _check_count names the dataset)
                sets.append(u.read_sets(i))
        except Exception as exc:
            raise ModelError("file", str(path), _unreadable_dataset(path, u, k, i, exc)) from None
    out = []
    for i, s in enumerate(sets):
        _check_count(path, i, s)
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
                _abscissa_rounding(s),
            )
        )
    return out


#: The memory reading a UFF file takes, in times its size (pyuff reads the whole file, splits it into
#: lines and ``struct.unpack``\ s the values into Python floats, 32 bytes each with the tuple's pointer, before
#: numpy's copy): measured peak RSS over the file's size, 12.5 M samples, 5.2x ASCII 4E20.12, 6.3x ASCII
#: 6E13.5, 8.1x binary double, 14.8x binary single precision; in review AO, files written by pyuff itself,
#: 8.73-9.34x binary double, 15.24x binary single, 7.27x ASCII single precision with an uneven abscissa:
#: rounded up from the largest (docs/identification.md section 6).
MEMORY_FACTOR = {"ascii": 8, "binary double": 10, "binary single": 16}
#: The share of the memory free (:func:`~cablecasing_core.files.memory_available`) a UFF read may take: the
#: margin leaves the other half for what follows the read (the record's wavelet transform, the circle fits,
#: the interpreter's own baseline) and covers a file whose factor the measured ones above do not reach.
MEMORY_SHARE = 0.5
_FORMATS = {
    "ascii": "an ASCII UFF file",
    "binary double": "a binary (58b) double-precision file",
    "binary single": "a binary (58b) single-precision file",
}
_SNIFF = 1 << 20  # (the bytes searched for the first dataset 58's header: past 151/164 headers)


def _memory_factor(path) -> tuple:
    """``(factor, format)`` of :data:`MEMORY_FACTOR` for the file ``path``, by its first dataset 58's header
    (binary or ASCII, its ordinate's precision) in its first MB; the largest factor without one there."""
    with open(path, "rb") as fh:
        head = fh.read(_SNIFF)
    m = re.search(rb"(?m)^ {4}58(b?)[^\n]*\n(?:[^\n]*\n){6}([ \d]{10})", head)
    if m is None:
        return MEMORY_FACTOR["binary single"], "binary single"
    if not m.group(1):
        return MEMORY_FACTOR["ascii"], "ascii"
    single = m.group(2).strip() in (b"2", b"5")
    kind = "binary single" if single else "binary double"
    return MEMORY_FACTOR[kind], kind


def _check_memory(path):
    """A ModelError naming the file, its size and the limit when reading it would take more than
    :data:`MEMORY_SHARE` of the memory free (:func:`~cablecasing_core.files.memory_available`, a container's
    cgroup limit counted): :data:`MEMORY_FACTOR` times its size (a process killed for want of memory says
    nothing)."""
    size = os.path.getsize(path)
    factor, kind = _memory_factor(path)
    free = memory_available()
    allowed = free * MEMORY_SHARE
    if size * factor <= allowed:
        return
    raise ModelError(
        "file",
        str(path),
        f"is {size / 1e6:.3g} MB: reading it takes about {factor} times that ({size * factor / 1e9:.3g} GB; "
        f"{_FORMATS[kind]} is read whole into Python numbers), more than {MEMORY_SHARE:.0%} of the "
        f"{free / 1e9:.3g} GB of memory free (the rest kept for what follows the read; the limit: "
        f"{allowed / factor / 1e6:.3g} MB for such a file); export fewer functions or a shorter "
        "record per file, or free memory",
    )


#: A dataset 58's first two lines: its start line ``    -1`` and its number, ``    58`` (ASCII) or ``    58b``
#: (binary), each in a field of 6 characters; then ID line 1 (``id1``, the function's name).
_START_58 = re.compile(rb"(?m)^ {4}-1[ \t]*\r?\n {4}58(?:b[^\n]*)?[ \t]*\r?\n([^\r\n]{0,80})")


def _refuse_truncated(path, complete):
    """A ModelError naming the file when it holds more dataset-58 headers than the ``complete`` datasets 58
    pyuff found (a dataset's end is the next ``    -1`` line; pyuff drops one without it, or says there is
    none): the file was cut (a copy or a write interrupted); the message names the cut dataset's id1."""
    import mmap

    with open(path, "rb") as fh:
        size = fh.seek(0, os.SEEK_END)
        fh.seek(max(0, size - 64))
        if size == 0 or fh.read().rstrip().endswith(b"\n    -1"):  # (ends with an end line: nothing cut off)
            return
        with mmap.mmap(fh.fileno(), 0, access=mmap.ACCESS_READ) as raw:  # (searched in place, not copied)
            found = [(m.start(), m.group(1)) for m in _START_58.finditer(raw)]
    if len(found) <= complete:
        return
    at, id1 = found[complete]
    name = id1.decode("utf-8", errors="replace").strip() or "function"
    raise ModelError(
        "file",
        str(path),
        f"is truncated: its dataset 58 number {complete + 1}, '{name}' (at byte {at}), has no end line "
        f"'    -1' ({len(found)} dataset 58 header(s), {complete} complete): the file was cut while it was copied "
        "or written; export it again",
    )


def _unreadable_dataset(path, u, k, i, exc):
    """What a refusal of the file ``path`` says of its dataset 58 number ``k + 1`` (the ``i``-th dataset of the
    pyuff reader ``u``) that pyuff could not read (``exc``): its id1 and byte offset from the file itself."""
    at = int(u._block_ind[i][0]) if len(getattr(u, "_block_ind", ())) > i else None
    name = "?"
    if at is not None:
        with open(path, "rb") as fh:
            fh.seek(at)
            m = _START_58.match(fh.read(400))
        if m:
            name = m.group(1).decode("utf-8", errors="replace").strip() or name
    where = "" if at is None else f" (at byte {at})"
    return (
        f"its dataset 58 number {k + 1}, '{name}'{where}, is not readable ({type(exc).__name__}: a header line "
        "damaged, or values of another format than its header declares): the file is refused as a whole; "
        "export it again"
    )


def _values_per_point(dataset):
    """The numbers a dataset 58 stores per point: 1 (real) or 2 (complex), and one more for an uneven abscissa."""
    complex_ = int(dataset.get("ord_data_type", 4)) in (5, 6)
    return (2 if complex_ else 1) + (0 if int(dataset.get("abscissa_spacing", 1)) == 1 else 1)


def _check_count(path, i, dataset):
    """A ModelError naming the file, the dataset (its place ``i`` among the datasets 58, its id1) and the
    counts when the number of points its header declares (``num_pts``) is not the number of values read
    (and of abscissa values): a dataset cut and closed, stray bytes, or a binary 58b whose line ends a
    copy in text mode changed (LF -> CRLF: a byte added after every 0x0a of its values, pyuff issue 61)."""
    declared = int(dataset.get("num_pts", -1))
    data, x = dataset.get("data"), dataset.get("x")
    n_data = 0 if data is None else len(data)
    n_x = 0 if x is None else len(x)
    if declared == n_data == n_x:
        return
    binary = bool(int(dataset.get("binary", 0)))
    name = str(dataset.get("id1", "")).strip() or "function"
    held = f"{n_data} values" + ("" if n_x == n_data else f" and {n_x} abscissa values")
    if binary:
        n_bytes = int(dataset.get("n_bytes", 0) or 0)
        per = 4 if int(dataset.get("ord_data_type", 4)) in (2, 5) else 8
        # (the byte count of all the values, as the package writes it; pyuff, and the package's writer before
        # review AY, put num_pts x bytes per value there for complex data and an uneven abscissa too: such files'
        # headers are not damaged by that, and they are read)
        expected, pyuffs = declared * per * _values_per_point(dataset), declared * per
        also = "" if pyuffs == expected else f" (nor {pyuffs}, pyuff's num_pts x bytes per value)"
        stated = f"; its header's byte count, {n_bytes}, is not {expected}{also} either"
        stated = "" if n_bytes in (expected, pyuffs) else stated
        why = (
            "truncated or corrupted: a dataset cut and closed, stray bytes in its values, or a binary 58b whose "
            "line ends were converted (LF -> CRLF) by a copy or transfer in text mode; copy the file in binary "
            "mode, or export it again"
        )
    else:
        stated = ""
        why = "truncated or corrupted: a dataset cut and closed, or lines lost or added; export it again"
    raise ModelError(
        "file",
        str(path),
        f"its dataset 58 number {i + 1}, '{name}', declares {declared} points in its header and holds {held}"
        f"{stated}: {why}",
    )


#: Relative rounding of the header's abscissa start and increment, E13.5 (six significant digits):
#: at most half a unit of the sixth digit, 5e-6 of the value (a mantissa of at least 1).
_E13_5 = 5e-6


def _abscissa_rounding(dataset) -> float:
    """How far each abscissa value of a dataset may lie from the one it stands for, relative to it
    (:attr:`Record.abscissa_rounding`): 0 for an even abscissa (start and increment: computed), else
    (stored point by point) E13.5's 5e-6 in ASCII, single precision's 2**-24 in binary at worst."""
    if int(dataset.get("abscissa_spacing", 0)) == 1:
        return 0.0
    return 2.0**-24 if int(dataset.get("binary", 0)) else _E13_5


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


def _abscissa_scale(path, name, kind, label):
    """Factor from the header's abscissa unit to s (time) or Hz (FRF); a ModelError for a unit it does not know."""
    key = label.lower().replace(" ", "")
    factor = (time_factor(key) if key else 1.0) if kind == "time" else frequency_factor(key)
    if factor is None:
        allowed = time_units_text() if kind == "time" else frequency_units_text()
        raise ModelError(
            "file",
            f"{path} ({name or kind})",
            f"its abscissa unit {label!r} is not one this reader converts; a "
            f"{'time record' if kind == 'time' else 'FRF'} needs one of {allowed} "
            f"(or none: {'s' if kind == 'time' else 'Hz'})",
        )
    return factor


def frf_kind(record, strict=True):
    """The FRF kind (:data:`FRF_KIND_TYPES`, ``circlefit.FRF_KINDS``) a UFF record's header declares,
    from its ordinate and denominator data types (:data:`DATA_TYPES`): a motion over a force
    (either force type) is that motion's kind, a force over an acceleration apparent mass, a force
    over a displacement (dynamic stiffness) the displacement form as it is; when a data type is 0
    (unknown: pyuff-based and older exporters write 0) the kind its unit labels say
    (:func:`frf_kind_of_labels`: ``g`` over ``N`` an accelerance), None when they do not say either;
    for a ratio the circle fit does not take (F/v, a/a, ...) a ModelError, or None when not ``strict``
    (the caller then says which kind to fit it as)."""
    num, den = int(record.data_type), int(record.denominator_type)
    if num == 0 or den == 0:
        return frf_kind_of_labels(record)
    motion = {code: quantity for code, (quantity, _) in DATA_TYPES.items() if code not in FORCE_TYPES}
    if den in FORCE_TYPES:
        kind = motion.get(num)
    elif num in FORCE_TYPES:
        kind = {"acceleration": "apparent_mass", "displacement": "displacement"}.get(motion.get(den))
    else:
        kind = None
    if kind is None and not strict:
        return None
    if kind is None:
        names = {code: quantity for code, (quantity, _) in DATA_TYPES.items()}
        raise ModelError(
            "file",
            f"{record.name or 'FRF'}: {names.get(num, f'type {num}')} / {names.get(den, f'type {den}')}",
            "the header declares an FRF the circle fit does not take; it needs x/F (receptance), v/F "
            "(mobility), a/F (accelerance), F/a (apparent mass) or F/x (dynamic stiffness); to fit it as one "
            "of them anyway, give its kind (--kind)",
        )
    return kind


#: Unit labels of an FRF's ordinate (a motion) by the kind they make over a force, and the labels of a force:
#: what :func:`frf_kind_of_labels` reads when the header's data types are 0. Compared in lower case without
#: spaces, brackets, ``^``, ``**`` (``m/s^2``, ``m/s**2`` and ``m/s²`` are ``m/s2``).
MOTION_LABELS = {
    "acceleration": ("g", "gn", "m/s2", "mm/s2", "in/s2", "ft/s2", "m/s/s", "ms-2"),
    "velocity": ("m/s", "mm/s", "in/s", "ft/s", "ips", "ms-1"),
    "displacement": ("m", "mm", "um", "µm", "μm", "in", "mil", "ft"),
}
FORCE_LABELS = ("n", "kn", "lbf", "lb", "kgf")


def frf_kind_of_labels(record):
    """The FRF kind (``circlefit.FRF_KINDS``) a UFF record's unit labels say (:data:`MOTION_LABELS` over
    :data:`FORCE_LABELS`: that motion's kind; a force over an acceleration: apparent mass; over a displacement:
    the displacement form), the ordinate's label alone when it holds the ratio (``g/N``, the denominator's
    empty); None when they say none of these (``V`` / ``V``, no labels)."""
    num, den = unit_key(record.unit), unit_key(record.denominator_unit)
    if not den and "/" in num:
        num, den = (unit_key(part) for part in num.rsplit("/", 1))  # (each in its brackets: (m/s^2)/N)
    motion = {label: kind for kind, labels in MOTION_LABELS.items() for label in labels}
    if den in FORCE_LABELS:
        return motion.get(num)
    if num in FORCE_LABELS:
        return {"acceleration": "apparent_mass", "displacement": "displacement"}.get(motion.get(den))
    return None


def _label(dataset, key):
    """A text field of a UFF dataset, "" for pyuff's "NONE"."""
    text = str(dataset.get(key, "")).strip()
    return "" if text == "NONE" else text


#: The UFF 58 data types (a function's ordinate or denominator "specific data type") this package
#: writes and reads, the one table of them: code -> (quantity, its unit labels, translation first);
#: 0 is unknown. A record's column of a unit here is written with its code (:func:`data_type`: a run's
#: forces and moments are reaction forces, 9), an FRF of a kind with those of :data:`FRF_KIND_TYPES`.
DATA_TYPES = {
    8: ("displacement", ("m",)),
    9: ("reaction force", ("N", "N.m")),
    11: ("velocity", ("m/s",)),
    12: ("acceleration", ("m/s2",)),
    13: ("excitation force", ("N", "N.m")),
}
#: The codes of :data:`DATA_TYPES` that are forces (an FRF's denominator of x/F, its ordinate of F/a).
FORCE_TYPES = tuple(code for code, (quantity, _) in DATA_TYPES.items() if quantity.endswith("force"))
_CODE = {quantity: code for code, (quantity, _) in DATA_TYPES.items()}


def data_type(unit: str) -> int:
    """The UFF 58 data type (:data:`DATA_TYPES`) of a record column in ``unit`` (``N`` and ``N.m``:
    9, reaction force, what a run's supports receive; ``m`` 8, ``m/s`` 11, ``m/s2`` 12), 0 (unknown)
    for another unit."""
    return next((code for code, (_, units) in DATA_TYPES.items() if unit in units), 0)


def _kind_types(numerator, denominator) -> tuple:
    """(ordinate data type, denominator data type, their unit labels) of an FRF of two quantities."""
    num, den = _CODE[numerator], _CODE[denominator]
    return num, den, DATA_TYPES[num][1][0], DATA_TYPES[den][1][0]


#: What :func:`write_uff_frf` writes for an FRF kind (``circlefit.FRF_KINDS``): (ordinate data type,
#: denominator data type, their unit labels), from :data:`DATA_TYPES`; :func:`frf_kind` reads each back
#: as that kind (apparent mass as the ``trfam`` command writes it, reaction force over acceleration).
FRF_KIND_TYPES = {
    "displacement": _kind_types("displacement", "excitation force"),
    "velocity": _kind_types("velocity", "excitation force"),
    "acceleration": _kind_types("acceleration", "excitation force"),
    "apparent_mass": _kind_types("reaction force", "acceleration"),
}


def frf_fields(kind: str) -> dict:
    """The :class:`Record` fields of an FRF of ``kind`` (:data:`FRF_KIND_TYPES`): ``data_type``,
    ``denominator_type``, ``unit`` and ``denominator_unit``; an unknown kind is a ModelError naming
    ``kind``."""
    num, den, unit, den_unit = FRF_KIND_TYPES[Choice(*FRF_KIND_TYPES)("kind", kind)]
    return {"data_type": num, "denominator_type": den, "unit": unit, "denominator_unit": den_unit}


def is_uff(path) -> bool:
    """Whether ``path`` names a UFF file (:data:`UFF_EXTENSIONS`, in any case)."""
    return os.path.splitext(str(path))[1].lower() in UFF_EXTENSIONS


#: A UFF 58 response direction's letters in a function's name (:func:`function_names`); 0 (a scalar) none.
_DIRECTIONS = {0: "", 1: "x", 2: "y", 3: "z", 4: "rx", 5: "ry", 6: "rz"}


def dof_name(node, direction) -> str:
    """A UFF node and direction as a function's name gives them: ``10z``, ``12-x`` (a minus for a negative
    direction; x, y, z; rx, ry, rz for the rotations 4-6; none for 0, a scalar)."""
    d = int(direction)
    return f"{int(node)}{'-' if d < 0 else ''}{_DIRECTIONS.get(abs(d), str(abs(d)))}"


def function_names(records, names=None):
    """The names a reader gives the UFF functions ``records``: each its ``id1`` (or ``names``, one
    per record), except where that repeats among them (an analyser's export names every function
    "Response" or "FRF" and tells them apart by node and direction): those are named
    ``<id1>@<node><direction>``, the response node and direction (:func:`dof_name`: x, y, z; rx, ry, rz
    for the rotations 4-6; a minus for a negative direction), ``Response@2z``; where that still
    repeats and the function has a reference (an FRF matrix: one response against several
    references), ``<id1>@<response>/<reference>``, ``FRF@10z/2z``. A name may still repeat (two
    functions of one id1, response and reference); the caller refuses it."""
    names = [r.name for r in records] if names is None else list(names)
    placed = [names.count(name) > 1 for name in names]
    out = [f"{n}@{dof_name(r.rsp_node, r.rsp_dir)}" if at else n for r, n, at in zip(records, names, placed)]
    return [
        f"{n}/{dof_name(r.ref_node, r.ref_dir)}" if at and r.ref_node and out.count(n) > 1 else n
        for r, n, at in zip(records, out, placed)
    ]
