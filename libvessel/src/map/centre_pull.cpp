#include "vessel/map/centre_pull.h"

#include "detail/centre_pull.h"
#include "vessel/core/errors.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

namespace vessel {
namespace {

Eigen::Vector2d centre(const std::vector<int>& vertices, const Eigen::VectorXd& x)
{
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (int v : vertices)
        c += x.segment<2>(2 * v);
    return c / static_cast<double>(vertices.size());
}

CentrePull make_pull(PullKind kind, const std::vector<int>& vertices, const Eigen::Vector2d& origin,
                     const Eigen::Vector2d& normal, double weight)
{
    CentrePull pull;
    pull.kind = kind;
    pull.vertices = vertices;
    pull.origin = origin;
    pull.normal = normal;
    pull.weight = weight;
    return pull;
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
    return a.x() * b.y() - a.y() * b.x();
}

// A pull's residual at the map x (detail::pull_residual()).
detail::PullResidual residual(const CentrePull& pull, const Eigen::VectorXd& x)
{
    return detail::pull_residual(pull, centre(pull.vertices, x) - pull.origin,
                                 pull.kind == PullKind::Order
                                     ? Eigen::Vector2d(centre(pull.second, x) - pull.origin)
                                     : Eigen::Vector2d::Zero());
}

// Calls f(vertex, w, g) for every vertex of an active pull: w = weight |dr/dc|^2 / |set| (the
// curvature of the diagonal proxy, which majorizes weight (dr . motion)^2 along any common
// motion of the set) and g = weight r dr/dc / |set| (half the energy's gradient by the vertex).
template <class F>
void for_each_active_vertex(const std::vector<CentrePull>& pulls, const Eigen::VectorXd& x, F f)
{
    for (const CentrePull& pull : pulls)
    {
        const detail::PullResidual res = residual(pull, x);
        if (!res.active)
            continue;
        const auto visit = [&](const std::vector<int>& set, const Eigen::Vector2d& d) {
            const double n = static_cast<double>(set.size());
            const double w = pull.weight * d.squaredNorm() / n;
            const Eigen::Vector2d g = pull.weight * res.r * d / n;
            for (int v : set)
                f(v, w, g);
        };
        visit(pull.vertices, res.by_first);
        if (pull.kind == PullKind::Order)
            visit(pull.second, res.by_second);
    }
}

}  // namespace

PullSteps LookPullOptions::solver_steps() const
{
    return form == LookPullForm::Rays ? PullSteps::DiagonalProxy : steps;
}

void LookPullOptions::validate() const
{
    if (!(weight >= 0.0 && std::isfinite(weight)))
        throw InvalidInputError("LookPullOptions: weight must be >= 0 and finite, got " +
                                std::to_string(weight));
    if (!(hold >= 0.0 && std::isfinite(hold)))
        throw InvalidInputError("LookPullOptions: hold must be >= 0 and finite, got " +
                                std::to_string(hold));
    if (!(margin_deg >= 0.0 && margin_deg < 90.0))
        throw InvalidInputError("LookPullOptions: margin_deg must be in [0, 90), got " +
                                std::to_string(margin_deg));
}

void validate_centre_pulls(const std::vector<CentrePull>& pulls, const std::string& who)
{
    for (std::size_t i = 0; i < pulls.size(); ++i)
    {
        const CentrePull& pull = pulls[i];
        const bool order = pull.kind == PullKind::Order;
        if (pull.vertices.empty() || !(pull.weight >= 0.0) || !std::isfinite(pull.weight) ||
            !pull.origin.allFinite() || !std::isfinite(pull.margin) ||
            (!order && !(std::abs(pull.normal.norm() - 1.0) < 1e-9)) ||
            (order && (pull.second.empty() || !(pull.length > 0.0) || !std::isfinite(pull.length))))
            throw InvalidInputError(who + ": centre pull " + std::to_string(i) +
                                    " needs vertices, a finite weight >= 0, a finite origin and "
                                    "margin, and a unit normal (an order pull: a second set "
                                    "and a finite length > 0 instead)");
    }
}

std::vector<CentrePull> look_pulls(const std::vector<BoundarySegment>& segments,
                                   const Eigen::MatrixX2d& uv, double weight, LookPullForm form,
                                   double margin_deg, double hold_weight, HingeMargin margins)
{
    std::map<int, std::vector<int>> loops;  // loop index -> its vertices (0 = inlet)
    std::vector<int> walk_order;            // the outlets' loops, in walk order
    const BoundarySegment* inlet_segment = nullptr;
    for (const BoundarySegment& seg : segments)
    {
        if (seg.loop == 0 && !seg.vertices.empty())
            inlet_segment = &seg;
        if (seg.loop > 0 && !seg.vertices.empty() && !loops.count(seg.loop))
            walk_order.push_back(seg.loop);
        for (VertexHandle v : seg.vertices)
        {
            if (v.idx() < 0 || v.idx() >= uv.rows())
                throw InvalidInputError("look_pulls: segment vertex " + std::to_string(v.idx()) +
                                        " is not a row of the map (" + std::to_string(uv.rows()) +
                                        " rows)");
            loops[seg.loop].push_back(v.idx());
        }
    }
    if (!loops.count(0))
        throw InvalidInputError("look_pulls: no inlet segment (loop 0) among the segments");
    const auto mean = [&](const std::vector<int>& vs) {
        Eigen::Vector2d c = Eigen::Vector2d::Zero();
        for (int v : vs)
            c += uv.row(v).transpose();
        return Eigen::Vector2d(c / static_cast<double>(vs.size()));
    };
    const Eigen::Vector2d inlet = mean(loops[0]);
    // The inlet's two halves (in walk order).
    const std::vector<int>& walk = loops[0];
    const std::size_t half = std::max<std::size_t>(walk.size() / 2, 1);
    const std::vector<int> halves[2] = {
        std::vector<int>(walk.begin(), walk.begin() + half),
        std::vector<int>(walk.begin() + (half < walk.size() ? half : 0), walk.end())};
    // The hinges' frame, map_look()'s: origin at the middle of the inlet's chord, up
    // perpendicular to it (the chord runs from the left end, the inlet's last vertex, to the
    // right end, its first).
    const Eigen::Vector2d right_end = uv.row(inlet_segment->vertices.front().idx()).transpose();
    const Eigen::Vector2d left_end = uv.row(inlet_segment->vertices.back().idx()).transpose();
    const Eigen::Vector2d chord = right_end - left_end;
    std::vector<CentrePull> pulls;
    if (form == LookPullForm::Rays || !(chord.norm() > 0.0))
    {
        // Each half held where it is (u and v): the inlet's centre and its chord's direction
        // stay, so the map cannot turn under the outlets' rays.
        for (const std::vector<int>& part : halves)
        {
            const Eigen::Vector2d at = mean(part);
            pulls.push_back(make_pull(PullKind::Line, part, at, Eigen::Vector2d::UnitX(), weight));
            pulls.push_back(make_pull(PullKind::Line, part, at, Eigen::Vector2d::UnitY(), weight));
        }
        if (form == LookPullForm::Hinges)
            return pulls;  // no frame to keep the hinges in: the inlet hold alone
        for (const auto& [loop, vertices] : loops)
        {
            const Eigen::Vector2d ray = mean(vertices) - inlet;
            if (loop == 0 || ray.norm() == 0.0)
                continue;
            pulls.push_back(make_pull(PullKind::Line, vertices, inlet,
                                      Eigen::Vector2d(-ray.y(), ray.x()).normalized(), weight));
        }
        return pulls;
    }
    // Hinges: the inlet held only up to a rigid motion (the frame's three degrees of freedom,
    // which SLIM's energy does not see): each half's height above the chord's line and the
    // inlet's centre along it. The inlet's width stays free.
    const double hold = std::max(weight, hold_weight);
    const Eigen::Vector2d origin = 0.5 * (right_end + left_end);
    const Eigen::Vector2d right = chord.normalized();
    const Eigen::Vector2d up(-right.y(), right.x());
    for (const std::vector<int>& part : halves)
        pulls.push_back(make_pull(PullKind::Line, part, mean(part), up, hold));
    pulls.push_back(make_pull(PullKind::Line, walk, inlet, right, hold));
    const double least_sine = std::sin(margin_deg * M_PI / 180.0);
    const bool whole = margins == HingeMargin::Whole;
    for (std::size_t i = 0; i < walk_order.size(); ++i)
    {
        const std::vector<int>& here = loops[walk_order[i]];
        const Eigen::Vector2d a = mean(here) - origin;
        CentrePull above = make_pull(PullKind::HalfPlane, here, origin, up, weight);
        above.margin = whole ? least_sine * a.norm()
                             : std::min(least_sine * a.norm(), std::max(up.dot(a), 0.0));
        pulls.push_back(above);
        if (i + 1 == walk_order.size())
            continue;
        const std::vector<int>& next = loops[walk_order[i + 1]];
        const Eigen::Vector2d b = mean(next) - origin;
        const double length = std::sqrt(a.norm() * b.norm());
        if (!(length > 0.0))
            continue;
        CentrePull order = make_pull(PullKind::Order, here, origin, up, weight);
        order.second = next;
        order.length = length;
        order.margin = whole ? least_sine * length
                             : std::min(least_sine * length, std::max(cross(b, a) / length, 0.0));
        pulls.push_back(order);
    }
    return pulls;
}

namespace detail {

void require_centre_pull_vertices(const std::vector<CentrePull>& pulls, int n,
                                  const std::string& who)
{
    for (const CentrePull& pull : pulls)
        for (const std::vector<int>* set : {&pull.vertices, &pull.second})
            for (int v : *set)
                if (v < 0 || v >= n)
                    throw InvalidInputError(who + ": centre pull vertex " + std::to_string(v) +
                                            " is not a vertex of the mesh (" + std::to_string(n) +
                                            ")");
}

double centre_pull_energy(const std::vector<CentrePull>& pulls, const Eigen::VectorXd& x)
{
    double e = 0.0;
    for (const CentrePull& pull : pulls)
    {
        const detail::PullResidual res = residual(pull, x);
        if (res.active)
            e += pull.weight * res.r * res.r;
    }
    return e;
}

PullResidual pull_residual(const CentrePull& pull, const Eigen::Vector2d& first,
                           const Eigen::Vector2d& second)
{
    PullResidual res;
    const Eigen::Vector2d& a = first;
    if (pull.kind == PullKind::Order)
    {
        const Eigen::Vector2d& b = second;
        res.r = cross(b, a) / pull.length - pull.margin;
        res.by_first = Eigen::Vector2d(-b.y(), b.x()) / pull.length;
        res.by_second = Eigen::Vector2d(a.y(), -a.x()) / pull.length;
    }
    else
    {
        res.r = pull.normal.dot(a) - (pull.kind == PullKind::HalfPlane ? pull.margin : 0.0);
        res.by_first = pull.normal;
    }
    res.active = pull.kind == PullKind::Line || res.r < 0.0;
    return res;
}

std::vector<PullRow> active_pull_rows(const std::vector<CentrePull>& pulls,
                                      const Eigen::VectorXd& x, double band)
{
    std::vector<PullRow> rows;
    for (const CentrePull& pull : pulls)
    {
        const detail::PullResidual res = residual(pull, x);
        const bool near =
            pull.kind != PullKind::Line && res.r < band * std::abs(pull.margin);
        if (!(res.active || near) || !(pull.weight > 0.0))
            continue;
        PullRow row;
        row.weight = pull.weight;
        row.r = pull.kind == PullKind::Line ? res.r : std::min(res.r, 0.0);
        const auto add = [&](const std::vector<int>& set, const Eigen::Vector2d& d) {
            const double n = static_cast<double>(set.size());
            for (int v : set)
                for (int k = 0; k < 2; ++k)
                    row.entries.emplace_back(2 * v + k, d[k] / n);
        };
        add(pull.vertices, res.by_first);
        if (pull.kind == PullKind::Order)
            add(pull.second, res.by_second);
        rows.push_back(std::move(row));
    }
    return rows;
}

PullColumns pull_columns(const std::vector<PullRow>& rows, Eigen::Index size, double scale,
                         const std::vector<int>* slot)
{
    const auto k = static_cast<Eigen::Index>(rows.size());
    PullColumns columns{Eigen::SparseMatrix<double>(size, k), Eigen::VectorXd(k)};
    std::vector<Eigen::Triplet<double>> entries;
    for (Eigen::Index j = 0; j < k; ++j)
    {
        const PullRow& row = rows[static_cast<std::size_t>(j)];
        for (const auto& [i, value] : row.entries)
        {
            if (!slot)
                entries.emplace_back(i, static_cast<int>(j), value);
            else if (const int s = (*slot)[static_cast<std::size_t>(i / 2)]; s >= 0)
                entries.emplace_back(2 * s + i % 2, static_cast<int>(j), value);
        }
        columns.c[j] = scale * row.weight;
    }
    columns.U.setFromTriplets(entries.begin(), entries.end());  // repeated entries summed
    return columns;
}

void add_centre_pulls(const std::vector<CentrePull>& pulls, const Eigen::VectorXd& x,
                      const std::vector<int>& diagonal, double* values, Eigen::VectorXd& rhs)
{
    // E = W r^2: dE/dx_v = 2 g (for_each_active_vertex). The proxy sum_v w |y_v - (x_v - g / w)|^2
    // has that gradient at y = x and curvature w per coordinate. For a Line pull (|dr/dc| = 1):
    // w = W / |S|, each vertex drawn to its place moved by r n.
    for_each_active_vertex(pulls, x, [&](int v, double w, const Eigen::Vector2d& g) {
        if (!(w > 0.0))
            return;
        for (int k = 0; k < 2; ++k)
        {
            const int i = 2 * v + k;
            values[diagonal[i]] += w;
            rhs[i] += w * x[i] - g[k];
        }
    });
}

void add_centre_pull_gradient(const std::vector<CentrePull>& pulls, const Eigen::VectorXd& x,
                              const std::vector<int>& slot, double* gradient)
{
    for_each_active_vertex(pulls, x, [&](int v, double, const Eigen::Vector2d& g) {
        if (slot[v] >= 0)
            for (int k = 0; k < 2; ++k)
                gradient[2 * slot[v] + k] += 2.0 * g[k];
    });
}

void add_centre_pull_curvature(const std::vector<CentrePull>& pulls, const Eigen::VectorXd& x,
                               const std::vector<int>& slot, const std::vector<int>& diagonal,
                               double* values)
{
    // The proxy's curvature, 2 w per coordinate (the energy's own Hessian is dense over the
    // sets; this one majorizes its Gauss-Newton part along any common motion of a set).
    for_each_active_vertex(pulls, x, [&](int v, double w, const Eigen::Vector2d&) {
        if (slot[v] >= 0)
            for (int k = 0; k < 2; ++k)
                values[diagonal[2 * slot[v] + k]] += 2.0 * w;
    });
}

}  // namespace detail
}  // namespace vessel
