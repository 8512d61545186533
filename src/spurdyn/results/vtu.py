"""ParaView output: the tooth frames as a time series of ``.vtu`` files and a ``.pvd``.

``write_vtu_series`` writes ``vtu/frame_0000.vtu`` ... (both teeth, 8-node quadrilaterals
at their deformed world positions) and ``result.pvd`` that lists them with their times.
Point data: ``displacement`` (absolute, world frame) and ``elastic_displacement`` (the
elastic part, turned with its gear: use *Warp By Vector* on it to magnify the
deformation); cell data: ``von_mises`` (Pa) and ``gear`` (0: A, 1: B).
"""

from __future__ import annotations

from pathlib import Path
from xml.sax.saxutils import quoteattr

import meshio
import numpy as np
import xarray as xr

from spurdyn.results.frames import tooth_frames

PVD_FILE = "result.pvd"
VTU_DIR = "vtu"


def _three(xy: np.ndarray) -> np.ndarray:
    return np.column_stack([xy, np.zeros(len(xy))])


def write_vtu_series(ds: xr.Dataset, directory: str | Path) -> Path:
    """Write the frames of ``ds`` for ParaView into ``directory``; return the ``.pvd``."""
    directory = Path(directory)
    frames = tooth_frames(ds)
    mesh_a, mesh_b = frames.meshes
    cells = np.vstack([mesh_a.elements, mesh_b.elements + mesh_a.n_nodes])
    gear_id = np.concatenate([np.zeros(mesh_a.n_elements, np.int32),
                              np.ones(mesh_b.n_elements, np.int32)])
    (directory / VTU_DIR).mkdir(exist_ok=True)
    entries = []
    for k in range(frames.n_frames):
        points, disp, elastic, vm = [], [], [], []
        for g in (0, 1):
            points.append(frames.positions(g, k))
            disp.append(frames.u[g][k])
            elastic.append(frames.elastic(g, k) @ frames.rotation(g, k).T)
            vm.append(frames.von_mises(g, k))
        name = f"{VTU_DIR}/frame_{k:04d}.vtu"
        meshio.write(directory / name, meshio.Mesh(
            _three(np.vstack(points)), [("quad8", cells)],
            point_data={"displacement": _three(np.vstack(disp)),
                        "elastic_displacement": _three(np.vstack(elastic))},
            cell_data={"von_mises": [np.concatenate(vm)], "gear": [gear_id]}),
            file_format="vtu", binary=True)
        entries.append(f'    <DataSet timestep="{frames.time[k]:.12g}" part="0" file={quoteattr(name)}/>')
    pvd = directory / PVD_FILE
    pvd.write_text('<?xml version="1.0"?>\n'
                   '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
                   "  <Collection>\n" + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n",
                   encoding="utf-8")
    return pvd
