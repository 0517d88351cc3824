#include "vessel/map/lscm.h"

#include "vessel/core/errors.h"
#include "vessel/core/operators.h"
#include "solve/paired_cholmod.h"
#include "solve/serial_openmp.h"

#include <Eigen/CholmodSupport>

#include <cmath>
#include <limits>
#include <string>
#include <vector>


namespace vessel {

namespace {

// Calls add(row, col, value) for every entry of L_C = blockdiag(L, L) - M, with L the cotan
// Laplacian (weights (cot a + cot b) / 2, so 1/2 u^T L u is the Dirichlet energy) and M the
// symmetric form with 1/2 x^T M x = signed area of the image (shoelace over the boundary).
// Dofs are in block order: u of vertex i is i, v of vertex i is n + i. Entries may repeat.
template <class Add>
void assemble_conformal(const Mesh& mesh, Add&& add)
{
    const int n = static_cast<int>(mesh.n_vertices());
    const Eigen::SparseMatrix<double> L = cotan_laplacian(mesh);
    for (int col = 0; col < L.outerSize(); ++col)
        for (Eigen::SparseMatrix<double>::InnerIterator it(L, col); it; ++it)
            for (int c = 0; c < 2; ++c)
                add(c * n + static_cast<int>(it.row()), c * n + col, it.value());
    // The face-side halfedge of a boundary edge runs with the interior on its left, so summing
    // u_i v_j - u_j v_i over them gives twice the signed (counter-clockwise positive) area.
    for (auto h : mesh.halfedges())
    {
        if (!h.is_boundary())
            continue;
        const auto o = h.opp();
        const int i = o.from().idx(), j = o.to().idx();
        add(i, n + j, -0.5);
        add(n + j, i, -0.5);
        add(j, n + i, 0.5);
        add(n + i, j, 0.5);
    }
}

void check_pins(const Mesh& mesh, const Pins& pins, std::vector<int>& pinned)
{
    if (pins.size() < 2)
        throw InvalidInputError("lscm: need at least two pins (got " + std::to_string(pins.size()) +
                                "); pin two vertices far apart, e.g. on the boundary");
    pinned = pin_index(mesh, pins, "lscm");
    bool distinct = false;
    for (const auto& pin : pins)
        distinct = distinct || (pin.uv - pins[0].uv).squaredNorm() > 0;
    if (!distinct)
        throw InvalidInputError("lscm: all " + std::to_string(pins.size()) +
                                " pins have the same target; give at least two distinct targets");
}

// Fallback when the supernodal LLT fails (CHOLMOD: "matrix not positive definite"; seen on the
// Glenn mesh with an experimental cut plan, where a near-degenerate region along the seam left
// a pivot at round-off): factor A + s I, s = 1e-10 x the largest diagonal entry, and refine the
// solution against A itself. The refinement converges to A's solution wherever A is definite;
// directions A does not constrain stay at the shift's minimum-norm answer instead of blowing up.
Eigen::VectorXd solve_regularised(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b)
{
    const double shift = 1e-10 * std::max(1e-300, A.diagonal().cwiseAbs().maxCoeff());
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> solver;
    solver.setShift(shift);
    {
        const detail::SerialOpenMp serial;
        solver.compute(A);
    }
    if (solver.info() != Eigen::Success)
        throw SolverError("lscm: CHOLMOD could not factor the conformal system (" +
                          std::to_string(A.rows()) + " unknowns), not even regularised; every " +
                          "connected component needs two pins and the mesh must have no " +
                          "degenerate triangles");
    const auto full = A.selfadjointView<Eigen::Upper>();
    Eigen::VectorXd x = solver.solve(b);
    for (int round = 0; round < 5 && x.allFinite(); ++round)
        x += solver.solve(b - full * x);
    if (!x.allFinite())
        throw SolverError("lscm: the regularised conformal solve failed; check the mesh for "
                          "degenerate triangles");
    return x;
}

}  // namespace

Eigen::SparseMatrix<double> lscm_energy_matrix(const Mesh& mesh)
{
    const int n = static_cast<int>(mesh.n_vertices());
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(4 * mesh.n_edges() + 2 * mesh.n_vertices() + 8 * mesh.n_edges() / 16);
    assemble_conformal(mesh, [&](int r, int c, double w) { triplets.emplace_back(r, c, w); });
    Eigen::SparseMatrix<double> L(2 * n, 2 * n);
    L.setFromTriplets(triplets.begin(), triplets.end());
    return L;
}

double conformal_energy(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    if (uv.rows() != static_cast<Eigen::Index>(mesh.n_vertices()))
        throw InvalidInputError("conformal_energy: uv has " + std::to_string(uv.rows()) +
                                " rows but the mesh has " + std::to_string(mesh.n_vertices()) +
                                " vertices; pass one row per vertex");
    double energy = 0.0;
    for (auto f : mesh.faces())
    {
        const auto h = f.halfedge();
        const int i0 = h.from().idx(), i1 = h.to().idx(), i2 = h.next().to().idx();
        const Eigen::Vector3d p0 = to_eigen(mesh.point(h.from()));
        const Eigen::Vector3d e1 = to_eigen(mesh.point(h.to())) - p0;
        const Eigen::Vector3d e2 = to_eigen(mesh.point(h.next().to())) - p0;
        // Isometric 2D frame of the triangle: x1 = (|e1|, 0), x2 = (a, b).
        const double l1 = e1.norm();
        const double a = e1.dot(e2) / l1, b = e1.cross(e2).norm() / l1;
        Eigen::Matrix2d X, D;
        X << l1, a, 0.0, b;
        D.col(0) = (uv.row(i1) - uv.row(i0)).transpose();
        D.col(1) = (uv.row(i2) - uv.row(i0)).transpose();
        const Eigen::Matrix2d J = D * X.inverse();
        const double area = 0.5 * l1 * b;
        energy +=
            0.5 * area *
            ((J(0, 0) - J(1, 1)) * (J(0, 0) - J(1, 1)) + (J(0, 1) + J(1, 0)) * (J(0, 1) + J(1, 0)));
    }
    return energy;
}

Eigen::MatrixX2d lscm(const Mesh& mesh, const Pins& pins, const VertexOrdering* ordering)
{
    const int n = static_cast<int>(mesh.n_vertices());
    if (mesh.n_faces() == 0)
        throw InvalidInputError("lscm: the mesh has no faces; pass a triangulated disk");
    std::vector<int> pinned;
    check_pins(mesh, pins, pinned);

    // Unknowns: (u, v) of every free vertex that has a face, interleaved (2k, 2k + 1).
    // Vertices without faces would make the system singular; they stay at (0, 0).
    Eigen::MatrixX2d uv = Eigen::MatrixX2d::Zero(n, 2);
    std::vector<int> dof(2 * n, -1);
    int n_free = 0;
    for (auto v : mesh.vertices())
    {
        if (pinned[v.idx()] >= 0)
            uv.row(v.idx()) = pins[pinned[v.idx()]].uv.transpose();
        else if (!mesh.is_isolated(v))
        {
            dof[v.idx()] = 2 * n_free;
            dof[n + v.idx()] = 2 * n_free + 1;
            ++n_free;
        }
    }
    if (n_free == 0)
        return uv;

    // Minimising 1/2 x^T L_C x with the pinned entries fixed: L_ff x_f = -L_fp x_p.
    const int m = 2 * n_free;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(2 * mesh.n_edges() + 2 * mesh.n_vertices());
    assemble_conformal(mesh, [&](int r, int c, double w) {
        const int fr = dof[r];
        if (fr < 0)
            return;
        const int fc = dof[c];
        if (fc >= 0)
        {
            if (fr <= fc)  // the solver reads the upper triangle only
                triplets.emplace_back(fr, fc, w);
        }
        else
            rhs[fr] -= w * uv(c % n, c / n);
    });
    Eigen::SparseMatrix<double> A(m, m);
    A.setFromTriplets(triplets.begin(), triplets.end());

    // CHOLMOD's supernodal LLT rather than Eigen's SimplicialLDLT: on a 300k-triangle mesh
    // (300k unknowns, ~17M nonzeros in the factor) its BLAS-3 supernodes factor 2.6x faster than
    // SimplicialLDLT and 3.3x faster than CHOLMOD's own simplicial LDLT (measured 4.0 s vs 10.3 s
    // vs 13.4 s wall on a loaded 2-core machine). The unknowns come in (u, v) pairs, so AMD
    // orders the vertex graph (PairedCholmod), a quarter of the entries. METIS would cut the
    // fill on large maps but costs more than it saves in this single factorization (carotid-300k
    // with METIS: slower in alternated runs). A given ordering skips AMD (about 0.1 s at 300k).
    std::vector<int> given;  // the pairs' order from `ordering`
    if (ordering)
    {
        std::vector<int> pair_of(n, -1);
        for (int i = 0; i < n; ++i)
            if (dof[i] >= 0)
                pair_of[i] = dof[i] / 2;
        given = unknown_order(*ordering, pair_of, n_free);
    }
    detail::PairedCholmod solver;
    {
        const detail::SerialOpenMp serial;
        solver.analyze_pairs(A, std::numeric_limits<int>::max(), ordering ? &given : nullptr);
        if (solver.info() == Eigen::Success)
            solver.factorize(A);
    }
    Eigen::VectorXd x;
    if (solver.info() == Eigen::Success)
        x = solver.solve(rhs);
    if (solver.info() != Eigen::Success || !x.allFinite())
        x = solve_regularised(A, rhs);  // numerically singular: never fail the run here
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 2; ++c)
            if (dof[c * n + i] >= 0)
                uv(i, c) = x[dof[c * n + i]];
    return uv;
}

}  // namespace vessel
