#include "vessel/cut/endpoints.h"

#include "vessel/core/errors.h"

#include <limits>
#include <string>

namespace vessel {

std::vector<VertexHandle> ImaginaryNodeEndpoints::allowed(const Mesh&, const BoundaryLoop& loop,
                                                          std::size_t) const
{
    return loop.vertices;
}

namespace {

void check_point(const Eigen::Vector3d& point, const char* policy)
{
    if (!point.allFinite())
        throw InvalidInputError(std::string(policy) +
                                ": the point (the viewpoint) must have 3 finite coordinates");
}

// The loop vertex whose squared distance from \p point, times \p sign, is least.
VertexHandle extreme_vertex(const Mesh& mesh, const BoundaryLoop& loop,
                            const Eigen::Vector3d& point, double sign)
{
    VertexHandle best;
    double best_d = std::numeric_limits<double>::infinity();
    for (auto v : loop.vertices)
    {
        const double d = sign * (to_eigen(mesh.point(v)) - point).squaredNorm();
        if (d < best_d)
        {
            best_d = d;
            best = v;
        }
    }
    return best;
}

}  // namespace

NearestPointEndpoints::NearestPointEndpoints(const Eigen::Vector3d& point) : point_(point)
{
    check_point(point, "NearestPointEndpoints");
}

std::vector<VertexHandle> NearestPointEndpoints::allowed(const Mesh& mesh,
                                                         const BoundaryLoop& loop,
                                                         std::size_t) const
{
    return {extreme_vertex(mesh, loop, point_, 1.0)};
}

FarSideEndpoints::FarSideEndpoints(const Eigen::Vector3d& point) : point_(point)
{
    check_point(point, "FarSideEndpoints");
}

std::vector<VertexHandle> FarSideEndpoints::allowed(const Mesh& mesh, const BoundaryLoop& loop,
                                                    std::size_t) const
{
    return {extreme_vertex(mesh, loop, point_, -1.0)};
}

}  // namespace vessel
