"""Files in and out: the one place where the package's output files are written, the check of an
output target before a run, and the one reader of numeric CSV tables.

**Writing.** A file is written under a temporary name in its target folder and renamed over the
target only when it is complete and flushed to disk (``os.replace``, atomic on POSIX and Windows
within a folder). An error or an interrupt (Ctrl-C) while writing leaves the target as it was, the
previous version bitwise intact, and no half-written file; the temporary file is removed. A file
that the system fails to write (a full disk, a quota, an I/O error) raises :class:`WriteError`, an
``OSError`` naming the target and the cause. A file written over an earlier one keeps its
permissions (mode bits). A target that is a symbolic link is written where the link points (the
link stays); a target that is not a regular file (a device such as ``/dev/full``, a folder) is
refused.

>>> check_writable("--out", "results.npz")     # before a long run: can a file be written there?
>>> with atomic_path("results.npz") as tmp:    # a writer that takes a path (numpy, pyuff, matplotlib)
...     np.savez(tmp, x=x)
>>> write_text("report.html", html)            # text in one call

**Reading.** :func:`read_csv_table` reads a numeric CSV table with one header line (time records,
CSV excitations, FRFs, measured frequencies). Its errors name the file, the line and the column,
never the content of a line: the file need not be a model file and may hold anything.
:func:`read_excitation_table` reads a CSV excitation's (time, value) table with it.
"""

from __future__ import annotations

import contextlib
import csv
import errno
import os
import re
import stat
import tempfile
from pathlib import Path

import numpy as np

from .errors import ModelError
from .units import TIME_UNITS as TIME_UNITS  # (re-exported: the table's earlier home)
from .units import time_factor


def _target(path, flag="path") -> Path:
    """The file that a write to ``path`` replaces: ``path``, or where it points if it is a link; a
    :class:`ModelError` naming ``flag`` for a name the file system refuses (over 255 bytes)."""
    shown, path = path, Path(path)
    try:
        if path.is_symlink():
            path = Path(os.path.realpath(path))
        path.exists()
    except OSError as exc:
        raise ModelError(flag, str(shown), f"is not a usable file name ({exc.strerror})") from None
    return path


def _regular_or_missing(flag, path, shown):
    if path.exists() and not path.is_file():
        what = "a folder" if path.is_dir() else "a device or another special file"
        raise ModelError(flag, str(shown), f"is {what} ({path}), not a regular file: output goes to regular files")


class WriteError(OSError):
    """An output file the system failed to write (a full disk, a quota, an I/O error, a folder made
    read-only during the run): an ``OSError`` with the cause's ``errno`` and ``strerror``, and
    ``filename`` the target as it was given. ``kept``: an earlier file at the target was left as it
    was (False: there was none, and none was made). Not a bug of the program, nor a bad input."""

    def __init__(self, errno, strerror, filename, kept):
        super().__init__(errno, strerror, filename)
        self.kept = kept


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike):
    """Yield a temporary path in ``path``'s folder with the same suffix (writers such as
    ``numpy.savez`` and ``savefig`` go by it); when the block ends without an exception, the file
    written there is given the mode bits of the file it replaces (if any), flushed to disk and
    renamed to ``path``. On any exception (KeyboardInterrupt too) it is deleted and ``path`` is left
    as it was; an ``OSError`` of the writing (``ENOSPC``: the disk is full) is raised again as
    :class:`WriteError`, and so is a folder that does not exist or in which no file can be created
    (naming the target, not the temporary file). A link is written where it points."""
    shown = path
    path = _target(path)
    _regular_or_missing("path", path, shown)
    if not path.parent.is_dir():  # (else mkstemp's error would name the temporary file, not the target)
        raise WriteError(
            errno.ENOENT, f"its folder {path.parent} does not exist (it is not created)", str(shown), False
        )
    # (a short prefix: the temporary name must fit wherever the target's name does)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem[:32]}.", suffix=f".part{path.suffix}", dir=path.parent)
    except OSError as exc:  # (a folder that is read-only or full: the target named, not the temporary file)
        raise WriteError(
            exc.errno, f"no file can be created in {path.parent} ({exc.strerror})", str(shown), path.exists()
        ) from exc
    os.close(fd)
    os.remove(tmp)  # the writer creates it (some refuse or append to an existing file)
    try:
        yield tmp
        with open(tmp, "rb+") as fh:
            os.fsync(fh.fileno())
        _keep_mode(path, tmp)
        os.replace(tmp, path)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.remove(tmp)
        if isinstance(exc, OSError) and not isinstance(exc, WriteError):
            raise WriteError(exc.errno, exc.strerror or str(exc), str(shown), path.exists()) from exc
        raise


def _keep_mode(path, tmp):
    """The mode bits of the file at ``path`` (if there is one) given to ``tmp``, which replaces it:
    a file of 0600 stays 0600 (the writer created ``tmp`` with the umask's default, 0644)."""
    try:
        mode = stat.S_IMODE(os.stat(path).st_mode)
    except FileNotFoundError:
        return
    with contextlib.suppress(OSError):  # (a file system without modes, such as FAT: what it gives)
        os.chmod(tmp, mode)


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically (see :func:`atomic_path`); returns the path."""
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", newline="") as fh:
        fh.write(text)
    return Path(path)


def check_writable(flag: str, path: str | os.PathLike) -> None:
    """Refuse an output target before a run rather than after it (a :class:`ModelError` naming
    ``flag``): its folder must exist, the target must be a regular file or not exist yet, and a
    byte written, flushed and synced to a temporary file in the folder must succeed (a full disk,
    a read-only or a pseudo file system such as ``/proc`` fail here). The probe is removed."""
    target = _target(path, flag)
    _regular_or_missing(flag, target, path)
    folder = target.parent
    if not folder.is_dir():
        raise ModelError(flag, str(path), f"must be a file in an existing folder ({folder} is not one)")
    try:
        fd, probe = tempfile.mkstemp(prefix=".cablecasing-probe.", dir=folder)
    except OSError as exc:
        raise ModelError(
            flag, str(path), f"cannot be written: no file can be created in {folder} ({exc.strerror})"
        ) from None
    try:
        os.write(fd, b"0")
        os.fsync(fd)
    except OSError as exc:
        raise ModelError(flag, str(path), f"cannot be written: writing to {folder} fails ({exc.strerror})") from None
    finally:
        os.close(fd)
        with contextlib.suppress(OSError):
            os.remove(probe)


def output_folder(flag: str, folder: str | os.PathLike, probe_name: str, create: bool = True) -> Path:
    """Create the output folder ``folder`` (and its parents) and check that ``probe_name`` can be
    written in it (:func:`check_writable`); a :class:`ModelError` naming ``flag`` otherwise: an
    empty path (which would be the current folder), a path that is an existing file or lies under
    one, a folder that cannot be created or written in. ``create=False`` checks without creating
    anything: an existing folder as above, a missing one by a file written in the nearest folder
    that exists (where it would be created: ``/sys/x`` is refused)."""
    if not os.fspath(folder):
        raise ModelError(flag, str(folder), "must name a folder (an empty path would write into the current folder)")
    folder = Path(folder)
    nearest = None
    for path in (folder, *folder.parents):  # (the nearest that exists must be a folder)
        try:
            found, is_folder = path.exists(), path.is_dir()
        except OSError:  # (not readable: mkdir below says why)
            break
        if found:
            if not is_folder:
                where = "is an existing file" if path == folder else f"lies under {path}, an existing file"
                raise ModelError(flag, str(folder), f"{where}, not a folder: must be a folder (or one to create)")
            nearest = path
            break
    if not create:
        if nearest == folder:
            check_writable(flag, folder / probe_name)
        elif nearest is not None:
            try:
                check_writable(flag, nearest / ".cablecasing-folder-probe")  # (a name no output takes)
            except ModelError as exc:
                raise ModelError(flag, str(folder), f"must be a folder that can be created ({exc.allowed})") from None
        return folder
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ModelError(flag, str(folder), f"must be a folder that can be created ({exc.strerror})") from None
    check_writable(flag, folder / probe_name)
    return folder


def is_number(text) -> bool:
    """Whether ``text`` reads as a float (what a CSV cell must hold to be a number)."""
    try:
        float(text)
        return True
    except ValueError:
        return False


#: The largest magnitude of a number read from a data file: its squares, spectra and sums stay finite.
MAX_MAGNITUDE = 1e100


def unreadable(data) -> np.ndarray:
    """Where the array ``data`` holds a value no record or table of this package reads: NaN, an
    infinity or a magnitude above :data:`MAX_MAGNITUDE` (a boolean array of ``data``'s shape). The
    one rule of :func:`check_values`, :func:`read_csv_table` and ``records.check_record_values``."""
    magnitude = np.abs(data)
    if magnitude.dtype.kind == "f" and magnitude.dtype.itemsize < 8:  # (compared in float64: 1e100 is no float32)
        magnitude = magnitude.astype(float)
    return ~np.isfinite(data) | (magnitude > MAX_MAGNITUDE)


def runs_to_keep(bad, before, after) -> list[str]:
    """The whole runs of points a file could be exported with instead, around the points where the
    boolean mask ``bad`` (one entry per point, n of them, at least one True) is True: the run before
    the first, named ``before(k)`` for points 1 to k (k the first bad index), and the run after the
    last, ``after(j)`` for points j + 1 to n (j the index after the last bad one), each with its
    point numbers (1-based). Empty when the bad points reach both ends. The one wording of the FRF
    readers' and the UFF time records' refusals of a non-finite value."""
    bad = np.asarray(bad, dtype=bool)
    if bad.ndim != 1:
        raise ValueError(f"bad must be a 1-D boolean mask, not of shape {bad.shape}")
    at = np.flatnonzero(bad)
    first, last, n = int(at[0]), int(at[-1]), bad.size
    keep = [f"{before(first)} (points 1 to {first})"] if first > 0 else []
    if last < n - 1:
        keep.append(f"{after(last + 1)} (points {last + 2} to {n})")
    return keep


def check_values(key: str, path, data) -> None:
    """Every value of the array ``data`` (samples, or rows x columns) read from ``path`` must be
    finite and at most :data:`MAX_MAGNITUDE` in magnitude; the :class:`ModelError` names the row
    and column and quotes no value."""
    data = np.asarray(data)
    if data.dtype.kind not in "fc":
        raise ModelError(key, str(path), "must hold numbers only")
    bad = np.argwhere(unreadable(data))
    if bad.size:
        where = bad[0]
        at = f"row {where[0] + 1}, column {where[1] + 1}" if data.ndim > 1 else f"sample {where[0] + 1}"
        raise ModelError(key, str(path), f"{at} is not a finite number of magnitude at most {MAX_MAGNITUDE:g}")


def _refuse_cut_last_row(key, shown, lines, rows):
    """A file whose write was cut ends without a line break, often in the middle of a number
    (``0.5,-5.`` of ``0.5,-5.12e-3``), which may still parse. Its last row is refused when the file
    ends without a line break and the row's last field ends as a cut number does (in ``.``, ``e``
    or a sign) or is shorter than every value of its column before it."""
    if not lines or rows[-1][0] != len(lines) or len(rows) < 3:
        return
    with open(shown, "rb") as fh:
        fh.seek(-1, os.SEEK_END)
        if fh.read(1) in (b"\n", b"\r"):
            return
    last = rows[-1][1].rstrip().split(",")[-1].strip().strip('"')
    before = [r.split(",")[-1].strip().strip('"') for _, r in rows[:-1]]
    if last[-1:] in (".", "e", "E", "+", "-") or len(last) < min(len(b) for b in before):
        raise ModelError(
            key,
            shown,
            f"ends without a line break and its last line ({rows[-1][0]}) looks cut in column "
            f"{rows[-1][1].count(',') + 1}: as a file whose write was interrupted; remove that line, or end the "
            "file with a line break if the line is complete",
        )


def read_csv_table(
    path,
    key: str = "file",
    *,
    min_rows: int = 2,
    min_columns: int = 2,
    rounding: bool = False,
    zero_row_free: bool = False,
):
    """``(names, data)`` of the numeric CSV table in ``path``: one header line of ``,``-separated
    column names (a name in double quotes is read without them), then rows of as many finite
    numbers (in quotes or not; blank lines and lines starting with ``#`` are skipped). A
    :class:`ModelError` names ``key`` (the field or option that gave the path), the file, and the
    line and column that are wrong, and says what is allowed; it quotes no part of the file (which
    may be any file). ``data`` is (rows, columns), float. With ``rounding``, ``(names, data,
    rounding)``: how far each row's first number may lie from the value it was printed from, in
    that column's unit (:func:`printed_rounding`; a record's time column printed with few digits).
    With ``zero_row_free`` (an FRF's reader: its 0 Hz line is left out by every fit), a first row
    whose first number is exactly 0 may hold NaN, an infinity or a magnitude above
    :data:`MAX_MAGNITUDE` in its other columns (an apparent mass, infinite at 0 Hz), returned as
    read; elsewhere they are refused as without it."""
    shown = str(path)
    p = _target(path, key)
    if not p.exists():
        raise ModelError(key, shown, "does not exist")
    if not p.is_file():
        raise ModelError(key, shown, "must be a regular CSV file (not a folder or a device)")
    try:
        size = p.stat().st_size
        if size > memory_available() // 4:  # (the parsed table takes up to 4x the text in memory)
            raise ModelError(key, shown, f"is {size / 1e9:.3g} GB: larger than the memory free to read it")
        with open(p, encoding="utf-8-sig", newline="") as fh:  # (-sig: a byte-order mark some editors write)
            lines = fh.read().splitlines()
    except UnicodeDecodeError as exc:
        raise ModelError(
            key, shown, f"is not a UTF-8 text CSV file (byte {exc.start} is not text: an .npz or .uff file?)"
        ) from None
    except OSError as exc:
        raise ModelError(key, shown, f"cannot be read ({exc.strerror})") from None
    numbered = [(i + 1, s) for i, s in enumerate(lines) if s.strip() and not s.lstrip().startswith("#")]
    need = f"a header line naming {min_columns} or more ','-separated columns and {min_rows} or more rows of numbers"
    if not numbered:
        raise ModelError(key, shown, f"is empty; a table needs {need}")
    (hline, head), rows = numbered[0], numbered[1:]
    # (the header by the csv module: a name in quotes, as Excel and pandas write them, loses its
    # quotes, and a quoted name may hold a comma; the rows are plain numbers, read below by numpy)
    names = [h.strip() for h in next(csv.reader([head], skipinitialspace=True))]
    if len(names) < min_columns:
        sep = next((c for c in (";", "\t", " ") if c in head.strip()), None)
        found = f"columns separated by {sep!r}" if sep else "one column"
        raise ModelError(key, shown, f"line {hline} has {found}; a table needs {need}")
    if all(is_number(h) for h in names):
        raise ModelError(
            key, shown, f"has no header line (line {hline} holds numbers); its first line must name the columns"
        )
    if len(rows) < min_rows:
        raise ModelError(key, shown, f"has {len(rows)} rows of numbers; a table needs {need}")
    _refuse_cut_last_row(key, shown, lines, rows)
    try:  # (numpy's C parser; the checks below only run to describe a failure)
        data = np.loadtxt([s for _, s in rows], delimiter=",", ndmin=2)
        ok = data.shape[1] == len(names)
    except ValueError:
        ok = False
    if not ok and any('"' in s for _, s in rows):  # numbers in quotes (a spreadsheet's "quote all")
        fields = [[f.strip() for f in r] for r in csv.reader([s for _, s in rows])]
        if all(len(r) == len(names) and all(is_number(f) for f in r) for r in fields):
            data, ok = np.array(fields, dtype=float).reshape(len(rows), len(names)), True
    if not ok:
        for lineno, s in rows:
            fields = s.split(",")
            if len(fields) != len(names):
                raise ModelError(
                    key, shown, f"line {lineno} has {len(fields)} fields; the header has {len(names)} columns"
                )
            for j, f in enumerate(fields):
                if not is_number(f):
                    raise ModelError(key, shown, f"line {lineno}, column {j + 1} is not a number")
        raise ModelError(key, shown, f"must be {need}")  # pragma: no cover - loadtxt agrees with the scan
    flagged = unreadable(data)
    if zero_row_free and data[0, 0] == 0.0:
        flagged[0, 1:] = False
    bad = np.argwhere(flagged)
    if bad.size:
        r, c = bad[0]
        only = " (only the 0 Hz line, which the fits leave out, may hold another value)" if zero_row_free else ""
        raise ModelError(
            key, shown, f"line {rows[r][0]}, column {c + 1} is not a finite number of magnitude at most 1e100{only}"
        )
    if rounding:
        return names, data, printed_rounding([s.split(",", 1)[0] for _, s in rows], data[:, 0])
    return names, data


def _last_digit(text: str) -> float:
    """The last digit a number printed as ``text`` shows (``"0.0125"``: 1e-4, ``"1.5e-3"``: 1e-4), NaN for
    a whole number (``"2"``, no point, no exponent); quotes and spaces around it are ignored."""
    mantissa, _, exponent = text.strip().strip("\"' ").lower().partition("e")
    point, decimals = mantissa.partition(".")[1:]
    return float("nan") if not (point or exponent) else 10.0 ** (int(exponent or 0) - len(decimals))


def printed_rounding(texts, values) -> np.ndarray:
    """How far each number of a column may lie from the value it was printed from (in the column's
    unit): half the last digit each of ``texts`` (the numbers as printed; quotes and spaces around
    them are ignored) shows, ``values`` being the numbers they read as (for their magnitudes).
    An analyser's ``%.6g`` time column at 2048 Hz rounds its steps by up to 1 % of themselves.

    A number printed short ("0.5", "-0.02": ``%g`` strips trailing zeros) is no evidence of a coarse
    resolution, and its own digit would widen the allowance of its row (a CSV with a sample missing
    was read at 2045.5 Hz): a number's digit counts at most as the larger of the column's median
    digit (``%.9f``: fixed decimals) and the digit the column's median number of significant digits
    gives at the number's own magnitude (``%.6g``: 1e-6 from 0.1, 1e-5 from 1, so that a record
    that crosses 1 s keeps its coarser rows past it). A whole number ("0", "2", no point, no
    exponent) says nothing of the digits kept and takes the column's median digit; a column of whole
    numbers only is taken as exact (0)."""
    values = np.abs(np.asarray(values, dtype=float))
    digit = np.array([_last_digit(text) for text in texts], dtype=float)  # (a loop: 4x numpy.char's speed)
    if digit.size == 0 or np.all(np.isnan(digit)):
        return np.zeros(values.shape)
    median = float(np.nanmedian(digit))
    with np.errstate(divide="ignore", invalid="ignore"):
        lead = np.where(values > 0, np.floor(np.log10(values)), np.nan)  # (the leading digit's exponent)
        significant = np.round(lead - np.log10(digit)) + 1.0  # (digits printed)
    if np.all(np.isnan(significant)):
        cap = np.full(values.shape, median)
    else:  # (fmax: a 0's nan magnitude gives the median)
        cap = np.fmax(median, 10.0 ** (lead - float(np.nanmedian(significant)) + 1.0))
    return 0.5 * np.where(np.isnan(digit), median, np.minimum(digit, cap))


#: A statement a comment line of a CSV table makes about it: ``# name = value (what it means)``
#: (``:`` for ``=`` too; the name in any case; the parenthesis is not part of the value).
_STATEMENT = re.compile(r"^#\s*([A-Za-z_]\w*)\s*[=:]\s*([^(]*?)\s*(?:\(.*)?$")


def csv_statements(path, names, key: str = "file") -> dict:
    """What the comment lines of the CSV table ``path`` state about it before its first row of
    numbers (before or after the header line), for the statement names ``names`` (lower case):
    ``{name: (line number, value text)}``, as a run's record states its passband (``# passband_hz =
    3500 (...)``, records.py) and an FRF its kind (``# kind = acceleration``, identification).
    Call it after :func:`read_csv_table` has read the file. A name stated twice raises
    :class:`ModelError` naming ``key``, the file and both lines."""
    found = {}
    header = False
    with open(path, encoding="utf-8-sig", errors="replace") as fh:
        for lineno, line in enumerate(fh, start=1):
            text = line.strip()
            if not text:
                continue
            if not text.startswith("#"):
                if header:  # (the first row of numbers: statements come before it)
                    break
                header = True
                continue
            m = _STATEMENT.match(text)
            if m is None or m.group(1).lower() not in names:
                continue
            name = m.group(1).lower()
            if name in found:
                raise ModelError(
                    key, str(path), f"lines {found[name][0]} and {lineno} both state {name}: a table states it once"
                )
            found[name] = (lineno, m.group(2))
    return found


#: The names of a time column that need no unit (s).
TIME_NAMES = ("time", "t")
_BRACKETS = re.compile(r"(.*?)\s*[\[(]\s*([^\])]*?)\s*[\])]")


def time_column(key: str, path, header: str, *, named: bool = False) -> float:
    """The factor (to s) of a table's time column (its first) from its header ``header``: the
    unit in brackets (``time [ms]``, also ``time (ms)``) or, as a record's other columns, the
    ``<name>_<unit>`` form (``time_ms``) of ``time`` and ``t`` (:data:`.units.TIME_UNITS`: s, ms, us or
    µs, also sec, msec, usec); 1.0 where the header gives no unit (a record's time is then in s).
    A unit that is not one of time raises a :class:`ModelError` naming ``key`` and the file
    (quoting none of it). ``named``: a header without a unit must be ``time`` or ``t``
    (a CSV excitation, whose first column must be the time: not a swapped pair of columns)."""
    text = header.strip()
    found = _BRACKETS.fullmatch(text)
    if found:
        unit = found.group(2)
    else:
        name, sep, unit = text.rpartition("_")
        if not sep or name.lower() not in TIME_NAMES:
            if named and text.lower() not in TIME_NAMES:
                raise ModelError(
                    key,
                    str(path),
                    "must have the time in its first column, headed time_s (or time [s]; a time in ms or us, "
                    "time_ms or time [ms], is converted to s); its header names another column first",
                )
            return 1.0
    factor = time_factor(unit)
    if factor is None:
        raise ModelError(
            key,
            str(path),
            "must give the time of its first column in s, ms or us (time [s], time_s, time [ms], time_ms, "
            "time [us]; also sec, msec, usec, µs); the unit its header gives that column is not one of time",
        )
    return factor


def read_excitation_table(path, key: str) -> tuple[np.ndarray, np.ndarray]:
    """(t, x) of a CSV excitation (``scenario.excitation.<name>.file``): a table with a header and two
    columns time_s, <value>, t in s and x in the excitation's unit (m, m/s or m/s2 by its
    ``quantity``); checked (errors name ``key``, the file and the line, and quote none of its content).
    The run (``timedomain.scenario``) and the model's load (``model.load``) read it by this one
    rule. A third column is refused, not ignored: it may be the column that was meant. The first
    column's header must name the time (:func:`time_column`): ``time_s``, ``time [s]`` (as a
    record's CSV), ``time`` or ``t`` are in s; ``time_ms``, ``time [ms]``, ``time_us``, ``time [us]`` are converted to
    s; another unit, or a first column that is not the time, is refused."""
    names, data = read_csv_table(path, key)
    if len(names) != 2:
        raise ModelError(
            key,
            str(path),
            f"must have two columns, time_s and the values; its header line names {len(names)} columns "
            "(one excitation per file: give each column its own file and excitation)",
        )
    to_s = time_column(key, path, names[0], named=True)
    t, x = data[:, 0] if to_s == 1.0 else data[:, 0] * to_s, data[:, 1]
    bad = np.nonzero(np.diff(t) <= 0)[0]
    if bad.size:
        raise ModelError(key, path, f"time (its first column) must increase strictly; data row {bad[0] + 2} does not")
    return t, x


def _read_text(path):
    """The text of the small file ``path``; None when it cannot be read (the cgroup files' reader, replaced
    in tests)."""
    with contextlib.suppress(OSError, UnicodeDecodeError):
        with open(path) as fh:
            return fh.read()
    return None


def _read_line(path):
    """The first line of the text file ``path``, stripped; None when it cannot be read."""
    text = _read_text(path)
    return None if text is None else (text.splitlines() or [""])[0].strip()


def _stat_value(path, key):
    """The number after ``key`` in the ``key value`` lines of the cgroup file ``path`` (memory.stat); 0
    when the file or the key is missing."""
    for line in (_read_text(path) or "").splitlines():
        name, _, value = line.partition(" ")
        if name == key and value.strip().isdigit():
            return int(value)
    return 0


#: cgroup v1's "no limit" (a page-rounded 2**63 - 1): limits at or above it are none.
_CGROUP_V1_NONE = 1 << 62


def _own_cgroups():
    """This process's cgroup paths from /proc/self/cgroup: ``(v2, v1)``, the unified hierarchy's (line
    ``0::<path>``) and the v1 memory controller's (line ``<n>:memory:<path>``, or with other controllers
    joined by commas), each None when not named."""
    v2 = v1 = None
    for line in (_read_text("/proc/self/cgroup") or "").splitlines():
        number, _, rest = line.partition(":")
        controllers, _, path = rest.partition(":")
        if number == "0" and controllers == "":
            v2 = path.strip()
        elif "memory" in controllers.split(","):
            v1 = path.strip()
    return v2, v1


def _and_parents(root, own):
    """The folder of the cgroup ``own`` (a path from /proc/self/cgroup) under the hierarchy's mount ``root``
    and each of its parents up to ``root``, innermost first (``root`` alone when ``own`` is None or /)."""
    parts = [p for p in (own or "").split("/") if p]
    return [os.path.join(root, *parts[:k]) for k in range(len(parts), 0, -1)] + [root]


def cgroup_memory_free():
    """Bytes the process's cgroups still allow, or None without a limit: the least, over its own cgroup and
    its parents, of a limit less its usage, the usage without the page cache the kernel reclaims before it
    kills (``inactive_file`` of ``memory.stat``, as docker and the kubelet count a container's working set).
    cgroup v2's ``memory.max`` (``max``: none) less ``memory.current``, in the folder /proc/self/cgroup names
    under /sys/fs/cgroup and its parents up to /sys/fs/cgroup itself (a container's own, usually: in a cgroup
    namespace the process's path is /); cgroup v1's ``memory.limit_in_bytes`` (2**63 rounded: none) less
    ``memory.usage_in_bytes`` (and ``total_inactive_file``), the same way under /sys/fs/cgroup/memory."""
    v2, v1 = _own_cgroups()
    folders = [(d, "memory.max", "memory.current", "inactive_file") for d in _and_parents("/sys/fs/cgroup", v2)]
    folders += [
        (d, "memory.limit_in_bytes", "memory.usage_in_bytes", "total_inactive_file")
        for d in _and_parents("/sys/fs/cgroup/memory", v1)
    ]
    free = None
    for folder, limit_name, usage_name, cache_name in folders:
        limit = _read_line(os.path.join(folder, limit_name))
        if limit is None or not limit.isdigit() or int(limit) >= _CGROUP_V1_NONE:  # (none here: "max", v1's 2**63)
            continue
        usage = _read_line(os.path.join(folder, usage_name))
        usage = int(usage) if usage and usage.isdigit() else 0
        cache = min(_stat_value(os.path.join(folder, "memory.stat"), cache_name), usage)
        here = max(int(limit) - (usage - cache), 0)
        free = here if free is None else min(free, here)
    return free


def memory_available() -> int:
    """Bytes of memory free for a new allocation: MemAvailable of /proc/meminfo (elsewhere the physical
    memory), or what the process's cgroup still allows (:func:`cgroup_memory_free`: a container's limit less
    its usage, reclaimable page cache not counted) when that is less (a container past its limit is killed,
    whatever the host has free)."""
    free = None
    with contextlib.suppress(OSError, ValueError):
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    free = int(line.split()[1]) * 1024
                    break
    if free is None:
        with contextlib.suppress(ValueError, OSError, AttributeError):
            free = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    if free is None:
        free = 1 << 34  # pragma: no cover
    cgroup = cgroup_memory_free()
    return free if cgroup is None else min(free, cgroup)
