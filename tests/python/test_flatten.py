"""vessel.flatten() against vessel-flatten on the same meshes and options: the same map, cut mesh
and report; and the properties of the result itself."""

import json
import subprocess

import numpy as np
import pytest

import vessel
from conftest import read_seam_obj, run_cli

# Valid real trees of ../shared/data/real that flatten in about a second or less each
# (docs/results.md); the others are exercised by the C++ suite.
REAL_TREES = [
    "vampy/artery-coarse.ply",
    "vampy/artery.vtp",
    "x-ray-angio-data/coronary-clinical-branch-fine.ply",
    "vmtk-test-data/aorta-surface-open-ends.ply",
    "simvascular-tests/demo-model-open.ply",
]


def assert_same_map_as_cli(flat, obj, input_points):
    v, vt, fv, ft = read_seam_obj(obj)
    # The OBJ's v lines are the input points; f v/vt names each corner's input point and cut vertex.
    np.testing.assert_allclose(v, input_points, rtol=1e-8, atol=1e-8 * np.ptp(input_points))
    np.testing.assert_array_equal(ft, flat.faces)
    np.testing.assert_array_equal(fv, flat.origin[flat.faces])
    assert vt.shape == flat.uv.shape
    # vt is printed with 9 significant digits.
    extent = np.ptp(flat.uv, axis=0).max()
    np.testing.assert_allclose(flat.uv, vt, rtol=0, atol=1e-8 * extent)


def check_result(flat, surface):
    n, m = len(surface.points), len(surface.faces)
    k = len(flat.points)
    assert flat.uv.shape == (k, 2) and flat.uv.dtype == np.float64
    assert flat.faces.shape == (m, 3) and flat.faces.min() >= 0 and flat.faces.max() < k
    assert flat.origin.shape == (k,) and flat.origin.min() >= 0 and flat.origin.max() < n
    # Cutting duplicates the seam's vertices: every input point is there, some more than once.
    assert k >= n and len(np.unique(flat.origin)) == n
    np.testing.assert_array_equal(flat.points, surface.points[flat.origin])
    np.testing.assert_array_equal(flat.face_origin, np.arange(m))
    assert np.isfinite(flat.uv).all()
    # Each cut runs over input points, from its outlet to where it ends.
    assert len(flat.cuts) >= 1
    for cut in flat.cuts:
        assert cut["vertices"].ndim == 1 and len(cut["vertices"]) == cut["edges"] + 1
        assert cut["vertices"].min() >= 0 and cut["vertices"].max() < n
    assert flat.quality["flipped_triangles"] == 0
    assert set(["Z", "GC", "VC", "AC", "L", "F", "total"]) <= set(flat.timings)
    assert all(t >= 0 for t in flat.timings.values())
    # The 2D area is the 3D area up to the map's distortion (docs/results.md: within 3.5%).
    assert abs(flat.quality["area_ratio"] - 1) < 0.05


def test_phantom_same_map_as_cli(carotid, flatten_exe, tmp_path):
    surface = vessel.read(carotid)
    flat = vessel.flatten(surface.points, surface.faces)
    check_result(flat, surface)
    obj, report = tmp_path / "carotid.obj", tmp_path / "carotid.json"
    done = run_cli(flatten_exe, carotid, obj, "--report", str(report))
    assert done.returncode == 0, done.stderr
    assert_same_map_as_cli(flat, obj, surface.points)
    cli = json.loads(report.read_text())
    for part in ("quality", "cuts", "counts", "relief_cuts", "notes"):
        assert flat.report[part] == cli[part], part


def test_aneurysm_phantom_same_surface_as_cli(phantom_exe, tmp_path):
    path = tmp_path / "aneurysm.ply"
    subprocess.run([str(phantom_exe), "aneurysm", "--sac-radius", "5", "--edge-length", "0.5",
                    "-q", "-o", str(path)], check=True)
    cli = vessel.read(path)
    made = vessel.phantom("aneurysm", sac_radius=5.0, edge_length=0.5)
    assert np.array_equal(made.faces, cli.faces)
    assert np.allclose(made.points, cli.points, rtol=0, atol=1e-5)
    # The sac bulges on +x, 2 + 0.8 * 5 + 5 = 11 mm off the parent's axis.
    assert made.points[:, 0].max() == pytest.approx(11.0, rel=0.02)


def test_phantom_same_map_as_cli_with_options(carotid, flatten_exe, tmp_path):
    surface = vessel.read(carotid)
    flat = vessel.flatten(surface, cost="blend", blend=0.3, alpha=30, refine="arap",
                          arap_iterations=20, viewpoint=(0, -200, 0))
    obj = tmp_path / "carotid.obj"
    done = run_cli(flatten_exe, carotid, obj, "--cost", "blend", "--blend", "0.3", "--alpha",
                   "30", "--refine", "arap", "--arap-iterations", "20",
                   "--viewpoint", "0", "-200", "0")
    assert done.returncode == 0, done.stderr
    assert_same_map_as_cli(flat, obj, surface.points)
    # ...and the options changed the map (the defaults give another one).
    default = vessel.flatten(surface)
    assert default.uv.shape != flat.uv.shape or not np.allclose(default.uv, flat.uv)


def test_face_on_viewpoint_same_map_as_cli(carotid, flatten_exe, tmp_path):
    surface = vessel.read(carotid)
    flat = vessel.flatten(surface, viewpoint="face-on")
    check_result(flat, surface)
    obj, report = tmp_path / "carotid.obj", tmp_path / "carotid.json"
    done = run_cli(flatten_exe, carotid, obj, "--viewpoint", "face-on", "--report", str(report))
    assert done.returncode == 0, done.stderr
    assert_same_map_as_cli(flat, obj, surface.points)
    cli = json.loads(report.read_text())
    # The viewpoint taken from the mesh, two bounding-box diagonals from its centre, and the
    # cuts behind the vessels from there.
    assert flat.report["cuts_viewpoint"] == cli["cuts_viewpoint"]
    assert cli["quality"]["seam_far_side_fraction"] >= 0.8


@pytest.mark.parametrize("name", REAL_TREES)
def test_real_tree_same_map_as_cli(name, real_data, flatten_exe, tmp_path):
    mesh = real_data / name
    surface = vessel.read(mesh)
    flat = vessel.flatten(surface)
    check_result(flat, surface)
    obj = tmp_path / "flat.obj"
    done = run_cli(flatten_exe, mesh, obj)
    assert done.returncode == 0, done.stderr
    assert_same_map_as_cli(flat, obj, surface.points)


def test_paper_preset_same_map_as_cli(real_data, flatten_exe, tmp_path):
    mesh = real_data / "vampy/artery-coarse.ply"
    surface = vessel.read(mesh)
    paper = vessel.flatten(surface, preset="paper")
    obj = tmp_path / "paper.obj"
    done = run_cli(flatten_exe, mesh, obj, "--preset", "paper")
    assert done.returncode == 0, done.stderr
    assert_same_map_as_cli(paper, obj, surface.points)
    # The paper's method: ARAP ran, no SLIM and no relief cut; not the default's map.
    assert paper.report["arap"]["iterations"] > 0 and paper.report["slim"]["iterations"] == 0
    assert paper.relief_cuts == []
    default = vessel.flatten(surface)
    assert default.uv.shape != paper.uv.shape or not np.allclose(default.uv, paper.uv)
    # Options given with the preset change it, as on the command line.
    obj = tmp_path / "paper-alpha.obj"
    done = run_cli(flatten_exe, mesh, obj, "--preset", "paper", "--alpha", "30")
    assert done.returncode == 0, done.stderr
    assert_same_map_as_cli(vessel.flatten(surface, preset="paper", alpha=30), obj, surface.points)


def test_options_and_presets_listed():
    names = vessel.flatten_options()
    for name in ("cost", "blend", "alpha", "refine", "overlaps", "area_polish", "viewpoint"):
        assert name in names
    assert {"default", "paper"} <= set(vessel.presets())


def test_threads_give_the_same_maps(carotid, real_data):
    # flatten() releases the GIL: maps made on two threads at once equal those made one by one.
    from concurrent.futures import ThreadPoolExecutor
    surfaces = [vessel.read(carotid), vessel.read(real_data / "vampy/artery-coarse.ply")]
    alone = [vessel.flatten(s).uv for s in surfaces]
    with ThreadPoolExecutor(max_workers=2) as pool:
        together = list(pool.map(lambda s: vessel.flatten(s).uv, surfaces))
    for a, b in zip(alone, together):
        np.testing.assert_array_equal(a, b)


def test_remove_caps_same_map_as_cli(real_data, flatten_exe, tmp_path):
    # SimVascular's capped demo model: its 3 flat caps removed, it maps as the open model does
    # (MANIFEST.md: demo-model-open.ply is this file without the caps' 145 triangles).
    mesh = real_data / "simvascular-tests/demo-model-capped.ply"
    surface = vessel.read(mesh)
    with pytest.raises(vessel.InvalidInputError, match="--remove-caps"):
        vessel.flatten(surface)
    flat = vessel.flatten(surface, remove_caps=True)
    obj = tmp_path / "flat.obj"
    done = run_cli(flatten_exe, mesh, obj, "--remove-caps")
    assert done.returncode == 0, done.stderr
    assert flat.report["flat_caps_removed"] == 3
    assert_same_map_as_cli(flat, obj, surface.points)
    assert len(flat.face_origin) == len(surface.faces) - 145
    assert flat.quality["flipped_triangles"] == 0
    opened = vessel.flatten(vessel.read(real_data / "simvascular-tests/demo-model-open.ply"))
    assert flat.quality["mean_abs_log_area_ratio"] == pytest.approx(
        opened.quality["mean_abs_log_area_ratio"], rel=1e-6)
