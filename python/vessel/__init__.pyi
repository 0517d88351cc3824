"""Type stubs of the vessel package (docstrings in vessel/__init__.py)."""

from typing import Any, Dict, List, Literal, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

class Error(Exception): ...
class InvalidInputError(Error, ValueError): ...
class TopologyError(Error, RuntimeError): ...
class SolverError(Error, RuntimeError): ...
class IoError(Error, OSError): ...

class Surface:
    points: npt.NDArray[np.float64]
    faces: npt.NDArray[np.int64]
    point_data: Dict[str, npt.NDArray[np.float64]]
    cell_data: Dict[str, npt.NDArray[np.float64]]
    face_origin: Optional[npt.NDArray[np.int64]]
    def __init__(
        self,
        points: npt.NDArray[np.float64],
        faces: npt.NDArray[np.int64],
        point_data: Dict[str, npt.NDArray[np.float64]] = ...,
        cell_data: Dict[str, npt.NDArray[np.float64]] = ...,
        face_origin: Optional[npt.NDArray[np.int64]] = ...,
    ) -> None: ...

class FlatMap:
    points: npt.NDArray[np.float64]
    faces: npt.NDArray[np.int64]
    uv: npt.NDArray[np.float64]
    origin: npt.NDArray[np.int64]
    face_origin: npt.NDArray[np.int64]
    cuts: List[Dict[str, Any]]
    relief_cuts: List[Dict[str, Any]]
    timings: Dict[str, float]
    quality: Dict[str, Any]
    report: Dict[str, Any]
    notes: List[str]
    n_input_points: int
    n_input_faces: int
    def map_points(self, values: npt.ArrayLike) -> npt.NDArray[Any]: ...
    def map_cells(self, values: npt.ArrayLike) -> npt.NDArray[Any]: ...
    def to_vtk(
        self,
        point_data: Optional[Mapping[str, npt.ArrayLike]] = ...,
        cell_data: Optional[Mapping[str, npt.ArrayLike]] = ...,
        flat: bool = ...,
    ) -> Any: ...

def read(path: str) -> Surface: ...
def phantom(
    kind: str = ...,
    *,
    stenosis: float = ...,
    outlets: int = ...,
    seed: int = ...,
    edge_length: float = ...,
) -> Surface: ...
def flatten(
    points: Union[npt.ArrayLike, Surface],
    faces: Optional[npt.ArrayLike] = ...,
    preset: str = ...,
    *,
    cost: str = ...,
    blend: float = ...,
    viewpoint: Union[Sequence[float], Literal["face-on"]] = ...,
    alpha: float = ...,
    layout: str = ...,
    curvature_scale: float = ...,
    arap_iterations: int = ...,
    slim_iterations: int = ...,
    slim_momentum: float = ...,
    scaffold_tolerance: float = ...,
    crossing_patience: int = ...,
    refine: str = ...,
    overlaps: str = ...,
    restart_circle: str = ...,
    look_pull: float = ...,
    look_pull_form: str = ...,
    look_hold: float = ...,
    look_margin: float = ...,
    look_retry: str = ...,
    look_retry_pull: float = ...,
    look_retry_inversions: float = ...,
    look_retry_area: float = ...,
    area_polish: Union[float, bool] = ...,
    arap_solver: str = ...,
    init: str = ...,
    direction_confidence: float = ...,
    cut_route: str = ...,
    stream_field: str = ...,
    band_rings: int = ...,
    join_rings: int = ...,
    join: str = ...,
    join_slack: float = ...,
    join_reach: float = ...,
    join_excess: float = ...,
    tie_tolerance: float = ...,
    natural_cuts: bool = ...,
    relief_cuts: int = ...,
    relief_target: float = ...,
    largest_component: bool = ...,
    remove_caps: bool = ...,
    refuse_polygons: bool = ...,
) -> FlatMap: ...
def flatten_options() -> List[str]: ...
def presets() -> List[str]: ...
def from_vtk(polydata: Any) -> Surface: ...
def to_vtk(
    result: FlatMap,
    point_data: Optional[Mapping[str, npt.ArrayLike]] = ...,
    cell_data: Optional[Mapping[str, npt.ArrayLike]] = ...,
    flat: bool = ...,
) -> Any: ...
