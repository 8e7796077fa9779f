"""The figure of a static state (``cablecasing static --plot``): the contact force on each cable node
along the arc length, beside the centerline's curvature (like Fig. 22's contact histogram)."""

from __future__ import annotations

import numpy as np


def plot_static_state(st, path, title="static state"):
    """Contact force magnitude per cable node (N, bars) and curvature (1/m, line) over the arc
    length from end A (m) of a :class:`~cablecasing_core.timedomain.static_state.StaticState`."""
    from ..plotting import plt, save_figure  # (figures are the data flow's last stage: imported when drawn)

    fig, ax = plt.subplots(figsize=(7, 3.8))
    s = st.arc_length
    F = np.linalg.norm(st.contact_force, axis=1)
    ax.bar(s, F, width=0.8 * (s[1] - s[0]), color="C0", label="contact force")
    ax.set_xlabel("arc length from A (m)")
    ax.set_ylabel("contact force on the cable (N)", color="C0")
    ax.set_title(f"{title}: {st.contact_nodes} nodes in contact, max penetration {st.max_penetration:.3g} m")
    k = ax.twinx()
    k.plot(s, st.curvature, "r-", label="curvature")
    k.set_ylabel("curvature (1/m)", color="r")
    save_figure(fig, path)
