#pragma once

// Internals shared by the two ARAP solvers (arap.cpp and arap_ceres.cpp). Ceres stays out of this
// header: glog's CHECK macros must not leak into code that includes it.

#include "vessel/map/arap.h"

#include <Eigen/Core>

#include <vector>

namespace vessel::detail {

//! One triangle in an isometric 2D frame: corner 0 at the origin, corner 1 on the +x axis.
struct ArapFace
{
    int v[3];                   //!< vertex indices, counter-clockwise
    Eigen::Vector2d x[3];       //!< corner positions in the local frame
    Eigen::Matrix2d X_inv;      //!< inverse of [x1 - x0, x2 - x0]; J = [u1 - u0, u2 - u0] X_inv
    double area = 0.0;          //!< 3D area
    double cot[3] = {0, 0, 0};  //!< cotangent of the angle at each corner
};

//! Local frames of all faces, indexed by `f.idx()`.
//! \throw InvalidInputError naming \p caller if a face is degenerate.
std::vector<ArapFace> arap_faces(const Mesh& mesh, const char* caller);

//! Jacobian of the map \p uv (|V| x 2) on \p face.
Eigen::Matrix2d arap_jacobian(const ArapFace& face, const Eigen::MatrixX2d& uv);

//! Angle of the rotation closest (Frobenius) to \p J: argmax_theta tr(R(theta)^T J).
double closest_rotation_angle(const Eigen::Matrix2d& J);

//! area * ||J - R||_F^2 for one face; \p R receives the closest rotation to J.
double face_energy(const ArapFace& face, const Eigen::MatrixX2d& uv, Eigen::Matrix2d& R);

//! face_energy() for a face of \p area with Jacobian \p J.
double jacobian_energy(double area, const Eigen::Matrix2d& J, Eigen::Matrix2d& R);

//! Sum over faces of area * ||J - R||_F^2 with R the closest rotation.
double arap_energy(const std::vector<ArapFace>& faces, const Eigen::MatrixX2d& uv);

//! The Ceres solver behind arap(options.solver == ArapSolver::Ceres).
//! \param is_pinned |V| flags indexed by `v.idx()`; pinned rows of \p uv already hold targets.
ArapSummary arap_ceres(const Mesh& mesh, const std::vector<ArapFace>& faces, Eigen::MatrixX2d& uv,
                       const std::vector<bool>& is_pinned, const ArapOptions& options);

}  // namespace vessel::detail
