"""Reading a run's dataset back: its case, its speeds and its tooth frames.

Below :mod:`spurdyn.results.io` and the pictures (:mod:`~spurdyn.results.plots`,
:mod:`~spurdyn.results.vtu`, :mod:`~spurdyn.results.animate`), which all use it.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from spurdyn.case.file import Case, case_from_dict
from spurdyn.errors import InputError


def case_from_run(ds: xr.Dataset) -> Case:
    """Rebuild the :class:`Case` stored in a run's ``case`` attribute."""
    try:
        data = json.loads(ds.attrs["case"])
    except (KeyError, json.JSONDecodeError):
        raise InputError("result.nc", "holds no case description") from None
    return case_from_dict(data, name=str(ds.attrs.get("case_name", "case")), check_step=False)


# -- tooth frames ----------------------------------------------------------------------

@dataclass(frozen=True)
class ToothFrames:
    """The tooth frames of a run, ready to draw: meshes, positions and stresses.

    Attributes
    ----------
    case
        The case of the run.
    meshes
        The tooth meshes of A and B (gear frame).
    X0
        ``(2,)`` tuple of ``(N, 2)`` world node positions at the start of contact.
    centres
        World positions of the gear centres.
    time, theta
        Frame times (s) and rotations since the start ``(k, 2)`` (rad).
    u
        ``(2,)`` tuple of ``(k, N, 2)`` absolute world displacements of each tooth.
    """

    case: Case
    meshes: tuple[Any, Any]
    X0: tuple[NDArray[np.float64], NDArray[np.float64]]
    centres: tuple[NDArray[np.float64], NDArray[np.float64]]
    time: NDArray[np.float64]
    theta: NDArray[np.float64]
    u: tuple[NDArray[np.float64], NDArray[np.float64]]

    @property
    def n_frames(self) -> int:
        return int(self.time.size)

    @staticmethod
    def _rot(angle: NDArray[np.float64]) -> NDArray[np.float64]:
        c, s = np.cos(angle), np.sin(angle)
        return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)  # (..., 2, 2)

    def rotation(self, gear: int, k: int) -> NDArray[np.float64]:
        """World rotation matrix of gear ``gear`` (0: A, clockwise; 1: B) at frame ``k``."""
        th = self.theta[k, gear]
        return self._rot(np.asarray(-th if gear == 0 else th))

    def elastic(self, gear: int, k: int) -> NDArray[np.float64]:
        """Elastic displacement ``R^T (X0 + u - c) - (X0 - c)`` in the start frame (m)."""
        c = self.centres[gear]
        r = self.rotation(gear, k)
        return (self.X0[gear] + self.u[gear][k] - c) @ r - (self.X0[gear] - c)

    def elastic_all(self, gear: int) -> NDArray[np.float64]:
        """:meth:`elastic` of every frame at once, ``(k, N, 2)``."""
        c = self.centres[gear]
        th = self.theta[:, gear]
        r = self._rot(-th if gear == 0 else th)                       # (k, 2, 2)
        return np.einsum("kni,kij->knj", self.X0[gear] + self.u[gear] - c, r) - (self.X0[gear] - c)

    def positions(self, gear: int, k: int, magnify: float = 1.0) -> NDArray[np.float64]:
        """World node positions at frame ``k`` with the elastic part magnified."""
        c = self.centres[gear]
        r = self.rotation(gear, k)
        return c + (self.X0[gear] - c + magnify * self.elastic(gear, k)) @ r.T

    def von_mises(self, gear: int, k: int) -> NDArray[np.float64]:
        """Von Mises stress (Pa) at each element centre of tooth ``gear`` at frame ``k``."""
        from spurdyn.fem.assembly import centroid_stresses, von_mises_plane_stress

        g = self.case.pair.gear_a if gear == 0 else self.case.pair.gear_b
        mesh = self.meshes[gear]
        sig = centroid_stresses(self.X0[gear], mesh.elements, self.elastic(gear, k).ravel(),
                                g.material)
        return von_mises_plane_stress(sig)


def tooth_frames(ds: xr.Dataset) -> ToothFrames:
    """Rebuild the tooth meshes from the case in ``ds`` and split the frames per tooth.

    Raises
    ------
    InputError
        If the run holds no frames or their size does not match the meshes.
    """
    from spurdyn.geometry.placement import mesh_angles, to_world_a, to_world_b
    from spurdyn.mesh.tooth import tooth_mesh

    if "frame_u" not in ds or ds.sizes.get("frame", 0) == 0:
        raise InputError(str(ds.attrs.get("case_name", "run")),
                         "holds no tooth frames (run with frames_every > 0)")
    case = case_from_run(ds)
    pair = case.pair
    mesh_a = tooth_mesh(pair.gear_a, case.run.nx, case.run.ny, grading=case.run.grading,
                        row_grading=case.run.row_grading)
    mesh_b = tooth_mesh(pair.gear_b, case.run.nx, case.run.ny, grading=case.run.grading,
                        row_grading=case.run.row_grading)
    theta_a0, theta_b0 = mesh_angles(pair, pair.start_roll_a)
    x0 = (to_world_a(mesh_a.nodes, theta_a0),
          to_world_b(mesh_b.nodes, theta_b0, pair.centre_distance))
    u = ds["frame_u"].values
    na, nb = mesh_a.n_dof, mesh_b.n_dof
    if u.shape[1] != na + nb:
        raise InputError("frame_u", f"has {u.shape[1]} DOFs per frame but the meshes of the "
                         f"case have {na} + {nb}")
    k = u.shape[0]
    theta = np.stack([ds["frame_theta_a"].values, ds["frame_theta_b"].values], axis=1)
    return ToothFrames(
        case=case, meshes=(mesh_a, mesh_b), X0=x0,
        centres=(np.zeros(2), np.array([0.0, pair.centre_distance])),
        time=ds["frame_time"].values, theta=theta,
        u=(u[:, :na].reshape(k, -1, 2), u[:, na:].reshape(k, -1, 2)),
    )


def speeds_label(ds: xr.Dataset) -> str:
    """``"4,000/4,000 rpm"`` for a run."""
    run = json.loads(ds.attrs["case"])["run"]
    return f"{run['speed_a_rpm']:,.0f}/{run['speed_b_rpm']:,.0f} rpm"


__all__ = ["ToothFrames", "case_from_run", "speeds_label", "tooth_frames"]
