#include "vessel/cut/cut_winding.h"

#include "vessel/core/errors.h"
#include "detail/edge_distance.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <limits>
#include <mutex>
#include <string>
#include <thread>

namespace vessel {

void WindingOptions::validate() const
{
    if (!(band > 0.0) || !std::isfinite(band))
        throw InvalidInputError("WindingOptions: band must be finite and > 0 mean edges, got " +
                                std::to_string(band));
    if (min_ring_vertices < 3)
        throw InvalidInputError("WindingOptions: min_ring_vertices must be >= 3, got " +
                                std::to_string(min_ring_vertices));
    if (!(max_spread > 0.0) || !std::isfinite(max_spread))
        throw InvalidInputError("WindingOptions: max_spread must be finite and > 0, got " +
                                std::to_string(max_spread));
    if (!(min_offset >= 0.0 && min_offset < 1.0))
        throw InvalidInputError("WindingOptions: min_offset must be in [0, 1), got " +
                                std::to_string(min_offset));
}

struct WindingMeter::Ring
{
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();  // unit, along increasing u
    double radius = 0.0;                              // mean distance from the axis
    double coherence = 0.0;                          // Band::coherence, set by ring_at()
    std::vector<VertexHandle> vertices;
};

WindingMeter::WindingMeter(const Mesh& mesh, const CutGraph* graph,
                           const Eigen::VectorXd& longitudinal, const WindingOptions& options)
    : mesh_(mesh), graph_(graph), u_(longitudinal), options_(options)
{
    options_.validate();
    if (static_cast<std::size_t>(longitudinal.size()) != mesh.n_vertices())
        throw InvalidInputError("WindingMeter: " + std::to_string(longitudinal.size()) +
                                " longitudinal values for " + std::to_string(mesh.n_vertices()) +
                                " vertices; pass one per vertex, indexed by v.idx()");
    // The neighbour lists, from the graph's arcs where given (they keep voh_range() order, so
    // both give the same rings in the same order, and the same sums).
    const auto n = static_cast<int>(mesh.n_vertices());
    neighbour_start_.assign(static_cast<std::size_t>(n) + 1, 0);
    neighbours_.reserve(mesh.n_halfedges());
    for (int v = 0; v < n; ++v)
    {
        if (graph)
        {
            const auto [first, last] = graph->arcs(v);
            for (const CutGraph::Arc* a = first; a != last; ++a)
                neighbours_.push_back(a->to);
        }
        else
            detail::mesh_neighbours(mesh)(v, [&](int w) { neighbours_.push_back(w); });
        neighbour_start_[static_cast<std::size_t>(v) + 1] = static_cast<int>(neighbours_.size());
    }
    stamp_.assign(mesh.n_vertices(), -1);
    fit_of_.assign(mesh.n_vertices(), -1);
    rate_of_.assign(mesh.n_vertices(), -1);
    direction_.assign(mesh.n_vertices(),
                      Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
}

WindingMeter::WindingMeter(const Mesh& mesh, const Eigen::VectorXd& longitudinal,
                           const WindingOptions& options)
    : WindingMeter(mesh, nullptr, longitudinal, options)
{
    half_width_ = options_.band * mean_edge_length(mesh);
}

WindingMeter::WindingMeter(const CutGraph& graph, const Eigen::VectorXd& longitudinal,
                           double mean_edge, const WindingOptions& options)
    : WindingMeter(graph.mesh(), &graph, longitudinal, options)
{
    if (!(mean_edge >= 0.0) || !std::isfinite(mean_edge))
        throw InvalidInputError("WindingMeter: mean edge length " + std::to_string(mean_edge) +
                                " must be finite and >= 0; pass mean_edge_length(graph.mesh())");
    half_width_ = options_.band * mean_edge;
}

WindingMeter::WindingMeter(const CutGraph& graph, const Eigen::VectorXd& longitudinal,
                           double mean_edge, const Eigen::MatrixX3d& axis_direction,
                           const WindingOptions& options)
    : WindingMeter(graph, longitudinal, mean_edge, options)
{
    if (static_cast<std::size_t>(axis_direction.rows()) != mesh_.n_vertices())
        throw InvalidInputError("WindingMeter: " + std::to_string(axis_direction.rows()) +
                                " axis directions for " + std::to_string(mesh_.n_vertices()) +
                                " vertices; pass one row per vertex, e.g. minus "
                                "descent_direction(mesh, longitudinal)");
    for (std::size_t v = 0; v < direction_.size(); ++v)
        direction_[v] = axis_direction.row(static_cast<Eigen::Index>(v)).transpose();
    directions_given_ = true;
}

namespace {

// Area-weighted gradient of the piecewise-linear u over the faces around v (unnormalized).
Eigen::Vector3d gradient_at(const Mesh& mesh, const Eigen::VectorXd& u, VertexHandle v)
{
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (auto f : mesh.vf_range(v))
    {
        Eigen::Vector3d p[3];
        double value[3];
        int k = 0;
        for (auto w : mesh.fv_range(f))
        {
            p[k] = to_eigen(mesh.point(w));
            value[k++] = u[w.idx()];
        }
        const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
        const double norm = n.norm();
        if (!(norm > 0.0))
            continue;
        // area * grad u = 1/2 sum_i u_i (n^ x e_i), e_i the edge opposite corner i.
        const Eigen::Vector3d unit = n / norm;
        for (int i = 0; i < 3; ++i)
            sum += 0.5 * value[i] * unit.cross(p[(i + 2) % 3] - p[(i + 1) % 3]);
    }
    return sum;
}

// The minimal rotation taking unit a onto unit b, applied to x.
Eigen::Vector3d transport(const Eigen::Vector3d& x, const Eigen::Vector3d& a,
                          const Eigen::Vector3d& b)
{
    return Eigen::Quaterniond::FromTwoVectors(a, b) * x;
}

}  // namespace

namespace {

// A vertex's ring in the Prefetch: not asked for, queued, being fitted ahead, fitted ahead,
// or fitted by the meter's own thread (which then never reads the prefetched one).
enum : signed char { kNone = 0, kQueued, kFitting, kFitted, kOwn };

}  // namespace

struct WindingMeter::Prefetch::State
{
    explicit State(const WindingMeter& m)
        : meter(m), n(m.mesh_.n_vertices()), status(new std::atomic<signed char>[n]()),
          fits(n), stamp(n, -1), hinted(n, 0)
    {
    }

    // The meter's thread: the ring of v if it was fitted ahead (into \p fit), else false, and
    // then the other thread will not fit it (or its fit is not read).
    bool take(int v, RingFit& fit)
    {
        signed char s = status[v].load(std::memory_order_acquire);
        while (s == kNone || s == kQueued)
            if (status[v].compare_exchange_weak(s, kOwn, std::memory_order_acq_rel))
                return false;
        if (s != kFitted)
            return false;  // being fitted: fitted here too (the same bits)
        fit = fits[static_cast<std::size_t>(v)];
        return true;
    }

    // The other thread: fits the queued rings, newest first (the search's front). Should a
    // fit fail (out of memory), it stops: the meter's thread then fits every ring itself (a
    // ring left kFitting is never read).
    void work() noexcept
    {
        try
        {
            fit_queued();
        }
        catch (...)
        {
        }
    }

    void fit_queued()
    {
        Ring ring;
        std::vector<int> batch;
        int round = 0;
        for (;;)
        {
            {
                std::unique_lock<std::mutex> lock(mutex);
                ready.wait(lock, [&] { return stop || !queue.empty(); });
                if (stop)
                    return;
                batch.swap(queue);
            }
            for (auto it = batch.rbegin(); it != batch.rend(); ++it)
            {
                const int v = *it;
                signed char expected = kQueued;
                if (!status[v].compare_exchange_strong(expected, kFitting,
                                                       std::memory_order_acq_rel))
                    continue;  // the meter's thread took it
                fits[static_cast<std::size_t>(v)] =
                    meter.fit_ring(VertexHandle(v), ring, stamp.data(), ++round);
                status[v].store(kFitted, std::memory_order_release);
                if (stop.load(std::memory_order_relaxed))
                    return;
            }
            batch.clear();
        }
    }

    const WindingMeter& meter;
    const std::size_t n;
    std::unique_ptr<std::atomic<signed char>[]> status;
    std::vector<RingFit> fits;  // per vertex, valid once its status is kFitted
    std::vector<int> stamp;     // the other thread's band marks
    std::vector<char> hinted;   // the meter's thread: vertices whose neighbourhood was queued
    std::vector<int> pending;   // the meter's thread: queued since the last hand-over
    std::mutex mutex;
    std::condition_variable ready;
    std::vector<int> queue;
    std::atomic<bool> stop{false};
    std::thread worker;
};

bool WindingMeter::ring_at(VertexHandle p, Ring& ring, int* const stamp, const int round) const
{
    const double lo = u_[p.idx()] - half_width_, hi = u_[p.idx()] + half_width_;
    // Breadth first, without a branch on the band test: about half of the neighbours a ring
    // meets lie in the band, so a branch there is mispredicted as often as not. Each
    // neighbour is written past the ring's end and kept by moving the end.
    std::vector<VertexHandle>& out = ring.vertices;
    out.assign(1, p);
    ring.radius = 0.0;
    ring.coherence = std::numeric_limits<double>::quiet_NaN();
    stamp[p.idx()] = round;
    // Plain pointers: the stores below may alias the members for the compiler, which would
    // then load them again for every neighbour.
    const double* const u = u_.data();
    const int* const start = neighbour_start_.data();
    const int* const neighbour = neighbours_.data();
    std::size_t size = 1;
    for (std::size_t head = 0; head < size; ++head)
    {
        const int v = out[head].idx();
        const int first = start[v], last = start[v + 1];
        if (out.size() < size + static_cast<std::size_t>(last - first))
            out.resize(std::max(2 * out.size(), size + static_cast<std::size_t>(last - first)));
        VertexHandle* const end = out.data();
        for (int k = first; k < last; ++k)
        {
            const int w = neighbour[k];
            const bool enter = (u[w] >= lo) & (u[w] <= hi) & (stamp[w] != round);
            end[size] = VertexHandle(w);
            stamp[w] = enter ? round : stamp[w];
            size += enter;
        }
    }
    out.resize(size);
    const auto n = static_cast<double>(ring.vertices.size());
    if (ring.vertices.size() < static_cast<std::size_t>(options_.min_ring_vertices))
        return false;
    ring.centre.setZero();
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    for (auto v : ring.vertices)
    {
        ring.centre += to_eigen(mesh_.point(v));
        Eigen::Vector3d& unit = direction_[static_cast<std::size_t>(v.idx())];
        if (std::isnan(unit.x()))
        {
            const Eigen::Vector3d g = gradient_at(mesh_, u_, v);
            const double length = g.norm();
            unit = length > 0.0 ? Eigen::Vector3d(g / length) : Eigen::Vector3d::Zero();
        }
        axis += unit;
    }
    ring.centre /= n;
    ring.coherence = axis.norm() / n;
    if (!(axis.norm() > 0.0))
        return false;
    ring.axis = axis.normalized();
    double sum = 0.0, squares = 0.0;
    for (auto v : ring.vertices)
    {
        Eigen::Vector3d q = to_eigen(mesh_.point(v)) - ring.centre;
        q -= q.dot(ring.axis) * ring.axis;
        const double r = q.norm();
        sum += r;
        squares += r * r;
    }
    ring.radius = sum / n;
    const double spread = std::sqrt(std::max(0.0, squares / n - ring.radius * ring.radius));
    return ring.radius > 0.0 && spread < options_.max_spread * ring.radius;
}

WindingMeter::RingFit WindingMeter::fit_ring(VertexHandle p, Ring& ring, int* const stamp,
                                             const int round) const
{
    RingFit fit;
    fit.ok = ring_at(p, ring, stamp, round);
    fit.centre = ring.centre;
    fit.axis = ring.axis;
    fit.radius = ring.radius;
    fit.coherence = ring.coherence;
    return fit;
}

const WindingMeter::RingFit& WindingMeter::ring_fit(VertexHandle p, Ring& scratch) const
{
    int& slot = fit_of_[static_cast<std::size_t>(p.idx())];
    if (slot < 0)
    {
        RingFit fit;
        if (!(ahead_ && ahead_->take(p.idx(), fit)))
            fit = fit_ring(p, scratch, stamp_.data(), ++round_);
        slot = static_cast<int>(fits_.size());
        fits_.push_back(fit);
    }
    return fits_[static_cast<std::size_t>(slot)];
}

WindingMeter::Prefetch::Prefetch(const WindingMeter& meter)
{
    if (!meter.directions_given_ || meter.ahead_ || std::thread::hardware_concurrency() < 2)
        return;
    state_ = std::make_unique<State>(meter);
    state_->worker = std::thread([state = state_.get()] { state->work(); });
    meter.ahead_ = state_.get();
}

WindingMeter::Prefetch::~Prefetch()
{
    if (!state_)
        return;
    {
        std::lock_guard<std::mutex> lock(state_->mutex);
        state_->stop = true;
    }
    state_->ready.notify_one();
    state_->worker.join();
    state_->meter.ahead_ = nullptr;
}

void WindingMeter::Prefetch::hint(VertexHandle v)
{
    if (!state_)
        return;
    State& s = *state_;
    char& seen = s.hinted[static_cast<std::size_t>(v.idx())];
    if (seen)
        return;
    seen = 1;
    const WindingMeter& m = s.meter;
    const auto queue = [&](int x) {
        if (m.fit_of_[static_cast<std::size_t>(x)] >= 0)
            return;
        signed char expected = kNone;
        if (s.status[x].compare_exchange_strong(expected, kQueued, std::memory_order_relaxed))
            s.pending.push_back(x);
    };
    // A meter given its directions walks a graph (the constructor that takes them).
    const auto around = detail::graph_neighbours(*m.graph_);
    around(v.idx(), [&](int w) {
        queue(w);
        around(w, queue);
    });
    if (s.pending.empty())
        return;
    {
        std::lock_guard<std::mutex> lock(s.mutex);
        s.queue.insert(s.queue.end(), s.pending.begin(), s.pending.end());
    }
    s.pending.clear();
    s.ready.notify_one();
}

std::vector<VertexHandle> WindingMeter::path_vertices(const CutPath& path) const
{
    std::vector<VertexHandle> vertices{path.start};
    for (auto h : path.halfedges)
        vertices.push_back(mesh_.to_vertex_handle(h));
    return vertices;
}

PathWinding WindingMeter::measure(const CutPath& path, OpenStretch* open) const
{
    return measure(path_vertices(path), open);
}

PathWinding WindingMeter::measure(const std::vector<VertexHandle>& path, OpenStretch* open) const
{
    for (auto v : path)
        if (!v.is_valid() || static_cast<std::size_t>(v.idx()) >= mesh_.n_vertices())
            throw InvalidInputError("WindingMeter: the path passes vertex " +
                                    std::to_string(v.idx()) + " of a mesh with " +
                                    std::to_string(mesh_.n_vertices()) +
                                    " vertices; measure on the mesh the cut was planned on");
    // With `open`, every vertex's ring is fitted here with the open test (the walk below then
    // finds them fitted): the test needs the ring's vertices, which the fits do not keep.
    std::vector<char> on_open;
    if (open)
    {
        *open = OpenStretch{};
        on_open.assign(path.size(), 0);
        for (auto v : path)
            open_tested_fit(v);
    }
    PathWinding result;
    result.vertices = static_cast<int>(path.size());
    double total = 0.0, low = 0.0, high = 0.0;
    // The frame restarts after every vertex step() does not measure (bridge 0).
    VertexHandle last, previous;  // the last measured vertex, the vertex before p
    for (std::size_t i = 0; i < path.size(); ++i)
    {
        const VertexHandle p = path[i];
        const double turn = step(last, p, previous != last);
        previous = p;
        if (std::isnan(turn))
            continue;  // p is not measured: the frame waits at `last`
        last = p;
        ++result.measured;
        total += turn;
        low = std::min(low, total);
        high = std::max(high, total);
        if (open && open_tested_fit(p).open == 1)  // fitted above: no ring again
        {
            on_open[i] = 1;
            open->turn_deg += std::abs(turn) * 180.0 / M_PI;
        }
    }
    for (std::size_t i = 1; i < path.size(); ++i)
    {
        const double edge = (mesh_.point(path[i]) - mesh_.point(path[i - 1])).norm();
        result.length += edge;
        if (open && (on_open[i - 1] || on_open[i]))
            open->length += edge;
    }
    result.winding_deg = total * 180.0 / M_PI;
    result.span_deg = (high - low) * 180.0 / M_PI;
    return result;
}

bool WindingMeter::ring_open(const Ring& ring) const
{
    // The bounds on a band's largest empty arc (measure()'s `open`).
    constexpr double kOpenGapDeg = 60.0;
    constexpr double kOpenGapOfMean = 4.0;
    const Eigen::Vector3d e1 = ring.axis.unitOrthogonal(), e2 = ring.axis.cross(e1);
    std::vector<double> angles;
    angles.reserve(ring.vertices.size());
    for (auto v : ring.vertices)
    {
        const Eigen::Vector3d q = to_eigen(mesh_.point(v)) - ring.centre;
        angles.push_back(std::atan2(q.dot(e2), q.dot(e1)));
    }
    std::sort(angles.begin(), angles.end());
    double gap = 2.0 * M_PI - (angles.back() - angles.front());
    for (std::size_t i = 1; i < angles.size(); ++i)
        gap = std::max(gap, angles[i] - angles[i - 1]);
    const double mean = 2.0 * M_PI / static_cast<double>(angles.size());
    return gap > kOpenGapDeg * M_PI / 180.0 && gap > kOpenGapOfMean * mean;
}

const WindingMeter::RingFit& WindingMeter::open_tested_fit(VertexHandle p) const
{
    Ring ring;  // holds p's ring after ring_fit() if it was fitted just now on this thread
    ring_fit(p, ring);
    RingFit& fit = fits_[static_cast<std::size_t>(fit_of_[static_cast<std::size_t>(p.idx())])];
    if (fit.open < 0)
    {
        if (fit.ok && ring.vertices.empty())
            ring_at(p, ring, stamp_.data(), ++round_);
        fit.open = fit.ok && ring_open(ring);
    }
    return fit;
}

bool WindingMeter::offset(VertexHandle p, Eigen::Vector3d& d, const RingFit*& fit) const
{
    Ring scratch;
    const RingFit& ring = ring_fit(p, scratch);
    fit = &ring;
    if (!ring.ok)
        return false;
    d = to_eigen(mesh_.point(p)) - ring.centre;
    d -= d.dot(ring.axis) * ring.axis;
    if (!(d.norm() > options_.min_offset * ring.radius))
        return false;
    d.normalize();
    return true;
}

double WindingMeter::step(VertexHandle last, VertexHandle w, bool gap, double bridge) const
{
    Eigen::Vector3d to;
    const RingFit* b = nullptr;
    if (!offset(w, to, b))
        return std::numeric_limits<double>::quiet_NaN();
    if (!last.is_valid())
        return 0.0;
    const Eigen::Vector3d axis_b = b->axis;  // fits_ may grow (and move) at the next fit
    Eigen::Vector3d from;
    const RingFit* a = nullptr;
    if (!offset(last, from, a))
        return 0.0;
    // Over a gap the frame is carried only a short way: across a junction or a sac it restarts.
    if (gap && !((mesh_.point(w) - mesh_.point(last)).norm() <= bridge * a->radius))
        return 0.0;
    Eigen::Vector3d carried = transport(from, a->axis, axis_b);
    carried -= carried.dot(axis_b) * axis_b;
    carried.normalize();
    return std::atan2(carried.cross(to).dot(axis_b), carried.dot(to));
}

Eigen::Vector3d WindingMeter::angular_rate(VertexHandle v) const
{
    int& slot = rate_of_[static_cast<std::size_t>(v.idx())];
    if (slot < 0)
    {
        Ring scratch;
        const int before = static_cast<int>(fits_.size());
        ring_fit(v, scratch);
        slot = fit_of_[static_cast<std::size_t>(v.idx())];
        // A ring made just now also serves, for the rate, the vertices of its inner half: a
        // steered search reads the rate of nearly every vertex it settles.
        if (slot >= before)
            for (auto w : scratch.vertices)
                if (rate_of_[static_cast<std::size_t>(w.idx())] < 0 &&
                    std::abs(u_[w.idx()] - u_[v.idx()]) <= 0.5 * half_width_)
                    rate_of_[static_cast<std::size_t>(w.idx())] = slot;
    }
    const RingFit& ring = fits_[static_cast<std::size_t>(slot)];
    if (!ring.ok)
        return Eigen::Vector3d::Zero();
    Eigen::Vector3d d = to_eigen(mesh_.point(v)) - ring.centre;
    d -= d.dot(ring.axis) * ring.axis;
    const double offset = d.norm();
    if (!(offset > options_.min_offset * ring.radius))
        return Eigen::Vector3d::Zero();
    return ring.axis.cross(d) / (offset * offset);
}

WindingMeter::Band WindingMeter::band(VertexHandle v) const
{
    Ring scratch;
    const RingFit& fit = ring_fit(v, scratch);
    return Band{fit.ok, fit.radius, fit.coherence};
}

SeamWinding seam_winding(const std::vector<PathWinding>& paths)
{
    SeamWinding all;
    double length = 0.0;
    for (const auto& one : paths)
    {
        all.mean_abs_deg += std::abs(one.winding_deg) * one.length;
        all.max_abs_deg = std::max(all.max_abs_deg, std::abs(one.winding_deg));
        length += one.length;
    }
    if (length > 0.0)
        all.mean_abs_deg /= length;
    return all;
}

}  // namespace vessel
