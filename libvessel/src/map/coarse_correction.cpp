#include "detail/coarse_correction.h"

#include "detail/segments.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace vessel::detail {

namespace {

// The energy of all faces at x: each face's on two threads (large meshes), summed in face
// order, so the same bits as one thread's loop.
double total_energy(const std::vector<FaceOperator>& faces, const VertexEnergy& energy,
                    const double* x, std::vector<double>& per_face)
{
    per_face.resize(faces.size());
    parallel_chunks(faces.size(), face_threads(faces.size()),
                    [&](std::size_t begin, std::size_t end, int) {
                        for (std::size_t f = begin; f < end; ++f)
                            per_face[f] = energy.face(faces[f], x);
                    });
    double e = 0.0;
    for (const double face : per_face)
        e += face;
    return e;
}

// The vertices [first, second) that thread t of `threads` owns when per-vertex sums are split
// among threads (each thread then adds only into its own vertices).
std::pair<int, int> owned_vertices(int n, int t, int threads)
{
    return {static_cast<int>(static_cast<long>(n) * t / threads),
            static_cast<int>(static_cast<long>(n) * (t + 1) / threads)};
}

// Per-vertex sums over the faces on two threads (large meshes) to the same bits as one thread's
// loop: a chunk of faces at a time, make(face, item) for each face on the threads, then
// add(face, item, t) for every face of the chunk in face order by each thread t, which adds
// only into the vertices it owns (owned_vertices()), so every sum keeps the face order.
template <class Item, class Make, class Add>
void sum_over_faces(const std::vector<FaceOperator>& faces, const Make& make, const Add& add)
{
    const int threads = face_threads(faces.size());
    constexpr std::size_t kChunk = 16384;
    std::vector<Item> items(std::min(kChunk, faces.size()));
    for (std::size_t base = 0; base < faces.size(); base += kChunk)
    {
        const std::size_t count = std::min(kChunk, faces.size() - base);
        parallel_chunks(count, threads, [&](std::size_t begin, std::size_t end, int) {
            for (std::size_t f = begin; f < end; ++f)
                make(faces[base + f], items[f]);
        });
        parallel_chunks(count, threads, [&](std::size_t, std::size_t, int t) {
            for (std::size_t f = 0; f < count; ++f)
                add(faces[base + f], items[f], t);
        });
    }
}

// A symmetric operator by 2 x 2 blocks over vertices: per vertex its diagonal block and, in a
// segment [seg[i], seg[i] + used[i]), its neighbours j and the blocks (rows i, columns j).
struct BlockOperator
{
    std::vector<int> seg, used, neighbour;
    std::vector<Eigen::Matrix2d> diagonal, offdiagonal;
};

// An interpolation P = W (x) I_2 given by the vertex weights W (n x m; the same weight for u and
// v), by rows (w_*) and by columns (t_*).
struct VertexWeights
{
    int m = 0;
    std::vector<int> w_first, w_coarse;
    std::vector<double> w_weight;
    std::vector<int> t_first, t_fine;
    std::vector<double> t_weight;
};

// W from P's even rows and columns; rows of the vertices with slot[v] < 0 left empty (null slot:
// none).
VertexWeights vertex_weights(const Eigen::SparseMatrix<double, Eigen::RowMajor>& interpolation,
                             const std::vector<int>* slot)
{
    const int n = static_cast<int>(interpolation.rows() / 2);
    VertexWeights W;
    W.m = static_cast<int>(interpolation.cols() / 2);
    W.w_first.assign(n + 1, 0);
    for (int v = 0; v < n; ++v)
    {
        if (!slot || (*slot)[v] >= 0)
            for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(interpolation, 2 * v);
                 it; ++it)
            {
                W.w_coarse.push_back(static_cast<int>(it.col() / 2));
                W.w_weight.push_back(it.value());
            }
        W.w_first[v + 1] = static_cast<int>(W.w_coarse.size());
    }
    W.t_first.assign(W.m + 1, 0);
    W.t_fine.resize(W.w_coarse.size());
    W.t_weight.resize(W.w_coarse.size());
    for (int a : W.w_coarse)
        ++W.t_first[a + 1];
    for (int a = 0; a < W.m; ++a)
        W.t_first[a + 1] += W.t_first[a];
    std::vector<int> next(W.t_first.begin(), W.t_first.end() - 1);
    for (int v = 0; v < n; ++v)
        for (int e = W.w_first[v]; e < W.w_first[v + 1]; ++e)
        {
            W.t_fine[next[W.w_coarse[e]]] = v;
            W.t_weight[next[W.w_coarse[e]]++] = W.w_weight[e];
        }
    return W;
}

// The upper triangle of P^T H P (P = W (x) I_2) by 2 x 2 blocks (Gustavson 1978, "Two fast
// algorithms for sparse matrices: multiplication and permuted transposition"): column a gathers
// C_ab = sum over i of a, and j = i or a neighbour of i, of w_ia w_jb H_ij, for b <= a (C is
// symmetric: C_ab(r, s) is the entry (2b + s, 2a + r)). The columns on up to two threads, each
// column summed alone as on one thread: the same bits.
Eigen::SparseMatrix<double> block_product(const BlockOperator& H, const VertexWeights& W,
                                          int threads)
{
    const int m = W.m;
    struct Part
    {
        std::vector<int> outer, inner;  // outer: the part's columns' ends, relative
        std::vector<double> values;
    };
    std::vector<Part> parts(static_cast<std::size_t>(std::max(threads, 1)));
    parallel_chunks(static_cast<std::size_t>(m), threads, [&](std::size_t first, std::size_t last, int t) {
        Part& part = parts[static_cast<std::size_t>(t)];
        std::vector<Eigen::Matrix2d> acc(m, Eigen::Matrix2d::Zero());
        std::vector<char> seen(m, 0);
        std::vector<int> touched;
        const auto gather = [&](int a, double wia, int j, const Eigen::Matrix2d& block) {
            for (int e = W.w_first[j]; e < W.w_first[j + 1]; ++e)
            {
                const int b = W.w_coarse[e];
                if (b > a)
                    continue;
                if (!seen[b])
                {
                    seen[b] = 1;
                    touched.push_back(b);
                }
                acc[b] += (wia * W.w_weight[e]) * block;
            }
        };
        for (int a = static_cast<int>(first); a < static_cast<int>(last); ++a)
        {
            touched.assign(1, a);  // the diagonal block, even if nothing adds to it
            seen[a] = 1;
            for (int t2 = W.t_first[a]; t2 < W.t_first[a + 1]; ++t2)
            {
                const int i = W.t_fine[t2];
                const double wia = W.t_weight[t2];
                gather(a, wia, i, H.diagonal[i]);
                for (int e = H.seg[i]; e < H.seg[i] + H.used[i]; ++e)
                    gather(a, wia, H.neighbour[e], H.offdiagonal[e]);
            }
            std::sort(touched.begin(), touched.end());
            for (int r = 0; r < 2; ++r)
            {
                for (int b : touched)
                    for (int s = 0; s < 2 && (b < a || s <= r); ++s)
                    {
                        part.inner.push_back(2 * b + s);
                        part.values.push_back(acc[b](r, s));
                    }
                part.outer.push_back(static_cast<int>(part.inner.size()));
            }
            for (int b : touched)
            {
                seen[b] = 0;
                acc[b].setZero();
            }
        }
    });
    std::size_t entries = 0;
    for (const Part& part : parts)
        entries += part.inner.size();
    Eigen::SparseMatrix<double> C(2 * m, 2 * m);
    C.resizeNonZeros(static_cast<Eigen::Index>(entries));
    int* outer = C.outerIndexPtr();
    outer[0] = 0;
    std::size_t column = 0, offset = 0;
    for (const Part& part : parts)
    {
        for (int end : part.outer)
            outer[++column] = static_cast<int>(offset) + end;
        std::copy(part.inner.begin(), part.inner.end(), C.innerIndexPtr() + offset);
        std::copy(part.values.begin(), part.values.end(), C.valuePtr() + offset);
        offset += part.inner.size();
    }
    return C;
}

// The blocks of a symmetric operator given by its upper triangle (2|V| square, compressed).
BlockOperator blocks_of_upper(const Eigen::SparseMatrix<double>& upper)
{
    const int n = static_cast<int>(upper.cols() / 2);
    BlockOperator H;
    H.seg.assign(n + 1, 0);
    H.used.assign(n, 0);
    H.diagonal.assign(n, Eigen::Matrix2d::Zero());
    // Each block (b, a), b < a, once per column pair: counted for both vertices.
    std::vector<int> last(n, -1);
    for (int a = 0; a < n; ++a)
        for (int c = 2 * a; c < 2 * a + 2; ++c)
            for (Eigen::SparseMatrix<double>::InnerIterator it(upper, c); it; ++it)
            {
                const int b = static_cast<int>(it.row() / 2);
                if (b < a && last[b] != a)
                {
                    last[b] = a;
                    ++H.seg[a + 1];
                    ++H.seg[b + 1];
                }
            }
    for (int v = 0; v < n; ++v)
        H.seg[v + 1] += H.seg[v];
    H.neighbour.resize(H.seg[n]);
    H.offdiagonal.assign(H.seg[n], Eigen::Matrix2d::Zero());
    std::fill(last.begin(), last.end(), -1);
    // Per b < a while column pair a is read: the entries of blocks (a, b) and (b, a).
    std::vector<int> in_a(n, -1), in_b(n, -1);
    for (int a = 0; a < n; ++a)
        for (int r = 0; r < 2; ++r)
            for (Eigen::SparseMatrix<double>::InnerIterator it(upper, 2 * a + r); it; ++it)
            {
                const int b = static_cast<int>(it.row() / 2), s = static_cast<int>(it.row() % 2);
                const double value = it.value();  // C(2b + s, 2a + r) = C_ab(r, s) = C_ba(s, r)
                if (b == a)
                {
                    H.diagonal[a](s, r) = value;
                    H.diagonal[a](r, s) = value;
                    continue;
                }
                if (b > a)
                    continue;  // not in an upper triangle
                if (last[b] != a)
                {
                    last[b] = a;
                    in_a[b] = H.seg[a] + H.used[a]++;
                    in_b[b] = H.seg[b] + H.used[b]++;
                    H.neighbour[in_a[b]] = b;
                    H.neighbour[in_b[b]] = a;
                }
                H.offdiagonal[in_a[b]](r, s) = value;
                H.offdiagonal[in_b[b]](s, r) = value;
            }
    return H;
}

}  // namespace

Eigen::SparseMatrix<double> galerkin_of_operator(
    const Eigen::SparseMatrix<double>& upper,
    const Eigen::SparseMatrix<double, Eigen::RowMajor>& interpolation, int threads)
{
    return block_product(blocks_of_upper(upper), vertex_weights(interpolation, nullptr), threads);
}

Eigen::SparseMatrix<double> galerkin_operator(
    const std::vector<FaceOperator>& faces, const std::vector<int>& slot, const double* x,
    double lambda, const Eigen::SparseMatrix<double, Eigen::RowMajor>& interpolation)
{
    const int n = static_cast<int>(slot.size());
    const VertexWeights W = vertex_weights(interpolation, &slot);
    // H by 2 x 2 blocks: per free fine vertex its diagonal block and, in a segment sized by its
    // faces (two neighbours each, shared ones once), its free neighbours' blocks, summed in face
    // order on two threads (sum_over_faces(): the faces' Hessians, whose projection is most of
    // the work, made in parallel), so the operator is the same bits as on one thread.
    BlockOperator H;
    H.seg.assign(n + 1, 0);
    H.used.assign(n, 0);
    for (const FaceOperator& op : faces)
        for (int v : op.corner)
            H.seg[v + 1] += 2;
    for (int v = 0; v < n; ++v)
        H.seg[v + 1] += H.seg[v];
    H.neighbour.resize(H.seg[n]);
    H.offdiagonal.assign(H.seg[n], Eigen::Matrix2d::Zero());
    H.diagonal.assign(n, Eigen::Matrix2d::Zero());
    const auto is_free = [&](const FaceOperator& op) {
        return slot[op.corner[0]] >= 0 || slot[op.corner[1]] >= 0 || slot[op.corner[2]] >= 0;
    };
    const int threads = face_threads(faces.size());
    sum_over_faces<FaceHessian>(
        faces,
        [&](const FaceOperator& op, FaceHessian& F) {
            if (is_free(op))
                F = FaceHessian(op, jacobian(op, x), lambda);
        },
        [&](const FaceOperator& op, const FaceHessian& F, int t) {
            if (!is_free(op))
                return;
            const auto [owned_begin, owned_end] = owned_vertices(n, t, threads);
            for (int k = 0; k < 3; ++k)
            {
                const int i = op.corner[k];
                if (slot[i] < 0 || i < owned_begin || i >= owned_end)
                    continue;
                H.diagonal[i] += F.block(k, k);
                for (int l = 0; l < 3; ++l)
                {
                    const int j = op.corner[l];
                    if (l == k || slot[j] < 0)
                        continue;
                    int e = H.seg[i];
                    while (e < H.seg[i] + H.used[i] && H.neighbour[e] != j)
                        ++e;
                    if (e == H.seg[i] + H.used[i])
                    {
                        H.neighbour[e] = j;
                        ++H.used[i];
                    }
                    H.offdiagonal[e] += F.block(k, l);
                }
            }
        });
    return block_product(H, W, threads);
}

Eigen::SparseMatrix<double> coarse_interpolation(const Mesh& coarse, const std::vector<int>& coarse_of,
                                                 const Eigen::MatrixX2d& coarse_uv,
                                                 const Eigen::MatrixX2d& fine_uv)
{
    const int n = static_cast<int>(fine_uv.rows());
    const int m = static_cast<int>(coarse_uv.rows());
    std::vector<std::array<int, 3>> triangles;
    triangles.reserve(coarse.n_faces());
    for (auto f : coarse.faces())
    {
        auto h = f.halfedge();
        triangles.push_back({h.from().idx(), h.to().idx(), h.next().to().idx()});
    }
    // A uniform grid of the coarse triangles' boxes, cells about two triangles wide.
    const Eigen::Vector2d lo = coarse_uv.colwise().minCoeff().transpose();
    const Eigen::Vector2d hi = coarse_uv.colwise().maxCoeff().transpose();
    const double cell = std::max(
        2.0 * std::sqrt((hi - lo).prod() / std::max<std::size_t>(triangles.size(), 1)), 1e-12);
    const int nx = static_cast<int>((hi.x() - lo.x()) / cell) + 1;
    const int ny = static_cast<int>((hi.y() - lo.y()) / cell) + 1;
    const auto column = [&](double u) { return std::clamp(static_cast<int>((u - lo.x()) / cell), 0, nx - 1); };
    const auto row = [&](double v) { return std::clamp(static_cast<int>((v - lo.y()) / cell), 0, ny - 1); };
    std::vector<std::vector<int>> grid(static_cast<std::size_t>(nx) * ny);
    for (int t = 0; t < static_cast<int>(triangles.size()); ++t)
    {
        Eigen::Vector2d a = coarse_uv.row(triangles[t][0]).transpose(), b = a;
        for (int k = 1; k < 3; ++k)
        {
            a = a.cwiseMin(coarse_uv.row(triangles[t][k]).transpose());
            b = b.cwiseMax(coarse_uv.row(triangles[t][k]).transpose());
        }
        for (int i = column(a.x()); i <= column(b.x()); ++i)
            for (int j = row(a.y()); j <= row(b.y()); ++j)
                grid[static_cast<std::size_t>(i) * ny + j].push_back(t);
    }
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(6 * static_cast<std::size_t>(n));
    const auto add = [&](int v, int c, double w) {
        triplets.emplace_back(2 * v, 2 * c, w);
        triplets.emplace_back(2 * v + 1, 2 * c + 1, w);
    };
    for (int v = 0; v < n; ++v)
    {
        if (coarse_of[v] >= 0)
        {
            add(v, coarse_of[v], 1.0);
            continue;
        }
        // The triangle whose smallest barycentric coordinate of the vertex is largest: the one
        // holding it, else the nearest in that sense, searched in rings of cells.
        const Eigen::Vector2d p = fine_uv.row(v).transpose();
        double best = -std::numeric_limits<double>::infinity();
        Eigen::Vector3d weights(1.0, 0.0, 0.0);
        int found = -1;
        const int i0 = column(p.x()), j0 = row(p.y());
        for (int ring = 0; ring <= 2 && best < 0.0; ++ring)
            for (int i = std::max(i0 - ring, 0); i <= std::min(i0 + ring, nx - 1); ++i)
                for (int j = std::max(j0 - ring, 0); j <= std::min(j0 + ring, ny - 1); ++j)
                {
                    if (std::max(std::abs(i - i0), std::abs(j - j0)) != ring)
                        continue;  // the ring's cells only
                    for (int t : grid[static_cast<std::size_t>(i) * ny + j])
                    {
                        Eigen::Vector3d w;
                        if (!barycentric(p, coarse_uv.row(triangles[t][0]).transpose(),
                                         coarse_uv.row(triangles[t][1]).transpose(),
                                         coarse_uv.row(triangles[t][2]).transpose(), w))
                            continue;
                        if (w.minCoeff() > best)
                        {
                            best = w.minCoeff();
                            weights = w;
                            found = t;
                        }
                    }
                }
        if (found < 0)
            continue;  // far from every coarse triangle: the correction does not move it
        weights = weights.cwiseMax(0.0);
        weights /= weights.sum();
        for (int k = 0; k < 3; ++k)
            if (weights[k] > 0.0)
                add(v, triangles[found][k], weights[k]);
    }
    Eigen::SparseMatrix<double> P(2 * n, 2 * m);
    P.setFromTriplets(triplets.begin(), triplets.end());
    return P;
}

namespace {

std::vector<int> free_slots(const std::vector<int>& pinned)
{
    std::vector<int> slot(pinned.size());
    for (std::size_t v = 0; v < pinned.size(); ++v)
        slot[v] = pinned[v] >= 0 ? -1 : static_cast<int>(v);
    return slot;
}

}  // namespace

CoarseCorrection::CoarseCorrection(const std::vector<FaceOperator>& faces,
                                   Eigen::SparseMatrix<double> interpolation,
                                   const std::vector<int>& pinned, double lambda,
                                   Eigen::SparseMatrix<double> below)
    : faces_(faces),
      P_(std::move(interpolation)),
      slot_(free_slots(pinned)),
      lambda_(lambda),
      below_(std::move(below)),
      below_rows_(below_),
      threads_(face_threads(faces.size()))
{
    // A pinned vertex does not move: its rows of P are emptied.
    P_.prune([&](Eigen::Index r, Eigen::Index, double) { return pinned[r / 2] < 0; });
    rows_ = P_;
    const int threads = face_threads(faces.size());
    const int n = static_cast<int>(slot_.size());
    for (int t = 0; t < threads; ++t)
    {
        std::vector<int>& owned = owned_slot_.emplace_back(n, -1);
        const auto [begin, end] = owned_vertices(n, t, threads);
        std::copy(slot_.begin() + begin, slot_.begin() + end, owned.begin() + begin);
    }
}

int CoarseCorrection::hold_around(int v, std::vector<char>& held) const
{
    int added = 0;
    for (int r = 2 * v; r < 2 * v + 2; ++r)
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(rows_, r); it; ++it)
            if (!held[it.col()])
            {
                held[it.col()] = 1;
                ++added;
            }
    return added;
}

void CoarseCorrection::factorize()
{
    if (below_.size() > 0)
    {
        // The V-cycle: the sweeps skip the held unknowns; the level below's operator is
        // P2^T C P2 (upper triangle) plus, per held unknown i, a stiff spring
        // kSpring x mean_diagonal_ x (P2 row i)^T (P2 row i). Without the springs the level
        // below moves the held unknowns, and zeroing them afterwards undoes most of its
        // correction (the cycle then diverged on the carotid phantoms); where no pin holds the
        // map they also fix its translations, which would leave P2^T C P2 singular. A spring
        // joins the vertices of one triangle of the level below: the pattern stays.
        constexpr double kSpring = 1e4;
        if (!analysed_)
        {
            full_ = coarse_.selfadjointView<Eigen::Upper>();
            below_base_ = galerkin_of_operator(coarse_, below_rows_, threads_);
            for (Eigen::Index c = 0; c < below_base_.cols(); ++c)
                below_base_.coeffRef(c, c) += 1e-8 * mean_diagonal_;
            below_base_.makeCompressed();
        }
        below_operator_ = below_base_;
        using RowIterator = Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator;
        for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(held_.size()); ++i)
            if (held_[i])
                for (RowIterator a(below_rows_, i); a; ++a)
                    for (RowIterator b(below_rows_, i); b; ++b)
                        if (a.col() <= b.col())
                            below_operator_.coeffRef(a.col(), b.col()) +=
                                kSpring * mean_diagonal_ * a.value() * b.value();
        if (!analysed_)
        {
            solver_.analyze_pairs(below_operator_);
            analysed_ = true;
        }
        if (solver_.info() == Eigen::Success)
            solver_.factorize(below_operator_);
        return;
    }
    // Held unknowns become identity rows with a zero right-hand side, so the pattern stays that
    // of the analysis.
    system_ = coarse_;
    for (Eigen::Index c = 0; c < system_.outerSize(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(system_, c); it; ++it)
        {
            if (held_[it.row()] || held_[c])
                it.valueRef() = it.row() == c ? mean_diagonal_ : 0.0;
            if (it.row() == c)
                it.valueRef() += 1e-8 * mean_diagonal_;
        }
    if (!analysed_)
    {
        solver_.analyze_pairs(system_);
        analysed_ = true;
    }
    if (solver_.info() == Eigen::Success)
        solver_.factorize(system_);
}

void CoarseCorrection::zero_held(Eigen::VectorXd& y) const
{
    for (Eigen::Index c = 0; c < y.size(); ++c)
        if (held_[c])
            y[c] = 0.0;
}

void CoarseCorrection::sweep(const Eigen::VectorXd& rhs, Eigen::VectorXd& d, bool forward) const
{
    // C is symmetric: column i holds row i. On two threads, each takes half of the unknowns (in
    // vertex pairs), swept in order, and reads the other half's entries of d as they were when
    // the sweep began (hybrid Gauss-Seidel: Gauss-Seidel within each half, Jacobi between the
    // halves; Baker, Falgout, Kolev and Yang 2011, "Multigrid smoothers for ultraparallel
    // computing"). The backward sweep runs each half in reverse, so a forward and a backward
    // sweep together stay a symmetric smoother.
    const Eigen::Index n = full_.cols();
    const int threads = full_threads();
    if (threads > 1)
        before_ = d;
    parallel_chunks(static_cast<std::size_t>(n / 2), threads,
                    [&](std::size_t first, std::size_t last, int) {
                        const auto begin = static_cast<Eigen::Index>(2 * first);
                        const auto end = static_cast<Eigen::Index>(2 * last);
                        const double* outside = threads > 1 ? before_.data() : d.data();
                        for (Eigen::Index k = 0; k < end - begin; ++k)
                        {
                            const Eigen::Index i = forward ? begin + k : end - 1 - k;
                            if (held_[i])
                                continue;
                            double sum = rhs[i], diagonal = 0.0;
                            for (Eigen::SparseMatrix<double>::InnerIterator it(full_, i); it; ++it)
                            {
                                const Eigen::Index j = it.row();
                                if (j == i)
                                    diagonal = it.value();
                                else
                                    sum -= it.value() * (j >= begin && j < end ? d[j] : outside[j]);
                            }
                            if (diagonal > 0.0)
                                d[i] = sum / diagonal;
                        }
                    });
}

Eigen::VectorXd CoarseCorrection::times_full(const Eigen::VectorXd& y) const
{
    // C is symmetric: entry i of C y is column i's dot product with y, a column range per thread.
    Eigen::VectorXd product(y.size());
    parallel_chunks(static_cast<std::size_t>(full_.cols()), full_threads(),
                    [&](std::size_t begin, std::size_t end, int) {
                        for (auto i = static_cast<Eigen::Index>(begin);
                             i < static_cast<Eigen::Index>(end); ++i)
                        {
                            double sum = 0.0;
                            for (Eigen::SparseMatrix<double>::InnerIterator it(full_, i); it; ++it)
                                sum += it.value() * y[it.row()];
                            product[i] = sum;
                        }
                    });
    return product;
}

Eigen::VectorXd CoarseCorrection::v_cycle(const Eigen::VectorXd& rhs)
{
    // Symmetric smoothing (forward before the level below's correction, backward after it)
    // keeps the cycle a symmetric positive definite approximation of C's inverse, so that the
    // step it gives descends (Briggs, Henson and McCormick 2000, ch. 3).
    constexpr int kSmoothing = 2;
    Eigen::VectorXd d = Eigen::VectorXd::Zero(rhs.size());
    for (int s = 0; s < kSmoothing; ++s)
        sweep(rhs, d, true);
    Eigen::VectorXd residual = rhs - times_full(d);
    zero_held(residual);
    d += below_ * solver_.solve(below_.transpose() * residual);
    zero_held(d);
    for (int s = 0; s < kSmoothing; ++s)
        sweep(rhs, d, false);
    return d;
}

Eigen::VectorXd CoarseCorrection::solve(const Eigen::VectorXd& rhs)
{
    if (below_.size() == 0)
        return solver_.solve(rhs);
    // Conjugate gradients on C restricted to the free unknowns, preconditioned by one V-cycle
    // (symmetric positive definite: symmetric smoothing around an exact solve below). Two
    // iterations: the step is line searched on the energy anyway, and further iterations cost
    // more than the steps they improve (docs/benchmarks.md "Coarse-to-fine").
    constexpr int kIterations = 2;
    constexpr double kTolerance = 0.05;  // of the first residual's norm
    Eigen::VectorXd d = Eigen::VectorXd::Zero(rhs.size());
    Eigen::VectorXd r = rhs;
    zero_held(r);
    const double r0 = r.norm();
    Eigen::VectorXd z = v_cycle(r);
    Eigen::VectorXd p = z;
    double rz = r.dot(z);
    for (int it = 0; it < kIterations && rz > 0.0; ++it)
    {
        Eigen::VectorXd Ap = times_full(p);
        zero_held(Ap);
        const double curvature = p.dot(Ap);
        if (!(curvature > 0.0))
            break;
        const double alpha = rz / curvature;
        d += alpha * p;
        r -= alpha * Ap;
        if (!(r.norm() > kTolerance * r0))
            break;
        z = v_cycle(r);
        const double next = r.dot(z);
        p = z + (next / rz) * p;
        rz = next;
    }
    return d;
}

double CoarseCorrection::step(const VertexEnergy& energy, Eigen::VectorXd& xv, BoundaryGuard* guard,
                              double& current,
                              const std::function<double(const Eigen::VectorXd&)>& extra)
{
    const double* x = xv.data();
    const Eigen::Index n2 = xv.size();
    // The gradient, summed per entry in face order on two threads (sum_over_faces(); each
    // thread's owned_slot_ holds its own vertices' slots).
    Eigen::VectorXd gradient = Eigen::VectorXd::Zero(n2);
    sum_over_faces<Eigen::Matrix2d>(
        faces_,
        [&](const FaceOperator& op, Eigen::Matrix2d& dE) {
            dE = op.area * polish_face_gradient(jacobian(op, x), lambda_);
        },
        [&](const FaceOperator& op, const Eigen::Matrix2d& dE, int t) {
            add_face_gradient(op, dE, owned_slot_[t], gradient.data());
        });
    if (coarse_.size() == 0)
    {
        // The coarse operator at the first step, kept for the next ones: the relaxation changes
        // the map little, and the line search makes up for the difference (a frozen Newton
        // matrix), while the Galerkin product costs several sweeps.
        coarse_ = galerkin_operator(faces_, slot_, x, lambda_, rows_);
        double trace = 0.0;
        for (Eigen::Index c = 0; c < coarse_.rows(); ++c)
            trace += coarse_.coeff(c, c);
        mean_diagonal_ = std::max(trace / std::max<Eigen::Index>(coarse_.rows(), 1), 1e-300);
        held_.assign(coarse_.rows(), 0);
        // Held from the start: the coarse vertices around boundary parts within half a boundary
        // edge of each other, where a step would soon close the gap.
        if (guard)
        {
            guard->rebuild(x);
            for (int v : guard->near_pairs(x, std::max(0.5 * guard->mean_edge(), guard->clearance())))
                hold_around(v, held_);
        }
        factorize();
    }
    const Eigen::VectorXd restricted = P_.transpose() * gradient;
    Eigen::VectorXd trial(n2);
    for (int round = 0; round < 8; ++round)
    {
        if (solver_.info() != Eigen::Success)
            return 0.0;
        Eigen::VectorXd rhs = -restricted;
        zero_held(rhs);
        const Eigen::VectorXd direction = P_ * solve(rhs);
        const double slope = gradient.dot(direction);
        if (!direction.allFinite() || !(slope < 0.0))
            return 0.0;
        double t = max_injective_step(faces_, xv, direction, face_threads(faces_.size()), 0, 0.9);
        double e = std::numeric_limits<double>::infinity();
        for (; t > 1e-3; t *= 0.5)
        {
            trial = xv + t * direction;
            e = total_energy(faces_, energy, trial.data(), per_face_);
            if (extra)
                e += extra(trial);
            if (e <= current + 1e-4 * t * slope)
                break;
        }
        if (!(t > 1e-3))
            return 0.0;
        // A step that brings boundary parts nearer than the clearance is solved again with the
        // coarse vertices there held.
        int added = 0;
        if (guard)
        {
            guard->rebuild(trial.data());
            for (int v : guard->near_contacts(trial.data()))
                added += hold_around(v, held_);
        }
        if (added == 0)
        {
            const double lowered = current - e;
            xv = trial;
            current = e;
            return lowered;
        }
        factorize();
    }
    return 0.0;
}

}  // namespace vessel::detail
