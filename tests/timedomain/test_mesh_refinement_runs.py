"""``benchmarks/mesh_refinement.py`` (docs/time_domain.md, "The mesh") runs against the present API
and writes its cache: two meshes, two seeds, a short record; on a built-in specimen (``--specimen``)
and on a model file (``--model``)."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "mesh_refinement.py"


@pytest.mark.slow
def test_the_mesh_refinement_prints_its_figures_and_writes_its_cache(tmp_path):
    cache = tmp_path / "mr.json"
    cmd = [sys.executable, str(BENCH), "--specimen", "default", "--seeds", "2", "--elements", "35", "70"]
    cmd += ["--modal-elements", "35", "70", "140", "--duration", "0.15", "--workers", "1", "--json", str(cache)]
    cmd += ["--fresh"]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    values = dict(line.split(": ", 1) for line in out.splitlines() if ": " in line)
    for name in ("band_mean_N_default_35", "band_mean_N_default_70", "normal_work_share_default_70"):
        assert name in values, name
    assert len(values["band_mean_N_default_35"].split()) == 9  # (the nine bands of Table 3)
    json.loads(cache.read_text())  # (the cache is whole JSON: written atomically)
    # the casing's natural frequencies converge at second order in the element length (the straight
    # elements' chord of the curved route; docs/time_domain.md, "The mesh"): the observed order from
    # 35, 70 and 140 elements in octaves 1-6 (measured 2.00-2.07)
    for band in ("oct1", "oct2", "oct3", "oct4", "oct5", "oct6"):
        order = float(values[f"freq_change_default_casing_{band}"].split("order 35_70_140:")[1])
        assert order == pytest.approx(2.0, abs=0.1), band


# A user's model file (``--model``): the built-in specimen's sections on a straight 0.85 m route (a
# polyline: its nodes at k * 0.85 / n m exactly), two clips, a short record. Few elements, so it runs
# in seconds.
STRAIGHT_CLIPPED = """
[geometry]
curve = "polyline"
n_elements = 10
nodes_at_clips = {on_nodes}
points = [[0.0, 0.0, 0.0], [0.85, 0.0, 0.0]]

[casing]
E = 5.0e9
nu = 0.3
rho = 4850.0
d_outer = 0.0095
d_inner = 0.004
I = 2.7261e-10
alpha = 11.1
beta = 4.23e-5
loss_factor = 0.05
supports = {{ A = "clamped", B = "clamped" }}

[[casing.clip]]
at = 0.30
stiffness = [2.0e4, 5.0e4, 5.0e4]
damping = 8.0

[[casing.clip]]
at = 0.55
stiffness = [2.0e4, 5.0e4, 5.0e4]
damping = 8.0

[cable]
E = 5.5e10
nu = 0.3
rho = 7850.0
d = 0.003
alpha = 5.0
beta = 2.0e-5
loss_factor = 0.02
supports = {{ A = "clamped", B = "clamped" }}

[scenario]
duration = 0.15
dt = 1.0e-5
ramp = 0.01

[scenario.excitation.casing_random]
target = "casing.A.z"
kind = "random"
rms = 5.0
band = [10.0, 1000.0]
"""
LENGTH = 0.85  # m, the polyline's length
CLIPS_AT = (0.30, 0.55)  # m


def _run_model(model, *extra):
    cmd = [sys.executable, str(BENCH), "--model", str(model), "--workers", "1", *extra]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return dict(line.split(": ", 1) for line in out.splitlines() if ": " in line)


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore::cablecasing_core.ModelWarning")  # (the loader's: the clips are off their nodes)
def test_the_mesh_refinement_runs_on_a_model_file(tmp_path):
    import numpy as np

    import cablecasing_core as cc
    from cablecasing_core.studies.evaluators import default_evaluate

    model = tmp_path / "straight_clipped.toml"
    model.write_text(STRAIGHT_CLIPPED.format(on_nodes="false"))
    values = _run_model(
        model, "--seeds", "2", "--elements", "10", "20", "--modal-elements", "10", "20", "40", "--duration", "0.15"
    )
    assert (tmp_path / "straight_clipped_mesh_refinement.json").exists()  # (the cache beside the file)
    label = "straight_clipped"

    # the modal part, against cc.natural_frequencies of the file at the same meshes: the modes of the
    # finest (40) below 5680 Hz matched by index, as many as the coarsest (10) has in all
    for body in ("casing", "cable"):
        f = {
            n: np.asarray(cc.natural_frequencies(cc.load_model(model).with_overrides({"geometry.n_elements": n}), body))
            for n in (10, 20, 40)
        }
        counts = values[f"modes_below_5680hz_{label}_{body}"]
        assert counts == " ".join(f"{n}:{np.count_nonzero(f[n] <= 5680.0)}" for n in (10, 20, 40))
        k = min(np.count_nonzero(f[40] <= 5680.0), len(f[10]))
        if k < np.count_nonzero(f[40] <= 5680.0):
            assert values[f"modes_compared_{label}_{body}"].startswith(f"{k} ")
        for n in (10, 20):
            printed = float(values[f"freq_max_abs_rel_change_{label}_{body}_{n}"].split()[0])
            expected = np.max(np.abs(f[n][:k] - f[40][:k]) / f[40][:k])
            assert printed == pytest.approx(expected, abs=6e-6)  # (printed to 5 decimals)

    # the band part: seeds 1 and 2 at 10 elements, each the package's own evaluator of that member
    # (default_evaluate with the record's boxcar window and the CLI's skip), their mean
    ev = [
        default_evaluate(
            {"geometry.n_elements": 10, "scenario.excitation.casing_random.seed": s},
            model_file=str(model),
            window="boxcar",
        )
        for s in (1, 2)
    ]
    mean = [0.5 * (ev[0][f"oct{b}"] + ev[1][f"oct{b}"]) for b in range(1, 10)]
    printed = [float(x) for x in values[f"band_mean_N_{label}_10"].split()]
    assert printed == pytest.approx(mean, rel=1e-3)  # (printed to 4 significant digits)
    assert f"band_rel_diff_{label}_10_vs_20" in values
    assert values[f"band_rel_diff_seeds_{label}_10_vs_20"] == "2"

    # the clips: with equal elements each acts at the nearest node k * L / n, a different place per mesh
    for i, at in enumerate(CLIPS_AT):
        row = dict(x.split(":") for x in values[f"clip_node_offset_mm_{label}_{i}"].split(" (")[0].split())
        for n in (10, 20, 40):
            h = LENGTH / n
            assert float(row[str(n)]) == pytest.approx(1e3 * (round(at / h) * h - at), abs=6e-4)  # (3 decimals)
    assert values[f"clips_stay_across_meshes_{label}"].startswith("false")

    # with geometry.nodes_at_clips = true every clip acts at its at on every mesh
    model.write_text(STRAIGHT_CLIPPED.format(on_nodes="true"))
    values = _run_model(model, "--elements", "10", "20", "--modal-elements", "40", "--no-modal", "--no-bands")
    for i in range(2):
        row = values[f"clip_node_offset_mm_{label}_{i}"].split(" (")[0].split()
        assert [abs(float(x.split(":")[1])) for x in row] == [0.0, 0.0, 0.0]
    assert values[f"clips_stay_across_meshes_{label}"].startswith("true")
