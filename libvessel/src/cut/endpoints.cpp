#include "vessel/cut/endpoints.h"

#include "vessel/core/errors.h"

#include <Eigen/Eigenvalues>

#include <limits>
#include <string>
#include <utility>
#include <vector>

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

Eigen::Vector3d face_on_viewpoint(const Mesh& mesh)
{
    if (mesh.n_faces() == 0)
        throw InvalidInputError("face_on_viewpoint: the mesh has no faces");
    // Area-weighted moments of the face centroids: they converge to the surface's own as the
    // triangles shrink, whatever their shapes.
    double total = 0.0;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d hi = -lo;
    std::vector<std::pair<double, Eigen::Vector3d>> faces;
    faces.reserve(mesh.n_faces());
    for (auto f : mesh.faces())
    {
        auto h = mesh.halfedge_handle(f);
        const Eigen::Vector3d a = to_eigen(mesh.point(mesh.from_vertex_handle(h)));
        const Eigen::Vector3d b = to_eigen(mesh.point(mesh.to_vertex_handle(h)));
        const Eigen::Vector3d c =
            to_eigen(mesh.point(mesh.to_vertex_handle(mesh.next_halfedge_handle(h))));
        const double area = 0.5 * (b - a).cross(c - a).norm();
        const Eigen::Vector3d centroid = (a + b + c) / 3.0;
        faces.emplace_back(area, centroid);
        total += area;
        centre += area * centroid;
    }
    for (auto v : mesh.vertices())
    {
        lo = lo.cwiseMin(to_eigen(mesh.point(v)));
        hi = hi.cwiseMax(to_eigen(mesh.point(v)));
    }
    if (!(total > 0.0))
        throw InvalidInputError("face_on_viewpoint: the mesh's faces have no area");
    centre /= total;
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (const auto& [area, centroid] : faces)
        covariance += area * (centroid - centre) * (centroid - centre).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> axes(covariance);
    Eigen::Vector3d axis = axes.eigenvectors().col(0);  // the least eigenvalue's
    // Its sign from the mesh's frame, not its shape: a surface symmetric about its mid-plane
    // (the carotid phantom) has no side of its own, and a moment's sign near 0 would follow
    // the triangulation.
    Eigen::Index largest = 0;
    axis.cwiseAbs().maxCoeff(&largest);
    if (axis[largest] < 0.0)
        axis = -axis;
    return centre + 2.0 * (hi - lo).norm() * axis;
}

}  // namespace vessel
