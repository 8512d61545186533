"""The driver of the sector model's compiled loop (:mod:`spurdyn.solvers.sector.step_compiled`):
the modal bodies' and the pair's arrays gathered for it, and the run in chunks so that
progress shows and an interrupt stops it between them."""

from __future__ import annotations

from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray


def gear_arrays(gears: Any, blocks: Any) -> list[tuple[Any, ...]]:
    """Per gear, what the compiled loops read of its modal body and block: ``S^-1`` (or
    ``M^-1``), the modes' damping and ``Omega^2``, the modes in each tooth's frame, the
    static blocks, the flank's geometry, and the body's first tooth and tooth count."""
    out = []
    for body, blk in zip(gears, blocks):
        fl = blk.body.flank
        geo = np.array([fl.r0, fl.r_tip, float(fl.ny), fl.base_radius, blk.gear.half_angle_base])
        out.append((np.ascontiguousarray(body._inv), np.ascontiguousarray(body._damp),
                    np.ascontiguousarray(body.reduced.omega2), np.ascontiguousarray(body._modes),
                    np.ascontiguousarray(body._flex), geo, blk.first, blk.count))
    return out


def run_compiled(gears: Any, blocks: Any, state: tuple[NDArray[np.float64], ...], teeth: NDArray[np.intp],
                 sides: NDArray[np.intp], offset: int, table: Any, consts: tuple[float, ...], hub: NDArray[np.float64], c_table: NDArray[np.float64],
                 outs: tuple[NDArray[np.float64], ...], first: int, n_steps: int, every: int,
                 progress: Callable[[int, float, float], None] | None,
                 total: float, done: list[int]) -> tuple[int, int]:
    """Run the loop with :func:`spurdyn.solvers.sector.step_compiled.run_steps` (modal bodies
    of whole gears) from step ``first`` to ``n_steps``, ``every`` steps a call, contact ``i``
    the driver's tooth ``teeth[i]`` on its flank ``sides[i]``, ``hub`` the hubs' torques at
    each step's end; ``(last step, 0)``, or the failed step and why (1: not finite, 2: the
    driver left the turns the contacts cover)."""
    from spurdyn.contact.hertz import strip_quadrature
    from spurdyn.solvers.sector.step_compiled import run_steps

    (i0, d0, o0, mo0, fx0, g0, fi0, c0), (i1, d1, o1, mo1, fx1, g1, fi1, c1) = gear_arrays(gears, blocks)
    xq, wq = strip_quadrature()
    q, v, acc, qdd, force = state
    teeth64, sides64, constants = np.asarray(teeth, np.int64), np.asarray(sides, np.int64), np.array(consts, dtype=float)
    step = first
    while step < n_steps:
        chunk = min(every, n_steps - step)
        step, failed = run_steps(step, chunk, q, v, acc, qdd, force, i0, i1, d0, d1, o0, o1, mo0, mo1,
                                 fx0, fx1, g0, g1, fi0, fi1, c0, c1, teeth64, sides64, int(offset),
                                 table.rho, table.gap, table.slope, table.r_a, table.r_b,
                                 constants, xq, wq, hub, c_table, *outs)
        if failed:
            return step, int(failed)
        done[0] = step
        if progress is not None:
            progress(step, float(q[0]), total)
    return step, 0


__all__ = ["run_compiled"]
