"""The results store of the Monte-Carlo study (Section 4.4): an append-only CSV, one row per sample,
flushed and fsynced per row, with a ``<csv>.meta.json`` sidecar of the settings; resume reads it."""

from __future__ import annotations

import contextlib
import csv
import io
import json
import os
import time
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError, excerpt, plain
from ..files import is_number
from .evaluators import DEFAULT_EVALUATE, EARLIER_RECORD_SETTINGS

META_COLUMNS = ("index", "status")
TAIL_COLUMNS = ("elapsed_s", "error")
#: The column of a sample's warnings, before TAIL_COLUMNS (studies begun before it have none: a
#: sidecar without ``"warnings": true``, whose header a resume keeps)
WARNINGS_COLUMN = "warnings"
STATUSES = ("ok", "failed", "infeasible")
FORMAT_VERSION = 2  # 2: Saltelli's design on a Sobol' sequence (1 was a Latin hypercube)
#: Settings of the sidecar that a resumed study must share with the file (the size may grow).
RESUME_KEYS = (
    "format",
    "seed",
    "bounds",
    "outputs",
    "quantity",
    "evaluate",
    "evaluate_kwargs",
    "constraints",
    "sampler",
)


@dataclass
class StudyResults:
    """Rows of a Monte-Carlo study (Section 4.4), sorted by sample index.

    index (n,) int; parameters (names); X (n, d) parameter values (SI); outputs (names);
    Y (n, m) output values (NaN where not ok); status (n,) str; error (n,) str; elapsed_s (n,) s;
    warnings (n,) str: what the sample's run warned, its messages joined by `` | `` (``""`` when it
    warned nothing, and for every row of a study begun before the CSV had the column);
    group_size: runs per base point of Saltelli's design (d + 2; 0 when the file has no such design);
    n_base: base points of the design (the study's size is n_base * group_size runs).
    """

    index: np.ndarray
    parameters: tuple
    X: np.ndarray
    outputs: tuple
    Y: np.ndarray
    status: np.ndarray
    error: np.ndarray
    elapsed_s: np.ndarray
    warnings: np.ndarray | None = None
    group_size: int = 0
    n_base: int = 0
    #: what every output is a value of: {"name": "casing.B.Fz", "unit": "N", "what": "band RMS"}
    #: (the sidecar's ``quantity``; None for a study that does not say)
    quantity: dict | None = None

    def __post_init__(self):
        if self.warnings is None:
            self.warnings = np.full(self.index.size, "", dtype=object).astype(str)

    @property
    def ok(self):
        """Boolean mask of the successful samples."""
        return self.status == "ok"

    @property
    def warned(self):
        """Boolean mask of the samples whose run warned (:attr:`warnings` not empty)."""
        return np.char.str_len(self.warnings.astype(str)) > 0

    def __len__(self):
        return self.index.size


def _meta_path(path):
    return str(path) + ".meta.json"


def _header(params, outputs, quantity=None, warnings=False, units=False):
    """The CSV's header: the output columns name the quantity and its unit when the study says
    (``casing.B.Fz oct1 [N]``), else the outputs' names alone (files of earlier versions); the
    parameter columns their unit when the sidecar says ``"units": true`` (``casing.E [Pa]``, a
    parameter that is no model key, or has no unit, by its name alone; files since 2026-12), and the
    warnings column when it says ``"warnings": true`` (files since it was added)."""
    if quantity:
        outputs = [f"{quantity['name']} {o} [{quantity['unit']}]" for o in outputs]
    if units:
        params = [f"{p} [{parameter_unit(p)}]" if parameter_unit(p) else p for p in params]
    extra = [WARNINGS_COLUMN] if warnings else []
    return list(META_COLUMNS) + list(params) + list(outputs) + extra + list(TAIL_COLUMNS)


def parameter_unit(key) -> str:
    """The unit of a study's parameter, the model key ``key`` (the schema's; ``-`` for a
    dimensionless one), or ``""`` when it is no key of the model file (a study with ``model=False``)."""
    from ..model.schema import lookup

    try:
        unit = lookup(key).unit
    except (ModelError, KeyError, TypeError):
        return ""
    return "-" if unit in ("1", "-") else (unit or "")


#: The line ending of a study's CSV (LF, as the ensemble files; a study begun with CRLF, the csv
#: module's default that earlier versions wrote, goes on with its own: :class:`ResultsWriter`).
LINE_END = "\n"


def _header_line(header, line_end=LINE_END):
    """The CSV text of the header line ``header`` (:func:`_header`), as the file holds it."""
    line = io.StringIO(newline="")
    csv.writer(line, lineterminator=line_end).writerow(header)
    return line.getvalue()


def _fmt(v):
    if isinstance(v, float):
        return repr(v)  # shortest repr round-trips the float exactly
    return str(v)


def _repair_tail(path):
    """Cut a torn last line (no trailing newline) left by a process killed mid-write."""
    with open(path, "rb+") as fh:
        data = fh.read()
        if data and not data.endswith(b"\n"):
            cut = data.rfind(b"\n") + 1
            fh.truncate(cut)
            return True
    return False


def load_results(path: str | os.PathLike) -> StudyResults:
    """Read a study CSV written by :func:`run_study` into :class:`StudyResults` (sorted by index;
    parameters and outputs in the units they were written in, SI). Section 4.4.

    The parameter and output columns are told from the sidecar ``<path>.meta.json``. If an index
    appears twice (not written by run_study), the first row wins.
    """
    path = str(path)
    try:
        with open(_meta_path(path)) as fh:
            meta = json.load(fh)
        params, outputs = tuple(meta["bounds"]), tuple(meta["outputs"])
    except (OSError, ValueError, KeyError) as exc:
        raise ModelError("path", path, f"must be a study CSV with its {_meta_path(path)} sidecar ({exc})") from None
    has_warnings = meta.get("warnings") is True
    header = _header(params, outputs, meta.get("quantity"), has_warnings, meta.get("units") is True)
    try:
        with open(path, newline="") as fh:
            text = fh.read()
    except OSError as exc:
        raise ModelError("path", path, f"must be a readable study CSV ({exc.strerror})") from None
    if text and not text.endswith("\n"):
        text = text[: text.rfind("\n") + 1]  # a torn last line is ignored (run_study cuts it off)
    reader = csv.reader(io.StringIO(text, newline=""))
    head = next(reader, None)
    if head != header:
        raise ModelError("path", path, f"must have the header {','.join(header)} (found {head})")
    rows = {}
    d, m = len(params), len(outputs)
    # (what each column must hold: the index, the status, then the parameters, outputs and elapsed_s)
    cells = [
        (0, str.isdigit, "a sample index (a whole number)"),
        (1, STATUSES.__contains__, "a status: " + ", ".join(STATUSES)),
    ]
    cells += [(c, lambda v: v == "" or is_number(v), "a number") for c in [*range(2, 2 + d + m), len(header) - 2]]
    for lineno, r in enumerate(reader, start=2):
        if len(r) != len(header):
            raise ModelError("path", path, f"line {lineno} has {len(r)} fields, expected {len(header)}")
        bad = next(((c, what) for c, holds, what in cells if not holds(r[c])), None)
        if bad is not None:
            raise ModelError(
                "path", path, f"line {lineno}, column {header[bad[0]]!r} must hold {bad[1]} (it was edited?)"
            )
        rows.setdefault(int(r[0]), r)
    order = sorted(rows)
    num = lambda s: float(s) if s != "" else np.nan  # noqa: E731
    X = np.array([[num(rows[i][2 + k]) for k in range(d)] for i in order], float).reshape(len(order), d)
    Y = np.array([[num(rows[i][2 + d + k]) for k in range(m)] for i in order], float).reshape(len(order), m)
    return StudyResults(
        index=np.array(order, int),
        parameters=params,
        X=X,
        outputs=outputs,
        Y=Y,
        status=np.array([rows[i][1] for i in order], dtype=object).astype(str),
        error=np.array([rows[i][-1] for i in order], dtype=object).astype(str),
        elapsed_s=np.array([num(rows[i][-2]) for i in order], float),
        warnings=np.array([rows[i][-3] if has_warnings else "" for i in order], dtype=object).astype(str),
        group_size=len(params) + 2 if meta.get("format") == FORMAT_VERSION else 0,
        n_base=int(meta.get("n_base", 0)),
        quantity=meta.get("quantity"),
    )


def _design_mismatch(path, res, j, i, design):
    """What a row of the study CSV ``path`` that is not the design's says: the line of sample ``i``
    (row ``j`` of ``res``), its first parameter's column that differs, both values."""
    with open(path, newline="") as fh:
        lineno = next((n for n, r in enumerate(csv.reader(fh), start=1) if n > 1 and r and r[0] == str(i)), "?")
    if not 0 <= i < len(design):
        return f"line {lineno}: sample {i} is not one of the design's {len(design)} samples (it was edited?)"
    k = int(np.flatnonzero(res.X[j] != design[i])[0])
    return (
        f"line {lineno}, column {res.parameters[k]!r} holds {res.X[j][k]!r} where the design of this seed and bounds "
        f"has {design[i][k]!r} for sample {i} (it was edited?)"
    )


class ResultsWriter:
    """Append-only CSV writer, one flushed and fsynced row per sample."""

    def __init__(self, path, params, outputs, design, warnings=True):
        self.path, self.params, self.outputs, self.design = path, params, outputs, design
        self.warnings = warnings  # (the file has the warnings column: its sidecar says so)
        with open(path, "rb") as fh:  # (the line ending of its header: CRLF in a study of earlier versions)
            first = fh.readline()
        line_end = "\r\n" if first.endswith(b"\r\n") else LINE_END
        self.fh = open(path, "a", newline="")
        self.w = csv.writer(self.fh, lineterminator=line_end)

    def write(self, row):
        i = row["index"]
        vals = [i, row["status"]] + [_fmt(float(v)) for v in self.design[i]]
        vals += [_fmt(row[o]) if o in row else "" for o in self.outputs]
        if self.warnings:
            vals.append(row.get(WARNINGS_COLUMN, ""))
        vals += [f"{row.get('elapsed_s', 0.0):.6g}", row.get("error", "")]
        self.w.writerow(vals)
        self.fh.flush()
        os.fsync(self.fh.fileno())

    def close(self):
        self.fh.close()


def read_meta(path) -> dict | None:
    """The sidecar of the study CSV ``path`` (None when there is no study there yet)."""
    if not (os.path.exists(path) and os.path.getsize(path) > 0):
        return None
    mp = _meta_path(path)
    try:
        with open(mp) as fh:
            return json.load(fh)
    except (OSError, ValueError) as exc:
        raise ModelError(
            "path", path, f"exists but its sidecar {mp} cannot be read ({exc}); choose a new file to start a study"
        ) from None


def lost_log_path(path) -> str:
    """The log of the samples of study ``path`` lost to the infrastructure (``<csv>.lost.log``)."""
    return str(path) + ".lost.log"


class LostLog:
    """Appends a line ``<UTC time> sample <index>: <cause>`` to :func:`lost_log_path` for every sample
    lost to the infrastructure (the study CSV has no row of it: a resume runs it again)."""

    def __init__(self, path):
        self.path = lost_log_path(path)
        self.count = 0

    def __call__(self, index, cause):
        stamp = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
        with open(self.path, "a", encoding="utf-8") as fh:
            fh.write(f"{stamp} sample {index}: {cause}\n")
        self.count += 1


@contextlib.contextmanager
def study_lock(path):
    """Hold the lock of the study ``path`` (``fcntl.flock`` on ``<csv>.lock``) while the block runs;
    a second run on the same file is refused with a :class:`ModelError` naming the process that holds
    it. The lock goes with the process (a killed run leaves no stale lock; a run that ends removes the
    file, and a run checks that the file it locked is still the one at that path). On NFS, Linux emulates
    ``flock`` with byte-range locks of the server's lock manager: it holds between machines when the
    server runs one (NFSv4, or v3 with lockd), and is only local otherwise. Without ``fcntl``
    (Windows) there is no lock."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - Windows
        yield
        return
    lock = str(path) + ".lock"
    for _ in range(3):  # (a lock file removed by its last holder between our open and flock: again)
        fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            holder = os.pread(fd, 64, 0).decode("ascii", "replace").strip() or "?"
            os.close(fd)
            raise ModelError(
                "path",
                str(path),
                f"is in use by another study run (process {excerpt(plain(holder), 20)}, {lock}); wait for it to end "
                "or choose another output",
            ) from None
        try:
            same = os.path.samestat(os.fstat(fd), os.stat(lock))
        except OSError:
            same = False
        if same:
            break
        os.close(fd)
    else:  # pragma: no cover - three removals in a row
        raise ModelError("path", str(path), f"its lock {lock} keeps being removed; try again")
    try:
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
        yield
    finally:
        try:  # removed while still held, so that no run ever locks a file that is gone
            os.remove(lock)
        except OSError:
            pass
        os.close(fd)  # (releases the lock)


def recover_header(path, params, outputs, quantity=None) -> bool:
    """A study CSV torn inside its header line (killed while it was created, by earlier versions
    that wrote it in place) holds no row: it is removed, so the study starts afresh in this run, and
    True returned. Such a file is one without a newline whose content begins the header of this
    study (``params``, ``outputs``, ``quantity``) or of the study its sidecar describes; any other
    file without a newline is no study and is refused (ModelError naming ``path``), left as it is."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(1 << 16)
    except OSError:
        return False
    if b"\n" in head:
        return False
    # (this study's header, and as versions before the parameters' units wrote it)
    headers = [_header(params, outputs, quantity, warnings=True, units=units) for units in (True, False)]
    try:
        with open(_meta_path(path)) as fh:
            meta = json.load(fh)
        headers.append(
            _header(
                meta["bounds"],
                meta["outputs"],
                meta.get("quantity"),
                meta.get("warnings") is True,
                meta.get("units") is True,
            )
        )
    except (OSError, ValueError, KeyError, TypeError):  # (no sidecar, or none of a study)
        pass
    for header in headers:
        if any(_header_line(header, end).encode().startswith(head) for end in (LINE_END, "\r\n")):
            os.remove(path)
            return True
    raise ModelError(
        "path",
        str(path),
        "exists and is no study's CSV (its content does not begin a study's header); choose a new file to start a "
        "study, or move that one away",
    )


#: The ``what`` of the quantity of a study of ``cablecasing study`` (its sidecar's), by which
#: :func:`_begun_by` tells its studies from run_study's.
COMMAND_QUANTITY_WHAT = "RMS in the octave bands of Table 3"
#: How a study begun by each is resumed (:func:`_begun_by`).
RESUMED_BY = {
    "`cablecasing study`": "the same `cablecasing study` command",
    "run_study": "run_study with the arguments it began with",
}


def _begun_by(meta):
    """Who began the study of the sidecar ``meta``: ``"`cablecasing study`"`` (default_evaluate with
    a ``model_file`` and the command's quantity) or ``"run_study"`` (any other)."""
    kwargs = meta.get("evaluate_kwargs") if isinstance(meta.get("evaluate_kwargs"), dict) else {}
    quantity = meta.get("quantity") if isinstance(meta.get("quantity"), dict) else {}
    command = (
        meta.get("evaluate") == DEFAULT_EVALUATE
        and "model_file" in kwargs
        and quantity.get("what") == COMMAND_QUANTITY_WHAT
    )
    return "`cablecasing study`" if command else "run_study"


def begun_by_other(begun, path):
    """The refusal to resume the study in ``path`` begun by ``begun`` (:func:`_begun_by`) through the
    other interface (raised by :func:`prepare_file`, and by ``cablecasing study`` before its plan)."""
    return ModelError(
        "path",
        path,
        f"holds a study begun by {begun}: `cablecasing study` and run_study write other sidecars and headers (the "
        "command records the model and the output's quantity and unit, run_study only when given model= and "
        f"quantity=), and neither resumes a study of the other: resume it the way it began ({RESUMED_BY[begun]}), "
        "or choose a new file",
    )


def begun_by_run_study(old):
    """Whether ``cablecasing study`` would refuse the study of the sidecar ``old`` as begun by
    run_study (:func:`prepare_file`'s rule: a sidecar that records a quantity, and is not the command's;
    one of an earlier version, without a quantity, is judged by its settings alone)."""
    return "quantity" in old and _begun_by(old) == "run_study"


def prepare_file(path, meta, design, params):
    """Create the CSV and sidecar, or check them for a resume (the settings of :data:`RESUME_KEYS`
    equal, every stored row equal to the design's row of its index) and record a larger size.
    Returns the set of indices present."""
    from ..files import write_text

    old = read_meta(path)
    if old is not None and "quantity" not in old:  # (a study of an earlier version: its header stays)
        meta.pop("quantity", None)
    if old is not None and old.get("warnings") is not True:  # (the same: no warnings column)
        meta.pop("warnings", None)
    if old is not None and old.get("units") is not True:  # (the same: parameter columns without units)
        meta.pop("units", None)
    if old is not None and "model_fingerprint" not in old and "model_file" in (old.get("evaluate_kwargs") or {}):
        meta.pop("model_fingerprint", None)  # (a study of an earlier version ran it but did not record it)
    if old is not None and old.get("evaluate") == DEFAULT_EVALUATE and isinstance(old.get("evaluate_kwargs"), dict):
        if "window" not in old["evaluate_kwargs"]:  # (its samples took the earlier skip and window)
            old["evaluate_kwargs"] = EARLIER_RECORD_SETTINGS | old["evaluate_kwargs"]
    header = _header(
        params, meta["outputs"], meta.get("quantity"), meta.get("warnings") is True, meta.get("units") is True
    )
    if old is None:
        d = os.path.dirname(os.path.abspath(path))
        os.makedirs(d, exist_ok=True)
        write_text(_meta_path(path), json.dumps(meta, indent=1))
        write_text(path, _header_line(header))  # (atomic: a header is whole or absent)
        return set()
    if old.get("format") != meta["format"]:
        raise ModelError(
            "format",
            old.get("format"),
            f"the study in {path} has another format ({meta['format']} is read); choose a new file to start a study",
        )
    if list(old.get("bounds", {})) != list(meta["bounds"]):  # (dicts compare equal in any order)
        raise ModelError(
            "bounds",
            list(meta["bounds"]),
            f"must name the parameters in the order of the study in {path}, {list(old.get('bounds', {}))} (its "
            "columns and design follow that order), to resume it (or choose a new file)",
        )
    begun, now = _begun_by(old), _begun_by(meta)
    if begun != now and any(old.get(k) != meta.get(k) for k in ("model_fingerprint", *RESUME_KEYS)):
        raise begun_by_other(begun, path)
    if old.get("model_fingerprint") != meta.get("model_fingerprint"):
        named = "model_file" in meta["evaluate_kwargs"]
        was = old.get("model_fingerprint") or "none: evaluate was given no model"
        raise ModelError(
            "model_file" if named else "model",
            meta["evaluate_kwargs"]["model_file"] if named else plain(f"fingerprint {meta.get('model_fingerprint')}"),
            f"holds another model than when the study in {path} began (fingerprint {was}; an edited file, or its CSV "
            "excitation): a resume runs the same model; choose a new file to start a study",
        )
    for key in RESUME_KEYS:
        if old.get(key) != meta.get(key):
            raise ModelError(
                key, meta.get(key), f"must equal {old.get(key)!r} to resume the study in {path} (or choose a new file)"
            )
    _repair_tail(path)
    res = load_results(path)
    for j, i in enumerate(res.index):
        if not (0 <= i < len(design)) or not np.array_equal(res.X[j], design[i]):
            raise ModelError("path", path, _design_mismatch(path, res, j, i, design))
    # (enlarged: the sidecar records the new size; or run with other kernels: it records them too)
    if old.get("n_base") != meta["n_base"] or old.get("kernels") != meta.get("kernels"):
        write_text(_meta_path(path), json.dumps(meta, indent=1))
    return set(int(i) for i in res.index)
