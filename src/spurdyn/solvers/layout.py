"""Typed packs of the solvers, each defined once: what compiled code passes around.

Numba takes namedtuples of arrays and scalars, so every pack that used to be a bare
array read by index is a namedtuple here, and every column layout is a tuple of names
with a namedtuple of indices beside it (``row[H.theta_a]``). Nothing here imports
spurdyn: the compiled modules read these globals, and the compiled-code gate
(:mod:`spurdyn.jit`) keys its cache on this file.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

#: Columns of the time history, one row per saved step, declared here only: every writer
#: builds a :class:`HistoryRow` (the compiled ``write_row`` of
#: :mod:`spurdyn.solvers.paper.step_compiled`, the NumPy steppers' ``row``), and the
#: reader (the time loop's result) reads the columns by these names.
HISTORY = ("t", "theta_a", "theta_b", "omega_a", "omega_b", "tau_a", "tau_b", "p", "s",
           "alpha", "beta", "mode", "res1", "res2", "res3", "it1", "it2", "it3", "half_width")
#: One history row by name; its field order is the column order. The writers construct it
#: with every field named (a column added to :data:`HISTORY` and not written fails there)
#: and copy it into the row in field order; the compiled writer passes floats only, so
#: Numba can index the tuple in a loop.
HistoryRow = namedtuple("HistoryRow", HISTORY)
#: Column indices of :data:`HISTORY` by name.
H = namedtuple("HistoryColumns", HISTORY)(*range(len(HISTORY)))
NCOL = len(HISTORY)

#: Status of a step (the compiled step returns it; the NumPy step reports it): a stage
#: that did not converge (in the order of :data:`spurdyn.result.STAGES`), a NaN, or a
#: distributed contact's strip wider than the slots the run gave it, or an implicit step's
#: Newton iteration that did not converge; the sector model's driver beyond the turns its
#: teeth cover, or its pairs' complementarity problem without a solution.
OK, FAIL_DISP, FAIL_VEL, FAIL_ACC, FAIL_NAN, FAIL_STRIP, FAIL_NEWTON = 0, 1, 2, 3, 4, 5, 6
FAIL_BEYOND, FAIL_LCP = 7, 8

#: The run settings a compiled step reads (SI units; ``eps_root`` is the smallest
#: eigenvalue of the root blocks of ``G M^-1 G^T``;
#: ``estar``, ``face`` the Hertz modulus and face width of the distributed contact, 0 for
#: the point contact, and ``c_h`` its strip compliance ``1 / (2 pi E* L)``).
Config = namedtuple("Config", ["dt", "tol_disp", "tol_vel", "tol_acc", "max_iter", "levels",
                               "eps_root", "estar", "face", "c_h"])

#: The model as plain arrays, the nodes of both teeth stacked (A first):
#: ``Y`` (2N,) initial offsets from the centres; ``mass`` (2N,) nodal masses;
#: ``node_gear`` (N,) the gear of each node; ``sense``, ``J``, ``centre`` per gear;
#: ``indptr``, ``indices``, ``data`` the stiffness in 2x2 block rows; ``keep`` 1 to keep the
#: elastic torque on the disks; ``tpar`` (2, 3) the torque schedule (amplitude, theta_s,
#: theta_2); ``rnode``, ``rgear`` root nodes and their gears; ``fpar`` (2, 13) flank
#: parameter rows (columns :data:`spurdyn.contact.constants.F`); ``fl_nodes``, ``fl_w``,
#: ``fl_delta`` the spline data points' edge nodes, weights and involute offsets;
#: ``side``, ``sideY`` the outline nodes and their offsets; ``rel_nodes`` the nodes the
#: constraints read and ``rel_pos`` their position in that list (-1 elsewhere).
Packed = namedtuple("Packed", [
    "Y", "mass", "node_gear", "sense", "J", "centre", "indptr", "indices", "data", "keep",
    "tpar", "rnode", "rgear", "fpar", "fl_nodes", "fl_w", "fl_delta", "side", "sideY",
    "rel_nodes", "rel_pos",
])

#: The state a compiled step updates in place: time, rotations, speeds, nodal
#: displacements and velocities, the forces ``x = [lambda; p]`` and the accelerations
#: they give, the contact rows (nodes ``cn``, weights ``cw``, ``normal``, the disk entries
#: ``gth``: zero for the point contact, docs/solver.md section 11.3), the contact
#: pair (``cpar``, columns :data:`CP`), ``C = G M^-1 G^T``, and the last step's stage
#: residuals and iterations.
CompiledState = namedtuple("CompiledState", [
    "t", "theta", "omega", "u", "v", "x", "alpha_n", "a_n", "cn", "cw", "normal", "gth", "cpar",
    "C", "res", "its",
])
#: Columns of ``cpar``: flank coordinates on A and B, contact mode, penetration, the
#: contact force the last displacement stage held (N), the half-width of the strip the
#: contact rows average over (m; 0 for a point) and how much re-spreading the strip at the
#: end of the last step moved the gap its rows hold (m; docs/solver.md section 11.4).
CP = namedtuple("ContactColumns", ("alpha", "beta", "mode", "s", "p_held", "half_width", "jump"))(
    0, 1, 2, 3, 4, 5, 6)

#: RK4 over a step with the last step's forces: the end state (``qs_*`` positions,
#: ``vs_*`` velocities) and what the linear response to a change of the forces needs (the
#: third and fourth stage rotations, ``w`` and ``K w``, and the torque schedule's slopes).
Prediction = namedtuple("Prediction", ["qs_th", "qs_u", "vs_th", "vs_u", "q3th", "w3", "kw3",
                                       "q4th", "w4", "kw4", "sl3", "sl4"])

#: The sparse response's workspace, made once a step and left clean by each use
#: (:func:`~spurdyn.solvers.paper.response_compiled.response_columns`): ``scratch``, ``zu``,
#: ``acc3``, ``acc4`` a vector of the teeth's DOFs each, ``mark`` a flag a node, ``touched``
#: and ``nz_nodes`` lists of nodes.
SparseWork = namedtuple("SparseWork", ["scratch", "mark", "touched", "nz_nodes", "zu", "acc3", "acc4"])

# -- the phases of the paper's compiled step (spurdyn.solvers.paper.step_compiled) ------------

#: The response to the forces on the rows the constraints read (``Wq`` positions, ``Wv``
#: velocities, one column a force) and the free state there (``qs_rel``, ``vs_rel``: the
#: prediction less the response to the last step's forces), with the sparse workspace.
StepResponse = namedtuple("StepResponse", ["Wq", "Wv", "qs_rel", "vs_rel", "sparse"])
#: Contact rows: the nodes ``cn`` and weights ``cw`` (A's half, then B's), the ``normal``
#: and the disk entries ``gth``.
ContactRows = namedtuple("ContactRows", ["cn", "cw", "normal", "gth"])
#: The last displacement iterate's strip: its rows, its ``delta_bar`` on A and B (4,), its
#: pair's roll with the disks (2,) and its row's disk entries (2,).
IterateStrip = namedtuple("IterateStrip", ["cn", "cw", "delta", "roll", "gth"])
#: The contact pair a displacement iterate found: flank coordinates, mode, normal, gap
#: and the half-width of its strip (0 for a point).
ContactFound = namedtuple("ContactFound", ["alpha", "beta", "mode", "nx", "ny", "s", "half_width"])
#: The step's scratch: the error ``e`` and its update's copy ``e_up`` (n_x,), the
#: iteration's ``Cp`` and ``work``, and the flank splines the search refits (``va``, ``vb``
#: positions, ``Ma``, ``Mb`` second derivatives) that the later stages read.
StepWork = namedtuple("StepWork", ["e", "e_up", "Cp", "work", "va", "vb", "Ma", "Mb"])
#: The motion at ``t + dt``: rotations and displacements (displacement stage), speeds
#: and velocities (velocity stage).
StepEnd = namedtuple("StepEnd", ["theta", "u", "omega", "v"])

#: What the compiled implicit step reads besides :class:`Packed` (docs/implicit.md):
#: ``h``, the generalized-alpha coefficients ``am``, ``af``, ``beta``, ``gamma`` and
#: ``bp = beta'``, ``gp = gamma'``; ``mq`` the masses of ``q = [theta, u]``; the teeth's
#: constant iteration blocks as one banded Cholesky factor ``A[perm][:, perm] = U^T U``,
#: ``band[j, bw + i - j] = U[i, j]`` (LAPACK's upper band storage, transposed); ``root_inv`` those blocks' inverse at the
#: root DOFs (``n_u`` by ``2 n_root``, columns in the order of ``Packed.rnode``); ``base``
#: ``(r_bA, -r_bB)``, ``c_mesh`` the mesh damper, ``ray_a``, ``ray_b`` Rayleigh's
#: coefficients, ``c_h``, ``estar``, ``face`` the strip's law (0 for a point), ``tol``,
#: ``max_iter`` and ``ns`` the contact-row slots per gear.
ImplicitPack = namedtuple("ImplicitPack", [
    "h", "am", "af", "beta", "gamma", "bp", "gp", "mq", "band", "perm", "root_inv", "base",
    "c_mesh", "ray_a", "ray_b", "c_h", "estar", "face", "tol", "max_iter", "ns",
])

# -- the sector model's compiled loops (spurdyn.solvers.sector): their states ----------------
# (the packs the model fills, ModalGear, GapArrays, SectorContacts, SectorConfig, are the
# model's data: spurdyn.sector.packs)

#: The implicit sector loop's state, changed in place: coordinates, velocities, the
#: scheme's two accelerations, the contacts' forces, a crack's faces' (none without) and per
#: contact its pit strip's force where a pit over part of the face width splits it, -1
#: elsewhere (none: no contact splits, the steppers refuse none where one may;
#: docs/faults.md, section 8).
SectorStepState = namedtuple("SectorStepState", ["q", "v", "acc", "qdd", "force", "faces", "pit"],
                             defaults=(np.zeros(0), np.zeros(0)))

#: The RK4 reference's state, changed in place: coordinates, velocities, the contacts'
#: forces at the step's start and the forces whose half-widths the step holds.
SectorRk4State = namedtuple("SectorRk4State", ["q", "v", "force", "held"])

#: A sector run's saved columns per step: the hubs' turns and speeds, the contacts'
#: forces and the smallest gap; and every few steps the coordinates (``states``, row
#: ``sample[step]`` of step ``step``, -1 for a step not sampled; none by default), from which
#: the teeth's root stress is recovered after the run; with a crack, per step its faces' largest
#: force, least and largest opening (``faces``, none without); with the hubs on bearings their
#: translations and rates per step (``hubs``, none without).
SectorOut = namedtuple("SectorOut", ["theta", "omega", "force", "gap", "states", "sample", "faces", "hubs"],
                       defaults=(np.zeros((0, 0)), np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros((0, 8))))
