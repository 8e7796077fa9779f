"""Exceptions raised by cablecasing_core.

Every input error names the offending field (a dotted key path such as ``casing.E``), the value
that was given, and what is allowed, so that a user can fix a model file without reading code.

A message is one line, and quotes a value only as a short excerpt (:func:`excerpt`: at most
:data:`EXCERPT` characters, numpy scalars as plain numbers): a value of 10 kB, a line of a file
that is not a model file or a secret in a TOML file that is not a model never reaches a terminal
or an FMU's log in full.
"""

from __future__ import annotations

import contextlib
import os
import sys
import warnings

#: The longest excerpt of a value (characters) that a message quotes.
EXCERPT = 80
#: The longest path a message quotes whole (characters): a file's path is the value a user needs in full
#: (its end names the file), and real folders are often longer than :data:`EXCERPT`.
PATH_EXCERPT = 1024


def and_joined(items) -> str:
    """Words of a message joined as a sentence lists them: 'a', 'a and b', 'a, b and c'."""
    items = list(items)
    return " and ".join([", ".join(items[:-1]), items[-1]] if len(items) > 1 else items)


def excerpt(value, limit: int = EXCERPT) -> str:
    """``repr(value)`` on one line and cut to ``limit`` characters (``...`` and the full length
    mark a cut; a path, a ``PathLike`` or a one-line string with the path separator, to no fewer than
    :data:`PATH_EXCERPT`); numpy scalars and arrays are shown as the plain numbers they hold (``nan``, not
    ``np.float64(nan)``; ``[]``, not ``array([], dtype=float64)``)."""
    item = getattr(value, "item", None)
    if item is not None and getattr(value, "shape", None) == ():
        value = item()  # a numpy scalar
    elif item is not None and hasattr(value, "tolist") and hasattr(value, "size"):  # a numpy array
        if value.size <= 20:
            value = value.tolist()
        else:  # (not the whole array's text, which may be large)
            value = _Plain(f"{value.size} numbers {repr(value.ravel()[:5].tolist())[:-1]}, ...]")
    text = value if isinstance(value, _Plain) else repr(value)
    text = " ".join(str(text).split("\n")).replace("\r", " ")
    if isinstance(value, os.PathLike) or (isinstance(value, str) and os.sep in value and "\n" not in value):
        limit = max(limit, PATH_EXCERPT)  # (a path: quoted whole up to PATH_EXCERPT)
    if len(text) > limit:
        text = f"{text[: limit - 25]}... ({len(text)} characters)"
    return text


def closest(word, names, n: int = 1) -> list[str]:
    """At most ``n`` of ``names`` closest to ``word``, best first, for a "did you mean ...?" hint:
    the names equal to it but for case first, then ``difflib``'s close matches compared without
    case (a key typed in the wrong case, ``casing.e``, is ``casing.E``, not ``casing.I``, which
    difflib's case-sensitive ratio ranks higher). The one helper of every such hint."""
    import difflib

    word = str(word)
    by_lower = {}
    for name in dict.fromkeys(map(str, names)):
        by_lower.setdefault(name.lower(), []).append(name)
    found = list(by_lower.get(word.lower(), []))
    for low in difflib.get_close_matches(word.lower(), list(by_lower), n=n):
        found += by_lower[low]
    return list(dict.fromkeys(found))[:n]


class _Plain(str):
    """A value shown as it is, without quotes (a description such as ``"array with nan"``)."""


def plain(text: str) -> str:
    """``text`` marked to be shown without quotes as the value of a :class:`ModelError`."""
    return _Plain(text)


class CableCasingError(Exception):
    """Base class of all errors raised by this package."""


#: The value of a :class:`ModelError` that is not shown (an unknown key's value, a file's content).
NOT_SHOWN = _Plain("")


class ModelError(CableCasingError, ValueError):
    """A model file, parameter or scenario that cannot work.

    Parameters
    ----------
    key : str
        Dotted path of the offending field, e.g. ``"casing.d_inner"``.
    value : object
        The value that was given (shown as a short excerpt; :data:`NOT_SHOWN` shows none).
    allowed : str
        Plain-language statement of what is allowed.
    """

    def __init__(self, key, value, allowed):
        self.key = key
        self.value = value
        self.allowed = allowed
        name = excerpt(_Plain(key) if isinstance(key, str) else key, 2 * EXCERPT)
        shown = "" if value is NOT_SHOWN else f" = {excerpt(value)}"
        super().__init__(f"{name}{shown}: {_one_line(allowed)}")


@contextlib.contextmanager
def renamed(names: dict, in_text: bool = False):
    """A :class:`ModelError` raised in the block whose key is one of ``names`` ({key: name}) is raised
    again under the name the caller's user knows it by: a CLI option (``--duration``), an FMU
    parameter (``solver.dt``), a record's column; with ``in_text`` the keys are renamed in what is
    allowed too (``must be at least f_min``). Other errors pass unchanged."""
    try:
        yield
    except ModelError as exc:
        if exc.key not in names:
            raise
        allowed = exc.allowed
        if in_text:
            for key, name in names.items():
                allowed = allowed.replace(key, name)
        raise ModelError(names[exc.key], exc.value, allowed) from None


class SimulationError(CableCasingError, RuntimeError):
    """A time-domain run that cannot continue (blow-up, excessive penetration).

    The message says when (time in s), where (body and node) and what happened.
    """


class RunStopped(BaseException):
    """A time-domain run stopped from outside, between two chunks of its steps
    (:func:`~cablecasing_core.timedomain.engine.stop_runs_on`): the engine is as it was before the
    call. Not an ``Exception``, as ``KeyboardInterrupt`` is not: a study does not record the sample as
    failed, it was stopped with the whole study."""


class InfrastructureError(CableCasingError, RuntimeError):
    """The computing infrastructure failed, not the model: a dask scheduler lost, every worker
    gone, no progress within the timeout. Nothing of the model is wrong; the same command resumes
    (the command line exits with status 3)."""


def _one_line(text) -> str:
    return " ".join(str(text).splitlines())


#: The longest excerpt of an unexpected exception's message that :func:`internal_error_text` quotes.
INTERNAL_EXCERPT = 200


def internal_error_text(exc: BaseException, report: str = "", note: str = "") -> str:
    """What a host shows of an unexpected exception ``exc`` (a bug of this package), in one line:
    ``Type: message (a bug; please report it<report>; CABLECASING_TRACEBACK=1 shows the traceback)<note>``,
    the message on one line and cut to :data:`INTERNAL_EXCERPT` characters (:func:`excerpt`); ``report``
    says what to send with it (the command line's ``" with the command"``), ``note`` what the host adds
    (an FMU's parameters set). A :class:`MemoryError` is no bug: its line says the run needs more memory
    than the machine has free. With the environment variable ``CABLECASING_TRACEBACK`` set, the
    traceback follows on the next lines. The one text of the command line's ``internal error`` and of
    the FMU's log."""
    import os
    import traceback

    if isinstance(exc, MemoryError):
        text = (
            "out of memory (MemoryError): the run needs more memory than this machine has free; fewer elements "
            f"(geometry.n_elements) need less (docs/model_file.md, Limits){note}"
        )
    else:
        text = (
            f"{type(exc).__name__}: {excerpt(_Plain(str(exc)), INTERNAL_EXCERPT)} (a bug; please report it{report}; "
            f"CABLECASING_TRACEBACK=1 shows the traceback){note}"
        )
    if os.environ.get("CABLECASING_TRACEBACK"):
        text += "\n" + "".join(traceback.format_exception(type(exc), exc, exc.__traceback__)).rstrip("\n")
    return text


class ModelWarning(UserWarning):
    """A valid value that is physically absurd, or a combination of values whose result may be
    meaningless; the message says why."""


class SolverWarning(ModelWarning):
    """What a time-domain run's step loop did not achieve (a contact Newton that did not converge,
    a step whose estimated local error stays above ``contact.event_tolerance``, a contact that made
    energy): the run went on, and the message says where and how much. A :class:`ModelWarning`,
    filterable on its own."""


class ModelPropertyWarning(ModelWarning):
    """A property of the model, not of a run (what its file's values mean, its static state): said
    once per process for the same words (:func:`warn_once_per_process`), not again by every command
    that builds the same model, every seed of an ensemble, or an ensemble's ``--against`` model. A
    :class:`ModelWarning`, filterable on its own."""


#: The messages :func:`warn_once_per_process` has said in this process (by their key).
_SAID_ONCE: set[str] = set()


def _filter_action(text, category, frame, filters=None):
    """The action the warnings filters (``filters``, default the process's) give ``text`` of
    ``category`` warned at ``frame`` (or the default action), matched as warnings.warn matches them:
    message, category, module, line."""
    module = frame.f_globals.get("__name__", "<string>") if frame is not None else "sys"
    lineno = frame.f_lineno if frame is not None else 1
    for action, msg, cat, mod, ln in warnings.filters if filters is None else filters:
        if (
            (msg is None or msg.match(text))
            and issubclass(category, cat)
            and (mod is None or mod.match(module))
            and (ln == 0 or ln == lineno)
        ):
            return action
    return warnings.defaultaction


def warn_once_per_process(text, category=None, stacklevel=2, key=None, filters=None):
    """``warnings.warn(text, category, stacklevel)`` unless the message ``key`` (default ``text``)
    was said before in this process. The warnings filters still decide: under "always" (a test's
    ``pytest.warns``, a study's sample recording its warnings to say them once itself) or "error"
    the message is warned every time and not counted as said; under "ignore" it is not said; under
    the other actions ("default", "module", "once") it is said the first time only, whatever filters
    other code swapped in meanwhile (``catch_warnings`` resets Python's own record of what was
    said, so a command that runs the model in several such blocks said it again in each)."""
    category = ModelPropertyWarning if category is None else category
    key = text if key is None else key
    try:
        frame = sys._getframe(stacklevel)
    except ValueError:
        frame = None
    action = _filter_action(text, category, frame, filters)
    if action in ("default", "module", "once"):
        if key in _SAID_ONCE:
            return
        _SAID_ONCE.add(key)
    warnings.warn(text, category, stacklevel=stacklevel + 1)


#: The plausibility warnings of a routing (``structure.route_summary.plausibility_warnings``, which
#: ``load_model`` issues) are :class:`ModelWarning` under their own name.
PlausibilityWarning = ModelWarning
