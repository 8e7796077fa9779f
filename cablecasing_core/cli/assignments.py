"""The model of the command line: the MODEL argument (a TOML file or a built-in specimen) and the
``KEY=VALUE`` model changes (``--set`` of ``simulate``, ``ensemble``, ``modes``, ``trfam``,
``geometry`` and ``static``, ``--against`` of ``ensemble``): a dotted model key of the schema and a
TOML value. A table (``contact``) is refused,
naming it (its keys are set one by one: ``Model.with_overrides``), and so is a key given twice. An
error echoes a value as it was typed (``true``, ``{stiffness=1e5}``), not in Python's spelling."""

from __future__ import annotations

from ..errors import NOT_SHOWN, ModelError, excerpt, plain, renamed


def add_model_argument(parser, settable=False):
    """The optional MODEL argument of a command (read by :func:`model_argument`); ``settable`` adds
    ``--set KEY=VALUE`` (model changes, e.g. ``geometry.n_elements=70`` for a mesh check without a
    copied model file), given to :func:`model_argument` as ``args.set``."""
    from .helptext import ASSIGNMENT_HELP

    parser.add_argument(
        "model",
        nargs="?",
        metavar="MODEL",
        default=None,
        help="model TOML file or built-in specimen name, e.g. installed (default: the built-in specimen)",
    )
    if settable:
        parser.add_argument(
            "--set", action="append", default=[], metavar="KEY=VALUE", help="model change; " + ASSIGNMENT_HELP
        )


def model_argument(path, sets=()):
    """The model of the MODEL argument ``path`` (None: the built-in specimen) with the ``--set``
    changes ``sets`` (:func:`with_assignments`); a file that cannot be read is named as the argument
    (``MODEL = 'nope.toml': ...``)."""
    from ..model import load_model

    with renamed({"model_file": "MODEL"}):
        model = load_model(path)
    return with_assignments(model, "--set", sets)


def assignment(flag, text):
    """``(key, value)`` of one ``KEY=VALUE`` given to ``flag``; VALUE is read as a TOML value (a bare
    word as text)."""
    from ..model.load import toml_value

    key, sep, value = text.partition("=")
    if not sep or not key.strip():
        raise ModelError(flag, text, "must be KEY=VALUE with a dotted model key, e.g. contact.friction=0.2")
    try:
        return key.strip(), toml_value(value.strip())
    except ValueError:  # (TOMLDecodeError) a bare word
        return key.strip(), value.strip()


def typed(texts):
    """``{key: VALUE}`` of ``KEY=VALUE`` texts: each value as it was typed, to be echoed in a message
    (:func:`~cablecasing_core.errors.plain`: ``true``, ``{stiffness=1e5}``, not ``True``,
    ``{'stiffness': 100000.0}``)."""
    out = {}
    for text in texts:
        key, _, value = text.partition("=")
        out.setdefault(key.strip(), plain(value.strip()))
    return out


def assignments(flag, texts):
    """``{key: value}`` of the ``KEY=VALUE`` texts of ``flag`` (:func:`assignment`). A key given
    twice is refused, naming both values as typed, as a TOML file refuses a key given twice (the
    first value would never be checked)."""
    out, shown = {}, {}
    for text in texts:
        key, value = assignment(flag, text)
        said = typed([text])[key]
        if key in out:
            raise ModelError(
                f"{flag} {key}",
                NOT_SHOWN,
                f"is given twice ({excerpt(shown[key])} and {excerpt(said)}): give each key once",
            )
        out[key], shown[key] = value, said
    return out


def with_assignments(model, flag, texts):
    """``model`` with the ``KEY=VALUE`` changes ``texts`` of ``flag`` (validated as a model file's
    keys; an error names the flag, the key, the value as typed and what is allowed; a key given
    twice is refused, :func:`assignments`)."""
    shown = typed(texts)
    return with_changes(model, {key: (flag, value, shown[key]) for key, value in assignments(flag, texts).items()})


def with_changes(model, changes, check=None):
    """``model`` with ``changes`` ({key: (flag, value)} or (flag, value, the value as typed)) applied
    and validated. A refused value is named by the flag that gave it (``--set casing.E = -1: ...``),
    as typed when it is the value of the key refused; a key the model file gives that the changes
    make invalid (its random band above the Nyquist frequency of a ``--set scenario.dt``) is named
    as the change that did it, with the model file's value it conflicts with. ``check(model)``, if
    given, is a check of the changed model beyond its keys' (``ensemble``'s
    :func:`~cablecasing_core.studies.evaluators.check_model_runs`: a tension above the casing's
    buckling load): what it refuses is named the same way (the model without changes is checked
    too, its error as it is)."""
    if not changes:
        if check is not None:
            check(model)
        return model
    checked = False  # (whether the keys passed and the check refused)
    try:
        changed = model.with_overrides({key: change[1] for key, change in changes.items()})
        if check is not None:
            checked = True
            check(changed)
        return changed
    except ModelError as exc:
        given = next((k for k in changes if _same_key(str(exc.key), k)), None)
        if given is not None:
            value = exc.value
            if exc.key == given and exc.value is not NOT_SHOWN:
                value = _shown(changes[given])
            raise ModelError(f"{changes[given][0]} {exc.key}", value, exc.allowed) from None
        raise _conflict(model, changes, exc, check, checked) from None


def _shown(change):
    """The value of a change (flag, value[, typed]) as it is echoed: as typed when known."""
    return change[2] if len(change) > 2 else change[1]


def _same_key(refused, key):
    """Whether the refused key is the changed ``key``, a component of it (``band[1]``) or the vector
    it is a component of (``loads.gravity`` of ``loads.gravity.z``)."""
    return refused == key or refused.startswith((key + ".", key + "[")) or key.startswith(refused + ".")


def _conflict(model, changes, exc, check=None, checked=False):
    """The error ``exc`` of a key of the model that ``changes`` did not set, named as the change(s)
    that make it fail alone (all of them if none does; the model's own error, as it is, when it
    fails ``check`` without them, ``checked``: ``exc`` is the check's): the value of the model it
    conflicts with and what is allowed; for a time step, the largest that the model's excitations
    allow."""
    if checked:
        try:
            check(model)
        except ModelError as own:  # (the model fails without the changes: none of them is to blame)
            return own

    def refused(key):
        try:
            changed = model.with_overrides({key: changes[key][1]})
            if checked:
                check(changed)
        except ModelError:
            return True
        return False

    culprits = [k for k in changes if refused(k)] or list(changes)
    allowed = exc.allowed
    if culprits == ["scenario.dt"]:
        allowed = _step_rule(model, changes["scenario.dt"][1]) or allowed
    shown = "" if exc.value is NOT_SHOWN else f" = {excerpt(exc.value)}"
    what = f"conflicts with {exc.key}{shown} of the model {model.source}: {allowed}"
    if len(culprits) == 1:
        return ModelError(f"{changes[culprits[0]][0]} {culprits[0]}", _shown(changes[culprits[0]]), what)
    named = ", ".join(f"{changes[k][0]} {k}={excerpt(_shown(changes[k]))}" for k in culprits)
    return ModelError(named, NOT_SHOWN, what)


def _step_rule(model, dt):
    """What the excitations of ``model`` allow of a time step ``dt`` (s) that they refuse (the
    message ``--dt`` gives: the largest step allowed), or None."""
    from ..timedomain.scenario import ScenarioMotion

    try:
        ScenarioMotion(model, dt)
    except ModelError as exc:
        return exc.allowed if exc.key == "dt" else None
    return None
