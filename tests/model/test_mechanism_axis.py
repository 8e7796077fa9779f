"""The rigid motion a single pin-like clip leaves free is a rotation about an
axis through the clip itself, wherever the clip is, not only at the centre of mass."""

import pytest

import cablecasing_core as cc

CASING = dict(E=5e9, rho=4850.0, d_outer=0.0095, d_inner=0.004, I=2.7261e-10)


@pytest.mark.parametrize("at", [0.2, 0.75])
def test_a_clip_off_the_centre_of_mass_leaves_a_rotation_about_itself_free(at):
    # A free-free straight casing (x from 0 to 1 m) held by one clip with translational stiffness
    # only: the clip is a ball joint, so every free rigid motion is a rotation about an axis through
    # the clip; the weight (-z) drives the rotation about y, whose axis point nearest the centre of
    # mass (0.5, 0, 0) is the clip (at, 0, 0). Exact geometry, printed to 3 significant digits.
    with pytest.raises(cc.ModelError) as err:
        cc.model_from_dict(
            {
                "geometry": {"points": [[0.0, 0, 0], [1.0, 0, 0]], "n_elements": 40, "curve": "polyline"},
                "casing": dict(CASING, supports={"A": "free", "B": "free"}, clip=[{"at": at, "stiffness": 1e5}]),
                "loads": {"gravity": [0, 0, -9.81]},
            }
        )
    msg = str(err.value)
    assert (
        "leave it free in a rotation about [0, 1, 0]" in msg or "leave it free in a rotation about [0, -1, 0]" in msg
    ), msg
    assert f"through [{at:.3g}, 0, 0] m" in msg, msg
