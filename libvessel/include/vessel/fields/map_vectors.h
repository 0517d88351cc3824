#pragma once

#include "vessel/fields/fields.h"

#include <vector>

namespace vessel {

//! \file 3D vector fields on a cut mesh carried onto its 2D map: the tangential part of each
//! vector pushed through the map's Jacobian, so that an arrow on the map points where the 3D
//! arrow points along the wall. Also the map's per-face distortion as fields.

//! A linear map from 3D vectors to map vectors (rows u, v).
using MapJacobian = Eigen::Matrix<double, 2, 3>;

//! \brief Per face f, the Jacobian J_f of the map restricted to the face's plane:
//! J_f (p_k - p_0) = uv_k - uv_0 for the corners k = 1, 2, and J_f n_f = 0 for the face normal,
//! so that J_f w = J_f t for t the part of w in the face's plane.
//! \param uv |V| x 2, row `v.idx()`.
//! \return one matrix per face, index `f.idx()`; zero for a face of zero 3D area.
//! \throw InvalidInputError if \p uv does not have one row per vertex.
std::vector<MapJacobian> face_map_jacobians(const Mesh& mesh, const Eigen::MatrixX2d& uv);

//! \brief Per vertex v, the unit normal n_v (area-weighted mean of its faces' normals) and the
//! Jacobian J_v = (sum_f A_f J_f / sum_f A_f)(I - n_v n_v^T) over its faces: a map of the
//! vertex's tangent plane (J_v n_v = 0). Rows `v.idx()`.
struct VertexMapJacobians
{
    std::vector<Eigen::Vector3d> normal;
    std::vector<MapJacobian> jacobian;
};

//! \copydoc VertexMapJacobians
VertexMapJacobians vertex_map_jacobians(const Mesh& mesh, const Eigen::MatrixX2d& uv);

//! \brief The fields as the map shows them: every 3-component field (point or cell) becomes
//! (J w, 0), its vector w's tangential part pushed through the vertex's or face's Jacobian
//! (vertex_map_jacobians(), face_map_jacobians()), same name and type; the others are unchanged.
//! \param fields rows indexed by `v.idx()` / `f.idx()` of \p mesh (transfer_fields()).
//! \throw InvalidInputError if \p uv or a field's rows do not fit \p mesh.
std::vector<Field> map_fields(const std::vector<Field>& fields, const Mesh& mesh,
                              const Eigen::MatrixX2d& uv);

//! Name of the cell array log(A_2D / A_3D) of each face (0 = area kept; see FlatQuality).
inline constexpr const char* log_area_ratio_array = "LogAreaRatio";
//! Name of the cell array sigma_max / sigma_min of each face's Jacobian (1 = conformal).
inline constexpr const char* conformal_array = "ConformalDistortion";

//! \brief The map's per-face distortion as two Float64 cell fields, log_area_ratio_array
//! (log of the signed map area over the 3D area: NaN for a flipped or degenerate face) and
//! conformal_array (infinite for a degenerate face), as FlatQuality averages them.
std::vector<Field> distortion_fields(const Mesh& mesh, const Eigen::MatrixX2d& uv);

}  // namespace vessel
