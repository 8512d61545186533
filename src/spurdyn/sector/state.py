"""Where a run of the sector model starts when it continues another's end (docs/sector.md,
6.3, "From another run's end"): the state and its flat numbers, as
:attr:`~spurdyn.settings.RunSettings.start_state` carries them."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from spurdyn.errors import InputError


class SectorState(NamedTuple):
    """Where a run of the sector model starts instead of the static equilibrium: the state at
    the start of a mesh cycle as another run of the same bodies ended, per radian of the
    driver's turn so that it holds at another speed (``v = omega dq``, ``a = omega^2 ddq``).

    ``offset``: the body tooth of the driver that the run's pair 0 is (a run of ``N`` cycles
    ends ``N`` teeth on); ``q`` with the hubs' turns less the whole pitches; ``dq``, ``ddq``
    and ``qdd`` the velocities and the scheme's two accelerations per angle; ``teeth``,
    ``forces``, ``sides`` the contacts' forces by the driver's body tooth and flank (0 the
    drive flank, 1 the back flank)."""

    offset: int
    q: NDArray[np.float64]
    dq: NDArray[np.float64]
    ddq: NDArray[np.float64]
    qdd: NDArray[np.float64]
    teeth: NDArray[np.intp]
    forces: NDArray[np.float64]
    sides: NDArray[np.intp]


def pack_state(state: SectorState) -> tuple[float, ...]:
    """``state`` as the flat numbers of :attr:`RunSettings.start_state`."""
    n = state.q.size
    return tuple(float(x) for x in (state.offset, n, *state.q, *state.dq, *state.ddq, *state.qdd,
                                    state.teeth.size, *state.teeth, *state.forces, *state.sides))


def unpack_state(flat: tuple[float, ...], n: int) -> SectorState:
    """The :class:`SectorState` of :func:`pack_state`'s numbers, for bodies of ``n``
    coordinates (refused in one line if they are another's)."""
    if len(flat) < 2 or int(flat[1]) != n or len(flat) < 2 + 4 * n + 1:
        raise InputError("start_state", f"is not a state of these sector bodies ({n} coordinates): "
                         "start from another run of the same case and mesh")
    x = np.asarray(flat, dtype=float)
    q, dq, ddq, qdd = (x[2 + i * n:2 + (i + 1) * n] for i in range(4))
    m = int(x[2 + 4 * n])
    rest = x[3 + 4 * n:]
    if rest.size != 3 * m:
        raise InputError("start_state", "is not a state of the sector model")
    return SectorState(int(x[0]), q.copy(), dq.copy(), ddq.copy(), qdd.copy(),
                       rest[:m].astype(np.intp), rest[m:2 * m].copy(), rest[2 * m:].astype(np.intp))


def common_rotation(momenta: tuple[float, float], inertias: tuple[float, float], ratio: float,
                    speed: float) -> float:
    """The speed (rad/s of the driver) to add to the driver's hub, and ``ratio`` times it to the
    driven gear's, for the pair's common rotation to be ``speed``: its momentum about the mesh
    ``p_A + ratio p_B`` (``ratio = r_bA / r_bB``; balanced torques keep it while the contact
    lies on the line of action) that of the whole gears (``inertias``) turning at ``speed``.

    A continuation's point starts so (docs/sector.md, 6.5): scaled from the end before, its
    speeds would keep that run's drift of the common rotation (a tip corner's force has other
    moment arms), and a chain of points would carry it on and add to it."""
    whole = inertias[0] + ratio**2 * inertias[1]
    return (speed * whole - momenta[0] - ratio * momenta[1]) / whole


__all__ = ["SectorState", "common_rotation", "pack_state", "unpack_state"]
