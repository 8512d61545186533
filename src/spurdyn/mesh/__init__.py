"""Q8 meshes of gear teeth."""

from spurdyn.mesh.tooth import DEFAULT_NX, DEFAULT_NY, ToothMesh, tooth_mesh

__all__ = ["DEFAULT_NX", "DEFAULT_NY", "ToothMesh", "tooth_mesh"]
