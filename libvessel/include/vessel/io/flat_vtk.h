#pragma once

#include "vessel/fields/fields.h"
#include "vessel/core/mesh.h"
#include "vessel/io/vtk_io.h"

#include <string>
#include <vector>

namespace vessel {

//! \file The flattened result as VTK PolyData for ParaView: the 3D cut mesh with `uv` as texture
//! coordinates, and the 2D map (z = 0) as its own PolyData, both with every field.

//! Name of the 2-component point array holding (u, v); also the texture coordinates.
inline constexpr const char* uv_array = "uv";
//! `int` point array: index in the input file of the vertex each cut vertex came from.
inline constexpr const char* input_vertex_array = "InputVertex";
//! `int` cell array: index in the input file of the polygon each triangle came from.
inline constexpr const char* input_cell_array = "InputCell";

//! \brief The cut mesh as PolyData: points are the cut mesh's vertices (seam copies included),
//! triangles its faces, point data `uv` (texture coordinates) and `InputVertex`, cell data
//! `InputCell`, plus \p fields.
//! \param map false: 3D positions and \p fields as they are; true: the flat map, points
//! (u, v, 0), 3-component fields as map vectors (map_fields()) and the cell arrays of
//! distortion_fields() (`LogAreaRatio`, `ConformalDistortion`).
//! \param fields rows indexed by `v.idx()` / `f.idx()` of \p mesh (see transfer_fields()).
//! \param uv |V| x 2, row `v.idx()`.
//! \throw InvalidInputError if sizes disagree or `prop::input_index` / `prop::input_face` is
//! missing.
PolyData flat_polydata(const Mesh& mesh, const Eigen::MatrixX2d& uv,
                       const std::vector<Field>& fields, bool map);

//! `OUT.vtp` -> `OUT-map.vtp`: where write_flat_vtp() puts the 2D map.
std::string map_path(const std::string& path);

//! \brief Write flat_polydata(..., false) to \p path and flat_polydata(..., true) to
//! map_path(\p path) (each through a temporary file + rename).
//! \throw InvalidInputError as flat_polydata(); IoError if writing fails.
void write_flat_vtp(const std::string& path, const Mesh& mesh, const Eigen::MatrixX2d& uv,
                    const std::vector<Field>& fields);

//! \brief Write a series on the cut mesh as two EnSight Gold cases (write_ensight_series()):
//! the 3D cut mesh in \p case_path and the map in map_path(\p case_path) (`OUT.case`,
//! `OUT-map.case`), each with its geometry and the arrays of flat_polydata() once and each
//! step's fields per step (on the map as flat_polydata(..., true) has them). Their data files
//! share the folder ensight_data_folder(\p case_path) (`OUT/`).
//! \param series rows indexed by the cut mesh (transfer_fields() on every step).
//! \throw InvalidInputError as flat_polydata(); IoError if writing fails.
void write_flat_series(const std::string& case_path, const Mesh& mesh, const Eigen::MatrixX2d& uv,
                       const std::vector<Field>& fields, const TimeSeries& series);

//! \brief Write the cut mesh as binary PLY: vertex x y z (3D), u v (the map, the names MeshLab
//! and Blender read as texture coordinates), `input_vertex`, and every scalar or vector point
//! field as float/double/int properties (vectors as NAME_0, NAME_1, ...; 64-bit integers as
//! double, PLY having no 64-bit integer type); faces carry
//! `input_cell` and the cell fields. Temporary file + rename.
//! \throw InvalidInputError as flat_polydata(); IoError if writing fails.
void write_flat_ply(const std::string& path, const Mesh& mesh, const Eigen::MatrixX2d& uv,
                    const std::vector<Field>& fields);

}  // namespace vessel
