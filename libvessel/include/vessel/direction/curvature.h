#pragma once

#include "vessel/core/mesh.h"

namespace vessel {

struct CurvatureOptions
{
    //! Radius of the fitting ball as a multiple of the mean edge length (Panozzo et al. 2010 use 5).
    double scale = 5.0;
    //! Minimum number of neighbours used in a fit (>= 5); the ball grows by rings until it has them.
    int min_neighbors = 8;
    //! Use all hardware threads for the per-vertex fits.
    bool parallel = true;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! Principal curvature per vertex, all arrays indexed by `v.idx()`. Curvatures are signed:
//! positive where the surface bends away from its normal (the face winding's side), e.g. +1/r
//! on an outward-wound sphere or cylinder of radius r. Isolated vertices get 0 and an arbitrary
//! orthonormal pair of directions.
struct PrincipalCurvature
{
    Eigen::MatrixX3d min_direction;  //!< |V| x 3 unit vectors (sign arbitrary), tangent to the surface
    Eigen::MatrixX3d max_direction;  //!< |V| x 3 unit vectors (sign arbitrary)
    Eigen::VectorXd k_min;           //!< |V| curvature along min_direction (smaller magnitude)
    Eigen::VectorXd k_max;           //!< |V| curvature along max_direction (larger magnitude)
};

//! \brief Principal curvatures and directions by fitting a quadric height function in the local
//! tangent frame over the vertices within a ball of radius `scale * mean edge length`
//! \cite panozzo_2010_efficient.
//! \throw InvalidInputError if the mesh has no faces or the options are invalid.
PrincipalCurvature principal_curvature(const Mesh& mesh, const CurvatureOptions& options = {});

}  // namespace vessel
