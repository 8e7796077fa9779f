"""Model files: TOML in, a validated :class:`~cablecasing_core.model.model.Model` out (validation
built from the schema, :mod:`.validate`); the built-in specimens in ``specimens/``, selected by name
(``load_model("installed")``).

A model is a TOML file with the sections ``[geometry]``, ``[casing]``, ``[cable]`` (either body may
be left out, at least one must be present), ``[contact]``, ``[loads]`` and ``[scenario]``; docs/model_file.md
lists every key. Every mistake raises :class:`~cablecasing_core.errors.ModelError` naming the dotted
key, the value and what is allowed; nothing is half-built.
"""

from __future__ import annotations

import os
import re
import stat
from importlib import resources
from pathlib import Path

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

from ..errors import ModelError
from ..files import read_excitation_table
from .model import Model
from .validate import derived_keys, validate

#: The largest model file read (bytes): a model is a few kB; anything larger is not one (and a
#: device such as /dev/zero would otherwise be read without end).
MAX_MODEL_BYTES = 1 << 20


def model_from_dict(data: dict, source: str = "<dict>", base_dir: str | None = None) -> Model:
    """Validate a raw nested dictionary (as read from TOML) and return a :class:`Model`; ``base_dir``
    is the folder relative CSV paths are read from."""
    model = Model(validate(data, base_dir=base_dir), source=source, base_dir=base_dir, derived=derived_keys(data))
    _warn_if_implausible(model)
    return model


def specimen_names() -> tuple[str, ...]:
    """Names of the built-in specimens (``model/specimens/<name>.toml``): ``default`` (the paper's
    specimen, stress-free in its routing) and ``installed`` (the same cable straight off the reel,
    with gravity and a tension: docs/installed.md)."""
    folder = resources.files("cablecasing_core.model").joinpath("specimens")
    return tuple(sorted(f.name[: -len(".toml")] for f in folder.iterdir() if f.name.endswith(".toml")))


def load_model(path: str | Path | None = None) -> Model:
    """Load and validate a model file (TOML). ``None`` gives the built-in specimen; the name of a
    built-in specimen (``"default"``, ``"installed"``: :func:`specimen_names`, a name without a
    folder or suffix) gives that specimen, so ``cablecasing simulate installed`` works wherever a
    model file is accepted.

    Raises :class:`ModelError` for a file that cannot be read or any invalid key, and naming
    ``path`` for one that is no path (an ``int``, a ``dict``).
    """
    if path is None:
        path = "default"
    if not isinstance(path, (str, os.PathLike)):
        raise ModelError(
            "path",
            path,
            "must be a model file's path (a str or pathlib.Path), a built-in specimen's name ("
            + ", ".join(specimen_names())
            + ") or None (the built-in specimen); a dict of the model file's tables goes to cc.model_from_dict",
        )
    if isinstance(path, str) and path in specimen_names():
        text = resources.files("cablecasing_core.model").joinpath(f"specimens/{path}.toml").read_text()
        raw = tomllib.loads(text)
        source = "<built-in>" if path == "default" else f"<built-in {path}>"
        return Model(validate(raw), source=source, derived=derived_keys(raw))
    p = Path(path)
    raw = toml_file(p, "model_file", MAX_MODEL_BYTES, " or a built-in specimen: " + ", ".join(specimen_names()))
    base = str(p.resolve().parent)
    try:
        model = Model(validate(raw, base_dir=base), source=str(p), base_dir=base, derived=derived_keys(raw))
    except RecursionError:  # (tables nested thousands deep)
        raise ModelError("model_file", str(path), "nests tables or arrays too deeply to be a model file") from None
    check_excitation_files(model)
    _warn_if_implausible(model)
    return model


def check_excitation_files(model: Model) -> None:
    """Read and check every CSV file of ``model``'s excitations now, with the reader of the run
    (:func:`~cablecasing_core.files.read_excitation_table`; ModelError naming
    ``scenario.excitation.<name>.file``, the file and the line): every command that loads a model
    file (``static`` and ``geometry`` as ``simulate``, the FMU's ``model_file``) refuses a bad table
    alike, before any work. (A model built from a dictionary reads them when its scenario's motion
    is built.)"""
    for name, e in model.scenario.get("excitation", {}).items():
        if e["kind"] == "csv":
            read_excitation_table(e["file"], f"scenario.excitation.{name}.file")


def toml_file(path: str | Path, key: str, limit: int, other: str = "") -> dict:
    """The TOML document in ``path``, read as UTF-8 (at most ``limit`` bytes); a :class:`ModelError`
    names ``key`` (the option or field that gave the path) and the file, and says what is wrong
    without quoting the file's content. Only a regular file is read: a FIFO would block the read
    until something writes into it (an FMU's initialisation hung on one), a device is no file."""
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            what = "must be a TOML file, a regular file (not a pipe, a device or a folder)"
            raise ModelError(key, str(path), what + other)
        with open(path, "rb") as fh:
            data = fh.read(limit + 1)
    except OSError as exc:
        raise ModelError(key, str(path), f"must be a readable TOML file ({exc.strerror}){other}") from None
    if len(data) > limit:
        raise ModelError(key, str(path), f"is larger than {limit} bytes: not a TOML file of this program")
    try:
        text = data.decode("utf-8-sig")  # (-sig: a byte-order mark some editors write)
    except UnicodeDecodeError as exc:
        raise ModelError(
            key, str(path), f"must be a UTF-8 text TOML file (byte {exc.start} is not UTF-8: a binary or Latin-1 file?)"
        ) from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:  # (its message gives the line and column, not the content)
        raise ModelError(key, str(path), f"must be valid TOML ({exc}){_given_twice(text, str(exc))}") from None
    except RecursionError:
        raise ModelError(key, str(path), "nests tables or arrays too deeply to be read") from None


def _given_twice(text, message):
    """For tomllib's error of a key given twice (``Cannot overwrite a value (at line 9, column 9)``):
    ``": casing.nu is given twice"``, the dotted key read from the line the error names under the
    table header above it (the key's name only, never a value of the file); else ``""``."""
    found = re.match(r"Cannot overwrite a value \(at line (\d+), column \d+\)", message)
    lines = text.splitlines()
    if not found or not 0 < int(found.group(1)) <= len(lines):
        return ""
    n = int(found.group(1)) - 1
    name = re.match(r"\s*([A-Za-z0-9_.\- ]+?)\s*=", lines[n])  # (bare keys only: a quoted one is not named)
    if not name:
        return ""
    table = next(
        (
            m.group(1)
            for line in reversed(lines[:n])
            if (m := re.match(r"\s*\[+\s*([A-Za-z_][A-Za-z0-9_.\- ]*?)\s*\]+\s*(#.*)?$", line))
        ),
        "",
    )
    dotted = ".".join(p.strip() for p in (table.split(".") if table else []) + name.group(1).split("."))
    return f": {dotted} is given twice (the second time on line {n + 1})"


def _warn_if_implausible(model):
    """A :class:`~cablecasing_core.errors.PlausibilityWarning` for each plausibility warning of a
    model file's or dictionary's routing but the element-length advice (the CLI prints each as one
    line; ``cablecasing geometry`` gives them all). The built-in specimens and a model's
    ``with_overrides`` copies are not checked again."""
    import warnings

    from ..errors import PlausibilityWarning
    from ..structure.route_summary import plausibility_warnings

    for text in plausibility_warnings(model, advice=False):
        warnings.warn(f"{model.source}: {text}", PlausibilityWarning, stacklevel=3)


def default_model() -> Model:
    """The built-in model of the paper's specimen (``model/specimens/default.toml``)."""
    return load_model(None)


def toml_value(text: str):
    """The TOML value written in ``text`` (``0.2``, ``"hertz"``, ``[10.0, 1000.0]``, ...); raises
    ``ValueError`` (tomllib's TOMLDecodeError) when it is not one."""
    return tomllib.loads(f"v = {text}")["v"]
