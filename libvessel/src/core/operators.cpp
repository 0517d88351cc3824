#include "vessel/core/operators.h"

#include "vessel/core/errors.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

namespace vessel {

namespace {

// Area below which a face counts as degenerate, relative to the squared mean edge length. Real
// patient meshes contain sliver and even collinear triangles; their cotangents would be
// infinite. Flooring the area (not each cotangent) keeps every face's 3x3 block positive
// semi-definite, because cot_a cot_b + cot_b cot_c + cot_c cot_a = (2A)^2 / (2A')^2 >= 0.
constexpr double area_floor_factor = 1e-8;

double area_floor(const Mesh& mesh)
{
    const double h = mean_edge_length(mesh);
    return area_floor_factor * h * h;
}

// Half the cotangent of the corner opposite each halfedge, 0 on boundary halfedges.
std::vector<double> halfedge_cotan_weights(const Mesh& mesh)
{
    const double min_area = area_floor(mesh);
    std::vector<double> w(mesh.n_halfedges(), 0.0);
    for (auto f : mesh.faces())
    {
        const auto h0 = f.halfedge();
        const auto h1 = h0.next();
        const auto h2 = h1.next();
        const Eigen::Vector3d a = to_eigen(mesh.point(h0.from()));
        const Eigen::Vector3d b = to_eigen(mesh.point(h1.from()));
        const Eigen::Vector3d c = to_eigen(mesh.point(h2.from()));
        const double twice_area = std::max((b - a).cross(c - a).norm(), 2.0 * min_area);
        // Corner opposite h0 (a->b) is c, opposite h1 (b->c) is a, opposite h2 (c->a) is b.
        w[h0.idx()] = 0.5 * (a - c).dot(b - c) / twice_area;
        w[h1.idx()] = 0.5 * (b - a).dot(c - a) / twice_area;
        w[h2.idx()] = 0.5 * (c - b).dot(a - b) / twice_area;
    }
    return w;
}

}  // namespace

Eigen::SparseMatrix<double> cotan_laplacian(const Mesh& mesh)
{
    const auto w = halfedge_cotan_weights(mesh);
    const int n = static_cast<int>(mesh.n_vertices());

    // Assembling the compressed columns directly from the vertex one-rings is several times
    // faster than setFromTriplets on large meshes, and the diagonal is always stored (even for
    // isolated vertices), which the geodesic solver relies on to edit values in place.
    std::vector<int> outer(n + 1, 0);
    for (auto v : mesh.vertices())
        outer[v.idx() + 1] = 1 + static_cast<int>(v.valence());
    for (int j = 0; j < n; ++j)
        outer[j + 1] += outer[j];
    std::vector<int> inner(outer[n]);
    std::vector<double> values(outer[n]);

    std::vector<std::pair<int, double>> column;
    for (auto v : mesh.vertices())
    {
        column.clear();
        double diagonal = 0.0;
        for (auto h : v.outgoing_halfedges())
        {
            const double weight = w[h.idx()] + w[h.opp().idx()];
            column.emplace_back(h.to().idx(), -weight);
            diagonal += weight;
        }
        column.emplace_back(v.idx(), diagonal);
        std::sort(column.begin(), column.end(),
                  [](const auto& x, const auto& y) { return x.first < y.first; });
        int k = outer[v.idx()];
        for (const auto& [i, value] : column)
        {
            inner[k] = i;
            values[k++] = value;
        }
    }
    Eigen::Map<const Eigen::SparseMatrix<double>> map(n, n, outer[n], outer.data(), inner.data(),
                                                      values.data());
    return Eigen::SparseMatrix<double>(map);
}

Eigen::VectorXd lumped_mass(const Mesh& mesh)
{
    const Eigen::VectorXd A = face_areas(mesh);
    Eigen::VectorXd m = Eigen::VectorXd::Zero(mesh.n_vertices());
    for (auto f : mesh.faces())
        for (auto v : f.vertices())
            m[v.idx()] += A[f.idx()] / 3.0;
    return m;
}

Eigen::MatrixX3d face_gradient(const Mesh& mesh, const Eigen::VectorXd& f)
{
    if (f.size() != static_cast<Eigen::Index>(mesh.n_vertices()))
        throw InvalidInputError("face_gradient: function has " + std::to_string(f.size()) +
                                " values but the mesh has " + std::to_string(mesh.n_vertices()) +
                                " vertices; pass one value per vertex, indexed by v.idx()");
    const double min_area = area_floor(mesh);
    Eigen::MatrixX3d G(mesh.n_faces(), 3);
    for (auto face : mesh.faces())
    {
        const auto h0 = face.halfedge();
        const auto h1 = h0.next();
        const auto h2 = h1.next();
        const int ia = h0.from().idx(), ib = h1.from().idx(), ic = h2.from().idx();
        const Eigen::Vector3d a = to_eigen(mesh.point(h0.from()));
        const Eigen::Vector3d b = to_eigen(mesh.point(h1.from()));
        const Eigen::Vector3d c = to_eigen(mesh.point(h2.from()));
        const Eigen::Vector3d cross = (b - a).cross(c - a);
        const double twice_area = cross.norm();
        if (twice_area <= 0.0)
        {
            // A collinear face has no plane and hence no gradient.
            G.row(face.idx()).setZero();
            continue;
        }
        const Eigen::Vector3d N = cross / twice_area;
        // N x (opposite edge, counter-clockwise) points toward the corner, with length equal to
        // that edge; dividing by 2A gives the gradient of the corner's hat function.
        const Eigen::Vector3d g = f[ia] * N.cross(c - b) + f[ib] * N.cross(a - c) +
                                  f[ic] * N.cross(b - a);
        G.row(face.idx()) = (g / std::max(twice_area, 2.0 * min_area)).transpose();
    }
    return G;
}

Eigen::MatrixX3d vertex_gradient(const Mesh& mesh, const Eigen::VectorXd& f)
{
    if (f.size() != static_cast<Eigen::Index>(mesh.n_vertices()))
        throw InvalidInputError("vertex_gradient: function has " + std::to_string(f.size()) +
                                " values but the mesh has " + std::to_string(mesh.n_vertices()) +
                                " vertices; pass one value per vertex, indexed by v.idx()");
    // face_gradient() and face_areas() in one pass over the faces, each face's gradient added
    // to its corners as it is made: the same values as averaging face_gradient() with the
    // face_areas() weights (each vertex still sums its faces in face order), without the two
    // |F| arrays and their second and third passes.
    const double floor = 2.0 * area_floor(mesh);
    Eigen::MatrixX3d Gv = Eigen::MatrixX3d::Zero(mesh.n_vertices(), 3);
    Eigen::VectorXd weight = Eigen::VectorXd::Zero(mesh.n_vertices());
    for (auto face : mesh.faces())
    {
        const auto h0 = face.halfedge();
        const auto h1 = h0.next();
        const auto h2 = h1.next();
        const int corner[3] = {h0.from().idx(), h1.from().idx(), h2.from().idx()};
        const auto& pa = mesh.point(h0.from());
        const auto& pb = mesh.point(h1.from());
        const auto& pc = mesh.point(h2.from());
        const Eigen::Vector3d a = to_eigen(pa), b = to_eigen(pb), c = to_eigen(pc);
        const Eigen::Vector3d cross = (b - a).cross(c - a);
        const double twice_area = cross.norm();
        Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
        if (twice_area > 0.0)  // else collinear: no plane, no gradient (as face_gradient())
        {
            const Eigen::Vector3d N = cross / twice_area;
            const Eigen::Vector3d g = f[corner[0]] * N.cross(c - b) +
                                      f[corner[1]] * N.cross(a - c) + f[corner[2]] * N.cross(b - a);
            gradient = g / std::max(twice_area, floor);
        }
        const double area = 0.5 * OpenMesh::cross(pb - pa, pc - pa).norm();  // as face_areas()
        for (int v : corner)
        {
            Gv.row(v) += area * gradient.transpose();
            weight[v] += area;
        }
    }
    for (Eigen::Index i = 0; i < Gv.rows(); ++i)
        if (weight[i] > 0.0)
            Gv.row(i) /= weight[i];
    return Gv;
}

}  // namespace vessel
