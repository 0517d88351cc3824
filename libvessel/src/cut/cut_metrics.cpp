#include "vessel/cut/cut_metrics.h"

#include "vessel/core/errors.h"
#include "vessel/core/operators.h"
#include "detail/edge_distance.h"
#include "solve/paired_cholmod.h"
#include "solve/serial_openmp.h"

#include <Eigen/CholmodSupport>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace vessel {

void SeamAlignmentOptions::validate() const
{
    if (window < 1)
        throw InvalidInputError("SeamAlignmentOptions: window must be >= 1 edge, got " +
                                std::to_string(window));
}

PathAlignment path_alignment(const Mesh& mesh, const CutPath& path,
                             const Eigen::MatrixX3d& reference, const SeamAlignmentOptions& options)
{
    options.validate();
    PathAlignment result;
    if (path.halfedges.empty())
        return result;
    std::vector<Eigen::Vector3d> points{to_eigen(mesh.point(path.start))};
    std::vector<int> ids{path.start.idx()};
    for (auto h : path.halfedges)
    {
        const VertexHandle v = mesh.to_vertex_handle(h);
        points.push_back(to_eigen(mesh.point(v)));
        ids.push_back(v.idx());
    }
    for (int id : ids)
        if (id >= reference.rows())
            throw InvalidInputError("path_alignment: the cut passes vertex " + std::to_string(id) +
                                    " but the reference field has " +
                                    std::to_string(reference.rows()) +
                                    " rows; pass one row per vertex, indexed by v.idx()");
    const int n = static_cast<int>(points.size());
    double weighted = 0.0, low = 0.0, total = 0.0;
    for (int i = 0; i < n; ++i)
    {
        // Half of each edge at the vertex: the weights sum to the path length.
        double weight = 0.0;
        if (i > 0)
            weight += 0.5 * (points[i] - points[i - 1]).norm();
        if (i + 1 < n)
            weight += 0.5 * (points[i + 1] - points[i]).norm();
        result.length += i > 0 ? (points[i] - points[i - 1]).norm() : 0.0;
        const Eigen::Vector3d chord =
            points[std::min(n - 1, i + options.window)] - points[std::max(0, i - options.window)];
        const Eigen::Vector3d z = reference.row(ids[i]).transpose();
        const double norms = chord.norm() * z.norm();
        if (!(norms > 0.0) || !std::isfinite(norms))
            continue;
        const double c = std::abs(chord.dot(z)) / norms;
        weighted += weight * c;
        low += c < 0.5 ? weight : 0.0;
        total += weight;
    }
    if (total > 0.0)
    {
        result.mean = weighted / total;
        result.low_fraction = low / total;
    }
    return result;
}

struct HarmonicLongitudinal::Impl
{
    std::vector<BoundaryLoop> loops;
    std::vector<Eigen::Index> unknown;  // per vertex: its unknown, or -1 on a loop
    Eigen::SparseMatrix<double> L;      // cotan Laplacian, for the loops' right-hand side
    detail::OrderedCholmod<Eigen::Lower> solver;
};

HarmonicLongitudinal::HarmonicLongitudinal(const Mesh& mesh,
                                           const std::vector<BoundaryLoop>& loops,
                                           const VertexOrdering* ordering)
    : impl_(std::make_unique<Impl>())
{
    if (loops.size() < 2)
        throw InvalidInputError("harmonic_longitudinal: " + std::to_string(loops.size()) +
                                " boundary loop(s); an inlet and at least one outlet are needed");
    Impl& d = *impl_;
    const auto n = static_cast<Eigen::Index>(mesh.n_vertices());
    d.loops = loops;
    std::vector<char> fixed(n, 0);
    for (const auto& loop : loops)
        for (auto v : loop.vertices)
            fixed[v.idx()] = 1;
    d.unknown.assign(n, -1);
    Eigen::Index n_free = 0;
    for (Eigen::Index i = 0; i < n; ++i)
        if (!fixed[i])
            d.unknown[i] = n_free++;
    d.L = cotan_laplacian(mesh);
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(static_cast<std::size_t>(d.L.nonZeros()));
    for (Eigen::Index col = 0; col < d.L.outerSize(); ++col)
        for (Eigen::SparseMatrix<double>::InnerIterator it(d.L, col); it; ++it)
        {
            const Eigen::Index r = d.unknown[it.row()];
            if (r >= 0 && d.unknown[col] >= 0)
                entries.emplace_back(r, d.unknown[col], it.value());
        }
    Eigen::SparseMatrix<double> A(n_free, n_free);
    A.setFromTriplets(entries.begin(), entries.end());
    {
        const detail::SerialOpenMp serial;  // serial BLAS: the same bits in every run
        d.solver.set_threads(1);  // flatten() makes it on a thread beside the curvature fits
        if (ordering)
        {
            std::vector<int> unknown_of(d.unknown.begin(), d.unknown.end());
            d.solver.analyze_given(A, unknown_order(*ordering, unknown_of,
                                                    static_cast<int>(n_free)));
        }
        else
            d.solver.analyzePattern(A);
        if (d.solver.info() == Eigen::Success)
            d.solver.factorize(A);
    }
    if (d.solver.info() != Eigen::Success)
        throw SolverError("harmonic_longitudinal: the Laplacian with the loops fixed could not be "
                          "factorized; every connected part of the mesh needs a boundary loop");
}

HarmonicLongitudinal::~HarmonicLongitudinal() = default;
HarmonicLongitudinal::HarmonicLongitudinal(HarmonicLongitudinal&&) noexcept = default;
HarmonicLongitudinal& HarmonicLongitudinal::operator=(HarmonicLongitudinal&&) noexcept = default;

Eigen::VectorXd HarmonicLongitudinal::solve(const Eigen::VectorXd& geodesic) const
{
    if (!impl_)
        throw InvalidInputError("HarmonicLongitudinal::solve: this solver was moved from; "
                                "construct a new one");
    const Impl& d = *impl_;
    const auto n = static_cast<Eigen::Index>(d.unknown.size());
    if (geodesic.size() != n)
        throw InvalidInputError("harmonic_longitudinal: " + std::to_string(geodesic.size()) +
                                " distances for " + std::to_string(n) + " vertices");
    // Dirichlet values on the loops; the other vertices are unknowns.
    Eigen::VectorXd value = Eigen::VectorXd::Zero(n);
    for (std::size_t l = 0; l < d.loops.size(); ++l)
    {
        double mean = 0.0;
        for (auto v : d.loops[l].vertices)
            mean += geodesic[v.idx()];
        mean = l == 0 ? 0.0 : mean / static_cast<double>(d.loops[l].vertices.size());
        for (auto v : d.loops[l].vertices)
            value[v.idx()] = mean;
    }
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(d.solver.rows());
    for (Eigen::Index col = 0; col < d.L.outerSize(); ++col)
        for (Eigen::SparseMatrix<double>::InnerIterator it(d.L, col); it; ++it)
        {
            const Eigen::Index r = d.unknown[it.row()];
            if (r >= 0 && d.unknown[col] < 0)
                rhs[r] -= it.value() * value[col];
        }
    const Eigen::VectorXd x = d.solver.solve(rhs);
    for (Eigen::Index i = 0; i < n; ++i)
        if (d.unknown[i] >= 0)
            value[i] = x[d.unknown[i]];
    return value;
}

Eigen::VectorXd harmonic_longitudinal(const Mesh& mesh, const std::vector<BoundaryLoop>& loops,
                                      const Eigen::VectorXd& geodesic)
{
    const auto n = static_cast<Eigen::Index>(mesh.n_vertices());
    if (loops.size() >= 2 && geodesic.size() != n)  // before paying for the factorization
        throw InvalidInputError("harmonic_longitudinal: " + std::to_string(geodesic.size()) +
                                " distances for " + std::to_string(n) + " vertices");
    return HarmonicLongitudinal(mesh, loops).solve(geodesic);
}

namespace {

void require_beside_distance(double distance)
{
    if (!(distance >= 0.0) || !std::isfinite(distance))
        throw InvalidInputError("beside_length: distance must be finite and >= 0");
}

void add_cut_vertices(const Mesh& mesh, const CutPath& path, std::vector<VertexHandle>& seeds)
{
    seeds.push_back(path.start);
    for (auto h : path.halfedges)
        seeds.push_back(mesh.to_vertex_handle(h));
}

// Within `distance` of the tree (\p dist: edge-path distance from the earlier cuts' vertices),
// an edge counts by the part of its length that does not bring the cut closer to the tree: a
// head-on approach scores ~0, a run at a constant offset its length.
double run_beside(const Mesh& mesh, const CutPath& cut, const std::vector<double>& dist,
                  double distance)
{
    double length = 0.0;
    for (auto h : cut.halfedges)
    {
        const double a = dist[mesh.from_vertex_handle(h).idx()];
        const double b = dist[mesh.to_vertex_handle(h).idx()];
        if (a <= distance && b <= distance)
            length += std::max(0.0, mesh.calc_edge_length(h) - (a - b));
    }
    return length;
}

}  // namespace

double beside_length(const Mesh& mesh, const CutPlan& plan, std::size_t index, double distance)
{
    if (index >= plan.paths.size())
        throw InvalidInputError("beside_length: cut " + std::to_string(index) + " of " +
                                std::to_string(plan.paths.size()));
    require_beside_distance(distance);
    std::vector<VertexHandle> seeds;
    for (std::size_t i = 0; i < index; ++i)
        add_cut_vertices(mesh, plan.paths[i], seeds);
    detail::EdgeDistance field;
    field.reset(mesh.n_vertices());
    field.grow(mesh, seeds, detail::mesh_neighbours(mesh), [](int) { return true; }, distance);
    return run_beside(mesh, plan.paths[index], field.dist, distance);
}

std::vector<double> beside_lengths(const Mesh& mesh, const CutPlan& plan,
                                   const std::vector<double>& distance)
{
    if (distance.size() != plan.paths.size())
        throw InvalidInputError("beside_lengths: " + std::to_string(distance.size()) +
                                " distances for " + std::to_string(plan.paths.size()) + " cuts");
    for (double d : distance)
        require_beside_distance(d);
    // One field, grown by each cut's vertices after the cut is measured: the distances within
    // each cut's bound are those of beside_length() (shortest paths; a larger bound only
    // reaches further).
    const double bound =
        distance.empty() ? 0.0 : *std::max_element(distance.begin(), distance.end());
    detail::EdgeDistance field;
    field.reset(mesh.n_vertices());
    std::vector<double> lengths(plan.paths.size(), 0.0);
    std::vector<VertexHandle> seeds;
    for (std::size_t i = 0; i < plan.paths.size(); ++i)
    {
        if (i > 0)
            lengths[i] = run_beside(mesh, plan.paths[i], field.dist, distance[i]);
        seeds.clear();
        add_cut_vertices(mesh, plan.paths[i], seeds);
        field.grow(mesh, seeds, detail::mesh_neighbours(mesh), [](int) { return true; }, bound);
    }
    return lengths;
}

PathAlignment seam_alignment(const std::vector<PathAlignment>& paths)
{
    PathAlignment all;
    for (const auto& one : paths)
    {
        all.mean += one.mean * one.length;
        all.low_fraction += one.low_fraction * one.length;
        all.length += one.length;
    }
    if (all.length > 0.0)
    {
        all.mean /= all.length;
        all.low_fraction /= all.length;
    }
    return all;
}

double far_side_fraction(const Mesh& mesh, const CutPlan& plan, const Eigen::Vector3d& viewpoint)
{
    if (!viewpoint.allFinite())
        throw InvalidInputError("far_side_fraction: the viewpoint must have 3 finite coordinates");
    double far = 0.0, total = 0.0;
    for (const CutPath& path : plan.paths)
        for (const HalfedgeHandle h : path.halfedges)
        {
            const Eigen::Vector3d a = to_eigen(mesh.point(mesh.from_vertex_handle(h)));
            const Eigen::Vector3d b = to_eigen(mesh.point(mesh.to_vertex_handle(h)));
            Eigen::Vector3d normal = Eigen::Vector3d::Zero();
            for (const HalfedgeHandle side : {h, mesh.opposite_halfedge_handle(h)})
            {
                if (mesh.is_boundary(side))
                    continue;
                const Eigen::Vector3d c =
                    to_eigen(mesh.point(mesh.to_vertex_handle(mesh.next_halfedge_handle(side))));
                const Eigen::Vector3d p = to_eigen(mesh.point(mesh.from_vertex_handle(side)));
                const Eigen::Vector3d q = to_eigen(mesh.point(mesh.to_vertex_handle(side)));
                normal += (q - p).cross(c - p);
            }
            const double length = (b - a).norm();
            total += length;
            if (normal.dot(viewpoint - 0.5 * (a + b)) < 0.0)
                far += length;
        }
    return total > 0.0 ? far / total : 0.0;
}

}  // namespace vessel
