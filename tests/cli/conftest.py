"""Fixtures shared by the command line's tests."""

import pytest


@pytest.fixture
def stubbed(monkeypatch):
    """write_report with its time-domain runs and the figures drawn from them stubbed (each stub
    writes its file, so that the run has files to move in); the modes, parameters and TRFAM real."""
    from cablecasing_core import report
    from cablecasing_core.files import write_text
    from cablecasing_core.report import figures, page

    monkeypatch.setattr(report, "run_variant", lambda *a, **k: None)
    for name in ("time_figure", "scalogram_figure", "contact_figures", "band_figure", "psd_figure"):
        monkeypatch.setattr(figures, name, lambda *a, **k: None)
    monkeypatch.setattr(figures, "apparent_mass_figure", lambda *a, **k: None)
    monkeypatch.setattr(figures, "net_table", lambda vs, path: write_text(path, "stub\n"))
    monkeypatch.setattr(figures, "rms_table", lambda *a, **k: [])
    monkeypatch.setattr(page, "render", lambda *a, **k: "<html>the new run</html>")
    return monkeypatch
