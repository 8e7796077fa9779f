"""The report's RMS table (review C, finding 11): the RMS of a support force with its mean (total)
and without it (dynamic, what the band levels and the PSD hold), and the mean."""

import re
import types
from pathlib import Path

import numpy as np
import pytest

from cablecasing_core.report import figures, page
from cablecasing_core.report.runs import Variant


def test_the_rms_table_gives_the_mean_the_total_and_the_dynamic_rms(tmp_path):
    """Review C, 11: the table's "RMS" of casing.B.Fz included its mean (0.896 N total, 0.883 N
    without the mean of 0.153 N), the band levels do not. A force c + A sin(2 pi 50 t) over 47
    whole periods after the skip: mean c, RMS total sqrt(c^2 + A^2/2), RMS dynamic A/sqrt(2) (to
    round-off: 1e-12)."""
    t = np.arange(10001) * 1e-4
    c, A = -0.153, 1.25
    forces = {
        "casing.B.Fx": 0 * t + 2.0,
        "casing.B.Fy": A * np.cos(2 * np.pi * 50 * t),
        "casing.B.Fz": c + A * np.sin(2 * np.pi * 50 * t),
    }
    res = types.SimpleNamespace(time=t, support_force=forces.__getitem__)
    v = Variant("drive", "with the cable drive", None, Path("records/drive.npz"), result=res)
    rows = figures.rms_table([v], tmp_path / "rms.csv", 0.06)
    mean, total, dynamic = rows[0][1]["casing.B.Fz"]
    assert mean == pytest.approx(c, rel=1e-12)
    assert total == pytest.approx(np.sqrt(c**2 + A**2 / 2), rel=1e-12)
    assert dynamic == pytest.approx(A / np.sqrt(2), rel=1e-12)
    assert rows[0][1]["casing.B.Fx"][2] == pytest.approx(0.0, abs=1e-12)  # (a static force: no dynamic RMS)
    lines = (tmp_path / "rms.csv").read_text().splitlines()
    assert lines[0] == "variant,record,output,mean [N],rms total [N],rms dynamic [N]"
    assert [float(x) for x in lines[3].split(",")[3:]] == [mean, total, dynamic]  # (repr: exact)
    html = "\n".join(page._rms_parts(rows, {"skip": 0.06}))
    assert "<th>RMS total (N)</th><th>RMS dynamic (N)</th>" in html
    fz = re.search(r"<td>casing.B.Fz</td>(.*?)</tr>", html)[1]
    assert re.findall(r"<td[^>]*>(.*?)</td>", fz) == [page._g(x, 6) for x in (mean, total, dynamic)]
    assert "the band levels and the PSD remove the mean too" in html
