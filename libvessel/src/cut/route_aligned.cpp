#include "vessel/cut/cut_route.h"

#include "detail/cost_to_tree.h"
#include "detail/streamline_tracer.h"
#include "vessel/core/errors.h"
#include "vessel/cut/cut_cost.h"
#include "vessel/cut/cut_metrics.h"
#include "vessel/cut/cut_winding.h"
#include "vessel/cut/winding_bound.h"

#include <cmath>
#include <functional>
#include <optional>
#include <string>

namespace vessel {

namespace {

CutPath as_cut(const Mesh& mesh, const GraphPath& p)
{
    CutPath c;
    c.halfedges = p.halfedges;
    c.start = mesh.from_vertex_handle(p.halfedges.front());
    return c;
}

// CutRoute::Aligned: whether the traced path replaces the cheapest one. With a winding meter,
// when it winds clearly less and is not much worse aligned; otherwise (or without a meter)
// when it follows the stream field clearly better. \p winding_meter returns the meter (built
// at its first call) or null.
bool keep_traced(const Mesh& mesh, const GraphPath& cheapest, const GraphPath& traced,
                 const Eigen::MatrixX3d& stream_field,
                 const std::function<const WindingMeter*()>& winding_meter,
                 const CutPlanOptions& options)
{
    const CutPath a = as_cut(mesh, cheapest), b = as_cut(mesh, traced);
    const double aligned_a = path_alignment(mesh, a, stream_field).mean;
    const double aligned_b = path_alignment(mesh, b, stream_field).mean;
    // Either test alone can keep it; the windings (the costly part) are measured only when
    // the alignments leave the answer open.
    if (aligned_b > aligned_a + options.aligned_min_gain)
        return true;
    if (!(aligned_b >= aligned_a - options.winding_max_alignment_loss))
        return false;
    const WindingMeter* meter = winding_meter();
    return meter && std::abs(meter->measure(b).winding_deg) <
                        std::abs(meter->measure(a).winding_deg) - options.winding_min_gain_deg;
}

// A natural cut with options.natural_cuts: within winding_limit_deg end to end and in span.
bool within_limit(const PathWinding& w, const CutPlanOptions& options)
{
    return std::abs(w.winding_deg) <= options.winding_limit_deg &&
           w.span_deg <= options.winding_limit_deg;
}

// A natural cut as the route weighs it: within_limit() with options.natural_cuts, else only
// its winding end to end within winding_limit_deg.
bool is_natural(const PathWinding& w, const CutPlanOptions& options)
{
    return options.natural_cuts ? within_limit(w, options)
                                : std::abs(w.winding_deg) <= options.winding_limit_deg;
}

// CutRoute::Aligned: whether \p other, traced along the vessel direction z, replaces \p current,
// a natural cut (traced or not) whose angle spans more than twice winding_target_deg. On a long
// coarse tube the descent of the discrete harmonic coordinate carries a small lateral error that
// varies round the tube, which its streamline integrates into a drift of a column or more; z,
// fitted per vertex, has none there (docs/design.md, "Per-cut route choice"). \p other is
// kept if it is natural, winds no more than \p current or the target, spans less by
// winding_min_gain_deg and is at most winding_max_alignment_loss less aligned with the stream
// field.
bool keep_direction_trace(const Mesh& mesh, const PathWinding& current_winding,
                          const GraphPath& current, const GraphPath& other,
                          const Eigen::MatrixX3d& stream_field, const WindingMeter& meter,
                          const CutPlanOptions& options)
{
    const PathWinding w = meter.measure(as_cut(mesh, other));
    if (!within_limit(w, options) ||
        !(w.span_deg < current_winding.span_deg - options.winding_min_gain_deg) ||
        !(std::abs(w.winding_deg) <=
          std::max(std::abs(current_winding.winding_deg), options.winding_target_deg)))
        return false;
    return path_alignment(mesh, as_cut(mesh, other), stream_field).mean >=
           path_alignment(mesh, as_cut(mesh, current), stream_field).mean -
               options.winding_max_alignment_loss;
}

// A sac's wall, as the meter's bands read it (crosses_sac()): the band's unit gradients of u
// point apart (WindingMeter::Band::coherence below this; a tube's bands read 0.95-1) ...
constexpr double kSacCoherence = 0.6;
// ... and the band is much wider than the outlet the cut comes from (its radius over the
// outlet's, perimeter / 2 pi): the cut has left its vessel for a bulge.
constexpr double kSacWidth = 2.0;
// The streamline gives way to the shortest passage only if it is longer by more than this
// factor: a hysteresis, so that near-equal routes are not traded on rounding.
constexpr double kPassageMinGain = 1.2;

// Whether \p path crosses a sac's wall (kSacCoherence, kSacWidth) for a cut from an outlet of
// radius \p outlet_radius.
bool crosses_sac(const Mesh& mesh, const GraphPath& path, const WindingMeter& meter,
                 double outlet_radius)
{
    const auto sac = [&](VertexHandle v) {
        const WindingMeter::Band band = meter.band(v);
        return band.coherence < kSacCoherence && band.radius > kSacWidth * outlet_radius;
    };
    for (auto h : path.halfedges)
        if (sac(mesh.to_vertex_handle(h)))
            return true;
    return false;
}

// CutRoute::Aligned: whether \p passage, the shortest path of the cut's query (by length),
// replaces \p traced, a streamline cut that crosses a sac (crosses_sac()). On a sac the vessel
// has no direction and its bands no axis: the harmonic streamline follows u's meanders over
// the bulge, and keep_traced() took it for an alignment that means nothing there
// (docs/results.md, "Sacs: the lateral-aneurysm phantom"). The shortest passage is
// taken if it is natural (the meter, as any cut), at least as aligned with the stream field,
// and \p traced is longer by more than kPassageMinGain: then it is no worse by any measure the
// route weighs.
bool keep_passage(const Mesh& mesh, const GraphPath& traced, const GraphPath& passage,
                  const Eigen::MatrixX3d& stream_field, const WindingMeter& meter,
                  const CutPlanOptions& options)
{
    const PathAlignment a = path_alignment(mesh, as_cut(mesh, traced), stream_field);
    const PathAlignment b = path_alignment(mesh, as_cut(mesh, passage), stream_field);
    if (!(a.length > kPassageMinGain * b.length) || !(b.mean >= a.mean))
        return false;
    return is_natural(meter.measure(as_cut(mesh, passage)), options);
}

// The bounded search of steer_path() carries a cut's frame over unmeasured vertices up to one
// ring radius (WindingMeter::step()). With the meter's own restart at every such vertex the
// search can turn where a band fails the spread test by noise alone, unseen by this meter and
// seen by another whose bands differ by rounding (seamwinding.py; docs/design.md, "Natural
// cuts"). A radius spans such noisy bands (one to four vertices) and stops short of junctions
// and sacs.
constexpr double kSearchBridge = 1.0;

// CutRoute::Aligned: a cut that winds more than options.winding_target_deg around its vessel
// end to end, or that is no natural cut (it winds more than options.winding_limit_deg, or with
// options.natural_cuts its angle spans more than that: WindingMeter), is searched again.
//
// 1. Its signed winding priced into the arcs (PathQuery::steer_rate =
//    WindingMeter::angular_rate(), a Lagrangian relaxation of "winds at most the target"): the
//    multiplier opposes the way \p current winds; it doubles from 1/16 of the path's cost per
//    half turn (up to 16) until the steered cut winds less than the target or the other way,
//    then three bisections between the last two. A multiplier reaches only the routes on the
//    convex hull of (winding, cost). A steered path replaces \p current if it winds less by
//    more than options.winding_min_gain_deg and its alignment with the stream field is at most
//    options.winding_max_alignment_loss lower; with options.natural_cuts, a natural route as
//    aligned that winds within the target replaces a natural cut above it whatever the gain
//    (the gain is a hysteresis against trading an aligned cut for one that winds a little
//    less; reaching the target is not a little).
// 2. With options.natural_cuts, while the best route so far is not natural or the winding a
//    replacement must beat (\p current's less winding_min_gain_deg at first, then set by
//    each route taken) lies above the target: winding_bounded_path() with the meter's steps
//    (WindingMeter::step(), carried over gaps of kSearchBridge ring radii) and the target as its
//    bound (then, while that gives no natural cut, half the limit; then the two again with the
//    meter's own steps; a cut that is natural already is offered the target's two only): the
//    cheapest route whose angle stays within +-bound at every vertex (span <= 2 x bound), inside
//    the hull too (on the vmtk aorta every route on the hull winds about +-80 degrees). There a
//    candidate must also keep a natural cut natural, and a cut that is not natural takes a natural
//    candidate whatever its alignment, and of two natural candidates the one that winds less (the
//    bound is what natural means; the alignment's floor was fitted on cuts that wind less, and
//    across a sac, where the stream field has no direction, no short passage is aligned).
// \p traced: \p current was taken along a streamline (it cannot drift from an aligned curve by
// more than its band); without options.natural_cuts it is searched again only if it is no
// natural cut, with them as any other cut (a streamline on a coarse tube may still turn a
// third of the way round it, and the bound finds a route that does not).
// \p finish / \p finish_held: the join policy's finish of a path found to the tree
// (CutStep::join(), e.g. the cut back of CutJoin::Approach) and of a bounded route, which keeps
// to its side of the vessel (CutStep::join_held(), given the bound its finish must keep).
// \p current_winding: the meter's reading of \p current where the caller has it (null: measured
// here). Empty = keep \p current.
template <class Finish, class FinishHeld>
std::optional<GraphPath> steer_path(CutGraph& graph, const PathQuery& step_query,
                                    const Eigen::MatrixX3d& winding_rate, const WindingMeter& meter,
                                    const GraphPath& current, const PathWinding* current_winding,
                                    bool traced, const Eigen::MatrixX3d& stream_field,
                                    const CutPlanOptions& options, detail::CostToTree& tree_cost,
                                    Finish finish, FinishHeld finish_held)
{
    const Mesh& mesh = graph.mesh();
    if (winding_rate.rows() == 0 || options.winding_target_deg <= 0.0)
        return std::nullopt;
    const bool strict = options.natural_cuts;
    const PathWinding now =
        current_winding ? *current_winding : meter.measure(as_cut(mesh, current));
    const double wound = std::abs(now.winding_deg);
    const bool was_natural = is_natural(now, options);
    if (was_natural && ((traced && !strict) || !(wound > options.winding_target_deg)))
        return std::nullopt;
    PathQuery query = step_query;  // steered below
    const double floor_alignment = path_alignment(mesh, as_cut(mesh, current), stream_field).mean -
                                   options.winding_max_alignment_loss;
    std::optional<GraphPath> best;
    bool best_natural = was_natural;
    double best_wound = wound - options.winding_min_gain_deg;
    double best_actual = wound;  // |winding| of the best so far (\p current at first)
    // Whether \p p replaces the best so far (and becomes it).
    const auto offer = [&](GraphPath& p) {
        const CutPath cut = as_cut(mesh, p);
        const PathWinding w = meter.measure(cut);
        const double wound_p = std::abs(w.winding_deg);
        const bool natural = is_natural(w, options);
        const bool aligned = path_alignment(mesh, cut, stream_field).mean >= floor_alignment;
        // A natural cut above the target gives way to an aligned natural route within it
        // whatever the gain.
        const bool on_target = strict && natural && aligned &&
                               wound_p <= options.winding_target_deg &&
                               best_actual > options.winding_target_deg && wound_p < best_actual;
        const bool better =
            on_target || (strict ? (!best_natural && natural) ||
                                       (wound_p < best_wound && (natural || !best_natural) &&
                                        (aligned || (natural && !was_natural)))
                                 : wound_p < best_wound && aligned);
        if (better)
        {
            // A route taken for the target alone keeps the gain's threshold for the next ones.
            best_wound = on_target ? std::min(wound_p, best_wound) : wound_p;
            best_actual = wound_p;
            best_natural = natural;
            best = std::move(p);
        }
        return w.winding_deg;
    };
    if (wound > options.winding_target_deg)
    {
        query.steer_rate = [&meter](int v) { return meter.angular_rate(VertexHandle(v)); };
        const double sign = now.winding_deg > 0.0 ? 1.0 : -1.0;
        const double unit = current.cost / M_PI;  // t = 1: a half turn costs the path's cost
        // The signed winding of the steered path at multiplier t (0 = on target).
        const auto steer = [&](double t) {
            query.steer_weight = sign * t * unit;
            GraphPath p = finish(graph.shortest_path(query, winding_rate));
            const double w = offer(p);
            return std::abs(w) <= options.winding_target_deg ? 0.0 : sign * w;
        };
        double low = 0.0, high = 0.0;
        for (double t = 1.0 / 16; t <= 16.0; t *= 2.0)
        {
            const double left = steer(t);
            if (left <= 0.0)
            {
                high = t;
                break;
            }
            low = t;
        }
        if (high > 0.0 && low == 0.0)
            low = high / 2.0;
        if (high > 0.0 && best_wound > options.winding_target_deg)
            for (int i = 0; i < 3 && best_wound > options.winding_target_deg; ++i)
            {
                const double t = std::sqrt(low * high);
                (steer(t) > 0.0 ? low : high) = t;
            }
        query.steer_rate = nullptr;
        query.steer_weight = 0.0;
    }
    // The target as the bound first; if no route keeps it (or none is taken), half the natural
    // limit, which still bounds the span by the limit. Then the two with the meter's own steps
    // (no bridge): the bound then holds exactly as the meter reads it, where a bridged route
    // may turn across a gap by more than the meter's restart lets it see.
    const std::pair<double, double> tries[] = {{options.winding_target_deg, kSearchBridge},
                                               {0.5 * options.winding_limit_deg, kSearchBridge},
                                               {options.winding_target_deg, 0.0},
                                               {0.5 * options.winding_limit_deg, 0.0}};
    for (const auto& [limit, bridge] : tries)
    {
        if (!(strict && (best_wound > options.winding_target_deg || !best_natural)) ||
            !(limit > 0.0 && limit < 180.0))
            break;
        // A natural cut gives way only to a route within the target or one that winds less by
        // winding_min_gain_deg: it is offered the target's bounds, bridged and then with the
        // meter's own steps (the bridged route may read above the target by the meter); half
        // the limit is for a cut that is not natural yet.
        if (best_natural && limit != options.winding_target_deg)
            continue;
        WindingBoundOptions bound;
        bound.limit_deg = limit;
        const double carry = bridge;
        WindingMeter::Prefetch ahead(meter);
        std::optional<GraphPath> bounded = winding_bounded_path(
            graph, query,
            [&meter, carry](VertexHandle last, VertexHandle w, bool gap) {
                return meter.step(last, w, gap, carry);
            },
            bound, [&ahead](VertexHandle v) { ahead.hint(v); }, &tree_cost.to(query.is_target));
        if (bounded)
        {
            // A later cut that would run beside the tree is cut back and bridged to it
            // (CutJoin::Approach); the bridge may turn, so the cut back is one that keeps the
            // route within the bound (else the route runs on beside the tree).
            GraphPath p = finish_held(*bounded, [&](const GraphPath& q) {
                return std::abs(meter.measure(as_cut(mesh, q)).winding_deg) <= bound.limit_deg;
            });
            offer(p);
        }
        if (best_natural && !was_natural)
            break;
    }
    return best;
}

// CutRoute::Aligned for one plan: the cheapest path, the traced one if keep_traced() prefers
// it (or, where that crosses a sac, the shortest passage if keep_passage() prefers it), then
// steer_path() unless the join policy narrows the ends.
class AlignedRouter : public CutRouter
{
public:
    explicit AlignedRouter(const CutPlanContext& context) : tracer_(context)
    {
        const std::size_t nv = context.mesh().n_vertices();
        const Eigen::VectorXd& longitudinal = *context.longitudinal;
        if (longitudinal.size() != 0 && static_cast<std::size_t>(longitudinal.size()) != nv)
            throw InvalidInputError(
                "plan_cuts: " + std::to_string(longitudinal.size()) + " longitudinal values for " +
                std::to_string(nv) +
                " vertices; pass harmonic_longitudinal() of the same mesh, or none");
    }

    RoutedCut route(CutStep& step) override
    {
        const CutPlanContext& context = step.context();
        const Mesh& mesh = context.mesh();
        const CutPlanOptions& options = *context.options;
        const Eigen::MatrixX3d& stream_field = *context.stream_field;
        // Built at the first cut whose alignments leave the choice to the windings.
        const auto winding_meter = [&]() -> const WindingMeter* {
            const Eigen::VectorXd& longitudinal = *context.longitudinal;
            if (longitudinal.size() == 0)
                return nullptr;
            // The harmonic stream field is the descent of `longitudinal`: minus it is the unit
            // gradient the meter would otherwise compute at every vertex its rings reach.
            if (!meter_)
            {
                if (options.stream_field == StreamField::Harmonic)
                    meter_.emplace(*context.graph, longitudinal, tracer_.mean_edge(),
                                   -stream_field);
                else
                    meter_.emplace(*context.graph, longitudinal, tracer_.mean_edge());
            }
            return &*meter_;
        };

        RoutedCut cut{step.cheapest(), false};
        std::optional<GraphPath> along =
            tracer_.trace(step, mesh.from_vertex_handle(cut.path.halfedges.front()));
        if (along && keep_traced(mesh, cut.path, *along, stream_field, winding_meter, options))
        {
            cut.path = std::move(*along);
            cut.traced = true;
        }
        // A streamline that crosses a sac is offered the shortest passage.
        if (cut.traced && !step.join_narrows_ends())
            if (const WindingMeter* meter = winding_meter())
            {
                const double outlet_radius = (*context.loops)[step.outlet()].radius();
                if (crosses_sac(mesh, cut.path, *meter, outlet_radius))
                {
                    const GraphPath passage = shortest_passage(step);
                    if (!passage.halfedges.empty() &&
                        keep_passage(mesh, cut.path, passage, stream_field, *meter, options))
                    {
                        cut.path = passage;
                        cut.traced = false;
                    }
                }
            }
        // A natural cut that spans wide is offered the streamline of z too. Its reading of the
        // cut, while the cut stays, is steer_path()'s too.
        std::optional<PathWinding> now;
        if (traces_direction(context))
            if (const WindingMeter* meter = winding_meter())
            {
                now = meter->measure(as_cut(mesh, cut.path));
                std::optional<GraphPath> other;
                if (within_limit(*now, options) && now->span_deg > 2.0 * options.winding_target_deg)
                    other = tracer_.trace(step, mesh.from_vertex_handle(cut.path.halfedges.front()),
                                          context.direction);
                if (other && keep_direction_trace(mesh, *now, cut.path, *other, stream_field,
                                                  *meter, options))
                {
                    cut.path = std::move(*other);
                    cut.traced = true;
                    now.reset();
                }
            }
        if (!step.join_narrows_ends())
            if (const WindingMeter* reader = winding_meter())
            {
                std::optional<GraphPath> held = steer_path(
                    *context.graph, step.query(), *context.winding_rate, *reader, cut.path,
                    now ? &*now : nullptr, cut.traced, stream_field, options,
                    tree_cost(*context.graph),
                    [&step](GraphPath p) { return step.join(std::move(p)); },
                    [&step](GraphPath p, const PathTest& keeps) {
                        return step.join_held(std::move(p), keeps);
                    });
                if (held)
                {
                    cut.path = std::move(*held);
                    cut.traced = false;
                }
            }
        return cut;
    }

    void added(const CutStep& step, const CutPath& cut) override { tracer_.added(step, cut); }

private:
    // Whether the plan has a vessel direction to trace beside a harmonic stream field.
    static bool traces_direction(const CutPlanContext& context)
    {
        return context.options->stream_field == StreamField::Harmonic && context.direction &&
               context.direction->rows() != 0;
    }

    // The shortest path of the step's query by 3D length (edge lengths: a graph of its own,
    // built at the first sac a cut crosses).
    GraphPath shortest_passage(const CutStep& step)
    {
        const Mesh& mesh = step.context().mesh();
        if (!length_graph_)
        {
            lengths_ = evaluate_cost(mesh, LengthCost{});  // E_g in mm
            length_graph_.emplace(mesh, lengths_);
        }
        PathQuery query = step.query();
        query.winding_rate.resize(0, 3);
        query.tie_tolerance = 0.0;
        return length_graph_->shortest_path(query);
    }

    // The bounded searches' A* bound, one field grown over the plan's cuts.
    detail::CostToTree& tree_cost(const CutGraph& graph)
    {
        if (!tree_cost_)
            tree_cost_.emplace(graph);
        return *tree_cost_;
    }

    detail::StreamlineTracer tracer_;
    std::optional<WindingMeter> meter_;
    std::optional<detail::CostToTree> tree_cost_;
    HalfedgeWeights lengths_;  // shortest_passage()'s arc weights
    std::optional<CutGraph> length_graph_;
};

}  // namespace

std::unique_ptr<CutRouter> AlignedRoute::start(const CutPlanContext& context) const
{
    return std::make_unique<AlignedRouter>(context);
}

}  // namespace vessel
