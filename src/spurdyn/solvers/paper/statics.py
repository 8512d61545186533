"""Static pair stiffness of the paper's model with either contact model.

Both teeth clamped at their root curves (the disks held), turned rigidly to where A's roll
angle is ``roll_a``, and pressed together by the force ``F`` through the contact rows of
the run's contact model: the point (``N(alpha)``) or the Hertzian strip of ``F``
(``N_bar``, docs/solver.md section 11). Each tooth's compliance is the work-conjugate one,
``c = f^T K^-1 f`` for the unit load ``f``; the pair's

    k = 1 / (c_A + c_B + c_H)

with the strip's curvature compliance ``c_H = 1 / (2 pi E* L)`` for the strip (0 for the
point). The point value equals :func:`spurdyn.model.stiffness.pair_stiffness` on the same mesh.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse.linalg import splu

from spurdyn.contact.hertz import strip_compliance
from spurdyn.geometry.involute import rot
from spurdyn.model.system import PairSystem
from spurdyn.solvers.paper.dynamics_numpy import contact_at, strip_law


@dataclass(frozen=True)
class StaticStiffness:
    """The static pair stiffness at one contact position.

    Attributes
    ----------
    stiffness
        ``1 / (c_A + c_B + c_H)`` (N/m).
    compliance_a, compliance_b, compliance_strip
        The teeth's compliances and the strip's ``c_H`` (m/N).
    half_width
        The strip's half-width (m; 0 for the point contact).
    """

    stiffness: float
    compliance_a: float
    compliance_b: float
    compliance_strip: float
    half_width: float


def static_stiffness(system: PairSystem, roll_a: float, force: float, contact: str) -> StaticStiffness:
    """Static pair stiffness with A's contact point at roll angle ``roll_a`` (rad) under the
    normal force ``force`` (N) for ``contact`` ``"point"`` or ``"hertz"``."""
    pair = system.pair
    d_a = roll_a - pair.start_roll_a
    d_b = float(pair.roll_b_from_roll_a(roll_a)) - float(pair.roll_b_from_roll_a(pair.start_roll_a))
    theta = np.array([d_a, -d_b])      # B's roll falls as it turns along its sense
    u = np.zeros(system.n_u)
    o = system.offsets
    for g, gb in enumerate(system.gears):
        y = gb.Y.reshape(-1, 2)
        u[o[g]:o[g + 1]] = (y @ rot(gb.sense * theta[g]).T - y).ravel()
    law = strip_law(system) if contact == "hertz" else None
    fa, fb = system.flanks(system.contacts[0])
    guess = (0.5 * (fa.t0 + fa.t1), 0.5 * (fb.t0 + fb.t1))
    c = contact_at(system, theta, u, guess, force, law)
    comp = []
    for g, (gb, nodes, w) in enumerate(zip(system.gears, (c.nodes_a, c.nodes_b),
                                          (c.weights_a, c.weights_b))):
        # the load in the tooth's own (initial) frame, where K was assembled
        n0 = rot(gb.sense * theta[g]).T @ c.normal
        f = np.zeros(gb.n_u)
        np.add.at(f, 2 * nodes, w * n0[0])
        np.add.at(f, 2 * nodes + 1, w * n0[1])
        free = np.setdiff1d(np.arange(gb.n_u), gb.root_dofs)
        lu = splu(gb.tooth.stiffness[free][:, free].tocsc())
        comp.append(float(f[free] @ lu.solve(f[free])))
    c_h = strip_compliance(*law) if law is not None else 0.0
    return StaticStiffness(stiffness=1.0 / (comp[0] + comp[1] + c_h), compliance_a=comp[0],
                           compliance_b=comp[1], compliance_strip=c_h, half_width=c.half_width)
