"""Cut a vessel-tree surface open along natural vessel cuts and flatten it into one 2D map.

The Python face of libvessel (README.md, docs/python.md)::

    import vessel
    surface = vessel.read("artery.vtp")              # points (n, 3), faces (m, 3), arrays
    flat = vessel.flatten(surface.points, surface.faces)
    flat.uv                                          # (k, 2) map of the cut mesh's vertices
    wss_on_map = flat.map_points(surface.point_data["WSS"])

Arrays go in and come out as numpy arrays. The flattening runs in the compiled library with the
GIL released, so threads (or Dask's threaded scheduler) flatten several meshes at once.

Errors of the library are raised as the exception classes below, with the library's one-line
message saying what to fix: :class:`InvalidInputError` (a ``ValueError``) for a surface that is
not a valid vessel tree or a bad option, :class:`IoError` (an ``OSError``) for unreadable files,
:class:`TopologyError` and :class:`SolverError` (``RuntimeError``) when a stage fails.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import json
from typing import Any, Dict, List, Optional, Sequence

import numpy as np

from . import _vessel

__all__ = [
    "Error", "InvalidInputError", "TopologyError", "SolverError", "IoError",
    "Surface", "FlatMap", "read", "phantom", "flatten", "flatten_options", "presets",
    "from_vtk", "to_vtk",
]


class Error(Exception):
    """Base class of the errors libvessel raises."""


class InvalidInputError(Error, ValueError):
    """The input (mesh, array, option) is not acceptable; the message says what to fix."""


class TopologyError(Error, RuntimeError):
    """The mesh has a topology a stage cannot handle."""


class SolverError(Error, RuntimeError):
    """A linear or nonlinear solver failed; the message carries the solver's report."""


class IoError(Error, OSError):
    """Reading or writing a file failed (missing, unreadable, corrupt)."""


_vessel._set_exceptions(InvalidInputError, TopologyError, SolverError, IoError)


@dataclass
class Surface:
    """A triangulated surface with its data arrays, as read from a file or a VTK object.

    Attributes:
        points: (n, 3) float64 vertex positions, in file order.
        faces: (m, 3) int64 corner indices into ``points``; polygons with more corners are split
            into triangle fans (``face_origin`` then maps each triangle to its polygon).
        point_data: name -> array with n rows ((n,) scalars, (n, c) vectors).
        cell_data: name -> array with one row per row of ``faces`` (polygon values repeated on
            each of its triangles).
        face_origin: (m,) int64 index of each triangle's polygon in the file.
    """

    points: np.ndarray
    faces: np.ndarray
    point_data: Dict[str, np.ndarray] = field(default_factory=dict)
    cell_data: Dict[str, np.ndarray] = field(default_factory=dict)
    face_origin: Optional[np.ndarray] = None


def _triangles(corners: np.ndarray, offsets: np.ndarray):
    """Triangle fans of polygons given as flat corners and offsets -> (faces, polygon index)."""
    sizes = np.diff(offsets)
    if sizes.size and np.all(sizes == 3):
        return corners.reshape(-1, 3), np.arange(sizes.size, dtype=np.int64)
    if sizes.size and sizes.min() < 3:
        bad = int(np.argmax(sizes < 3))
        raise InvalidInputError(
            f"face {bad} has {int(sizes[bad])} corners; a surface needs at least 3 per face")
    tris, owner = [], []
    for f, (start, size) in enumerate(zip(offsets[:-1], sizes)):
        for k in range(1, size - 1):
            tris.append((corners[start], corners[start + k], corners[start + k + 1]))
            owner.append(f)
    return (np.asarray(tris, dtype=np.int64).reshape(-1, 3), np.asarray(owner, dtype=np.int64))


def _surface(points, corners, offsets, point_data, cell_data) -> Surface:
    faces, owner = _triangles(np.asarray(corners, dtype=np.int64),
                              np.asarray(offsets, dtype=np.int64))
    return Surface(points=np.asarray(points, dtype=np.float64), faces=faces,
                   point_data=dict(point_data),
                   cell_data={k: np.asarray(v)[owner] for k, v in cell_data.items()},
                   face_origin=owner)


def read(path: str) -> Surface:
    """Read a surface file: OBJ, OFF, PLY, STL, or VTK PolyData (.vtp, legacy .vtk) with its
    point and cell data arrays (as float64 numpy arrays).

    Raises:
        IoError: the file is missing, unreadable, of an unknown format or corrupt.
    """
    d = _vessel.read(str(path))
    return _surface(d["points"], d["corners"], d["offsets"], d["point_data"], d["cell_data"])


def phantom(kind: str = "carotid", *, stenosis: float = 0.5, outlets: int = 4, seed: int = 1,
            sac_radius: float = 3.0, edge_length: float = 0.5) -> Surface:
    """A generated vessel surface, as ``vessel-phantom`` makes them (lengths in mm).

    Args:
        kind: ``"carotid"`` (CCA -> ICA with a sinus bulb and a stenosis, + ECA; 3 open ends),
            ``"tree"`` (a seeded random planar-ish tree with ``outlets`` outlets) or
            ``"aneurysm"`` (a straight 2 mm parent artery with a spherical sac on its side; 2
            open ends).
        stenosis: carotid: fractional diameter reduction of the ICA narrowing, in [0, 0.8].
        outlets: tree: number of outlets, in [1, 30].
        seed: tree: random seed (the same tree for the same seed).
        sac_radius: aneurysm: radius of the sac, in [1.5, 6] mm (0.75 to 3 parent radii).
        edge_length: target edge length (mm).

    Raises:
        InvalidInputError: an argument is out of its range (the message names it).
    """
    if kind == "carotid":
        d = _vessel.carotid_phantom(stenosis, edge_length)
    elif kind == "tree":
        d = _vessel.tree_phantom(outlets, seed, edge_length)
    elif kind == "aneurysm":
        d = _vessel.aneurysm_phantom(sac_radius, edge_length)
    else:
        raise InvalidInputError(f"unknown phantom '{kind}'; known: aneurysm, carotid, tree")
    return _surface(d["points"], d["corners"], d["offsets"], {}, {})


def flatten_options() -> List[str]:
    """The keyword options :func:`flatten` accepts (vessel-flatten's flags with ``_`` for ``-``)."""
    return list(_vessel.option_names())


def presets() -> List[str]:
    """The option presets :func:`flatten` accepts (``preset=``)."""
    return list(_vessel.preset_names())


def _mapped(values, rows: int, index: np.ndarray, what: str, arg: str) -> np.ndarray:
    """values[index] along the axis with ``rows`` rows: (rows, ...) or a series (T, rows, ...)."""
    a = np.asarray(values)
    if a.ndim >= 1 and a.shape[0] == rows:
        return a[index]
    if a.ndim >= 2 and a.shape[1] == rows:
        return a[:, index]
    raise InvalidInputError(
        f"{arg} must have one row per input {what} ({rows}): shape ({rows},), ({rows}, c), or a "
        f"time series (T, {rows}) or (T, {rows}, c); got shape {a.shape}")


class FlatMap:
    """The result of :func:`flatten`: the cut mesh, its 2D map and the report.

    Attributes:
        points: (k, 3) float64 positions of the cut mesh's vertices (seam vertices appear once per
            side of the cut; the first vertices are the uncut mesh's).
        faces: (m, 3) int64 triangles of the cut mesh, in the order of the input's faces.
        uv: (k, 2) float64 map coordinates of the cut mesh's vertices.
        origin: (k,) int64 index of each cut vertex's input point (``points == input[origin]``).
        face_origin: (m,) int64 index of each triangle's input face.
        cuts: one dict per vessel cut as in the report (outlet loop, where it ends, cost,
            alignment, ...), plus ``vertices``: the input point indices along it, outlet first.
        relief_cuts: the relief cuts (slits that open a bulge), likewise.
        timings: seconds per stage under the paper's Table 1 names (Z, GC, VC, AC, L, F, total).
        quality: the map's quality (flipped and overlapping triangles, area ratio, mean |log area
            ratio|, conformal distortion, seam alignment, the map's look).
        report: the whole report, as ``vessel-flatten --report`` writes it.
        notes: repairs and fallbacks taken, one line each.
    """

    def __init__(self, d: Dict[str, Any]):
        self.points: np.ndarray = d["points"]
        self.faces: np.ndarray = d["faces"]
        self.uv: np.ndarray = d["uv"]
        self.origin: np.ndarray = d["origin"]
        self.face_origin: np.ndarray = d["face_origin"]
        self.report: Dict[str, Any] = json.loads(d["report"])
        self.n_input_points: int = int(d["input_points"])
        self.n_input_faces: int = int(d["input_faces"])
        self.cuts: List[Dict[str, Any]] = [
            dict(c, vertices=v) for c, v in zip(self.report["cuts"], d["cut_vertices"])]
        self.relief_cuts: List[Dict[str, Any]] = [
            dict(c, vertices=v) for c, v in zip(self.report["relief_cuts"], d["relief_vertices"])]
        self.timings: Dict[str, float] = dict(self.report["timings"])
        self.quality: Dict[str, Any] = self.report["quality"]
        self.notes: List[str] = list(self.report["notes"])

    def __repr__(self) -> str:
        q = self.quality
        return (f"<vessel.FlatMap {len(self.points)} vertices, {len(self.faces)} faces, "
                f"{len(self.cuts)} cuts, mean |log area| {q['mean_abs_log_area_ratio']:.4f}, "
                f"{q['flipped_triangles']} flipped>")

    def map_points(self, values) -> np.ndarray:
        """Carry a per-point array of the input onto the cut mesh (and so onto ``uv``).

        ``values`` has one row per input point: (n,) scalars, (n, c) vectors, or a time series
        (T, n) / (T, n, c). Returns the same shape with n replaced by the cut mesh's k vertices:
        every seam copy gets its original's value.

        Raises:
            InvalidInputError: no axis (first, or second for a series) has n rows.
        """
        return _mapped(values, self.n_input_points, self.origin, "point", "values")

    def map_cells(self, values) -> np.ndarray:
        """Carry a per-face array of the input onto the cut mesh's faces (same rules as
        :meth:`map_points`, one row per input face)."""
        return _mapped(values, self.n_input_faces, self.face_origin, "face", "values")

    def to_vtk(self, point_data=None, cell_data=None, flat: bool = False):
        """This map as a ``vtkPolyData`` (see :func:`to_vtk`)."""
        return to_vtk(self, point_data=point_data, cell_data=cell_data, flat=flat)


def flatten(points, faces=None, preset: str = "default", **options) -> FlatMap:
    """Cut a vessel tree surface open along natural vessel cuts and flatten it into one map.

    Args:
        points: (n, 3) vertex positions, or a :class:`Surface` (then ``faces`` is omitted).
        faces: (m, 3) triangle corner indices into ``points`` (0-based).
        preset: the starting options, as vessel-flatten's ``--preset``: ``"default"``
            (libvessel's defaults) or ``"paper"`` (the published method: the paper's cuts,
            ARAP with the inlet pinned, no SLIM, no relief cuts; FlattenOptions::paper()).
        **options: single settings over the preset, named as vessel-flatten's flags with ``_``
            for ``-`` (:func:`flatten_options` lists them), e.g. ``cost="blend", blend=0.3,
            alpha=30, refine="arap", area_polish=False, viewpoint=(0, -200, 0)``.

    Returns:
        A :class:`FlatMap`.

    Raises:
        InvalidInputError: the surface is not a valid vessel tree (the message names the problem),
            an array has the wrong shape, or an option's value is out of range.
        TypeError: an unknown option or a value of the wrong type.
        TopologyError, SolverError: a stage failed.
    """
    if isinstance(points, Surface):
        if faces is not None:
            raise TypeError("flatten(surface) takes the faces from the surface; do not pass faces")
        points, faces = points.points, points.faces
    elif faces is None:
        raise TypeError("flatten() needs points and faces (or one vessel.Surface)")
    p = np.asarray(points)
    f = np.asarray(faces)
    if not np.issubdtype(p.dtype, np.number) or np.issubdtype(p.dtype, np.complexfloating):
        raise InvalidInputError(f"points must be real numbers, got dtype {p.dtype}")
    if f.size and not np.issubdtype(f.dtype, np.integer):
        raise InvalidInputError(f"faces must be integer indices, got dtype {f.dtype}")
    return FlatMap(_vessel.flatten(p.astype(np.float64, copy=False),
                                   f.astype(np.int64, copy=False), preset, options))


# VTK interop (VTK's Python, python3-vtk9; a PyVista PolyData is a vtkPolyData too).

def _vtk_modules():
    try:
        from vtkmodules.util import numpy_support
        from vtkmodules.vtkCommonCore import vtkPoints
        from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
    except ImportError as e:  # pragma: no cover - depends on the machine
        raise ImportError("vessel.from_vtk/to_vtk need VTK's Python (Debian: python3-vtk9)") from e
    return numpy_support, vtkPoints, vtkCellArray, vtkPolyData


def _arrays(data) -> Dict[str, np.ndarray]:
    numpy_support = _vtk_modules()[0]
    out = {}
    for i in range(data.GetNumberOfArrays()):
        arr = data.GetArray(i)
        if arr is None:  # not numeric (e.g. strings)
            continue
        name = arr.GetName() or f"array{i}"
        out[name] = np.asarray(numpy_support.vtk_to_numpy(arr), dtype=np.float64).copy()
    return out


def from_vtk(polydata) -> Surface:
    """A :class:`Surface` from a ``vtkPolyData`` (or a PyVista ``PolyData``): points, polygons
    (triangulated as fans) and the point and cell data arrays.

    Raises:
        InvalidInputError: not a vtkPolyData, or it holds vertex, line or strip cells.
    """
    numpy_support, _, _, vtkPolyData = _vtk_modules()
    if not isinstance(polydata, vtkPolyData):
        raise InvalidInputError(
            f"from_vtk() takes a vtkPolyData (e.g. a PyVista PolyData), got "
            f"{type(polydata).__name__}; extract its surface first (vtkDataSetSurfaceFilter)")
    for kind, count in (("vertex", polydata.GetNumberOfVerts()),
                        ("line", polydata.GetNumberOfLines()),
                        ("strip", polydata.GetNumberOfStrips())):
        if count:
            raise InvalidInputError(
                f"the PolyData has {count} {kind} cells; a vessel wall has polygons only "
                f"(remove them, e.g. with vtkTriangleFilter)")
    pts = polydata.GetPoints()
    points = (numpy_support.vtk_to_numpy(pts.GetData()).astype(np.float64)
              if pts is not None else np.zeros((0, 3)))
    polys = polydata.GetPolys()
    offsets = numpy_support.vtk_to_numpy(polys.GetOffsetsArray()).astype(np.int64)
    corners = numpy_support.vtk_to_numpy(polys.GetConnectivityArray()).astype(np.int64)
    return _surface(points, corners, offsets, _arrays(polydata.GetPointData()),
                    _arrays(polydata.GetCellData()))


def to_vtk(result: FlatMap, point_data=None, cell_data=None, flat: bool = False):
    """The cut mesh of a :class:`FlatMap` as a ``vtkPolyData`` with ``uv`` as its texture
    coordinates (point array "uv").

    Args:
        result: the FlatMap.
        point_data: name -> per-input-point array ((n,) or (n, c)), carried through
            :meth:`FlatMap.map_points` and added as point arrays.
        cell_data: name -> per-input-face array, carried through :meth:`FlatMap.map_cells`.
        flat: True for the map itself (points (u, v, 0)) instead of the 3D cut mesh.

    Raises:
        InvalidInputError: an array has the wrong shape (a time series: pass one step).
    """
    numpy_support, vtkPoints, vtkCellArray, vtkPolyData = _vtk_modules()
    m = result
    out = vtkPolyData()
    xyz = np.column_stack([m.uv, np.zeros(len(m.uv))]) if flat else m.points
    points = vtkPoints()
    points.SetData(numpy_support.numpy_to_vtk(np.ascontiguousarray(xyz, dtype=np.float64),
                                              deep=True))
    out.SetPoints(points)
    cells = vtkCellArray()
    offsets = np.arange(0, 3 * len(m.faces) + 1, 3, dtype=np.int64)
    cells.SetData(numpy_support.numpy_to_vtkIdTypeArray(offsets, deep=True),
                  numpy_support.numpy_to_vtkIdTypeArray(
                      np.ascontiguousarray(m.faces.reshape(-1), dtype=np.int64), deep=True))
    out.SetPolys(cells)
    tcoords = numpy_support.numpy_to_vtk(np.ascontiguousarray(m.uv), deep=True)
    tcoords.SetName("uv")
    out.GetPointData().SetTCoords(tcoords)

    def add(target, arrays, mapper, kind):
        for name, values in (arrays or {}).items():
            mapped = np.ascontiguousarray(mapper(values), dtype=np.float64)
            if mapped.ndim > 2 or (mapped.ndim == 2 and len(mapped) != expected[kind]):
                raise InvalidInputError(
                    f"{kind}_data['{name}'] has shape {np.shape(values)}; to_vtk() takes one "
                    f"time step per array (index the series first)")
            a = numpy_support.numpy_to_vtk(mapped, deep=True)
            a.SetName(name)
            target.AddArray(a)

    expected = {"point": len(m.points), "cell": len(m.faces)}
    add(out.GetPointData(), point_data, m.map_points, "point")
    add(out.GetCellData(), cell_data, m.map_cells, "cell")
    return out
