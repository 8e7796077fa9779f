"""What the demo (examples/demo.py, ``make demo``) checks and draws, without building the FMU: its
FMU check fails beyond the agreement docs/fmu.md gives, and the title of its study figure
(results/study/correlations.png) lies inside the figure."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from cablecasing_core.studies import plots
from cablecasing_core.studies.results_store import StudyResults
from cablecasing_core.studies.sampling import PAPER_BOUNDS

DEMO = Path(__file__).resolve().parents[2] / "examples" / "demo.py"


@pytest.fixture(scope="module")
def demo():
    spec = importlib.util.spec_from_file_location("demo", DEMO)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("said", ["3.1e-05 (casing.B.Fz, over 5000 steps)", "nan (casing.A.Fx, over 5000 steps)"])
def test_the_fmu_check_fails_beyond_the_agreement_of_fmu_outputs_csv(demo, said):
    """It only reported the largest deviation, however large."""
    failed = demo.fmu_failure({demo.DEVIATION: said})
    assert failed.startswith(f"the FMU deviates from the core driven by the same sampled record by {said}"), failed
    assert "they agree to 1e-08 (docs/fmu.md)" in failed
    assert demo.fmu_failure({demo.DEVIATION: "4.2e-09 (casing.B.Fz, over 5000 steps)"}) is None


def test_the_fmu_check_reads_the_summary_of_fmu_check(demo, tmp_path):
    from cablecasing_core.report.runs import fmu_check

    t = np.arange(0.0, 0.0105, 1e-3)
    (tmp_path / "fmu.csv").write_text("time,casing.B.Fz\n" + "".join(f"{x:.9g},1\n" for x in t))
    check = fmu_check(tmp_path / "fmu.csv", 1e-3, 0.01)  # (a constant 1 N: far from the core's force)
    failed = demo.fmu_failure(check)
    said = check[demo.DEVIATION]  # (the one column given, at the ten steps of 1e-3 s in 0.01 s)
    assert said.endswith(" (casing.B.Fz, over 10 steps)") and float(said.split()[0]) > 1e-8, said
    assert check["FMU outputs"] == "fmu.csv"  # (its name, relative to the report's folder: review S, D4)
    assert failed.startswith(f"the FMU deviates from the core driven by the same sampled record by {said}"), failed


def test_the_study_figure_title_of_the_demo_lies_inside_the_figure(monkeypatch, tmp_path):
    """The demo's study (the paper's six parameters, 4 complete base points) has a long p-value note,
    which ran out of the figure at both edges."""
    names = tuple(PAPER_BOUNDS)
    n = 4 * (len(names) + 2)
    lo, hi = np.array([PAPER_BOUNDS[k] for k in names]).T
    rng = np.random.default_rng(0)
    res = StudyResults(
        np.arange(n),
        names,
        lo + (hi - lo) * rng.random((n, len(names))),
        tuple(f"oct{k}" for k in range(1, 10)),
        rng.random((n, 9)),
        np.full(n, "ok"),
        np.full(n, ""),
        np.zeros(n),
        group_size=len(names) + 2,
        n_base=4,
        quantity={"name": "casing.B.Fz", "unit": "N", "what": "RMS in the octave bands of Table 3"},
    )
    seen = {}

    def measure(fig, path):
        fig.tight_layout()  # (as save_figure lays it out)
        seen["title"] = fig._suptitle.get_text()
        seen["box"] = fig._suptitle.get_window_extent(fig.canvas.get_renderer())
        seen["figure"] = fig.bbox

    monkeypatch.setattr(plots, "save_figure", measure)
    plots.plot_correlations(res, tmp_path / "correlations.png")
    assert "(its smallest p-value is 2/4! = 0.083: none can reach 0.05)" in " ".join(seen["title"].split())
    box, figure = seen["box"], seen["figure"]
    assert figure.x0 <= box.x0 and box.x1 <= figure.x1 and figure.y0 <= box.y0 and box.y1 <= figure.y1, (box, figure)
