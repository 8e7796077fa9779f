"""``KEY=VALUE`` model changes on the command line (``--set`` of ``simulate`` and ``ensemble``,
``--against`` of ``ensemble``): a dotted model key of the schema and a TOML value."""

from __future__ import annotations

from ..errors import ModelError


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


def with_assignments(model, flag, texts):
    """``model`` with the ``KEY=VALUE`` changes ``texts`` of ``flag`` (validated as a model file's
    keys; an error names the flag, the key, the value and what is allowed)."""
    changes = dict(assignment(flag, t) for t in texts)
    if not changes:
        return model
    try:
        return model.with_overrides(changes)
    except ModelError as exc:
        raise ModelError(f"{flag} {exc.key}", exc.value, exc.allowed) from None
