#include "vessel/direction.h"

#include "vessel/errors.h"
#include "vessel/operators.h"

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

}  // namespace vessel
