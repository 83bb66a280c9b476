"""Conversions between mesohex results and meshio (python3-meshio), for everything meshio reads and writes."""
import numpy as np


def to_meshio(result):
    """A ``meshio.Mesh`` of a ``mesohex.HexMesh`` or of a meshing result (``mesohex.mesh`` / ``mesohex.auto``).

    Hexes are meshio "hexahedron" cells (VTK order, as in mesohex). A result's per-hex scaled Jacobian and, when it
    was partitioned, its part ids become the cell data "scaled_jacobian" and "partition"."""
    import meshio

    mesh = getattr(result, "mesh", result)
    cell_data = {}
    sj = getattr(result, "scaled_jacobian", None)
    if sj is not None and len(sj) == len(mesh.hexes):
        cell_data["scaled_jacobian"] = [np.asarray(sj, dtype=np.float64)]
    part = getattr(result, "partition", None)
    if part is not None:
        cell_data["partition"] = [np.asarray(part, dtype=np.int32)]
    return meshio.Mesh(mesh.vertices, [("hexahedron", mesh.hexes)], cell_data=cell_data)


def from_meshio(mesh):
    """A ``mesohex.HexMesh`` from the "hexahedron" cells of a ``meshio.Mesh`` (other cell types are ignored)."""
    from ._mesohex import HexMesh, InvalidInput

    blocks = [np.asarray(c.data) for c in mesh.cells if c.type == "hexahedron"]
    if not blocks:
        raise InvalidInput("from_meshio: the meshio mesh has no hexahedron cells")
    return HexMesh(np.asarray(mesh.points, dtype=np.float64)[:, :3], np.concatenate(blocks))
