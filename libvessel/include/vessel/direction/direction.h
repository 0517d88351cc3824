#pragma once

#include "vessel/cut/boundary.h"
#include "vessel/direction/curvature.h"
#include "vessel/core/mesh.h"

namespace vessel {

//! \brief Orient each minimal principal direction toward the root: z = c if <c, grad G> < 0,
//! else -c (step 3 of the method).
//! \param min_direction |V| x 3 unit directions (sign arbitrary), row `v.idx()`.
//! \param geodesic |V| distances from the inlet, indexed by `v.idx()`.
//! \return |V| x 3 unit directions pointing toward decreasing geodesic distance; where the
//! gradient of \p geodesic is undefined (e.g. infinite distances) the row of \p min_direction is
//! returned unchanged.
//! \throw InvalidInputError if the array sizes do not match the mesh.
Eigen::MatrixX3d align_to_root(const Mesh& mesh, const Eigen::MatrixX3d& min_direction,
                               const Eigen::VectorXd& geodesic);

//! \brief Unit direction of steepest descent of a scalar field \p f per vertex: -grad f / |grad f|
//! from the area-weighted face gradients (vertex_gradient()). With f = G (distance from the
//! inlet) or a harmonic longitudinal coordinate it points along the vessel toward the root.
//! It is not the cut direction of the method: tried as E_c's z, the geodesic descent leans to
//! the inner side of bends, and its cut follows the turns of a helical tube where the minimal
//! curvature direction's stays on one side (docs/results.md has the figures).
//! \param f |V| values indexed by `v.idx()`.
//! \return |V| x 3; rows where the gradient vanishes or is undefined (e.g. infinite distances)
//! are zero.
//! \throw InvalidInputError if \p f does not have |V| entries.
Eigen::MatrixX3d descent_direction(const Mesh& mesh, const Eigen::VectorXd& f);

//! Where the vessel direction z comes from (step 3). The paper's z is the minimal principal
//! direction everywhere; where the two principal curvatures are nearly equal in magnitude
//! (saddles at a junction hub, short wide bulbs, sacs) that direction is noise, and a cut that
//! follows it wanders across the vessel. This policy trusts the curvature only where it is
//! anisotropic and elsewhere leans z toward a guide field (flatten() passes the descent of the
//! harmonic longitudinal coordinate, cut_metrics.h, which runs along every vessel).
struct DirectionOptions
{
    //! Anisotropy a = (|k_max| - |k_min|) / (|k_max| + |k_min|) (1 on a cylinder, 0 at an
    //! umbilic or a symmetric saddle) at or above which z is the pure minimal curvature
    //! direction. Below it z = normalize(t c + (1 - t) g) with t = a / confident_anisotropy,
    //! c the curvature direction, g the guide. 0 = the paper's pure curvature field everywhere
    //! (no guide is computed), the default: a guided field aligns the seams of junction-rich
    //! trees better, but branch cuts elsewhere then run beside the main cut before they join
    //! it, and relief cuts can stop short of their area bound (docs/results.md). Tubes (a ~ 1)
    //! keep the curvature field at any setting.
    double confident_anisotropy = 0.0;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! \brief Curvature anisotropy per vertex, (|k_max| - |k_min|) / (|k_max| + |k_min|) in [0, 1];
//! 0 where both curvatures vanish (flat). \return |V| values, row `v.idx()`.
Eigen::VectorXd curvature_anisotropy(const PrincipalCurvature& curvature);

//! \brief Blend an oriented curvature direction field toward a guide where the curvature is not
//! anisotropic (DirectionOptions). Each row of \p z with anisotropy a below the threshold
//! becomes normalize(t z + (1 - t) g), t = a / confident_anisotropy; rows where the guide is zero
//! (undefined) or the blend vanishes keep z.
//! \param z |V| x 3 unit directions toward the root (align_to_root()).
//! \param anisotropy |V| values from curvature_anisotropy().
//! \param guide |V| x 3 unit directions toward the root, or zero rows (e.g. descent_direction()).
//! \return |V| x 3 unit directions.
//! \throw InvalidInputError if the sizes differ or the options are invalid.
Eigen::MatrixX3d confident_direction(const Eigen::MatrixX3d& z, const Eigen::VectorXd& anisotropy,
                                     const Eigen::MatrixX3d& guide,
                                     const DirectionOptions& options = {});

//! \brief The vessel direction z of step 3 as flatten() makes it: align_to_root() of the
//! minimal principal direction, then, unless `options.confident_anisotropy` is 0,
//! confident_direction() with the descent of harmonic_longitudinal() (cut_metrics.h; one more
//! sparse Cholesky factorization) as the guide.
//! \param loops boundary_loops(mesh), loops[0] the inlet. \param geodesic |V| distances from
//! the inlet.
//! \return |V| x 3 unit directions toward the root, row `v.idx()`.
//! \throw InvalidInputError if sizes disagree or the options are invalid.
Eigen::MatrixX3d vessel_direction(const Mesh& mesh, const PrincipalCurvature& curvature,
                                  const std::vector<BoundaryLoop>& loops,
                                  const Eigen::VectorXd& geodesic,
                                  const DirectionOptions& options = {});

//! \brief vessel_direction() with the harmonic longitudinal coordinate already at hand
//! (flatten() computes it once in stage Z and reuses it): no factorization here.
//! \param geodesic |V| distances from the inlet. \param longitudinal |V| values of
//! harmonic_longitudinal(); unused when `options.confident_anisotropy` is 0.
//! \throw InvalidInputError if sizes disagree or the options are invalid.
Eigen::MatrixX3d vessel_direction_guided(const Mesh& mesh, const PrincipalCurvature& curvature,
                                         const Eigen::VectorXd& geodesic,
                                         const Eigen::VectorXd& longitudinal,
                                         const DirectionOptions& options = {});

}  // namespace vessel
