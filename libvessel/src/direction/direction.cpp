#include "vessel/direction/direction.h"

#include "vessel/cut/cut_metrics.h"
#include "vessel/core/errors.h"
#include "vessel/core/operators.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace vessel {

Eigen::MatrixX3d align_to_root(const Mesh& mesh, const Eigen::MatrixX3d& min_direction,
                               const Eigen::VectorXd& geodesic)
{
    const auto n = static_cast<Eigen::Index>(mesh.n_vertices());
    if (min_direction.rows() != n || geodesic.size() != n)
        throw InvalidInputError("align_to_root: got " + std::to_string(min_direction.rows()) +
                                " directions and " + std::to_string(geodesic.size()) +
                                " distances for " + std::to_string(n) +
                                " vertices; pass one row/value per vertex, indexed by v.idx()");
    const Eigen::MatrixX3d grad = vertex_gradient(mesh, geodesic);
    Eigen::MatrixX3d z(n, 3);
    for (Eigen::Index i = 0; i < n; ++i)
    {
        // The root is where G decreases, so z must make an obtuse angle with grad G. Vertices
        // unreachable from the inlet (G = inf, gradient NaN) keep the direction as given.
        const bool points_to_root = !(min_direction.row(i).dot(grad.row(i)) >= 0.0);
        z.row(i) = points_to_root ? min_direction.row(i) : Eigen::RowVector3d(-min_direction.row(i));
    }
    return z;
}

Eigen::MatrixX3d descent_direction(const Mesh& mesh, const Eigen::VectorXd& f)
{
    const Eigen::MatrixX3d grad = vertex_gradient(mesh, f);
    Eigen::MatrixX3d z = Eigen::MatrixX3d::Zero(grad.rows(), 3);
    for (Eigen::Index i = 0; i < grad.rows(); ++i)
    {
        const double length = grad.row(i).norm();
        if (std::isfinite(length) && length > 0.0)
            z.row(i) = -grad.row(i) / length;
    }
    return z;
}

void DirectionOptions::validate() const
{
    if (!(confident_anisotropy >= 0.0 && confident_anisotropy <= 1.0))
        throw InvalidInputError("DirectionOptions: confident_anisotropy must be in [0, 1] (0 = "
                                "pure curvature direction), got " +
                                std::to_string(confident_anisotropy));
}

Eigen::VectorXd curvature_anisotropy(const PrincipalCurvature& curvature)
{
    const Eigen::ArrayXd big = curvature.k_max.array().abs();
    const Eigen::ArrayXd small = curvature.k_min.array().abs();
    const Eigen::ArrayXd sum = big + small;
    return (sum > 0.0).select((big - small) / sum, 0.0).max(0.0).min(1.0).matrix();
}

Eigen::MatrixX3d confident_direction(const Eigen::MatrixX3d& z, const Eigen::VectorXd& anisotropy,
                                     const Eigen::MatrixX3d& guide,
                                     const DirectionOptions& options)
{
    options.validate();
    if (anisotropy.size() != z.rows() || guide.rows() != z.rows())
        throw InvalidInputError("confident_direction: got " + std::to_string(z.rows()) +
                                " directions, " + std::to_string(anisotropy.size()) +
                                " anisotropy values and " + std::to_string(guide.rows()) +
                                " guide directions; pass one per vertex, indexed by v.idx()");
    Eigen::MatrixX3d blended = z;
    if (options.confident_anisotropy <= 0.0)
        return blended;
    for (Eigen::Index i = 0; i < z.rows(); ++i)
    {
        const double t = std::clamp(anisotropy[i] / options.confident_anisotropy, 0.0, 1.0);
        if (t >= 1.0 || !(guide.row(i).squaredNorm() > 0.0))
            continue;
        const Eigen::RowVector3d mix = t * z.row(i) + (1.0 - t) * guide.row(i);
        const double length = mix.norm();
        if (length > 1e-12)
            blended.row(i) = mix / length;
    }
    return blended;
}

Eigen::MatrixX3d vessel_direction(const Mesh& mesh, const PrincipalCurvature& curvature,
                                  const std::vector<BoundaryLoop>& loops,
                                  const Eigen::VectorXd& geodesic,
                                  const DirectionOptions& options)
{
    options.validate();  // before the solve below
    // The guide is solved only when the blend reads it.
    const Eigen::VectorXd longitudinal = options.confident_anisotropy > 0.0
                                             ? harmonic_longitudinal(mesh, loops, geodesic)
                                             : Eigen::VectorXd();
    return vessel_direction_guided(mesh, curvature, geodesic, longitudinal, options);
}

Eigen::MatrixX3d vessel_direction_guided(const Mesh& mesh, const PrincipalCurvature& curvature,
                                         const Eigen::VectorXd& geodesic,
                                         const Eigen::VectorXd& longitudinal,
                                         const DirectionOptions& options)
{
    options.validate();
    const Eigen::MatrixX3d z = align_to_root(mesh, curvature.min_direction, geodesic);
    if (options.confident_anisotropy <= 0.0)
        return z;
    if (longitudinal.size() != geodesic.size())
        throw InvalidInputError("vessel_direction_guided: " + std::to_string(longitudinal.size()) +
                                " longitudinal values for " + std::to_string(geodesic.size()) +
                                " distances; pass harmonic_longitudinal() of the same mesh");
    return confident_direction(z, curvature_anisotropy(curvature),
                               descent_direction(mesh, longitudinal), options);
}

}  // namespace vessel
