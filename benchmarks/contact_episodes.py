"""How long the contacts of the reference case last, and whether that converges as dt shrinks.

A contact episode is a run of consecutive steps in which one cable node is in contact (stick or
slip). For each time step (and once more with the contact damper off, c_n = 0) the default model
runs its scenario for ``--duration`` s, and prints name: value lines:
* <label>_episodes: the number of episodes (all nodes);
* <label>_contact_steps_per_step: the mean number of nodes in contact per step;
* <label>_episodes_of_1_2_steps: the share of episodes that last one or two steps, and
  <label>_their_share_of_contact_time: the share of the contact time they hold;
* <label>_reopen_within_3_steps: the share of a node's gaps between two episodes that last at most
  three steps (the contact opens and closes again at once);
* <label>_rms_casing_B_Fz_N: the RMS of casing.B.Fz after 0.05 s.
An episode count that grows like 1/dt, with episodes that last one or two steps whatever the step,
looks like chatter at the scale of the time step. It is not: it is the model's own rattle (a
sequence of ever shorter bounces after a contact lets go, with the contact damper on), which a
step of 1e-5 s cannot resolve and renders as episodes of one or two steps;
``benchmarks/rattle.py`` follows one such sequence under refinement down to dt = 3.9e-8 s, where
it converges (docs/time_domain.md, Known limits).
Run: .venv/bin/python benchmarks/contact_episodes.py [--duration 0.5]   (about 30 s, one core)
"""

import numpy as np
from _options import parser

import cablecasing_core as cc

p = parser(__doc__)
p.add_argument("--duration", type=float, default=0.5, help="s simulated per run")
args = p.parse_args()
if not args.duration >= 0.1:
    p.error(f"--duration {args.duration}: must be at least 0.1 s (the RMS is taken after 0.05 s)")
model = cc.load_model()


def episodes(contact_state):
    """Lengths of the contact episodes (steps), and of the gaps between a node's episodes."""
    node, start, length = cc.contact_episodes(contact_state)
    same = node[1:] == node[:-1]
    return length, (start[1:] - (start + length)[:-1])[same]


runs = [(f"dt_{dt:g}", model, dt) for dt in (1e-5, 5e-6, 2.5e-6)]
runs.append(("no_damper_dt_1e-05", model.with_overrides({"contact.damping": 0.0}), 1e-5))
for label, m, dt in runs:
    res = cc.simulate(m, duration=args.duration, dt=dt)
    in_contact = res.contact_state > 0
    lengths, gaps = episodes(res.contact_state)
    short = lengths <= 2
    F = res.support_force("casing.B.Fz")[res.time > 0.05]
    print(f"{label}_episodes: {len(lengths)}")
    print(f"{label}_contact_steps_per_step: {in_contact.sum() / len(in_contact):.3f}")
    print(f"{label}_episodes_of_1_2_steps: {short.mean():.3f}")
    print(f"{label}_their_share_of_contact_time: {lengths[short].sum() / lengths.sum():.3f}")
    print(f"{label}_reopen_within_3_steps: {np.mean(gaps <= 3):.3f}")
    print(f"{label}_rms_casing_B_Fz_N: {np.sqrt(np.mean(F**2)):.4f}")
