"""Q8 meshes of gear teeth: one tooth (:mod:`~spurdyn.mesh.tooth`), and a sector of K teeth
on their rim down to the hub (:mod:`~spurdyn.mesh.sector`)."""

from spurdyn.mesh.tooth import DEFAULT_NX, DEFAULT_NY, ToothMesh, tooth_mesh

__all__ = ["DEFAULT_NX", "DEFAULT_NY", "ToothMesh", "tooth_mesh"]
