#include "vessel/map/injective.h"

#include "detail/centre_pull.h"
#include "detail/face_jacobian.h"
#include "detail/scaffold.h"
#include "detail/split_proxy.h"
#include "detail/uv_rows.h"
#include "solve/paired_cholmod.h"
#include "solve/paired_pattern.h"
#include "solve/serial_openmp.h"
#include "vessel/core/errors.h"
#include "vessel/cut/boundary.h"
#include "vessel/map/embedding.h"
#include "vessel/quality/metrics.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numeric>
#include <optional>
#include <thread>
#include <vector>


namespace vessel {

void InjectiveOptions::validate() const
{
    if (max_iterations < 1)
        throw InvalidInputError("InjectiveOptions: max_iterations must be >= 1");
    if (!(tolerance > 0.0))
        throw InvalidInputError("InjectiveOptions: tolerance must be > 0");
    if (!(scaffold_weight > 0.0))
        throw InvalidInputError("InjectiveOptions: scaffold_weight must be > 0");
    if (!(scaffold_tolerance >= 0.0 && std::isfinite(scaffold_tolerance)))
        throw InvalidInputError("InjectiveOptions: scaffold_tolerance must be >= 0 (0 = "
                                "automatic) and finite");
    if (crossing_patience < 1)
        throw InvalidInputError("InjectiveOptions: crossing_patience must be >= 1, got " +
                                std::to_string(crossing_patience));
    if (!(momentum >= 0.0 && momentum < 1.0))
        throw InvalidInputError("InjectiveOptions: momentum must be in [0, 1), got " +
                                std::to_string(momentum));
    if (!std::isfinite(scaffold_skip_gap))
        throw InvalidInputError("InjectiveOptions: scaffold_skip_gap must be finite (0 = "
                                "automatic, < 0 = never)");
    if (scaffold_passes < 1)
        throw InvalidInputError("InjectiveOptions: scaffold_passes must be >= 1, got " +
                                std::to_string(scaffold_passes));
    validate_centre_pulls(centre_pulls, "InjectiveOptions");
}

Eigen::MatrixX2d tutte_embedding(const Mesh& mesh)
{
    const auto loops = boundary_loops(mesh);
    if (loops.size() != 1)
        throw TopologyError("tutte_embedding: the mesh has " + std::to_string(loops.size()) +
                            " boundary loops; a disk (one loop) is required — cut it first");
    const auto& loop = loops[0];
    // Boundary halfedges run clockwise around the disk; walking them backwards is
    // counter-clockwise, which makes the faces counter-clockwise.
    const double radius = loop.radius();
    double s = 0.0;
    Pins boundary;
    for (std::size_t i = 0; i < loop.halfedges.size(); ++i)
    {
        const double angle = -2.0 * M_PI * s / loop.arc_length;
        boundary.push_back({loop.vertices[i], {radius * std::cos(angle), radius * std::sin(angle)}});
        s += mesh.calc_edge_length(loop.halfedges[i]);
    }
    return tutte_embedding(mesh, boundary);
}

Eigen::MatrixX2d tutte_embedding(const Mesh& mesh, const Pins& boundary)
{
    const int n = static_cast<int>(mesh.n_vertices());
    Eigen::MatrixX2d uv = Eigen::MatrixX2d::Zero(n, 2);
    std::vector<int> slot(n, -1);  // index among the free vertices, -1 on the boundary
    std::vector<char> on_boundary(n, 0);
    const std::vector<int> pinned = pin_index(mesh, boundary, "tutte_embedding");
    for (const Pin& pin : boundary)
    {
        if (!mesh.is_boundary(pin.vertex))
            throw InvalidInputError("tutte_embedding: pinned vertex " +
                                    std::to_string(pin.vertex.idx()) +
                                    " is not on the boundary; pin the boundary vertices only");
        on_boundary[pin.vertex.idx()] = 1;
        uv.row(pin.vertex.idx()) = pin.uv.transpose();
    }
    for (auto v : mesh.vertices())
        if (mesh.is_boundary(v) && pinned[v.idx()] < 0)
            throw InvalidInputError("tutte_embedding: boundary vertex " + std::to_string(v.idx()) +
                                    " has no position; pin every boundary vertex");
    int n_free = 0;
    for (int v = 0; v < n; ++v)
        if (!on_boundary[v])
            slot[v] = n_free++;
    if (n_free == 0)
        return uv;
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(n_free, 2);
    for (auto v : mesh.vertices())
    {
        const int i = slot[v.idx()];
        if (i < 0)
            continue;
        double degree = 0.0;
        for (auto w : v.vertices())
        {
            degree += 1.0;
            if (slot[w.idx()] >= 0)
                triplets.emplace_back(i, slot[w.idx()], -1.0);
            else
                rhs.row(i) += uv.row(w.idx());
        }
        triplets.emplace_back(i, i, degree);
    }
    Eigen::SparseMatrix<double> L(n_free, n_free);
    L.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> solver;
    {
        const detail::SerialOpenMp serial;
        solver.compute(L);
    }
    if (solver.info() != Eigen::Success)
        throw SolverError("tutte_embedding: CHOLMOD could not factor the graph Laplacian");
    const Eigen::MatrixX2d x = solver.solve(rhs);
    if (solver.info() != Eigen::Success || !x.allFinite())
        throw SolverError("tutte_embedding: CHOLMOD solve failed");
    for (int v = 0; v < n; ++v)
        if (slot[v] >= 0)
            uv.row(v) = x.row(slot[v]);
    // A circle of the boundary's perimeter encloses far more than the surface's area; scale to
    // the 3D area so that a distortion energy starts from the right size.
    scale_to_surface_area(mesh, uv);
    return uv;
}

namespace {

using detail::FaceOperator;
using detail::face_operators;
using detail::face_threads;
using detail::PairedPattern;
using detail::parallel_chunks;

Eigen::Matrix2d jacobian(const FaceOperator& op, const Eigen::VectorXd& x)
{
    return detail::jacobian(op, x.data());
}

// Symmetric Dirichlet energy; +infinity if a triangle is flipped or collapsed.
double energy(const std::vector<FaceOperator>& ops, const Eigen::VectorXd& x, int threads)
{
    std::array<double, 2> partial{0.0, 0.0};
    const int used = std::min(threads, 2);
    parallel_chunks(ops.size(), used, [&](std::size_t begin, std::size_t end, int t) {
        double e = 0.0;
        for (std::size_t f = begin; f < end; ++f)
        {
            const FaceOperator& op = ops[f];
            const Eigen::Matrix2d J = jacobian(op, x);
            const double det = J.determinant();
            if (!(det > 0.0))
            {
                e = INFINITY;
                break;
            }
            const double frob = J.squaredNorm();
            e += op.area * (frob + frob / (det * det));
        }
        partial[t] = e;
    });
    return partial[0] + partial[1];
}

// Gradient of energy() at x (no face flipped), interleaved like x: per face, with
// E = area (|J|^2 + |J|^2 / det^2) (|J^-1|^2 = |J|^2 / det^2 in 2D), dE/dJ = 2 area (J (1 +
// 1 / det^2) - |J|^2 / det^3 cof J), cof J = [[J11, -J10], [-J01, J00]] = d det / dJ.
Eigen::VectorXd energy_gradient(const std::vector<FaceOperator>& ops, const Eigen::VectorXd& x)
{
    Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
    for (const FaceOperator& op : ops)
    {
        const Eigen::Matrix2d J = jacobian(op, x);
        const double det = J.determinant(), frob = J.squaredNorm();
        Eigen::Matrix2d cof;
        cof << J(1, 1), -J(1, 0), -J(0, 1), J(0, 0);
        const Eigen::Matrix2d dJ =
            2.0 * op.area * (J * (1.0 + 1.0 / (det * det)) - frob / (det * det * det) * cof);
        for (int k = 0; k < 3; ++k)
        {
            const int i = 2 * op.corner[k];
            g[i] += dJ(0, 0) * op.d0[k] + dJ(0, 1) * op.d1[k];
            g[i + 1] += dJ(1, 0) * op.d0[k] + dJ(1, 1) * op.d1[k];
        }
    }
    return g;
}

// The global step's normal matrix has a fixed pattern: the u and v of a face's three corners
// couple in a 6 x 6 block. Only one triangle is stored (CHOLMOD reads no more). With the
// corners in increasing vertex order, local unknown l = 2 * (sorted corner) + (0 for u, 1 for
// v) increases with the global one, so the block's lower triangle is a >= b: 21 entries. They
// are stored transposed, as the upper triangle: CHOLMOD then spends less of each supernodal
// factorization transposing its input (cholmod_transpose_sym 5.4% -> 4.3% of the perf samples
// of a 44k phantom run; its SLIM factorizations 6% faster, the map bit-identical).
struct FaceBlock
{
    std::array<int, 21> slot{};  //!< value index of (a, b), a >= b, in order a = 0..5, b <= a
    std::array<int, 3> corner{};  //!< corner of the face operator at each sorted position
    //! area * (D0_k D0_l + D1_k D1_l) over sorted corners (k, l): (0,0) (1,0) (1,1) (2,0) (2,1) (2,2)
    std::array<double, 6> gram{};
};

// A face fitted to a pattern that does not couple all of its corners (a scaffold triangle made
// by edge flips after the pattern was analysed): its term of the proxy is split
// (detail::split_gram(); FaceBlock::gram holds the split Gram matrix), and the right-hand side is
// corrected by kron(gram' - gram, W^2) x, so that the proxy's gradient at the current map, and
// with it the step's descent, stays the same.
struct SplitFace
{
    std::size_t face = 0;
    std::array<double, 6> delta{};  //!< gram' - gram, in FaceBlock::gram's order
};

struct NormalMatrix
{
    Eigen::SparseMatrix<double> A;  // upper triangle (see FaceBlock)
    std::vector<FaceBlock> blocks;  // per face
    std::vector<int> diagonal;      // value index of (i, i)
    std::optional<PairedPattern> pattern;  // A's, for faces fitted to it later
    std::vector<SplitFace> split;
};

// \p op's block in \p pattern. Where the pattern does not couple a pair of its corners, the
// face's Gram matrix is split (detail::split_gram()): its term still bounds the face's own from
// above, and its slots of the uncoupled pairs point at a corner's own diagonal entry with a
// weight of 0. Returns whether the face was split, with gram' - gram in \p delta.
bool fit_block(const FaceOperator& op, const PairedPattern& pattern, FaceBlock& block,
               std::array<double, 6>& delta)
{
    block.corner = {0, 1, 2};
    std::sort(block.corner.begin(), block.corner.end(),
              [&](int p, int q) { return op.corner[p] < op.corner[q]; });
    std::array<int, 3> vertex{};  // the face's corners in increasing order
    for (int k = 0; k < 3; ++k)
        vertex[k] = op.corner[block.corner[k]];
    int g = 0;
    for (int k = 0; k < 3; ++k)
        for (int l = 0; l <= k; ++l)
        {
            const int p = block.corner[k], q = block.corner[l];
            block.gram[g++] = op.area * (op.d0[p] * op.d0[q] + op.d1[p] * op.d1[q]);
        }
    std::array<std::array<int, 3>, 3> rank{};  // of corners (l, k), l <= k; -1: uncoupled
    std::array<bool, 3> uncoupled{};           // the pair of corners other than k
    for (int k = 0; k < 3; ++k)
        for (int l = 0; l <= k; ++l)
        {
            rank[l][k] = l == k ? pattern.rank(vertex[k], vertex[k])
                                : pattern.coupled_rank(vertex[l], vertex[k]);
            if (rank[l][k] < 0)
                uncoupled[3 - k - l] = true;
        }
    const bool split = uncoupled[0] || uncoupled[1] || uncoupled[2];
    if (split)
    {
        const std::array<double, 6> gram = detail::split_gram(block.gram, uncoupled);
        for (g = 0; g < 6; ++g)
            delta[g] = gram[g] - block.gram[g];
        block.gram = gram;
    }
    int s = 0;
    for (int a = 0; a < 6; ++a)  // local column: corner a / 2, u or v by a % 2
        for (int b = 0; b <= a; ++b)
        {
            const int r = rank[b / 2][a / 2];
            const int at = 2 * vertex[a / 2] + a % 2;
            block.slot[s++] =
                r >= 0 ? pattern.index_at(r, 2 * vertex[b / 2] + b % 2, at) : pattern.index(at, at);
        }
    return split;
}

// Faces [first, ops.size()) fitted to M's pattern (M.blocks resized, their splits noted in
// M.split); every corner must be one of the pattern's vertices.
void fit_faces(const std::vector<FaceOperator>& ops, std::size_t first, NormalMatrix& M)
{
    M.blocks.resize(ops.size());
    M.split.erase(std::remove_if(M.split.begin(), M.split.end(),
                                 [&](const SplitFace& s) { return s.face >= first; }),
                  M.split.end());
    SplitFace split;
    for (std::size_t f = first; f < ops.size(); ++f)
        if (fit_block(ops[f], *M.pattern, M.blocks[f], split.delta))
        {
            split.face = f;
            M.split.push_back(split);
        }
}

NormalMatrix normal_matrix_pattern(const std::vector<FaceOperator>& ops, int n)
{
    NormalMatrix M;
    // Two vertices couple when they share a face.
    M.pattern.emplace(
        PairedPattern::of_triangles(n, ops.size(), [&](std::size_t f, std::array<int, 3>& s) {
            s = ops[f].corner;
            std::sort(s.begin(), s.end());
            return 3;
        }));
    M.pattern->into(M.A);
    fit_faces(ops, 0, M);
    M.diagonal.resize(2 * n);
    for (int i = 0; i < 2 * n; ++i)
        M.diagonal[i] = M.pattern->index(i, i);
    return M;
}

// SLIM's local step on one face: the proxy ||W (J - R)||^2 with R the closest rotation to J
// and W = U diag(w) U^T (J = U diag(sigma) V^T) enters the normal equations as
// area * kron(Gram, W^2) and the right-hand side as area * W^2 R D_k. The 2 x 2 polar and
// singular value decompositions are closed-form: with E, F, G, H the conformal and
// anti-conformal halves of J, sigma = sqrt(E^2 + H^2) +- sqrt(F^2 + G^2), R rotates by
// atan2(H, E), and U by half the sum of atan2(G, F) and atan2(H, E).
// The proxy's weights W^2 and area * W^2 R of one face at \p x.
struct FaceProxy
{
    Eigen::Matrix2d W2;
    Eigen::Matrix2d T;  // rhs of corner k: T (D0_k, D1_k)
};

FaceProxy face_proxy(const FaceOperator& op, const Eigen::VectorXd& x)
{
    const Eigen::Matrix2d J = jacobian(op, x);
    const double E = 0.5 * (J(0, 0) + J(1, 1)), F = 0.5 * (J(0, 0) - J(1, 1));
    const double G = 0.5 * (J(1, 0) + J(0, 1)), H = 0.5 * (J(1, 0) - J(0, 1));
    const double q = std::sqrt(E * E + H * H), r = std::sqrt(F * F + G * G);
    // Clamped: on a Tutte start, deep branches are compressed by orders of magnitude, and
    // weights ~ sigma^-1.5 would make the system numerically indefinite. A weaker proxy still
    // descends: the line search uses the true energy.
    const auto weight = [](double sigma) {
        const double s = std::max(sigma, 1e-2);
        return std::sqrt(1.0 + 1.0 / s + 1.0 / (s * s) + 1.0 / (s * s * s));
    };
    const double w0 = weight(q + r), w1 = weight(q - r);
    const double w_mean = 0.5 * (w0 + w1), w_half = 0.5 * (w0 - w1);
    // U diag(w) U^T = w_mean I + w_half S, S = [[cos 2phi, sin 2phi], [sin 2phi, -cos 2phi]];
    // S^2 = I, so W^2 = (w_mean^2 + w_half^2) I + 2 w_mean w_half S.
    double c2 = 1.0, s2 = 0.0;
    if (r > 0.0 && q > 0.0)
    {
        c2 = (F * E - G * H) / (r * q);
        s2 = (G * E + F * H) / (r * q);
    }
    const double iso = w_mean * w_mean + w_half * w_half, aniso = 2.0 * w_mean * w_half;
    Eigen::Matrix2d W2;
    W2 << iso + aniso * c2, aniso * s2, aniso * s2, iso - aniso * c2;
    Eigen::Matrix2d R = Eigen::Matrix2d::Identity();
    if (q > 0.0)
        R << E / q, -H / q, H / q, E / q;
    return {W2, op.area * (W2 * R)};
}

void add_face(const FaceOperator& op, const FaceBlock& block, const Eigen::VectorXd& x,
              double* values, double* rhs)
{
    const auto [W2, T] = face_proxy(op, x);
    int corner_dof[3];
    for (int k = 0; k < 3; ++k)
    {
        const int p = block.corner[k];
        corner_dof[k] = 2 * op.corner[p];
        rhs[corner_dof[k]] += T(0, 0) * op.d0[p] + T(0, 1) * op.d1[p];
        rhs[corner_dof[k] + 1] += T(1, 0) * op.d0[p] + T(1, 1) * op.d1[p];
    }
    const double w00 = W2(0, 0), w10 = W2(1, 0), w11 = W2(1, 1);
    const int* slot = block.slot.data();
    const double* gram = block.gram.data();
    // Rows a = 2k + i, columns b = 2l + j <= a; gram index of (k, l), l <= k: k (k + 1) / 2 + l.
    for (int k = 0; k < 3; ++k)
    {
        const double* g = gram + k * (k + 1) / 2;
        // Row 2k (u of corner k): columns 2l, 2l + 1 for l < k, then 2k.
        for (int l = 0; l < k; ++l)
        {
            values[*slot++] += g[l] * w00;
            values[*slot++] += g[l] * w10;
        }
        values[*slot++] += g[k] * w00;
        // Row 2k + 1 (v of corner k): columns 2l, 2l + 1 for l < k, then 2k, 2k + 1.
        for (int l = 0; l < k; ++l)
        {
            values[*slot++] += g[l] * w10;
            values[*slot++] += g[l] * w11;
        }
        values[*slot++] += g[k] * w10;
        values[*slot++] += g[k] * w11;
    }
}

}  // namespace

namespace {

// Scaffold faces (Jiang et al. 2017) between the map's boundary and a box around it, rebuilt
// every iteration. None may flip (the line search sees them), so the boundary cannot run into
// itself; their energy, small against the surface's, keeps them in shape.
class Scaffold
{
public:
    Scaffold(const Mesh& mesh, int n, double weight) : n_(n), weight_(weight)
    {
        const auto loops = boundary_loops(mesh);
        if (loops.size() != 1)
            throw TopologyError("injective_refine: a scaffold needs a disk (one boundary loop), "
                                "got " + std::to_string(loops.size()) + " loops");
        for (auto v : loops[0].vertices)
            boundary_.push_back(v.idx());
        for (auto v : mesh.fv_range(mesh.face_handle(0)))
            inside_face_.push_back(v.idx());
    }

    //! Box corner vertices are n .. n + 3, then come the Steiner vertices (free).
    std::array<int, 4> box() const { return {n_, n_ + 1, n_ + 2, n_ + 3}; }

    //! Places the box around the map and the Steiner vertices in \p x (resized) and returns
    //! the scaffold's face operators.
    std::vector<FaceOperator> rebuild(Eigen::VectorXd& x)
    {
        triangulated_anew();
        Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
        for (int v : boundary_)
        {
            lo = lo.cwiseMin(x.segment<2>(2 * v));
            hi = hi.cwiseMax(x.segment<2>(2 * v));
        }
        const double margin = 0.5 * (hi - lo).maxCoeff();
        lo.array() -= margin;
        hi.array() += margin;
        const std::array<int, 4> box = this->box();
        x.conservativeResize(2 * (n_ + 4));
        x.segment<2>(2 * box[0]) << lo.x(), lo.y();
        x.segment<2>(2 * box[1]) << hi.x(), lo.y();
        x.segment<2>(2 * box[2]) << hi.x(), hi.y();
        x.segment<2>(2 * box[3]) << lo.x(), hi.y();
        Eigen::Vector2d inside = Eigen::Vector2d::Zero();
        for (int v : inside_face_)
            inside += x.segment<2>(2 * v) / 3.0;
        detail::ScaffoldMesh scaffold =
            detail::scaffold_triangles(x, boundary_, box, inside, n_ + 4, detail::kSlimScaffoldShape);
        x.conservativeResize(2 * (n_ + 4 + static_cast<int>(scaffold.steiner.size())));
        for (std::size_t j = 0; j < scaffold.steiner.size(); ++j)
            x.segment<2>(2 * (n_ + 4 + j)) = scaffold.steiner[j];
        triangles_ = std::move(scaffold.triangles);
        return *reshape(x);
    }

    //! The same vertices' triangles made the constrained Delaunay triangulation of the free
    //! space again at \p x by edge flips (detail::flip_to_delaunay()), as the scaffold's face
    //! operators; empty if no edge flipped (then only a new triangulation can help).
    std::optional<std::vector<FaceOperator>> refit(const Eigen::VectorXd& x)
    {
        if (triangles_.empty() || detail::flip_to_delaunay(x, boundary_, box(), triangles_) == 0)
            return std::nullopt;
        triangulated_anew();
        return reshape(x);
    }

    //! The same scaffold triangles (box and Steiner vertices where the steps took them), with
    //! their rest shapes set to their current shapes: no new triangulation, so the global
    //! step's sparsity pattern stays the same. Empty if a triangle has become degenerate (then
    //! rebuild).
    std::optional<std::vector<FaceOperator>> reshape(const Eigen::VectorXd& x) const
    {
        if (triangles_.empty())
            return std::nullopt;  // not triangulated yet
        std::vector<FaceOperator> ops;
        ops.reserve(triangles_.size());
        for (const auto& t : triangles_)
        {
            FaceOperator op;
            op.corner = t;
            const Eigen::Vector2d e1 = x.segment<2>(2 * t[1]) - x.segment<2>(2 * t[0]);
            const Eigen::Vector2d e2 = x.segment<2>(2 * t[2]) - x.segment<2>(2 * t[0]);
            Eigen::Matrix2d P;
            P << e1, e2;
            const double det = P.determinant();
            if (!(det > 0.0) && reused_count_ >= 0)
                return std::nullopt;  // dropping it would change the pattern: rebuild
            if (!(det > 0.0))
                continue;  // a sliver at the scale of rounding: nothing can pass through it
            // Rest shape: the triangle's current shape (Jiang et al.), so the scaffold does not
            // resist the map's motion; but for slivers (twice the area below 1/20 of the longest
            // edge squared) the equilateral triangle of the same area, since their own shape would
            // make the global step ill-conditioned.
            const double longest = std::max({e1.squaredNorm(), e2.squaredNorm(), (e2 - e1).squaredNorm()});
            if (det < 0.05 * longest)
            {
                const double side = std::sqrt(2.0 * det / std::sqrt(3.0));
                P << side, 0.5 * side, 0.0, 0.5 * std::sqrt(3.0) * side;
            }
            const Eigen::Matrix2d Pi = P.inverse();
            op.d0 = {-(Pi(0, 0) + Pi(1, 0)), Pi(0, 0), Pi(1, 0)};
            op.d1 = {-(Pi(0, 1) + Pi(1, 1)), Pi(0, 1), Pi(1, 1)};
            ops.push_back(op);
        }
        // All of them together weigh `weight_` (a fraction of the surface), each the same: a
        // sliver between two parts of the boundary that nearly touch then counts as much in
        // the step's direction as a large triangle, so the step slides those parts along each
        // other instead of pushing them together and stopping at its collapse (weighted by
        // area, slivers would count for nothing and the steps would shrink to nothing).
        for (auto& op : ops)
            op.area = weight_ / static_cast<double>(ops.size());
        reused_count_ = static_cast<int>(ops.size());
        return ops;
    }

    //! Sets the Steiner vertices' entries of the displacement \p d (sized for the current
    //! triangulation; the map's and the box's entries given) to its harmonic extension over
    //! the scaffold's edges (uniform weights): the free space follows the boundary's motion.
    void extend(Eigen::VectorXd& d) const
    {
        const int first = n_ + 4;
        const int m = static_cast<int>(d.size() / 2) - first;
        if (m <= 0)
            return;
        // The Laplacian depends on the triangulation alone: factored once per triangulation.
        const bool factored = extension_ && extension_->rows() == m;
        std::vector<Eigen::Triplet<double>> triplets;
        Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(m, 2);
        const auto couple = [&](int p, int q) {
            if (p < first)
                return;
            if (q < first)
                rhs.row(p - first) += d.segment<2>(2 * q).transpose();
            if (factored)
                return;
            triplets.emplace_back(p - first, p - first, 1.0);
            if (q >= first)
                triplets.emplace_back(p - first, q - first, -1.0);
        };
        for (const auto& t : triangles_)
            for (int a = 0; a < 3; ++a)
            {
                couple(t[a], t[(a + 1) % 3]);
                couple(t[(a + 1) % 3], t[a]);
            }
        if (!factored)
        {
            Eigen::SparseMatrix<double> L(m, m);
            L.setFromTriplets(triplets.begin(), triplets.end());
            extension_ = std::make_unique<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>>(L);
        }
        const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>& solver = *extension_;
        const Eigen::MatrixX2d steiner = solver.solve(rhs);
        if (solver.info() != Eigen::Success || !steiner.allFinite())
        {
            d.tail(2 * m).setZero();  // no extension: the line search keeps them in place
            return;
        }
        for (int j = 0; j < m; ++j)
            d.segment<2>(2 * (first + j)) = steiner.row(j).transpose();
    }

private:
    // What depends on triangles_, dropped where they change: the next reshape() may drop
    // slivers (the pattern is new anyway), and extend() factors the new Laplacian.
    void triangulated_anew()
    {
        reused_count_ = -1;
        extension_.reset();
    }

    int n_;
    double weight_;
    std::vector<std::array<int, 3>> triangles_;
    // extend()'s factor of the Steiner vertices' Laplacian, for triangles_ (triangulated_anew()).
    mutable std::unique_ptr<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>> extension_;
    mutable int reused_count_ = -1;
    std::vector<int> boundary_;
    std::vector<int> inside_face_;
};

// Where a line search ends along a direction (Slim::line_search()).
struct LineStep
{
    double step = 0.0;         // the step taken along the direction
    double bound = 0.0;        // the largest step that flips no triangle
    double energy = 0.0;       // the energy minimized (faces and centre pulls) there
    bool by_scaffold = false;  // it stopped at the bound, and the bound is a scaffold triangle's
};

// One run of injective_refine(): SLIM (Rabinovich et al. 2017) with its state across
// iterations. Each iteration fits, per face, the rotation R and weights W of a quadratic proxy
// ||W (J - R)||^2 whose gradient matches the symmetric Dirichlet energy's, solves the proxy
// globally, and line-searches toward its minimizer without letting a triangle (of the surface or
// of the scaffold) flip. Pins are soft constraints with a large weight; a small proximal term
// removes the free translation. Without a scaffold (and with scaffold_on_contact) a first phase
// runs until the boundary crosses itself; the second goes on from the last iterate whose
// boundary was simple, with a scaffold.
class Slim
{
public:
    // The arguments are checked by injective_refine().
    Slim(const Mesh& mesh, const Eigen::MatrixX2d& uv, const Pins& pins,
         const InjectiveOptions& options);

    // Both phases; \p uv receives the map.
    InjectiveSummary run(Eigen::MatrixX2d& uv);

private:
    void start_scaffold();
    bool crosses(const Eigen::VectorXd& y);
    void analyse();  // the global step's pattern and its symbolic factorization
    double total_energy(const std::vector<FaceOperator>& faces, const Eigen::VectorXd& y) const;
    // The largest step along \p dir that flips no triangle, halved until the energy does not
    // grow above \p e0.
    LineStep line_search(const std::vector<FaceOperator>& faces, const Eigen::VectorXd& y,
                         const Eigen::VectorXd& dir, double e0);
    // ops_: the surface's faces and the scaffold's, reshaped, or triangulated anew after a step
    // that a scaffold triangle stopped.
    void place_scaffold();
    // The proxy's minimizer: assembled on threads_, factored (damped if it must be), solved.
    Eigen::VectorXd global_target();
    // After a step \p t along \p d that a scaffold triangle stopped: a new triangulation, and the
    // rest of \p d line-searched again (scaffold_passes).
    void continue_past_scaffold(const Eigen::VectorXd& d, double t);
    // With scaffold_on_contact, before the boundary has crossed: \p step along \p d (from x_,
    // at energy \p e) halved until the boundary stays simple. Where kContactHalvings halvings
    // still cross, or the shortened step no longer descends, the boundary's parts are in
    // contact: the step stays whole and the phase goes on as without shortening (it crosses,
    // and after crossing_patience iterations goes back to the last simple iterate, this one).
    // Returns whether the boundary at the end of the step taken crosses (tested here already).
    bool shorten_to_contact(const Eigen::VectorXd& d, LineStep& step, double e);
    // One iteration (the it-th of this phase, after \p done of earlier phases); false = the
    // phase ends.
    bool iterate(int it, int done);
    std::string report() const;

    const Mesh& mesh_;
    const InjectiveOptions& options_;
    const int n_;  // the surface's vertices
    const double scaffold_tolerance_;
    const std::vector<FaceOperator> surface_;
    const double total_area_;
    const int threads_;
    int n_all_;  // with the scaffold's vertices after each rebuild
    Eigen::VectorXd x_;
    std::vector<int> pinned_;  // soft pins: the given ones, and the scaffold's box corners
    std::optional<Scaffold> scaffold_;
    Eigen::MatrixX2d probe_;  // crosses()'s map
    // With scaffold_on_contact, the boundary of each step is checked; the scaffold can only
    // start from a map whose boundary is simple.
    bool watch_ = false;
    // With watch_: steps are still shortened to keep the boundary simple (shorten_to_contact()).
    // The scaffold phase starts from the last simple iterate; on trees from the layout circle
    // the unshortened steps cross the boundary at the first or second iterate (where a branch
    // squeezed against the circle folds), orders of magnitude above the minimum, and the
    // scaffold phase then unrolls the whole tree at a new triangulation per blocked step.
    // Shortened steps go on unrolling it without a scaffold until its parts touch.
    bool shorten_to_contact_ = true;
    static constexpr int kContactHalvings = 6;
    InjectiveSummary summary_;
    double pin_weight_ = 0.0, proximal_ = 0.0;
    std::vector<FaceOperator> ops_;
    NormalMatrix M_;
    detail::PairedCholmod solver_;
    std::vector<std::vector<double>> partial_values_;
    Eigen::VectorXd line_trial_;  // the line search's trial point, kept (no 2|V|-vector per try)
    std::vector<Eigen::VectorXd> partial_rhs_;
    double e_surface_ = 0.0;
    int slow_ = 0;  // consecutive iterations below the tolerance
    // Consecutive iterations whose step was cut below kShortStep of the proxy's step (its
    // minimizer is step 1): a nearly collapsed triangle in the way, or a line search that
    // halved ten times.
    int short_ = 0;
    static constexpr double kShortStep = 1e-3;
    static constexpr int kMaxStallsPassed = 3;
    // With scaffold_on_contact: the last iterate whose boundary is simple, and its number.
    Eigen::VectorXd last_simple_;
    int last_simple_it_ = 0;
    // The scaffold's triangulation is not the one the blocks were fitted for (a continued step
    // triangulated again), and whether the last step stopped at a collapsing
    // scaffold triangle (then a new triangulation is due).
    bool pattern_stale_ = false;
    bool blocked_by_scaffold_ = true;
    Eigen::VectorXd momentum_;  // the last iteration's motion of the surface's vertices
};

Slim::Slim(const Mesh& mesh, const Eigen::MatrixX2d& uv, const Pins& pins,
           const InjectiveOptions& options)
    : mesh_(mesh),
      options_(options),
      n_(static_cast<int>(mesh.n_vertices())),
      scaffold_tolerance_(options.scaffold_tolerance > 0.0 ? options.scaffold_tolerance
                                                           : InjectiveOptions::kScaffoldTolerance),
      surface_(face_operators(mesh)),
      total_area_(std::accumulate(surface_.begin(), surface_.end(), 0.0,
                                  [](double s, const FaceOperator& op) { return s + op.area; })),
      threads_(face_threads(surface_.size())),
      n_all_(n_),
      x_(detail::interleaved(uv)),
      probe_(uv)
{
    for (const auto& pin : pins)
        x_.segment<2>(2 * pin.vertex.idx()) = pin.uv;
    for (const auto& pin : pins)
        pinned_.push_back(pin.vertex.idx());
    if (options_.scaffold)
        start_scaffold();
    watch_ = !scaffold_ && options_.scaffold_on_contact && !crosses(x_);
    summary_.initial_energy = energy(surface_, x_, threads_);
    if (!std::isfinite(summary_.initial_energy))
        throw InvalidInputError("injective_refine: the start map has a flipped or collapsed "
                                "triangle; start from a map without flips (e.g. tutte_embedding)");
    pin_weight_ = 1e6 * total_area_ / n_;
    proximal_ = 1e-8 * total_area_ / n_;
    ops_ = surface_;
    if (!scaffold_)
        analyse();  // the pattern never changes
    partial_values_.resize(threads_ - 1);
    partial_rhs_.resize(threads_);
    e_surface_ = summary_.initial_energy;
    last_simple_ = x_;
}

void Slim::start_scaffold()
{
    scaffold_.emplace(mesh_, n_, options_.scaffold_weight * total_area_);
    for (int v : scaffold_->box())
        pinned_.push_back(v);
}

bool Slim::crosses(const Eigen::VectorXd& y)
{
    detail::deinterleave(y, probe_);
    return boundary_self_intersection(mesh_, probe_).first >= 0;
}

void Slim::analyse()
{
    M_ = normal_matrix_pattern(ops_, n_all_);
    ++summary_.pattern_analyses;
    const detail::SerialOpenMp serial;
    solver_.analyze_pairs(M_.A);
    if (solver_.info() != Eigen::Success)
        throw SolverError("injective_refine: CHOLMOD could not analyse the global step");
}

double Slim::total_energy(const std::vector<FaceOperator>& faces, const Eigen::VectorXd& y) const
{
    const double e = energy(faces, y, threads_);
    return options_.centre_pulls.empty() ? e
                                         : e + detail::centre_pull_energy(options_.centre_pulls, y);
}

LineStep Slim::line_search(const std::vector<FaceOperator>& faces, const Eigen::VectorXd& y,
                           const Eigen::VectorXd& dir, double e0)
{
    const double bound = max_injective_step(faces, y, dir, threads_);
    double step = bound;
    line_trial_ = y + step * dir;
    double e1 = total_energy(faces, line_trial_);
    while (!(e1 <= e0) && step > 1e-12)
    {
        step *= 0.5;
        line_trial_ = y + step * dir;
        e1 = total_energy(faces, line_trial_);
    }
    const bool at_bound = step < 1.0 && step == bound;
    // Stopped where a scaffold triangle would collapse, not a surface one: only then can a new
    // triangulation let the step go further (a new one costs a symbolic factorization).
    const bool by_scaffold = at_bound && faces.size() > surface_.size() &&
                             max_injective_step(faces, y, dir, threads_, surface_.size()) <= bound;
    return {step, bound, e1, by_scaffold};
}

void Slim::place_scaffold()
{
    // A new triangulation (and symbolic factorization) only after a step that a scaffold
    // triangle stopped; otherwise the same scaffold triangles, reshaped to where the steps took
    // them. Triangulating anew at every iteration (Jiang et al.) pays a symbolic factorization
    // for no better map; keeping a triangulation for several iterations regardless lets its
    // triangles thin out and shorten the steps (docs/journal/overlaps-2026-11.md).
    std::optional<std::vector<FaceOperator>> extra;
    if (!blocked_by_scaffold_)
        extra = scaffold_->reshape(x_);
    ops_ = surface_;
    const bool rebuilt = !extra;
    if (rebuilt)
    {
        extra = scaffold_->rebuild(x_);
        ++summary_.scaffold_rebuilds;
    }
    ops_.insert(ops_.end(), extra->begin(), extra->end());
    // Edge flips (continue_past_scaffold()) keep the vertices: their triangles are fitted to the
    // pattern analysed before, the couplings it lacks split off (fit_block()), so that no
    // symbolic factorization is made anew.
    if (rebuilt || (pattern_stale_ && 2 * M_.pattern->vertices() != x_.size()))
    {
        n_all_ = static_cast<int>(x_.size() / 2);
        analyse();
    }
    else if (pattern_stale_)
        fit_faces(ops_, surface_.size(), M_);
    pattern_stale_ = false;
}

Eigen::VectorXd Slim::global_target()
{
    for (auto& r : partial_rhs_)
        r.resize(2 * n_all_);
    const Eigen::Index nnz = M_.A.nonZeros();
    for (auto& values : partial_values_)
        values.resize(nnz);
    double* values = M_.A.valuePtr();
    parallel_chunks(ops_.size(), threads_, [&](std::size_t begin, std::size_t end, int t) {
        double* v = t == 0 ? values : partial_values_[t - 1].data();
        std::fill(v, v + nnz, 0.0);
        partial_rhs_[t].setZero();
        double* r = partial_rhs_[t].data();
        for (std::size_t f = begin; f < end; ++f)
            add_face(ops_[f], M_.blocks[f], x_, v, r);
    });
    Eigen::VectorXd rhs = partial_rhs_[0];
    for (int t = 1; t < threads_; ++t)
    {
        const double* v = partial_values_[t - 1].data();
        for (Eigen::Index i = 0; i < nnz; ++i)
            values[i] += v[i];
        rhs += partial_rhs_[t];
    }
    // Split faces (fit_block()): rhs += (gram' - gram) (x) W^2 x, the proxy's gradient at x_ kept.
    for (const SplitFace& split : M_.split)
    {
        const FaceOperator& op = ops_[split.face];
        const FaceBlock& block = M_.blocks[split.face];
        const Eigen::Matrix2d W2 = face_proxy(op, x_).W2;
        int g = 0;
        for (int k = 0; k < 3; ++k)
            for (int l = 0; l <= k; ++l, ++g)
            {
                const int vk = op.corner[block.corner[k]], vl = op.corner[block.corner[l]];
                rhs.segment<2>(2 * vk) += split.delta[g] * (W2 * x_.segment<2>(2 * vl));
                if (l != k)
                    rhs.segment<2>(2 * vl) += split.delta[g] * (W2 * x_.segment<2>(2 * vk));
            }
    }
    for (int i = 0; i < 2 * n_all_; ++i)
    {
        values[M_.diagonal[i]] += proximal_;
        rhs[i] += proximal_ * x_[i];
    }
    for (int v : pinned_)
        for (int k = 0; k < 2; ++k)
        {
            const int i = 2 * v + k;
            values[M_.diagonal[i]] += pin_weight_;
            rhs[i] += pin_weight_ * x_[i];
        }
    // The pulls: the proxy in the matrix, or the Gauss-Newton terms W (r + u . (y - x))^2,
    // whose part of the right-hand side is W (u . x - r) u and whose W u u^T the solve adds
    // by the Woodbury identity.
    std::vector<detail::PullRow> pull_rows;
    if (options_.pull_steps == PullSteps::GaussNewton)
        pull_rows = detail::active_pull_rows(options_.centre_pulls, x_);
    else
        detail::add_centre_pulls(options_.centre_pulls, x_, M_.diagonal, values, rhs);
    for (const detail::PullRow& row : pull_rows)
    {
        double ux = 0.0;
        for (const auto& [i, value] : row.entries)
            ux += value * x_[i];
        for (const auto& [i, value] : row.entries)
            rhs[i] += row.weight * (ux - row.r) * value;
    }
    // Scaffold slivers can make the matrix numerically indefinite; a stronger proximal term (a
    // Levenberg-style damping: the line search still uses the true energy) fixes it.
    for (double damping = 0.0;; damping = damping == 0.0 ? 1e-10 : 100.0 * damping)
    {
        if (damping > 0.0)
        {
            double largest = 0.0;
            for (int i = 0; i < 2 * n_all_; ++i)
                largest = std::max(largest, values[M_.diagonal[i]]);
            for (int i = 0; i < 2 * n_all_; ++i)
                values[M_.diagonal[i]] += damping * largest;
        }
        const detail::SerialOpenMp serial;
        solver_.factorize(M_.A);
        if (solver_.info() == Eigen::Success || damping > 1e-3)
            break;
    }
    if (solver_.info() != Eigen::Success)
        throw SolverError("injective_refine: CHOLMOD could not factor the global step");
    Eigen::VectorXd target;
    if (pull_rows.empty())
        target = solver_.solve(rhs);
    else
    {
        const detail::PullColumns columns = detail::pull_columns(pull_rows, 2 * n_all_, 1.0);
        target = solver_.solve_with_low_rank(rhs, columns.U, columns.c);
    }
    if (solver_.info() != Eigen::Success || !target.allFinite())
        throw SolverError("injective_refine: CHOLMOD solve failed");
    return target;
}

void Slim::continue_past_scaffold(const Eigen::VectorXd& d, double t)
{
    // The step stopped where a scaffold triangle would collapse. Another triangulation of the
    // free space there usually lets the same direction go further: line search the rest of it
    // again (no new factorization), a few times. Where an edge flips, that triangulation is
    // the same vertices' made Delaunay again by the flips (no new vertices, no refinement: a
    // fraction of the CGAL mesher's cost); otherwise a new one by the mesher
    // (docs/benchmarks.md, "The scaffold refitted by edge flips"). The Steiner vertices' motion
    // is the boundary's, extended.
    bool blocked = blocked_by_scaffold_;
    double left = 1.0 - t;
    for (int pass = 1; pass < options_.scaffold_passes && blocked && left > 0.05; ++pass)
    {
        std::optional<std::vector<FaceOperator>> extra = scaffold_->refit(x_);
        if (extra)
            ++summary_.scaffold_refits;
        else
        {
            extra = scaffold_->rebuild(x_);
            ++summary_.scaffold_rebuilds;
        }
        // The next iteration triangulates anew unless this one stays unblocked; either way its
        // faces are not those the blocks were fitted for (place_scaffold()).
        pattern_stale_ = true;
        blocked_by_scaffold_ = false;  // a new triangulation at x
        ops_ = surface_;
        ops_.insert(ops_.end(), extra->begin(), extra->end());
        Eigen::VectorXd rest = Eigen::VectorXd::Zero(x_.size());  // box corners stay
        rest.head(2 * n_) = left * d.head(2 * n_);
        scaffold_->extend(rest);
        const double e_pass = total_energy(ops_, x_);
        const LineStep s = line_search(ops_, x_, rest, e_pass);
        if (!(s.energy < e_pass))
            break;
        x_ += s.step * rest;
        ++summary_.scaffold_passes;
        blocked = s.by_scaffold;
        blocked_by_scaffold_ = blocked;
        left *= 1.0 - s.step;
    }
}

bool Slim::shorten_to_contact(const Eigen::VectorXd& d, LineStep& step, double e)
{
    double t = step.step;
    for (int halvings = 0; crosses(x_ + t * d); ++halvings)
    {
        if (halvings == kContactHalvings)
        {
            shorten_to_contact_ = false;  // in contact: the whole step, and watch it cross
            return true;
        }
        t *= 0.5;
    }
    if (t == step.step)
        return false;
    const double shortened = total_energy(ops_, x_ + t * d);
    if (!(shortened < e))
    {
        shorten_to_contact_ = false;
        return true;  // the whole step, which crossed
    }
    step.step = t;
    step.energy = shortened;
    ++summary_.shortened_steps;
    return false;
}

bool Slim::iterate(int it, int done)
{
    if (scaffold_)
        place_scaffold();
    Eigen::VectorXd d = global_target() - x_;
    if (scaffold_)
        for (int v : scaffold_->box())
            d.segment<2>(2 * v).setZero();  // the box stays put
    const double e = total_energy(ops_, x_);
    LineStep step = line_search(ops_, x_, d, e);
    if (options_.momentum > 0.0 && momentum_.size() == 2 * n_)
    {
        // Heavy ball: the proxy's direction plus a share of the last iteration's motion (the
        // scaffold's Steiner vertices follow it, extended), kept when its line search ends
        // lower. SLIM's slow tail is a smooth drift of area along the branches that every step
        // repeats; the momentum carries it on.
        Eigen::VectorXd m = Eigen::VectorXd::Zero(x_.size());
        m.head(2 * n_) = options_.momentum * momentum_;
        if (scaffold_)
            scaffold_->extend(m);
        Eigen::VectorXd dm = d + m;
        const LineStep with_momentum = line_search(ops_, x_, dm, e);
        if (with_momentum.energy < step.energy)
        {
            d = dm;
            step = with_momentum;
            ++summary_.accelerated;
        }
    }
    if (!(step.energy < e))
    {
        // No descent along the proxy's direction. Where faces compressed below the weights'
        // clamp (add_face()) carry the energy, the clamped proxy's gradient is not the energy's,
        // and its minimizer need not descend (tree maps from the layout circle: SLIM then
        // stalled orders of magnitude above its minimum). The factorized proxy matrix M applied
        // to the true gradient g does: -M^-1 g is a descent direction for any positive
        // definite M, and equals the proxy's direction wherever no weight is clamped.
        Eigen::VectorXd g = energy_gradient(ops_, x_);
        if (!options_.centre_pulls.empty())
        {
            std::vector<int> slot(static_cast<std::size_t>(n_all_));
            for (int v = 0; v < n_all_; ++v)
                slot[static_cast<std::size_t>(v)] = v;
            detail::add_centre_pull_gradient(options_.centre_pulls, x_, slot, g.data());
        }
        Eigen::VectorXd descent = -solver_.solve(g);
        if (scaffold_)
            for (int v : scaffold_->box())
                descent.segment<2>(2 * v).setZero();
        if (solver_.info() == Eigen::Success && descent.allFinite())
        {
            const LineStep by_gradient = line_search(ops_, x_, descent, e);
            if (by_gradient.energy < e)
            {
                d = std::move(descent);
                step = by_gradient;
                ++summary_.gradient_steps;
            }
        }
    }
    // Whether the step's end crosses the boundary, where shorten_to_contact() tested it.
    std::optional<bool> end_crosses;
    if (watch_ && shorten_to_contact_ && step.energy < e)
        end_crosses = shorten_to_contact(d, step, e);
    const Eigen::VectorXd x_before = x_.head(2 * n_);
    summary_.iterations = done + it + 1;
    if (options_.on_iteration)
        options_.on_iteration(it + 1, static_cast<bool>(scaffold_));
    if (!(step.energy <= e))
    {
        summary_.converged = true;  // no descent left along the proxy's direction
        return false;
    }
    x_ += step.step * d;
    // Only a step that a scaffold triangle stopped gets a new triangulation (here and at the
    // next iteration): where a surface triangle stops it, the new scaffold would not let it go
    // further.
    blocked_by_scaffold_ = step.by_scaffold;
    if (scaffold_ && options_.scaffold_passes > 1)
        continue_past_scaffold(d, step.step);
    momentum_ = x_.head(2 * n_) - x_before;
    if (watch_ && !(end_crosses ? *end_crosses : crosses(x_)))
    {
        last_simple_ = x_;
        last_simple_it_ = summary_.iterations;
    }
    else if (watch_ && summary_.iterations - last_simple_it_ >= options_.crossing_patience)
        return false;  // crossed for that long: it will not come apart by itself
    const double e_surface_new = scaffold_ || !options_.centre_pulls.empty()
                                     ? energy(surface_, x_, threads_)
                                     : step.energy;
    const double decrease = (e_surface_ - e_surface_new) / e_surface_;
    e_surface_ = e_surface_new;
    // One small step can come from a short line search (a nearly collapsed triangle in the
    // way), not from convergence; three in a row are convergence unless each step was cut
    // short too. Then a nearly collapsed triangle bounds every step along the proxy's
    // direction while the energy is still orders of magnitude above its minimum (a decimated
    // many-outlet tree from the layout circle); the next iterations' proxies, fitted at the
    // moved map, and the true gradient's steps get past it (docs/design.md, "SLIM's stopping
    // rule"). kMaxStallsPassed bounds the extra iterations.
    slow_ = decrease < (scaffold_ ? scaffold_tolerance_ : options_.tolerance) ? slow_ + 1 : 0;
    short_ = step.step < kShortStep ? short_ + 1 : 0;
    if (slow_ == 3)
    {
        if (short_ >= 3 && summary_.stalls_passed < kMaxStallsPassed)
        {
            ++summary_.stalls_passed;
            slow_ = 0;
            return true;
        }
        summary_.converged = true;
        return false;
    }
    return true;
}

InjectiveSummary Slim::run(Eigen::MatrixX2d& uv)
{
    for (int phase = 0; phase < 2; ++phase)
    {
        const int done = summary_.iterations;
        for (int it = 0; it < options_.max_iterations; ++it)
            if (!iterate(it, done))
                break;
        // Unconstrained SLIM may move the boundary across itself (branches relaxing into each
        // other). Then go back to the last iterate without that and go on with a scaffold,
        // which keeps the free space between the boundary's parts open: the end map is
        // one-to-one.
        if (!watch_ || !crosses(x_))
            break;
        watch_ = false;
        const double crossed = e_surface_;
        x_ = last_simple_;
        summary_.scaffold_from = last_simple_it_;
        e_surface_ = energy(surface_, x_, threads_);
        // Where the unconstrained steps had all but converged when the boundary crossed, the
        // scaffold phase could gain about the gap between the last simple iterate and the
        // crossed one: stop at the former (scaffold_skip_gap).
        if (options_.scaffold_skip_gap > 0.0 &&
            e_surface_ <= (1.0 + options_.scaffold_skip_gap) * crossed)
        {
            summary_.scaffold_skipped = true;
            break;
        }
        summary_.converged = false;
        slow_ = 0;
        start_scaffold();
        momentum_.resize(0);
    }
    detail::deinterleave(x_, uv);
    summary_.final_energy = e_surface_;
    summary_.report = report();
    return summary_;
}

std::string Slim::report() const
{
    const InjectiveSummary& s = summary_;
    return std::string(s.scaffold_skipped
                           ? "SLIM (boundary crossed; stopped at iterate " +
                                 std::to_string(s.scaffold_from) +
                                 ", the last simple one, within the scaffold's skip gap)"
                       : !scaffold_           ? "SLIM"
                       : s.scaffold_from >= 0 ? "SLIM (boundary crossed; scaffold from iterate " +
                                                    std::to_string(s.scaffold_from) + ")"
                                              : "SLIM with scaffold") +
           " symmetric Dirichlet: " + std::to_string(s.iterations) + " iterations, energy " +
           std::to_string(s.initial_energy) + " -> " + std::to_string(s.final_energy) +
           (s.scaffold_skipped ? std::string()
            : s.converged      ? std::string(" (converged)")
                               : std::string(" (iteration limit)")) +
           (scaffold_ ? ", " + std::to_string(s.scaffold_rebuilds) + " scaffold triangulations, " +
                            std::to_string(s.scaffold_refits) + " refitted by flips, " +
                            std::to_string(s.scaffold_passes) + " continued steps"
                      : std::string()) +
           (s.accelerated > 0 ? ", " + std::to_string(s.accelerated) + " steps with momentum"
                              : std::string()) +
           (s.gradient_steps > 0
                ? ", " + std::to_string(s.gradient_steps) + " steps along the true gradient"
                : std::string()) +
           (s.shortened_steps > 0 ? ", " + std::to_string(s.shortened_steps) +
                                        " steps shortened to keep the boundary simple"
                                  : std::string()) +
           (s.stalls_passed > 0 ? ", " + std::to_string(s.stalls_passed) + " stalls passed"
                                : std::string());
}

}  // namespace

InjectiveSummary injective_refine(const Mesh& mesh, Eigen::MatrixX2d& uv, const Pins& pins,
                                  const InjectiveOptions& options)
{
    options.validate();
    detail::require_uv_rows(mesh, uv, "injective_refine");
    pin_index(mesh, pins, "injective_refine");
    detail::require_centre_pull_vertices(options.centre_pulls,
                                         static_cast<int>(mesh.n_vertices()), "injective_refine");
    return Slim(mesh, uv, pins, options).run(uv);
}

}  // namespace vessel
