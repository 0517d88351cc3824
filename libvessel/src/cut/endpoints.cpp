#include "vessel/cut/endpoints.h"

#include "vessel/core/errors.h"

#include <Eigen/Eigenvalues>

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

Eigen::Vector3d face_on_viewpoint(const Mesh& mesh)
{
    if (mesh.n_faces() == 0)
        throw InvalidInputError("face_on_viewpoint: the mesh has no faces");
    // Area-weighted moments of the face centroids: they converge to the surface's own as the
    // triangles shrink, whatever their shapes.
    const Eigen::MatrixX3d points = vertex_positions(mesh);
    const Eigen::MatrixX3i corners = face_indices(mesh);
    const Eigen::VectorXd areas = face_areas(mesh);
    const double total = areas.sum();
    if (!(total > 0.0))
        throw InvalidInputError("face_on_viewpoint: the mesh's faces have no area");
    Eigen::MatrixX3d centroids(corners.rows(), 3);
    for (Eigen::Index f = 0; f < corners.rows(); ++f)
        centroids.row(f) = (points.row(corners(f, 0)) + points.row(corners(f, 1)) +
                            points.row(corners(f, 2))) /
                           3.0;
    const Eigen::RowVector3d centre = areas.transpose() * centroids / total;
    const Eigen::MatrixX3d offsets = centroids.rowwise() - centre;
    const Eigen::Matrix3d covariance = offsets.transpose() * areas.asDiagonal() * offsets;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> axes(covariance);
    Eigen::Vector3d axis = axes.eigenvectors().col(0);  // the least eigenvalue's
    // Its sign from the mesh's frame, not its shape: a surface symmetric about its mid-plane
    // (the carotid phantom) has no side of its own, and a moment's sign near 0 would follow
    // the triangulation.
    Eigen::Index largest = 0;
    axis.cwiseAbs().maxCoeff(&largest);
    if (axis[largest] < 0.0)
        axis = -axis;
    const double diagonal = (points.colwise().maxCoeff() - points.colwise().minCoeff()).norm();
    return centre.transpose() + 2.0 * diagonal * axis;
}

}  // namespace vessel
