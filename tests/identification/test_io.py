"""UFF dataset 58 and CSV round trips; identified parameters as model-file TOML."""

import sys

import numpy as np
import pytest

from cablecasing_core import load_model
from cablecasing_core.errors import ModelError
from cablecasing_core.identification import (
    Record,
    loss_factor_circle,
    parameters_toml,
    read_csv_frf,
    read_csv_time,
    read_frf,
    read_time_record,
    read_uff,
    write_csv_frf,
    write_csv_time,
    write_uff,
    write_uff_frf,
    write_uff_time,
)

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

pytest.importorskip("pyuff")


def _frf():
    f = np.arange(0.5, 400.0, 0.5)
    w2 = (2 * np.pi * f) ** 2
    return f, 1.0 / ((2 * np.pi * 182.0) ** 2 * (1 + 0.046j) - w2) + 1e-7j


@pytest.mark.parametrize("binary", [True, False])
def test_uff_round_trip_frf_and_time(tmp_path, binary):
    f, H = _frf()
    fs = 4096.0
    x = np.sin(2 * np.pi * 115.8 * np.arange(3000) / fs) * np.exp(-np.arange(3000) / 900.0)
    p_frf, p_time = tmp_path / "frf.uff", tmp_path / "x.uff"
    write_uff_frf(p_frf, f, H, name="TRFAM casing", binary=binary, rsp_node=2, rsp_dir=3, ref_node=1, ref_dir=1)
    write_uff_time(p_time, x, fs, name="impulse response", binary=binary)
    (r,) = read_uff(p_frf)
    assert r.kind == "frf" and r.name == "TRFAM casing" and (r.rsp_node, r.rsp_dir, r.ref_node) == (2, 3, 1)
    # binary 58b stores doubles: exact; ASCII stores E20.11 (12 significant digits)
    tol = 0.0 if binary else 1e-11
    np.testing.assert_allclose(r.data, H, rtol=tol, atol=0)
    np.testing.assert_array_equal(r.x, f)  # exact even abscissa from the ID-line tag
    x2, fs2, name = read_time_record(p_time)
    np.testing.assert_allclose(x2, x, rtol=tol, atol=tol * np.abs(x).max())
    assert fs2 == fs and name == "impulse response"
    f3, H3 = read_frf(p_frf)
    np.testing.assert_allclose(H3, H, rtol=tol, atol=0)


def test_uff_several_functions_and_uneven_abscissa(tmp_path):
    f_uneven = np.geomspace(10.0, 400.0, 57)
    H = 1.0 / (1.0 + 1j * f_uneven)
    recs = [
        Record("time", np.arange(10) * 0.5e-3, np.arange(10.0), "t1"),
        Record("frf", f_uneven, H, "uneven"),
        Record("time", np.arange(10) * 0.5e-3, -np.arange(10.0), "t2"),
    ]
    p = tmp_path / "many.unv"
    write_uff(p, recs)
    back = read_uff(p)
    assert [r.kind for r in back] == ["time", "frf", "time"]
    np.testing.assert_array_equal(back[1].x, f_uneven)  # binary: abscissa stored point by point, exact
    np.testing.assert_array_equal(back[1].data, H)
    x, fs, name = read_time_record(p, channel=1)
    assert name == "t2" and fs == pytest.approx(2000.0, rel=1e-12)
    np.testing.assert_array_equal(x, -np.arange(10.0))


def test_csv_round_trip(tmp_path):
    f, H = _frf()
    p = tmp_path / "h.csv"
    write_csv_frf(p, f, H, name="kg")
    f2, H2 = read_frf(p)
    np.testing.assert_array_equal(f2, f)  # %.17g round-trips doubles exactly
    np.testing.assert_array_equal(H2, H)
    X = np.column_stack([np.linspace(0, 1, 50), np.cos(np.arange(50))])
    pt = tmp_path / "x.csv"
    write_csv_time(pt, X, 1000.0, names=["force_N", "acc_m_s2"])
    x, fs, name = read_csv_time(pt, "acc_m_s2")
    np.testing.assert_array_equal(x, X[:, 1])
    assert name == "acc_m_s2" and fs == pytest.approx(1000.0, rel=1e-12)
    # the trfam CLI's CSV layout is accepted
    pc = tmp_path / "trfam.csv"
    np.savetxt(
        pc,
        np.column_stack([f, H.real, H.imag, abs(H), np.degrees(np.angle(H))]),
        delimiter=",",
        header="frequency_hz,re_kg,im_kg,magnitude_kg,phase_deg",
        comments="",
    )
    np.testing.assert_allclose(read_csv_frf(pc)[1], H, rtol=1e-15)


def test_io_errors(tmp_path):
    with pytest.raises(ModelError) as e:
        read_time_record(tmp_path / "missing.csv")
    assert e.value.key == "file"
    p = tmp_path / "frf.uff"
    f, H = _frf()
    write_uff_frf(p, f, H)
    with pytest.raises(ModelError) as e:
        read_time_record(p)
    assert e.value.key == "file" and "no time record" in e.value.allowed
    bad = tmp_path / "bad.csv"
    bad.write_text("time_s,x\n0,1\n0.1,2\n0.3,3\n")
    with pytest.raises(ModelError) as e:
        read_time_record(bad)
    assert "evenly" in e.value.allowed
    good = tmp_path / "good.csv"
    good.write_text("time_s,x\n0,1\n0.1,2\n0.2,3\n")
    with pytest.raises(ModelError) as e:
        read_csv_time(good, "y")
    assert e.value.key == "channel"
    nofrf = tmp_path / "n.csv"
    nofrf.write_text("frequency_hz,mag\n1,2\n")
    with pytest.raises(ModelError) as e:
        read_frf(nofrf)
    assert e.value.key == "file"


def test_parameters_toml_is_accepted_by_the_model():
    f, _ = _frf()
    w2 = (2 * np.pi * f) ** 2
    H = sum(1.0 / ((2 * np.pi * fk) ** 2 * (1 + 1j * e) - w2) for fk, e in [(115.8, 0.0764), (182.0, 0.046)])
    circles = loss_factor_circle(f, H, [115.8, 182.0])
    E_table = [[200.0, 5.3e9], [100.0, 5.1e9]]  # unsorted on purpose: written sorted
    text = parameters_toml(
        "casing", alpha=47.97, beta=8.5e-6, loss_factor=circles, E=E_table, comment="identified from Table 1"
    )
    data = tomllib.loads(text)["casing"]
    assert data["E"] == [[100.0, 5.1e9], [200.0, 5.3e9]]
    np.testing.assert_allclose(np.array(data["loss_factor"])[:, 1], [0.0764, 0.046], rtol=1e-6)
    m = load_model().with_overrides({f"casing.{k}": v for k, v in data.items()})
    spec = m.bodies["casing"]
    assert spec.alpha == 47.97 and spec.beta == 8.5e-6
    assert spec.modulus(150.0) == pytest.approx(5.2e9, rel=1e-12)
    # scalar form, no section header (to paste under an existing [cable])
    lines = parameters_toml(alpha=1.0, loss_factor=0.02, E=2.1e11)
    assert tomllib.loads(lines) == {"alpha": 1.0, "loss_factor": 0.02, "E": 2.1e11}


def test_parameters_toml_rejects_what_the_model_rejects():
    with pytest.raises(ModelError) as e:
        parameters_toml("casing", beta=-1e-6)
    assert e.value.key == "beta" and "nonnegative" in e.value.allowed
    with pytest.raises(ModelError) as e:
        parameters_toml("casing", E=[[100.0, 5e9], [100.0, 6e9]])
    assert e.value.key == "E"
    with pytest.raises(ModelError) as e:
        parameters_toml("housing", alpha=1.0)
    assert e.value.key == "body"


def test_a_uff_function_of_one_value_is_refused_by_name(tmp_path):
    """pyuff cannot write one abscissa value (an internal error before)."""
    from cablecasing_core.identification import write_uff_frf

    with pytest.raises(ModelError, match=r"a UFF 58 FRF needs at least 2 abscissa values"):
        write_uff_frf(tmp_path / "one.uff", [10.0], [1.0 + 0.0j])
    assert not (tmp_path / "one.uff").exists()
