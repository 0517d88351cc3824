"""Per-point and per-face arrays carried onto the cut mesh, and VTK's Python objects in and out."""

import subprocess

import numpy as np
import pytest

import vessel
from conftest import run_cli


@pytest.fixture(scope="module")
def artery(real_data):
    surface = vessel.read(real_data / "vampy/artery.vtp")
    return surface, vessel.flatten(surface)


def test_point_arrays_follow_their_points(artery):
    surface, flat = artery
    # The input's coordinates, carried across, are the cut mesh's coordinates.
    np.testing.assert_array_equal(flat.map_points(surface.points), flat.points)
    x = surface.points[:, 0]
    np.testing.assert_array_equal(flat.map_points(x), flat.points[:, 0])
    # A series (T, n) and (T, n, c): each step carried alike.
    steps = np.stack([surface.points * (t + 1) for t in range(4)])
    mapped = flat.map_points(steps)
    assert mapped.shape == (4, len(flat.points), 3)
    for t in range(4):
        np.testing.assert_array_equal(mapped[t], flat.points * (t + 1))
    np.testing.assert_array_equal(flat.map_points(steps[:, :, 2]), mapped[:, :, 2])
    # The file's own arrays (Normals) as well.
    normals = flat.map_points(surface.point_data["Normals"])
    assert normals.shape == (len(flat.points), 3)


def test_cell_arrays_follow_their_faces(artery):
    surface, flat = artery
    centroids = surface.points[surface.faces].mean(axis=1)
    np.testing.assert_allclose(flat.map_cells(centroids), flat.points[flat.faces].mean(axis=1))
    series = np.stack([centroids[:, 0], centroids[:, 1]])
    assert flat.map_cells(series).shape == (2, len(flat.faces))


def test_same_fields_as_cli_vtp(real_data, flatten_exe, tmp_path):
    # vessel-flatten OUT.vtp carries the input's arrays through the cut: the same as map_points.
    from vtkmodules.util import numpy_support
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    mesh = real_data / "svfsi-tests/pulmonary-glenn-wall.vtp"
    surface = vessel.read(mesh)
    assert set(surface.point_data) == {"GlobalNodeID"}
    assert set(surface.cell_data) == {"GlobalElementID", "GlobalElementID2"}
    flat = vessel.flatten(surface, refine="none", relief_cuts=0)
    out = tmp_path / "glenn.vtp"
    done = run_cli(flatten_exe, mesh, out, "--refine", "none", "--relief-cuts", "0")
    assert done.returncode == 0, done.stderr
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(out))
    reader.Update()
    cli = reader.GetOutput()
    assert cli.GetNumberOfPoints() == len(flat.points)
    ids = numpy_support.vtk_to_numpy(cli.GetPointData().GetArray("GlobalNodeID"))
    np.testing.assert_array_equal(ids, flat.map_points(surface.point_data["GlobalNodeID"]))
    cells = numpy_support.vtk_to_numpy(cli.GetCellData().GetArray("GlobalElementID"))
    np.testing.assert_array_equal(cells, flat.map_cells(surface.cell_data["GlobalElementID"]))
    uv = numpy_support.vtk_to_numpy(cli.GetPointData().GetTCoords())
    np.testing.assert_allclose(uv, flat.uv, rtol=1e-6, atol=1e-6 * np.ptp(flat.uv))


def test_from_vtk_reads_like_read(real_data):
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    path = real_data / "vampy/artery.vtp"
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(path))
    reader.Update()
    ours = vessel.from_vtk(reader.GetOutput())
    read = vessel.read(path)
    np.testing.assert_array_equal(ours.points, read.points)
    np.testing.assert_array_equal(ours.faces, read.faces)
    assert set(ours.point_data) == set(read.point_data)
    np.testing.assert_allclose(ours.point_data["Normals"], read.point_data["Normals"])
    with pytest.raises(vessel.InvalidInputError, match="takes a vtkPolyData"):
        vessel.from_vtk(read.points)


def test_from_vtk_refuses_lines():
    from vtkmodules.vtkFiltersSources import vtkLineSource
    line = vtkLineSource()
    line.Update()
    with pytest.raises(vessel.InvalidInputError, match="line cells"):
        vessel.from_vtk(line.GetOutput())


def test_to_vtk_round_trip(artery):
    from vtkmodules.util import numpy_support
    surface, flat = artery
    x = surface.points[:, 0]
    pd = vessel.to_vtk(flat, point_data={"x": x}, cell_data={"face": np.arange(len(surface.faces))})
    assert pd.GetNumberOfPoints() == len(flat.points)
    assert pd.GetNumberOfCells() == len(flat.faces)
    np.testing.assert_array_equal(numpy_support.vtk_to_numpy(pd.GetPointData().GetTCoords()), flat.uv)
    np.testing.assert_array_equal(numpy_support.vtk_to_numpy(pd.GetPointData().GetArray("x")),
                                  flat.points[:, 0])
    back = vessel.from_vtk(pd)
    np.testing.assert_array_equal(back.points, flat.points)
    np.testing.assert_array_equal(back.faces, flat.faces)
    # The map as a flat surface: z = 0, same triangles; flattening it again is refused (a disk
    # with no open end but one is flattened without cuts, so check the geometry only).
    m = flat.to_vtk(flat=True)
    pts = numpy_support.vtk_to_numpy(m.GetPoints().GetData())
    np.testing.assert_array_equal(pts[:, :2], flat.uv)
    assert not pts[:, 2].any()
    with pytest.raises(vessel.InvalidInputError, match="one time step"):
        vessel.to_vtk(flat, point_data={"series": np.zeros((3, len(surface.points)))})
    with pytest.raises(vessel.InvalidInputError, match="one row per input point"):
        vessel.to_vtk(flat, point_data={"bad": np.zeros(5)})


def test_flatten_from_vtk_source_object(real_data):
    # A notebook's vtkPolyData (here from VTK's reader) passes straight in.
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(real_data / "vampy/artery.vtp"))
    reader.Update()
    flat = vessel.flatten(vessel.from_vtk(reader.GetOutput()))
    np.testing.assert_array_equal(flat.uv, vessel.flatten(vessel.read(reader.GetFileName())).uv)
