"""``--set KEY=VALUE`` on the commands that read a model without running it (``modes``, ``trfam``,
``geometry``, ``static``): each gives what the model file with that key changed gives, so a mesh
or material check needs no copied file (docs/model_file.md, "Your own model")."""

import json

import pytest

from cablecasing_core.cli import main


def _run(capsys, argv):
    assert main(argv) == 0
    return capsys.readouterr().out


def _file_with(tmp_path, old, new):
    """The built-in default specimen's TOML with the line ``old`` replaced by ``new`` by hand (the
    route the --set must equal: an independent path through the loader)."""
    import importlib.resources as ir

    text = (ir.files("cablecasing_core.model") / "specimens" / "default.toml").read_text()
    assert text.count(old) == 1, old
    p = tmp_path / "changed.toml"
    p.write_text(text.replace(old, new))
    return str(p)


@pytest.mark.parametrize(
    "command",
    [
        ["modes", "--json", "--count", "4"],
        ["geometry", "--json"],
        ["static", "--json"],
        ["trfam", "--fmin", "10", "--fmax", "30", "--df", "10"],
    ],
)
def test_set_gives_what_the_changed_file_gives(tmp_path, capsys, command):
    by_set = _run(capsys, [*command, "--set", "geometry.n_elements=40"])
    by_file = _run(capsys, [command[0], _file_with(tmp_path, "n_elements = 35", "n_elements = 40"), *command[1:]])
    assert by_set == by_file
    assert by_set != _run(capsys, command)  # (the change does change the answer: 40 elements, not 35)


def test_set_refuses_a_bad_value_naming_the_flag_and_a_clash_with_no_contact(capsys):
    assert main(["modes", "--set", "casing.E=-1"]) != 0
    assert "--set casing.E = -1" in capsys.readouterr().err
    assert main(["static", "--no-contact", "--set", "contact.enabled=true"]) != 0
    err = capsys.readouterr().err
    assert "--set contact.enabled" in err and "--no-contact" in err, err


def test_modes_json_with_set_reads_as_json(capsys):
    out = json.loads(_run(capsys, ["modes", "--json", "--count", "2", "--set", "casing.E=2e9"]))
    base = json.loads(_run(capsys, ["modes", "--json", "--count", "2"]))
    # the casing's bending frequencies scale as sqrt(E) (Euler-Bernoulli; the cable's do not move)
    from cablecasing_core.model import default_model

    e0 = default_model().data["casing"]["E"]
    ratio = out["casing"][0] / base["casing"][0]
    assert ratio == pytest.approx((2e9 / e0) ** 0.5, rel=0.02)  # (2 %: the casing's prestress K_G does not scale)
    assert out["cable"] == base["cable"]
