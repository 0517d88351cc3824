#include "vessel/direction/geodesic.h"

#include "vessel/core/errors.h"
#include "vessel/core/operators.h"
#include "solve/cholmod_common.h"
#include "solve/serial_openmp.h"
#include "solve/subtree_factorization.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <numeric>
#include <string>
#include <thread>

namespace vessel {

namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

// Eigen's CholmodSupernodalLLT cannot share one symbolic analysis between several matrices, so
// the factors are driven through CHOLMOD's own API (on Eigen's zero-copy viewAsCholmod views).
// Each thread and each query uses its own Common, so const queries are thread-safe.
using Common = detail::CholmodCommon;

struct FactorDeleter
{
    void operator()(cholmod_factor* L) const
    {
        Common common;
        cholmod_free_factor(&L, &common.c);
    }
};
using FactorPtr = std::unique_ptr<cholmod_factor, FactorDeleter>;

[[noreturn]] void throw_cholmod(const std::string& what, const cholmod_common& c)
{
    throw SolverError("HeatGeodesics: CHOLMOD " + what + " failed (status " +
                      std::to_string(c.status) +
                      "); the mesh may contain degenerate or duplicated faces, try repairing it "
                      "first");
}

cholmod_sparse lower_view(const SparseMatrix& A)
{
    return Eigen::viewAsCholmod(A.selfadjointView<Eigen::Lower>());
}

void factorize(const SparseMatrix& A, cholmod_factor* L, const char* what)
{
    Common common;
    cholmod_sparse view = lower_view(A);
    const detail::SerialOpenMp serial;  // serial BLAS: the same bits in every run (see there)
    // One thread each: the three factorizations already share the two cores.
    if (!detail::factorize_once(view, *L, common.c, 1))
        throw_cholmod(std::string("factorization of the ") + what, common.c);
}

// Solves A x = b for sys = CHOLMOD_A (other CHOLMOD_* systems work the same way).
Eigen::VectorXd cholmod_solve_vector(int sys, cholmod_factor* L, Eigen::VectorXd b,
                                     const char* what)
{
    Common common;
    cholmod_dense B{};
    B.nrow = B.nzmax = B.d = static_cast<size_t>(b.size());
    B.ncol = 1;
    B.x = b.data();
    B.xtype = CHOLMOD_REAL;
    B.dtype = CHOLMOD_DOUBLE;
    cholmod_dense* X = cholmod_solve(sys, L, &B, &common.c);
    if (X == nullptr || common.c.status != CHOLMOD_OK)
    {
        cholmod_free_dense(&X, &common.c);
        throw_cholmod(std::string("solve of the ") + what, common.c);
    }
    Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(static_cast<double*>(X->x), b.size());
    cholmod_free_dense(&X, &common.c);
    if (!x.allFinite())
        throw_cholmod(std::string("solve of the ") + what + " (non-finite result)", common.c);
    return x;
}

// Replaces the rows and columns of the flagged vertices by those of the identity while keeping
// every stored entry (explicit zeros), so that all systems share one sparsity pattern.
void make_identity_rows(SparseMatrix& A, const std::vector<char>& fixed)
{
    for (int j = 0; j < A.outerSize(); ++j)
        for (SparseMatrix::InnerIterator it(A, j); it; ++it)
            if (fixed[it.row()] || fixed[j])
                it.valueRef() = it.row() == j ? 1.0 : 0.0;
}

// Connected components over mesh edges; isolated vertices form their own component.
std::vector<int> vertex_components(const Mesh& mesh, int& n_components)
{
    std::vector<int> parent(mesh.n_vertices());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int x) {
        while (parent[x] != x)
            x = parent[x] = parent[parent[x]];
        return x;
    };
    for (auto e : mesh.edges())
    {
        const int a = find(e.v0().idx()), b = find(e.v1().idx());
        if (a != b)
            parent[std::max(a, b)] = std::min(a, b);
    }
    std::vector<int> label(mesh.n_vertices(), -1);
    n_components = 0;
    for (int i = 0; i < static_cast<int>(parent.size()); ++i)
    {
        const int root = find(i);
        if (label[root] < 0)
            label[root] = n_components++;
        label[i] = label[root];
    }
    return label;
}

}  // namespace

void HeatGeodesicsOptions::validate() const
{
    if (!(time_factor > 0.0) || !std::isfinite(time_factor))
        throw InvalidInputError("HeatGeodesicsOptions: time_factor = " +
                                std::to_string(time_factor) +
                                " is not a positive finite number; use about 1 (Crane et al.), "
                                "larger values give smoother distances");
    if (boundary_condition != HeatBoundaryCondition::Neumann &&
        boundary_condition != HeatBoundaryCondition::Average)
        throw InvalidInputError("HeatGeodesicsOptions: boundary_condition = " +
                                std::to_string(static_cast<int>(boundary_condition)) +
                                " is not a HeatBoundaryCondition; use Neumann or Average");
}

// Up to three Cholesky factors of matrices with the sparsity pattern of L: the heat operator
// M + tL (Neumann), the same with identity rows on the boundary (Dirichlet), and L with one
// pinned vertex per component. They share one AMD ordering and symbolic analysis.
//
// Neumann is the default boundary condition although Crane et al. 2013 recommend averaging it
// with Dirichlet. libvessel measures from a boundary loop (the inlet rim), where the Neumann
// solution is exact by reflection for straight boundaries, and a Dirichlet solution has to be
// patched so that it does not erase the sources. Measured: on a plane grid from a corner and an
// edge midpoint, and on a cylinder from a rim vertex, Neumann alone has equal or smaller error
// (max relative error 0.057 vs 0.079 from the edge midpoint, 0.10 vs 0.16 on the cylinder); on
// the 277k-triangle pulmonary Glenn mesh from its inlet the two differ by < 0.01% of the range.
// The average costs a third factorization, i.e. about half again the construction time.
struct HeatGeodesics::Impl
{
    int n_vertices = 0;
    HeatBoundaryCondition boundary_condition = HeatBoundaryCondition::Neumann;
    // Per face: corner vertex indices and, per corner, half of N x (opposite edge), i.e. the
    // area-weighted gradient of the corner's hat function. The heat gradient only needs its
    // direction and the divergence is G^T A X, so the area cancels and is never stored.
    std::vector<std::array<int, 3>> corners;
    std::vector<std::array<Eigen::Vector3d, 3>> hat_gradients;

    std::vector<char> is_boundary;
    bool has_boundary = false;
    std::vector<int> component;
    int n_components = 0;
    std::vector<int> pins;  // first vertex of each component, held at 0 in the Poisson system

    SparseMatrix heat;  // M + tL, kept to lift boundary values into the Dirichlet right-hand side
    FactorPtr heat_neumann;
    FactorPtr heat_dirichlet;  // only for HeatBoundaryCondition::Average on meshes with boundary
    FactorPtr poisson;
};

HeatGeodesics::HeatGeodesics(const Mesh& mesh, const HeatGeodesicsOptions& options)
    : impl_(std::make_unique<Impl>())
{
    options.validate();
    if (mesh.n_faces() == 0)
        throw InvalidInputError("HeatGeodesics: the mesh has no faces (" +
                                std::to_string(mesh.n_vertices()) +
                                " vertices); pass a triangle mesh");
    Impl& d = *impl_;
    const int n = static_cast<int>(mesh.n_vertices());
    d.n_vertices = n;

    d.corners.resize(mesh.n_faces());
    d.hat_gradients.resize(mesh.n_faces());
    for (auto f : mesh.faces())
    {
        auto h = f.halfedge();
        Eigen::Vector3d p[3];
        for (int k = 0; k < 3; ++k, h = h.next())
        {
            d.corners[f.idx()][k] = h.from().idx();
            p[k] = to_eigen(mesh.point(h.from()));
        }
        const Eigen::Vector3d cross = (p[1] - p[0]).cross(p[2] - p[0]);
        const double norm = cross.norm();
        const Eigen::Vector3d N =
            norm > 0.0 ? Eigen::Vector3d(cross / norm) : Eigen::Vector3d(0, 0, 0);
        for (int k = 0; k < 3; ++k)
            d.hat_gradients[f.idx()][k] = 0.5 * N.cross(p[(k + 2) % 3] - p[(k + 1) % 3]);
    }

    d.is_boundary.assign(n, 0);
    std::vector<char> is_isolated(n, 0);
    for (auto v : mesh.vertices())
    {
        is_isolated[v.idx()] = mesh.is_isolated(v);
        d.is_boundary[v.idx()] = v.is_boundary() && !is_isolated[v.idx()];
        d.has_boundary = d.has_boundary || d.is_boundary[v.idx()];
    }
    d.component = vertex_components(mesh, d.n_components);

    const SparseMatrix L = cotan_laplacian(mesh);
    const Eigen::VectorXd M = lumped_mass(mesh);
    const double h = mean_edge_length(mesh);
    const double t = options.time_factor * h * h;

    d.heat = t * L;
    for (int i = 0; i < n; ++i)
        d.heat.coeffRef(i, i) += M[i];
    // Isolated vertices have an empty row; an identity row keeps the systems definite.
    make_identity_rows(d.heat, is_isolated);

    // L is singular (constants per component). Pinning one vertex per component gives the exact
    // solution of the compatible Poisson system (the divergence sums to zero per component),
    // unlike an L + eps*M shift whose error grows with the mesh diameter.
    SparseMatrix P = L;
    {
        std::vector<char> pinned(n, 0);
        std::vector<char> seen(d.n_components, 0);
        for (int i = 0; i < n; ++i)
            if (!seen[d.component[i]])
            {
                seen[d.component[i]] = 1;
                pinned[i] = 1;
                d.pins.push_back(i);
            }
        make_identity_rows(P, pinned);
    }

    const bool use_dirichlet =
        d.has_boundary && options.boundary_condition == HeatBoundaryCondition::Average;
    SparseMatrix dirichlet;
    if (use_dirichlet)
    {
        dirichlet = d.heat;
        make_identity_rows(dirichlet, d.is_boundary);
    }

    {
        Common common;
        // The given ordering, else AMD only: CHOLMOD's default may also try METIS, which is
        // much slower to order meshes of this kind and gains less than it costs for a few
        // solves.
        std::vector<int> given;
        if (options.ordering)
        {
            std::vector<int> all(n);
            std::iota(all.begin(), all.end(), 0);
            given = unknown_order(*options.ordering, all, n);
        }
        common.c.nmethods = 1;
        common.c.method[0].ordering = CHOLMOD_AMD;
        common.c.supernodal = CHOLMOD_SUPERNODAL;
        cholmod_sparse view = lower_view(d.heat);
        d.heat_neumann.reset(
            detail::analyze_in_order(view, options.ordering ? &given : nullptr, common.c));
        if (!d.heat_neumann || common.c.status != CHOLMOD_OK)
            throw_cholmod("symbolic analysis", common.c);
        d.poisson.reset(cholmod_copy_factor(d.heat_neumann.get(), &common.c));
        if (use_dirichlet)
            d.heat_dirichlet.reset(cholmod_copy_factor(d.heat_neumann.get(), &common.c));
        if (!d.poisson || (use_dirichlet && !d.heat_dirichlet))
            throw_cholmod("copy of the symbolic analysis", common.c);
    }

    // The numeric factorizations are independent; two threads share them (the target machines
    // have two cores; factorize() keeps the BLAS serial).
    struct Task
    {
        const SparseMatrix* A;
        cholmod_factor* L;
        const char* what;
    };
    std::vector<Task> tasks{{&P, d.poisson.get(), "Poisson system (cotan Laplacian)"},
                            {&d.heat, d.heat_neumann.get(), "heat system (M + tL)"}};
    if (use_dirichlet)
        tasks.push_back({&dirichlet, d.heat_dirichlet.get(), "Dirichlet heat system"});
    std::atomic<size_t> next_task{0};
    std::exception_ptr errors[2];
    auto run = [&](int slot) {
        try
        {
            for (size_t k = next_task++; k < tasks.size(); k = next_task++)
                factorize(*tasks[k].A, tasks[k].L, tasks[k].what);
        }
        catch (...)
        {
            errors[slot] = std::current_exception();
        }
    };
    std::thread worker(run, 1);
    run(0);
    worker.join();
    for (const auto& error : errors)
        if (error)
            std::rethrow_exception(error);
}

HeatGeodesics::~HeatGeodesics() = default;
HeatGeodesics::HeatGeodesics(HeatGeodesics&&) noexcept = default;
HeatGeodesics& HeatGeodesics::operator=(HeatGeodesics&&) noexcept = default;

Eigen::VectorXd HeatGeodesics::distance(const std::vector<VertexHandle>& sources) const
{
    if (!impl_)
        throw InvalidInputError("HeatGeodesics::distance: this solver was moved from; construct "
                                "a new one");
    const Impl& d = *impl_;
    if (sources.empty())
        throw InvalidInputError("HeatGeodesics::distance: no source vertices; pass at least one "
                                "vertex (e.g. the inlet rim)");
    for (const auto& s : sources)
        if (!s.is_valid() || s.idx() >= d.n_vertices)
            throw InvalidInputError("HeatGeodesics::distance: source vertex " +
                                    std::to_string(s.idx()) + " is not a vertex of the mesh (" +
                                    std::to_string(d.n_vertices) +
                                    " vertices); pass handles of the mesh given to the "
                                    "constructor");
    const int n = d.n_vertices;

    Eigen::VectorXd delta = Eigen::VectorXd::Zero(n);
    for (const auto& s : sources)
        delta[s.idx()] = 1.0;
    Eigen::VectorXd u =
        cholmod_solve_vector(CHOLMOD_A, d.heat_neumann.get(), delta, "heat system");

    if (d.heat_dirichlet)
    {
        // Crane et al. 2013 (sec. 3.2.2) average the Neumann and Dirichlet (u = 0 on the
        // boundary) solutions: Neumann alone bends isolines to meet the open rims at right
        // angles, Dirichlet alone pulls them parallel to the rims. A source on the boundary
        // (such as an inlet rim) would be erased by u = 0, so it keeps its Neumann value there;
        // that known value is moved to the right-hand side of the neighbouring interior rows.
        Eigen::VectorXd rhs = delta;
        for (int b = 0; b < n; ++b)
            if (d.is_boundary[b])
                rhs[b] = 0.0;
        for (const auto& s : sources)
        {
            const int b = s.idx();
            if (!d.is_boundary[b])
                continue;
            rhs[b] = u[b];
            for (SparseMatrix::InnerIterator it(d.heat, b); it; ++it)
                if (!d.is_boundary[it.row()])
                    rhs[it.row()] -= it.value() * u[b];
        }
        u = 0.5 * (u + cholmod_solve_vector(CHOLMOD_A, d.heat_dirichlet.get(), std::move(rhs),
                                            "Dirichlet heat system"));
    }

    // Divergence of the normalized field X = -grad u / |grad u|, as G^T A X.
    Eigen::VectorXd div = Eigen::VectorXd::Zero(n);
    for (size_t f = 0; f < d.corners.size(); ++f)
    {
        const auto& c = d.corners[f];
        const auto& g = d.hat_gradients[f];
        const Eigen::Vector3d grad = u[c[0]] * g[0] + u[c[1]] * g[1] + u[c[2]] * g[2];
        const double norm = grad.norm();
        // Far from the sources (or in a component without sources) the heat underflows to
        // zero and has no direction; such faces contribute no divergence.
        if (!(norm > 0.0) || !std::isfinite(norm))
            continue;
        const Eigen::Vector3d X = -grad / norm;
        for (int k = 0; k < 3; ++k)
            div[c[k]] += X.dot(g[k]);
    }
    // A pinned row replaces the one redundant equation of its component.
    for (int i : d.pins)
        div[i] = 0.0;
    // L phi = G^T A X makes grad phi the least-squares fit of X, so phi grows away from sources.
    Eigen::VectorXd phi =
        cholmod_solve_vector(CHOLMOD_A, d.poisson.get(), std::move(div), "Poisson system");

    const double inf = std::numeric_limits<double>::infinity();
    std::vector<double> offset(d.n_components, inf);
    for (const auto& s : sources)
        offset[d.component[s.idx()]] = std::min(offset[d.component[s.idx()]], phi[s.idx()]);
    for (int i = 0; i < n; ++i)
    {
        const double o = offset[d.component[i]];
        phi[i] = o == inf ? inf : phi[i] - o;
    }
    return phi;
}

Eigen::VectorXd heat_geodesic_distance(const Mesh& mesh, const std::vector<VertexHandle>& sources,
                                       const HeatGeodesicsOptions& options)
{
    // Reject empty sources before paying for the factorizations.
    if (sources.empty())
        throw InvalidInputError("heat_geodesic_distance: no source vertices; pass at least one "
                                "vertex (e.g. the inlet rim)");
    return HeatGeodesics(mesh, options).distance(sources);
}

}  // namespace vessel
