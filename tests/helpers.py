"""Model builders shared by the tests (straight beams, arcs, rings), all SI."""
import numpy as np

from cablecasing_core import model_from_dict

STEEL = dict(E=2.1e11, nu=0.3, rho=7850.0)


def beam_model(points, n_elements, d=0.01, supports=("clamped", "free"), curve="polyline", **mat):
    """A cable-only model (solid circular section of diameter d, m) along ``points``."""
    body = dict(STEEL, d=d, alpha=0.0, beta=0.0, loss_factor=0.0,
                supports={"A": supports[0], "B": supports[1]})
    body.update(mat)
    return model_from_dict({"geometry": {"points": [list(map(float, p)) for p in points],
                                         "n_elements": n_elements, "curve": curve},
                            "cable": body})


def straight(L=1.0, n=40, **kw):
    return beam_model([[0, 0, 0], [L, 0, 0]], n, **kw)


def arc_points(R, theta, n):
    """n+1 points on a circular arc of radius R (m) and opening angle theta (rad) in the x-y plane."""
    a = np.linspace(0.0, theta, n + 1)
    return np.column_stack([R * np.sin(a), R * (1 - np.cos(a)), np.zeros_like(a)])


def section(d=0.01):
    A = np.pi * d**2 / 4
    I = np.pi * d**4 / 64
    return A, I, 2 * I


def dominant_family(shape):
    """'axial', 'lateral' or 'torsion' for a mode of a straight beam along x (by DOF share)."""
    u = shape.reshape(-1, 6)
    share = {"axial": np.sum(u[:, 0] ** 2), "lateral": np.sum(u[:, 1:3] ** 2), "torsion": np.sum(u[:, 3] ** 2)}
    return max(share, key=share.get)


# --------------------------------------------------------------------------- probes of the contact kernels
def search_casing(x1, t1, Xs, Rs, Ls, Us, e_guess, far_below):
    """The contact search of one cable node (point x1, unit tangent t1; Eqs. 32-39) as the contact
    solve runs it (``kernels.search_node``): (element, xi, far)."""
    from cablecasing_core.timedomain import kernels as K

    e, xi, far, _, _, _ = K.search_node(x1[0], x1[1], x1[2], t1[0], t1[1], t1[2], Xs, Rs, Ls, Us, e_guess, far_below)
    return e, xi, far


def casing_point(Xs, Rs, Ls, Us, e, xi):
    """Deformed casing axis point (m) at xi of element e (``kernels.axis_at``), as an array."""
    from cablecasing_core.timedomain import kernels as K

    px, py, pz, _, _, _ = K.axis_at(Xs, Rs, Ls, e, xi, K.element_dofs(Rs, Us, e))
    return np.array([px, py, pz])


def line_plane_intersection(ia, ib, p0, p1, p2):
    """Eq. (39), the paper's general form: (l, u, v) of the intersection of the line
    ia + (ib - ia) l with the plane p0 + (p1 - p0) u + (p2 - p0) v (the search itself uses the
    equivalent normal-plane form, one division; this checks it). l = nan for a parallel line."""
    A = np.column_stack([ia - ib, p1 - p0, p2 - p0])
    if abs(np.linalg.det(A)) < 1e-300:
        return np.nan, np.nan, np.nan
    return tuple(np.linalg.solve(A, ia - p0))
