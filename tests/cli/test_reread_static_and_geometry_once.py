"""``static`` assembles each body once, for its solve, the casing's buckling load and the end forces
of a tension without contact; ``geometry`` builds no centerline for the clips' nodes beside the one
the casing's buckling load is assembled on. What they print is checked against closed forms."""

import json
from pathlib import Path

import numpy as np
import pytest

import cablecasing_core as cc
from cablecasing_core.cli import main
from cablecasing_core.structure import geometry as geometry_module
from cablecasing_core.timedomain import body_storage

T = 10.0  # N, the cable's tension (the casing's compression)
INSTALLATION = Path(__file__).resolve().parents[2] / "examples" / "installation.toml"


@pytest.fixture(scope="module")
def straight_tensioned(tmp_path_factory):
    """The built-in specimen on a straight 0.85 m route (both ends clamped) under T, as a file."""
    model = cc.load_model().with_overrides(
        {
            "geometry.points": [[0.0, 0.0, 0.0], [0.85, 0.0, 0.0]],
            "geometry.curve": "polyline",
            "loads.cable_tension": T,
            "contact.friction_law": "regularized",
        }
    )
    path = tmp_path_factory.mktemp("static") / "straight.toml"
    path.write_text(model.to_toml())
    return path, model


def test_static_without_contact_assembles_each_body_once(straight_tensioned, monkeypatch, capsys):
    path, model = straight_tensioned
    built = []
    assemble = body_storage.time_domain_system

    def counted(m, name):
        built.append(name)
        return assemble(m, name)

    monkeypatch.setattr(body_storage, "time_domain_system", counted)
    assert main(["static", str(path), "--no-contact"]) == 0
    assert sorted(built) == ["cable", "casing"]  # (before: five, the solve's two, buckling's, the end forces' two)
    text = capsys.readouterr().out
    # a straight body holds a fixed prestress without moving: its end elements carry N0 itself
    assert f"the end elements carry casing {-T:g} and {-T:g} N, cable {T:g} and {T:g} N (tension positive)" in text
    built.clear()
    assert main(["static", str(path), "--no-contact", "--json"]) == 0
    assert sorted(built) == ["cable", "casing"]
    out = json.loads(capsys.readouterr().out)
    c = model.data["casing"]
    P_cr = 4 * np.pi**2 * c["E"] * c["I"] / 0.85**2  # N, Euler's load of a column clamped at both ends
    # 35 cubic beam elements: the load of the first mode to ~1e-5; 1e-3 leaves that a margin
    assert out["buckling"]["casing"]["load_N"] == pytest.approx(P_cr, rel=1e-3)


def _centerline_builds(monkeypatch):
    """A list that counts each centerline built (``geometry.centerline_of``'s two ways)."""
    builds = []
    for name in ("build_centerline", "centerline_from_route"):
        real = getattr(geometry_module, name)
        monkeypatch.setattr(geometry_module, name, lambda *a, _real=real, **k: builds.append(1) or _real(*a, **k))
    return builds


def test_geometry_builds_no_centerline_for_the_clips_nodes(monkeypatch, capsys):
    clipped = cc.load_model(INSTALLATION)
    data = clipped.to_dict()
    del data["casing"]["clip"]
    bare = cc.model_from_dict(data)
    counts = {}
    for name, model in (("clipped", clipped), ("bare", bare)):
        monkeypatch.setattr("cablecasing_core.cli.geometry.model_argument", lambda _path, _sets=(), _m=model: _m)
        builds = _centerline_builds(monkeypatch)
        assert main(["geometry", "model.toml", "--json"]) == 0
        counts[name] = len(builds)
        out = json.loads(capsys.readouterr().out)
    monkeypatch.undo()
    assert counts["clipped"] == counts["bare"] > 0  # (the clips' nodes come from the casing as built)
    assert out["clips"] == []
    monkeypatch.setattr("cablecasing_core.cli.geometry.model_argument", lambda _path, _sets=(): clipped)
    assert main(["geometry", "model.toml", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    # geometry.nodes_at_clips (true by default) puts a node at each clip's at: it acts there
    at = [c["at"] for c in clipped.data["casing"]["clip"]]
    assert [c["at_m"] for c in out["clips"]] == at
    assert [c["node_s_m"] for c in out["clips"]] == pytest.approx(at, abs=1e-12)  # (the spans' ends, rounded)
    # with it false a segments route is cut into elements of equal arc length: a clip acts at the node nearest to it
    data = clipped.to_dict()
    data["geometry"]["nodes_at_clips"] = False
    nearest = cc.model_from_dict(data)
    monkeypatch.setattr("cablecasing_core.cli.geometry.model_argument", lambda _path, _sets=(): nearest)
    assert main(["geometry", "model.toml", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    n, L = nearest.geometry["n_elements"], out["length_m"]
    s = np.linspace(0.0, L, n + 1)
    assert out["clips"] == [{"at_m": a, "node_s_m": float(s[round(a * n / L)])} for a in at]
