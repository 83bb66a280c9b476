"""mesohex.mesh and mesohex.auto: the same library call, options, report keys and errors as the CLI."""
import json

import numpy as np
import pytest

import mesohex

FAST = dict(levels=0, iterations=30, threads=1)  # a small mesh and a short fit: about a second


@pytest.fixture(scope="module")
def plate(tmp_path_factory):
    """A generated 2 x 2 plate skeleton and its thickened domain, as files."""
    d = tmp_path_factory.mktemp("plate")
    mesohex.write_skeleton(str(d / "plate.obj"), mesohex.generate("plate", n=2, m=2))
    mesohex.write_surface(str(d / "plate.off"), mesohex.thicken(mesohex.read_skeleton(str(d / "plate.obj")),
                                                                resolution=2))
    return d


def test_raw_mesh_matches_the_prediction():
    s = mesohex.generate("plate", n=2, m=2)
    r = mesohex.mesh(s, no_resample=True)
    # A 2 x 2 plate, input sampling: 4 quads -> plates and half-chunks as predicted by the analysis.
    assert r.report["prediction_matches"] is True
    assert len(r.hexes) == r.report["predicted"]["hexes"] == r.report["quality"]["hexes"]
    assert r.vertices.dtype == np.float64 and r.hexes.dtype == np.int32 and r.hexes.shape[1] == 8
    assert r.scaled_jacobian.shape == (len(r.hexes),)
    assert abs(r.scaled_jacobian.min() - r.report["quality"]["sj_min"]) < 1e-12
    assert r.partition is None and "partition" not in r.report
    assert r.status == (5 if r.report["quality"]["inverted"] > 0 else 0)


def test_mesh_in_a_domain_like_the_cli(plate, tmp_path, cli):
    r = mesohex.mesh(str(plate / "plate.obj"), str(plate / "plate.off"), output=str(tmp_path / "py.vtu"),
                     report=str(tmp_path / "py.json"), partitions=4, **FAST)
    cli("mesh", plate / "plate.obj", "--surface", plate / "plate.off", "-o", tmp_path / "cli.vtu", "--report",
        tmp_path / "cli.json", "--levels", "0", "--iterations", "30", "--threads", "1", "--partitions", "4", "-q")
    ours = json.loads((tmp_path / "py.json").read_text())
    theirs = json.loads((tmp_path / "cli.json").read_text())
    assert sorted(ours) == sorted(theirs) == sorted(r.report)
    assert sorted(ours["timings_ms"]) == sorted(theirs["timings_ms"])
    for key in ("quality", "raw_quality", "predicted", "partition", "hausdorff", "attempts", "subdivision_levels"):
        assert ours[key] == theirs[key], key
    assert (tmp_path / "py.vtu").read_bytes() == (tmp_path / "cli.vtu").read_bytes()  # the same file
    assert r.report["input"] == str(plate / "plate.obj") and r.report["surface"] == str(plate / "plate.off")
    # 4 parts of the final mesh, as cell data too
    assert sorted(set(r.partition.tolist())) == [0, 1, 2, 3]
    assert r.report["partition"]["parts"] == 4 and sum(r.report["partition"]["part_sizes"]) == len(r.hexes)
    m = mesohex.to_meshio(r)
    assert m.cell_data["partition"][0].tolist() == r.partition.tolist()
    assert np.array_equal(m.cell_data["scaled_jacobian"][0], r.scaled_jacobian)


def test_objects_in_objects_out(plate):
    s = mesohex.read_skeleton(str(plate / "plate.obj"))
    domain = mesohex.read_surface(str(plate / "plate.off"))
    r = mesohex.mesh(s, domain, **FAST)
    assert r.report["surface"] == "" and r.report["output"] == ""
    assert r.report["quality"]["hexes"] == len(r.hexes) > 0
    assert "hausdorff" in r.report


def test_errors_carry_the_exit_status(plate, tmp_path):
    with pytest.raises(mesohex.IoError) as e:
        mesohex.mesh(str(tmp_path / "missing.obj"))
    assert e.value.code == 4 and "missing.obj" in str(e.value)
    with pytest.raises(mesohex.InvalidInput) as e:
        mesohex.mesh(str(plate / "plate.obj"), levls=1)
    assert "unknown option 'levls'" in str(e.value) and "levels" in str(e.value)
    with pytest.raises(mesohex.InvalidInput):
        mesohex.auto(str(plate / "plate.off"), radius=1.0)  # auto has no --radius
    with pytest.raises(mesohex.InvalidInput):
        mesohex.mesh(str(plate / "plate.obj"), refine="diagonal")
    broken = tmp_path / "broken.obj"
    broken.write_text("v 0 0 0\nv 1 0 0\nl 1 7\n")
    with pytest.raises(mesohex.InvalidInput) as e:
        mesohex.mesh(str(broken))
    assert "broken.obj:3" in str(e.value) and e.value.code == 2
    with pytest.raises(mesohex.InvalidInput) as e:
        mesohex.mesh(mesohex.generate("plate", n=1, m=1), partitions=1000)
    assert "1000" in str(e.value)
    with pytest.raises(mesohex.UnsupportedConfiguration):
        mesohex.mesh(mesohex.generate("plate", n=1, m=1), output=str(tmp_path / "m.stl"))
    assert not (tmp_path / "m.stl").exists()


def test_no_retry_is_one_attempt(tmp_path):
    """no_retry=True is the CLI's --no-retry: one attempt, no structural alternative either. A segment along the axis
    of a 4 x 1 x 1 box, one level: the first mesh misses a goal (tests/unit/test_mesh.cpp,
    StructuralAlternativesSkippedWhenTheyChangeNothing), so by default it is finished fully padded too and the
    structural alternatives are considered."""
    (tmp_path / "seg.obj").write_text("v 0.5 0.5 0.5\nv 3.5 0.5 0.5\nl 1 2\n")
    pts = [(0, 0, 0), (4, 0, 0), (4, 1, 0), (0, 1, 0), (0, 0, 1), (4, 0, 1), (4, 1, 1), (0, 1, 1)]
    quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    tris = [t for q in quads for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
    (tmp_path / "box.off").write_text("OFF\n8 12 0\n" + "".join("%d %d %d\n" % p for p in pts) +
                                      "".join("3 %d %d %d\n" % t for t in tris))
    args = (str(tmp_path / "seg.obj"), str(tmp_path / "box.off"))
    default = mesohex.mesh(*args, levels=1, threads=1).report
    assert [a["what"] for a in default["attempts"]] == ["first", "fully padded"]
    assert "structural_retry" in default
    one = mesohex.mesh(*args, levels=1, threads=1, no_retry=True).report
    assert [a["what"] for a in one["attempts"]] == ["first"] and one["kept_attempt"] == 0
    assert "structural_retry" not in one


def test_auto_on_a_capsule(tmp_path):
    capsule = mesohex.thicken(mesohex.Skeleton(np.array([[0, 0, 0], [4, 0, 0]], dtype=float), np.array([[0, 1]]),
                                               radii=np.array([0.6, 0.6])), resolution=3)
    out = tmp_path / "capsule.mesh"
    r = mesohex.auto(capsule, output=str(out), raw=True, threads=1)
    assert r.report["mode"] == "auto"
    assert r.report["skeleton_used"]["path"] == str(tmp_path / "capsule.skeleton.obj")
    assert (tmp_path / "capsule.skeleton.obj").exists()
    assert mesohex.read_hex_mesh(str(out)) == r.mesh
    assert r.report["skeleton_used"]["vertices"] >= 2 and len(r.hexes) > 0


def test_medial_of_a_capsule(tmp_path):
    # A capsule (a thickened segment) is a ball topologically: its medial mesh is one curve along the axis, no
    # sheet, Euler characteristic 1; the .ma file written has the header "V E F" of that mesh.
    capsule = mesohex.thicken(mesohex.Skeleton(np.array([[0, 0, 0], [4, 0, 0]], dtype=float), np.array([[0, 1]]),
                                               radii=np.array([0.6, 0.6])), resolution=3)
    out = tmp_path / "capsule.ma"
    m = mesohex.medial(capsule, output=str(out))
    assert m["euler_characteristic"] == 1
    assert m["sheets"] == 0 and m["curves"] == 1
    header = out.read_text().split("\n", 1)[0].split()
    medial = m["medial"]
    assert [int(x) for x in header] == [len(medial.points), len(medial.edges), len(medial.faces)]
