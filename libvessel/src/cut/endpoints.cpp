#include "vessel/cut/endpoints.h"

#include "vessel/core/errors.h"

#include <limits>

namespace vessel {

std::vector<VertexHandle> ImaginaryNodeEndpoints::allowed(const Mesh&, const BoundaryLoop& loop,
                                                          std::size_t) const
{
    return loop.vertices;
}

NearestPointEndpoints::NearestPointEndpoints(const Eigen::Vector3d& point) : point_(point)
{
    if (!point.allFinite())
        throw InvalidInputError("NearestPointEndpoints: the point (the viewpoint) must have 3 "
                                "finite coordinates");
}

std::vector<VertexHandle> NearestPointEndpoints::allowed(const Mesh& mesh,
                                                         const BoundaryLoop& loop,
                                                         std::size_t) const
{
    VertexHandle best;
    double best_d = std::numeric_limits<double>::infinity();
    for (auto v : loop.vertices)
    {
        const double d = (to_eigen(mesh.point(v)) - point_).squaredNorm();
        if (d < best_d)
        {
            best_d = d;
            best = v;
        }
    }
    return {best};
}

}  // namespace vessel
