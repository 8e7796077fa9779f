"""The PSD plot (review C, finding 12): drawn from 2 df, where Welch's lines measure (docs/nvh.md,
"Power spectral density"), in the report's psd.png and in `spectrum --plot`."""

import numpy as np
import pytest

from cablecasing_core.nvh import psd


def test_the_psd_is_drawn_from_two_lines_where_welch_measures(drawn):
    """docs/nvh.md: Welch's lines below 2 df are no measurement (``PSD.covered``). The plot began at
    df (12.2 Hz for the report's 9-average PSD) and `spectrum --plot` drew the segment from df
    into its axis: each line now starts at its own 2 df, and so does the axis."""
    from cablecasing_core.nvh.plots import plot_psd

    rng = np.random.default_rng(3)
    fs = 1e5
    x = rng.standard_normal(44000)
    fine, coarse = psd(x, fs, nperseg=8192, name="fine"), psd(x, fs, nperseg=2048, name="coarse")
    plot_psd([fine, coarse], "p.png")
    ax = drawn[0].axes[0]
    starts = [ln.get_xdata()[0] for ln in ax.get_lines()]
    assert starts == [fine.f_hz[2], coarse.f_hz[2]]  # (the lines at 2 df, the first that measure)
    np.testing.assert_allclose(starts, [fine.covered()[0], coarse.covered()[0]], rtol=1e-12)
    assert ax.get_xlim()[0] == pytest.approx(2 * fine.df)
    plot_psd([coarse], "q.png", f_range=(20.0, 3000.0))  # (2 df = 97.7 Hz lies above the range's 20 Hz)
    ax = drawn[1].axes[0]
    assert ax.get_lines()[0].get_xdata()[0] == coarse.f_hz[2] and ax.get_xlim()[0] == pytest.approx(2 * coarse.df)
    plot_psd([psd(x, fs, nperseg=256)], "r.png", f_range=(1000.0, 3000.0))  # (2 df = 781 Hz: the range's)
    line = drawn[2].axes[0].get_lines()[0].get_xdata()
    assert line[0] >= 1000.0 and line[-1] <= 3000.0 and drawn[2].axes[0].get_xlim()[0] == 1000.0
