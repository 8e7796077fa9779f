"""``modes`` names the rigid motions a body's supports and mounts leave free when no load acts (its
0 Hz modes), as the loads check names them when it refuses the same mounts under gravity (review AN,
B2: a casing on isolators without torsional stiffness listed ``1  0.0001`` and nothing else)."""

import warnings

import numpy as np
import pytest

from cablecasing_core import load_model, natural_frequencies
from cablecasing_core.cli import main
from cablecasing_core.errors import ModelError
from cablecasing_core.structure.support_check import free_motions

# A straight casing of 0.6 m along x (Table 2's section) on isolators at both ends: ROT is their
# rotational stiffness [torsional, bending, bending] (N.m/rad); the translations are held stiffly.
CASING = """
[geometry]
curve = "polyline"
n_elements = 12
points = [[0.0, 0.0, 0.0], [0.6, 0.0, 0.0]]

[casing]
E = 5.0e9
nu = 0.3
rho = 4850.0
d_outer = 0.0095
d_inner = 0.004
I = 2.7261e-10
alpha = 2.0
beta = 4.23e-5
loss_factor = 0.05
supports = {{ A = "{A}", B = "{B}" }}
{isolators}
[loads]
gravity = {gravity}
"""

ISOLATORS = """
[casing.isolator.A]
stiffness = [1.0e6, 1.0e6, 1.0e6]
rotational_stiffness = {rot}
[casing.isolator.B]
stiffness = [1.0e6, 1.0e6, 1.0e6]
rotational_stiffness = {rot}
"""


def model_file(tmp_path, A="isolator", B="isolator", rot="[0.0, 50.0, 50.0]", gravity="[0.0, 0.0, 0.0]"):
    tmp_path.mkdir(exist_ok=True)
    isolators = ISOLATORS.format(rot=rot) if "isolator" in (A, B) else ""
    path = tmp_path / "casing.toml"
    path.write_text(CASING.format(A=A, B=B, isolators=isolators, gravity=gravity))
    return path


def warnings_of(capsys, path):
    assert main(["modes", str(path), "--count", "3"]) == 0
    return [line for line in capsys.readouterr().err.splitlines() if "rigid" in line]


def test_a_twist_left_free_is_named_and_is_the_0_hz_mode(tmp_path, capsys):
    path = model_file(tmp_path)
    said = warnings_of(capsys, path)
    assert len(said) == 1 and said[0].startswith("cablecasing: warning: the casing of ")
    # the twist about the casing's own axis, the x axis through its line (y = z = 0)
    assert "free in 1 rigid motion: a rotation about [1, 0, 0] through [0.3, 0, 0] m" in said[0]
    assert "its first mode is rigid at 0 Hz" in said[0]
    # the same, independently: one mode at 0 Hz (rounding: below 1e-3 Hz, where the first elastic
    # mode of these pins lies at ~10 Hz), the next elastic
    f = natural_frequencies(load_model(path), "casing", 2)
    assert f[0] < 1e-3 and f[1] > 1.0
    # and the loads check refuses the same mounts under gravity, naming the same motion
    with pytest.raises(ModelError, match=r"free in a rotation about \[1, 0, 0\] through \[0.3, 0, 0\] m"):
        load_model(model_file(tmp_path, gravity="[0.0, 0.0, -9.81]"))


def test_a_floating_body_has_six_and_a_held_one_none(tmp_path, capsys):
    said = warnings_of(capsys, model_file(tmp_path, A="free", B="free"))
    assert len(said) == 1 and "free in all six rigid motions" in said[0] and "first 6 modes are rigid" in said[0]
    f = natural_frequencies(load_model(tmp_path / "casing.toml"), "casing", 7)
    assert np.all(f[:6] < 1e-3) and f[6] > 1.0  # (the six at 0 Hz to rounding, then the first bending mode)
    assert warnings_of(capsys, model_file(tmp_path, rot="[5.0, 50.0, 50.0]")) == []  # (held: no warning)
    # A clamped end holds all six: no warning, and no 0 Hz mode (the first is the cantilever's bending,
    # 1.875^2/(2 pi) sqrt(EI/(rho A L^4)) = 3.4 Hz for these 0.6 m: 1 Hz is far from both). "always": the
    # free/free warning above came from the same line of the CLI, so the default filter would hide a repeat.
    clamped = model_file(tmp_path / "clamped", A="clamped", B="free")
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        assert warnings_of(capsys, clamped) == []
    assert free_motions(load_model(clamped), "casing") == []
    assert natural_frequencies(load_model(clamped), "casing", 1)[0] > 1.0
