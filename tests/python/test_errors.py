"""Bad input raises the library's exceptions with its messages, never a crash; arrays of the
wrong shape are refused with a message naming the expected shape."""

import numpy as np
import pytest

import vessel
from conftest import run_cli

# Real meshes the library refuses, with words of the documented message (docs/bad-input.md).
REFUSED = {
    "vmtk-test-data/aorta-surface.vtp": "the surface is closed (no open ends)",
    "openlb/aneurysm3d.stl": "1 duplicate face (same three vertices as another face)",
    "vmtk-test-data/aorta-surface-branch-split.ply": "coincident boundary loops",
}


@pytest.mark.parametrize("name", sorted(REFUSED))
def test_refused_real_mesh_same_message_as_cli(name, real_data, flatten_exe, tmp_path):
    mesh = real_data / name
    surface = vessel.read(mesh)
    with pytest.raises(vessel.InvalidInputError) as raised:
        vessel.flatten(surface)
    assert isinstance(raised.value, ValueError)
    message = str(raised.value)
    assert REFUSED[name] in message
    done = run_cli(flatten_exe, mesh, tmp_path / "out.obj")
    assert done.returncode == 1
    # The CLI names the input before the library's message (one line: file, place, what to do).
    assert done.stderr.strip() == f"vessel-flatten: {mesh}: {message}"


@pytest.fixture(scope="module")
def tube(carotid):
    return vessel.read(carotid)


def test_points_of_wrong_shape(tube):
    with pytest.raises(vessel.InvalidInputError, match=r"points must be an \(n, 3\) array.*\(.*, 2\)"):
        vessel.flatten(tube.points[:, :2], tube.faces)
    with pytest.raises(vessel.InvalidInputError, match=r"points must be an \(n, 3\)"):
        vessel.flatten(tube.points.reshape(-1), tube.faces)


def test_faces_of_wrong_shape_or_type(tube):
    with pytest.raises(vessel.InvalidInputError, match=r"faces must be an \(m, 3\) array"):
        vessel.flatten(tube.points, tube.faces[:, :2])
    with pytest.raises(vessel.InvalidInputError, match="faces must be integer indices"):
        vessel.flatten(tube.points, tube.faces.astype(float))
    with pytest.raises(vessel.InvalidInputError, match="points must be real numbers"):
        vessel.flatten(tube.points.astype(str), tube.faces)


def test_corner_outside_the_points(tube):
    faces = tube.faces.copy()
    faces[7, 1] = len(tube.points)
    with pytest.raises(vessel.InvalidInputError, match=r"faces\[7\] has corner .* outside the"):
        vessel.flatten(tube.points, faces)
    faces[7, 1] = -1
    with pytest.raises(vessel.InvalidInputError, match=r"faces\[7\]"):
        vessel.flatten(tube.points, faces)


def test_not_a_tree_surface(tube):
    points = tube.points.copy()
    points[3, 0] = np.nan
    with pytest.raises(vessel.InvalidInputError, match="NaN|finite"):
        vessel.flatten(points, tube.faces)
    # Two copies side by side: several components.
    two = np.vstack([tube.faces, tube.faces + len(tube.points)])
    with pytest.raises(vessel.InvalidInputError, match="component"):
        vessel.flatten(np.vstack([tube.points, tube.points + 100]), two)
    with pytest.raises(vessel.InvalidInputError):
        vessel.flatten(np.zeros((0, 3)), np.zeros((0, 3), dtype=int))


def test_bad_options(tube):
    with pytest.raises(TypeError, match="unknown option 'colour'"):
        vessel.flatten(tube, colour="red")
    with pytest.raises(TypeError, match="option 'blend' must be a number"):
        vessel.flatten(tube, blend="much")
    with pytest.raises(vessel.InvalidInputError, match="blend must be in"):
        vessel.flatten(tube, cost="blend", blend=2.0)
    with pytest.raises(vessel.InvalidInputError, match="cost='straight' is not one of"):
        vessel.flatten(tube, cost="straight")
    with pytest.raises(vessel.InvalidInputError, match="unknown preset 'fancy'; known presets"):
        vessel.flatten(tube, preset="fancy")
    with pytest.raises(vessel.InvalidInputError, match="viewpoint must be 3 numbers"):
        vessel.flatten(tube, viewpoint=(1, 2))
    with pytest.raises(vessel.InvalidInputError, match='or "face-on", got "sideways"'):
        vessel.flatten(tube, viewpoint="sideways")


def test_unreadable_files(tmp_path):
    with pytest.raises(vessel.IoError) as raised:
        vessel.read(tmp_path / "missing.ply")
    assert isinstance(raised.value, OSError) and "missing.ply" in str(raised.value)
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nf 1 2 3\n")
    with pytest.raises(vessel.Error):
        vessel.read(bad)


def test_map_arrays_of_wrong_shape(tube):
    flat = vessel.flatten(tube)
    n = len(tube.points)
    for shape in [(n + 1,), (n - 1, 3), (4, n + 2), ()]:
        with pytest.raises(vessel.InvalidInputError, match=r"one row per input point"):
            flat.map_points(np.zeros(shape))
    with pytest.raises(vessel.InvalidInputError, match=r"one row per input face"):
        flat.map_cells(np.zeros(len(tube.faces) + 3))
