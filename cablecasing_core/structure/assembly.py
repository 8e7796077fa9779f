"""Assembly of a body's global matrices, its constant loads and the support partition of Eq. (13).

Global DOFs are numbered node by node, six per node ``[ux uy uz rx ry rz]`` in global axes, so the
assembled matrices are banded (half-bandwidth 11). They are stored sparse (CSR); the partitioned
blocks of Eq. (13), ``A_ff, A_fp, A_pf, A_pp`` (f: free DOFs, p: prescribed support DOFs), are
dense and small. A clamped support prescribes all six DOFs of its end node (translations follow
the support motion, rotations stay zero); a free support prescribes none. An isolator support or a
clip (a :class:`~.mount_element.Mount`) adds a node of its own, the support's, after the body's
nodes: its six DOFs are prescribed (the support's motion) and the mount's spring joins it to the
body's node. ``K_blocks`` and ``M_blocks`` partition this augmented system (the mount's static
stiffness in K), so the modes and the TRFAM see the mounts and the reaction of Eq. (13) at a
mount's support DOFs is the force through the mount; ``K`` and ``M`` stay the beams' own.

An installed model (docs/installed.md) prestresses its bodies: the cable carries the axial force
N0 = +T of ``loads.cable_tension``, the casing N0 = -T. ``K`` is then the tangent stiffness
K_E + K_G (the elastic stiffness and the geometric stiffness of N0, element_beam.py), which every
consumer uses (modes, TRFAM, the time domain); ``f`` holds the body's constant load at rest
(structure/loads.py: gravity, the prestress's load in the routing, a straight cable's rest shape).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from ..model.schema import SUPPORT_NAMES
from ..model.validators import Choice, check_model
from .buckling import check_compression
from .element_beam import geometric_stiffness, global_matrices, transformation
from .geometry import centerline_of
from .loads import gravity_load, prestress_load, rest_shape_load
from .mount_element import mounts_of
from .sections import section_of

DOF_PER_NODE = 6


@dataclass
class BodySystem:
    """A body's assembled system. K in N/m (N, N.m per m or rad), M in kg (kg.m, kg.m2).

    K = K_E + K_G is the tangent stiffness: K_E built with the body's reference modulus ``E`` (Pa;
    a frequency-dependent modulus scales K_E as a whole, G = E / (2 (1 + nu)) scales with E), K_G
    the geometric stiffness of the axial prestress ``N0`` (N, tension positive; zero matrix without
    one). ``f``: the constant load at rest over all DOFs (N, N.m; zeros when the model has none),
    of which N0 ``f_axial`` is the prestress's own (``f_axial``: the load of a unit axial force,
    structure/loads.py; the static state replaces the cable's N0 there by its pre-stretch force).
    """

    name: str
    spec: object
    section: object
    centerline: object
    E: float
    K: sp.csr_matrix
    M: sp.csr_matrix
    support_nodes: dict
    prescribed: np.ndarray
    free: np.ndarray
    mounts: tuple = ()
    K_E: sp.csr_matrix = None
    K_G: sp.csr_matrix = None
    N0: float = 0.0
    f: np.ndarray = None
    f_axial: np.ndarray = None

    @property
    def prestressed(self):
        """True when the body carries an axial prestress (K_G is not zero)."""
        return self.N0 != 0.0

    @property
    def ndof(self):
        """The beam's DOFs (six per node); the augmented system has :attr:`n_augmented`."""
        return self.K.shape[0]

    @property
    def n_augmented(self):
        """DOFs of the augmented system: the beam's and six per mount (its support node)."""
        return self.ndof + DOF_PER_NODE * len(self.mounts)

    def mount_dofs(self, m):
        """(node DOFs, support DOFs) of mount index ``m`` in the augmented system (6 each)."""
        node = self.mounts[m].node
        base = self.ndof + DOF_PER_NODE * m
        return np.arange(DOF_PER_NODE * node, DOF_PER_NODE * node + 6), np.arange(base, base + 6)

    def mount_of_support(self, support):
        """Index among :attr:`mounts` of the isolator of ``support`` ("A", "B") or of the clip
        labelled ``support`` ("clip0", ...), or None."""
        return next((i for i, m in enumerate(self.mounts) if support in (m.support, m.label)), None)

    def augmented(self, A, mount_blocks=None):
        """Dense ``A`` (beam size) on the augmented DOFs, plus ``mount_blocks[m]`` (6 x 6, e.g.
        K6) joining each mount's node and support: [[k, -k], [-k, k]]."""
        A = A.toarray() if sp.issparse(A) else np.asarray(A)
        n = self.n_augmented
        out = np.zeros((n, n), dtype=np.result_type(A, *(mount_blocks or [0.0])))
        out[: self.ndof, : self.ndof] = A
        for m, k in enumerate(mount_blocks or []):
            i, j = self.mount_dofs(m)
            out[np.ix_(i, i)] += k
            out[np.ix_(j, j)] += k
            out[np.ix_(i, j)] -= k
            out[np.ix_(j, i)] -= k
        return out

    @property
    def n_nodes(self):
        return self.ndof // DOF_PER_NODE

    def support_dofs(self, support):
        """Global DOF indices (6) of a support: its end node's when clamped (or free), its own
        support node's (in the augmented system) when an isolator."""
        m = self.mount_of_support(support)
        if m is not None:
            return self.mount_dofs(m)[1]
        n = self.support_nodes[support]
        return np.arange(DOF_PER_NODE * n, DOF_PER_NODE * n + DOF_PER_NODE)

    def prescribed_index(self, support, component):
        """Position, within the prescribed DOFs, of ``component`` (0..5) of ``support`` (clamped,
        or an isolator's support node).

        Raises KeyError if the support is free.
        """
        if self.spec.supports.get(support) == "free":
            raise KeyError(f"{self.name}.{support} is a free support")
        dof = self.support_dofs(support)[component]
        return int(np.searchsorted(self.prescribed, dof))

    def blocks(self, A):
        """Dense partitioned blocks (A_ff, A_fp, A_pf, A_pp) of Eq. (13) of an augmented matrix
        (or of a beam-size one, taken onto the augmented DOFs without mounts), in A's units (N/m,
        N/rad, N.m/rad for a stiffness; kg, kg.m, kg.m^2 for a mass)."""
        A = A.toarray() if sp.issparse(A) else A
        if A.shape[0] != self.n_augmented:
            A = self.augmented(A)
        f, p = self.free, self.prescribed
        return A[np.ix_(f, f)], A[np.ix_(f, p)], A[np.ix_(p, f)], A[np.ix_(p, p)]

    @cached_property
    def K_blocks(self):
        """K's blocks (N/m, N/rad, N.m/rad; :meth:`blocks`) with the mounts' static stiffness K6."""
        return self.blocks(self.augmented(self.K, [m.K6 for m in self.mounts]))

    @cached_property
    def M_blocks(self):
        """M's blocks (kg, kg.m, kg.m^2; :meth:`blocks`): the consistent mass of Eq. (4)."""
        return self.blocks(self.M)


def axial_prestress(model, name):
    """The axial force N0 (N, tension positive) body ``name`` carries at rest: the cable's tension
    ``loads.cable_tension``, and its negative for the casing (which carries the equal compression)."""
    T = model.loads["cable_tension"]
    return T if name == "cable" else -T if "cable" in model.bodies else 0.0


def assemble_body(model, name, E=None, check_buckling=True):
    """Assemble body ``name`` ("casing" or "cable") of ``model``, with its prestress and loads.

    E : float, optional modulus in Pa to build K_E with (default: the body's reference modulus,
        the scalar ``E`` or the first row of its table).
    check_buckling : refuse a compression at or above the body's buckling load (a ModelError naming
        loads.cable_tension; structure/buckling.py).

    A ``model`` that is no :class:`~cablecasing_core.Model`, or a ``name`` that is not one of its
    bodies, raises :class:`~cablecasing_core.errors.ModelError` naming it (Eqs. 4-9: K_E, M; Eq. 32:
    K_G of the prestress).
    """
    check_model(model)
    Choice(*model.bodies)("name", name)
    spec = model.bodies[name]
    sec = section_of(spec)
    cl = centerline_of(model)
    E = spec.E_ref if E is None else float(E)
    G = E / (2.0 * (1.0 + spec.nu))
    N0 = axial_prestress(model, name)
    ne = cl.n_elements
    ndof = DOF_PER_NODE * (ne + 1)
    rows, cols, kv, mv, gv = [], [], [], [], []
    for e in range(ne):
        Ke, Me = global_matrices(cl.lengths[e], cl.frames[e], E, G, sec.A, sec.I, sec.J, spec.rho, sec.Ip)
        dofs = np.arange(DOF_PER_NODE * e, DOF_PER_NODE * e + 12)
        r, c = np.meshgrid(dofs, dofs, indexing="ij")
        rows.append(r.ravel())
        cols.append(c.ravel())
        kv.append(Ke.ravel())
        mv.append(Me.ravel())
        if N0:
            T = transformation(cl.frames[e])
            gv.append((T.T @ geometric_stiffness(cl.lengths[e], N0, sec.A, sec.Ip) @ T).ravel())
    rows, cols = np.concatenate(rows), np.concatenate(cols)
    K_E = sp.csr_matrix((np.concatenate(kv), (rows, cols)), shape=(ndof, ndof))
    M = sp.csr_matrix((np.concatenate(mv), (rows, cols)), shape=(ndof, ndof))
    K_G = sp.csr_matrix((np.concatenate(gv), (rows, cols)), shape=(ndof, ndof)) if N0 else sp.csr_matrix((ndof, ndof))
    K = K_E + K_G if N0 else K_E
    f_axial = prestress_load(cl, 1.0)
    f = gravity_load(M, model.loads["gravity"]) + N0 * f_axial
    if spec.rest_shape == "straight":
        f += rest_shape_load(cl, E * sec.I)
    support_nodes = {"A": 0, "B": ne}
    pres = [
        np.arange(DOF_PER_NODE * support_nodes[s], DOF_PER_NODE * support_nodes[s] + DOF_PER_NODE)
        for s in SUPPORT_NAMES
        if spec.supports[s] == "clamped"
    ]
    mounts = mounts_of(model, name, cl)
    pres.append(np.arange(ndof, ndof + DOF_PER_NODE * len(mounts)))  # the mounts' support nodes
    prescribed = np.sort(np.concatenate(pres)).astype(int)
    free = np.setdiff1d(np.arange(ndof), prescribed)
    system = BodySystem(
        name=name,
        spec=spec,
        section=sec,
        centerline=cl,
        E=E,
        K=K,
        M=M,
        support_nodes=support_nodes,
        prescribed=prescribed,
        free=free,
        mounts=mounts,
        K_E=K_E,
        K_G=K_G,
        N0=N0,
        f=f,
        f_axial=f_axial,
    )
    if check_buckling and N0 < 0.0:
        check_compression(system)
    return system
