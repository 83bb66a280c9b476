"""The compiled module: data types, files, quality, partition, generate, thicken, errors, meshio conversion."""
import os

import numpy as np
import pytest

import mesohex
from conftest import block


def test_hexmesh_arrays_and_validation():
    m = block(2, 1, 1)
    assert m.vertices.shape == (12, 3) and m.vertices.dtype == np.float64
    assert m.hexes.shape == (2, 8) and m.hexes.dtype == np.int32
    assert m.hexes[1].tolist() == [1, 2, 5, 4, 7, 8, 11, 10]
    with pytest.raises(mesohex.InvalidInput) as e:
        mesohex.HexMesh(m.vertices, np.array([[0, 1, 2, 3, 4, 5, 6, 12]]))
    assert "refers to vertex 12" in str(e.value)
    assert e.value.code == 2 and e.value.category == "InvalidInput"
    with pytest.raises(mesohex.InvalidInput):
        mesohex.HexMesh(np.zeros((4, 2)), np.zeros((0, 8), dtype=int))
    with pytest.raises(mesohex.InvalidInput):
        mesohex.HexMesh(np.array([[0.0, np.nan, 0.0]]), np.zeros((0, 8), dtype=int))


def test_error_hierarchy_and_codes():
    assert issubclass(mesohex.InvalidInput, mesohex.Error)
    assert issubclass(mesohex.Error, RuntimeError)
    codes = {cls.__name__: cls.code for cls in (mesohex.InvalidInput, mesohex.UnsupportedConfiguration,
                                                  mesohex.IoError, mesohex.NumericalFailure)}
    assert codes == {"InvalidInput": 2, "UnsupportedConfiguration": 3, "IoError": 4, "NumericalFailure": 6}


def test_files_round_trip(tmp_path):
    m = block(3, 2, 2)
    for ext in (".mesh", ".vtk", ".vtu", ".msh"):
        path = str(tmp_path / ("m" + ext))
        mesohex.write_hex_mesh(path, m)
        assert mesohex.read_hex_mesh(path) == m
    with pytest.raises(mesohex.UnsupportedConfiguration) as e:
        mesohex.write_hex_mesh(str(tmp_path / "m.obj"), m)
    assert e.value.code == 3
    with pytest.raises(mesohex.IoError) as e:
        mesohex.read_hex_mesh(str(tmp_path / "missing.mesh"))
    assert "missing.mesh" in str(e.value) and e.value.code == 4
    bad = tmp_path / "bad.mesh"
    bad.write_text("MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 0 zero 0\n")
    with pytest.raises(mesohex.InvalidInput) as e:
        mesohex.read_hex_mesh(str(bad))
    assert "bad.mesh:5" in str(e.value)


def test_quality_of_a_block_and_a_mirrored_cube():
    q = mesohex.quality(block(2, 2, 2))
    assert q["hexes"] == 8 and q["vertices"] == 27
    assert q["sj_min"] == 1.0 and q["inverted"] == 0
    cube = block(1, 1, 1)
    mirrored = mesohex.HexMesh(cube.vertices * np.array([-1.0, 1.0, 1.0]), cube.hexes)
    assert mesohex.scaled_jacobians(mirrored).tolist() == [-1.0]
    assert mesohex.quality(mirrored)["inverted"] == 1


def test_partition_of_a_grid():
    p = mesohex.partition(block(4, 4, 4), 4)
    assert p["parts"] == 4
    assert p["part"].shape == (64,)
    assert sorted(set(p["part"].tolist())) == [0, 1, 2, 3]
    assert sum(p["part_sizes"]) == 64 and min(p["part_sizes"]) > 0
    assert p["imbalance"] <= 0.05
    assert 32 <= p["edge_cut"] <= 48  # optimum 32 (two cutting planes), slabs 48
    with pytest.raises(mesohex.InvalidInput):
        mesohex.partition(block(2, 1, 1), 3)


def test_exodus_through_the_module(tmp_path):
    import netCDF4
    m = block(2, 2, 2)
    path = str(tmp_path / "m.exo")
    mesohex.write_hex_mesh(path, m, scaled_jacobian=mesohex.scaled_jacobians(m),
                           partition=mesohex.partition(m, 2)["part"])
    ds = netCDF4.Dataset(path)
    assert ds.file_format == "NETCDF3_64BIT_OFFSET"
    assert len(ds.dimensions["num_elem"]) == 8 and len(ds.dimensions["num_el_blk"]) == 2
    assert len(ds.dimensions["num_side_ss1"]) == 24
    ds.close()


def test_generate_and_skeleton_files(tmp_path):
    assert "plate" in mesohex.generator_names()
    s = mesohex.generate("plate", n=2, m=3)
    # a 2 x 3 plate of quads: 3 x 4 points, 2*4 + 3*3 = 17 edges, 6 faces
    assert s.points.shape == (12, 3) and s.edges.shape == (17, 2) and len(s.faces) == 6
    assert s.radii.shape == (12,) and (s.radii > 0).all()
    path = str(tmp_path / "plate.obj")
    mesohex.write_skeleton(path, s)
    back = mesohex.read_skeleton(path)
    assert back.points.shape == (12, 3) and len(back.faces) == 6 and back.edges.shape == (17, 2)
    with pytest.raises(mesohex.InvalidInput) as e:
        mesohex.generate("no-such-shape")
    assert "plate" in str(e.value)  # the message lists the valid names


def test_skeleton_from_arrays_adds_face_edges():
    pts = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]], dtype=float)
    s = mesohex.Skeleton(pts, np.array([[1, 4]]), faces=[[0, 1, 2, 3]], radii=np.full(5, 0.2))
    assert s.edges.shape == (5, 2)  # the branch edge + the 4 sides of the quad
    with pytest.raises(mesohex.InvalidInput):
        mesohex.Skeleton(pts, np.array([[0, 5]]))
    with pytest.raises(mesohex.InvalidInput):
        mesohex.Skeleton(pts, np.zeros((0, 2), dtype=int), faces=[[0, 1, 9, 3]])
    with pytest.raises(mesohex.InvalidInput):
        mesohex.Skeleton(pts, np.zeros((0, 2), dtype=int), radii=np.ones(3))


def test_thicken_a_single_edge(tmp_path):
    s = mesohex.Skeleton(np.array([[0, 0, 0], [2, 0, 0]], dtype=float), np.array([[0, 1]]), radii=np.array([0.5, 0.5]))
    surface = mesohex.thicken(s, resolution=3)
    v, t = surface.vertices, surface.triangles
    assert len(v) > 0 and t.shape[1] == 3
    # closed: every edge of the triangles is shared by exactly two triangles
    edges = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert (counts == 2).all()
    # the capsule lies within radius 0.5 (+ one grid cell) of the segment, x in [-0.5, 2.5]
    assert v[:, 0].min() >= -0.5 - 0.2 and v[:, 0].max() <= 2.5 + 0.2
    path = str(tmp_path / "capsule.off")
    mesohex.write_surface(path, surface)
    assert mesohex.read_surface(path).triangles.shape == t.shape
    with pytest.raises(mesohex.InvalidInput):
        mesohex.thicken(mesohex.Skeleton(np.zeros((1, 3)), np.zeros((0, 2), dtype=int)))


def test_meshio_conversion(tmp_path):
    import meshio
    m = block(2, 2, 1)
    mm = mesohex.to_meshio(m)
    assert mm.points.shape == (18, 3)
    assert mm.cells[0].type == "hexahedron" and mm.cells[0].data.tolist() == m.hexes.tolist()
    path = str(tmp_path / "via_meshio.vtu")
    mm.write(path, binary=False)
    assert mesohex.read_hex_mesh(path) == m
    assert mesohex.from_meshio(meshio.read(path)) == m
