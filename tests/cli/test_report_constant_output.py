"""Review V, D12: a model whose casing.B.Fz stays 0 (the straight casing knocked in y): the report's
PSD has nothing to draw on its log axis; it draws nothing of that series, without matplotlib's
"Data has no positive values" warning (which named no figure), and the figure and the page say so."""

import warnings
from pathlib import Path

import numpy as np

import cablecasing_core as cc
from cablecasing_core.report import figures, page
from cablecasing_core.report.runs import Variant

ROOT = Path(__file__).resolve().parents[2]


def test_a_constant_output_is_not_drawn_on_the_psds_log_axis(tmp_path):
    model = cc.load_model(str(ROOT / "examples" / "straight_casing.toml"))
    v = Variant("scenario", "the model's scenario", model, tmp_path / "scenario.npz")
    v.result = cc.simulate(model, duration=0.1)
    assert not np.any(v.result.support_force("casing.B.Fz"))  # (the knock in y gives no force in z at B)
    info = {"seeds": [1], "duration": 0.1, "dt": 1e-5, "skip": 0.05}
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # (matplotlib's warning of a log axis without positive data)
        drawn = figures.psd_figure([v], tmp_path / "psd.png", 0.05, info)
    assert drawn["constant"] == ["casing.B.Fz (the model's scenario)"] and drawn["from_hz"] is None
    assert (tmp_path / "psd.png").stat().st_size > 0
    note = page.psd_note([v], info)
    assert page._e("casing.B.Fz (the model's scenario)") + " is constant after the skip" in note
    assert not figures.constant(v.result.support_force("casing.B.Fy"))  # (what the knock does move)
