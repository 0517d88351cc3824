#include "vessel/core/mesh.h"

namespace vessel {

Eigen::MatrixX3d vertex_positions(const Mesh& mesh)
{
    Eigen::MatrixX3d V(mesh.n_vertices(), 3);
    for (auto v : mesh.vertices())
        V.row(v.idx()) = to_eigen(mesh.point(v)).transpose();
    return V;
}

Eigen::MatrixX3i face_indices(const Mesh& mesh)
{
    Eigen::MatrixX3i F(mesh.n_faces(), 3);
    for (auto f : mesh.faces())
    {
        int k = 0;
        for (auto v : f.vertices())
            F(f.idx(), k++) = v.idx();
    }
    return F;
}

double mean_edge_length(const Mesh& mesh)
{
    if (mesh.n_edges() == 0)
        return 0.0;
    double sum = 0.0;
    for (auto e : mesh.edges())
        sum += mesh.calc_edge_length(e);
    return sum / static_cast<double>(mesh.n_edges());
}

Eigen::VectorXd face_areas(const Mesh& mesh)
{
    Eigen::VectorXd A(mesh.n_faces());
    for (auto f : mesh.faces())
    {
        auto h = f.halfedge();
        const auto& a = mesh.point(h.from());
        const auto& b = mesh.point(h.to());
        const auto& c = mesh.point(h.next().to());
        A[f.idx()] = 0.5 * OpenMesh::cross(b - a, c - a).norm();
    }
    return A;
}

}  // namespace vessel
