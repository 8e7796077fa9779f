"""The model of the command line: the MODEL argument (a TOML file or a built-in specimen) and the
``KEY=VALUE`` model changes (``--set`` of ``simulate``, ``ensemble``, ``modes``, ``trfam``,
``geometry`` and ``static``, ``--against`` of ``ensemble``): a dotted model key of the schema and a
TOML value. A table (``contact``) is refused,
naming it (its keys are set one by one: ``Model.with_overrides``), and so is a key given twice. An
error echoes a value as it was typed (``true``, ``{stiffness=1e5}``), not in Python's spelling; whose
fault a refusal is (the change, or the model's key it conflicts with) is the core's rule
(:func:`~cablecasing_core.model.changes.with_changes`), which the FMU's parameters share."""

from __future__ import annotations

from ..errors import NOT_SHOWN, ModelError, excerpt, plain, renamed
from ..model.changes import with_changes


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
