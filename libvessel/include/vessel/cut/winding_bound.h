#pragma once

#include "vessel/cut/cut_graph.h"

#include <functional>
#include <optional>
#include <vector>

namespace vessel {

//! How winding_bounded_path() resolves the winding.
struct WindingBoundOptions
{
    //! The running signed winding must stay within +-limit_deg at every vertex of the path.
    double limit_deg = 15.0;
    //! Bins of the winding over [-limit, limit]: of the routes that reach a vertex with their
    //! winding in one bin, only the cheapest is continued (an approximation of the exact
    //! resource-constrained search, which would keep every Pareto-optimal route). 24 bins of
    //! 1.25 degrees at the default limit.
    int bins = 24;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! \brief The cheapest path of \p query whose signed winding around the vessel, the sum of
//! \p turn over its steps, stays within +-WindingBoundOptions::limit_deg at every vertex: a
//! resource-constrained shortest path (Handler and Zang, "A dual algorithm for the constrained
//! shortest path problem", Networks 10, 1980), solved as Dijkstra on the product of the
//! vertices and the bins of the winding, guided by A* with the unconstrained cost to the
//! targets (a lower bound, so the first target settled is the cheapest of the labels kept).
//!
//! \p turn(last, w, gap) is the angle a route adds on reaching w, given `last`, the route's
//! last vertex for which \p turn gave an angle (invalid before the first), and `gap`, whether
//! the route passed vertices without one since: NaN if w has none (then `last` stays), else
//! the angle (then w becomes `last`). It must depend on its arguments alone: where `last` is
//! the arc's tail, the search asks once per arc however many bins reach the tail. With
//! WindingMeter::step() the bound
//! is the meter's own reading: the path's measure() winding lies within the limit, and so does
//! every partial sum (span <= 2 x limit).
//! Unlike a Lagrange multiplier on the winding (PathQuery::steer_weight), which reaches only
//! the routes on the convex hull of (winding, cost), it finds routes inside the hull: on a
//! coarse mesh whose only cheap routes wind about +-80 degrees, the cheapest one that winds
//! little. A route that visits a vertex twice (the product graph allows it) has the loop cut
//! out. The query's steering, winding_rate and tie_tolerance are not read.
//! \param turn see above; radians.
//! \param settled if set, called with the vertex of each label the search settles (whose arcs
//! it follows next): e.g. WindingMeter::Prefetch::hint(), so that the turns it asks for next
//! are made ready on another thread.
//! \param cost_to_targets if set, the A* bound per vertex (|V| entries, `v.idx()`) instead of
//! the search's own Dijkstra from the targets: a lower bound of the cost of every route from
//! the vertex to the query's targets, consistent (for every arc v -> w, bound(v) <= the arc's
//! weight + bound(w)) and infinite only where no target is reached; e.g. the unconstrained
//! cost to the same targets with fewer vertices blocked. The path is then the same (but for
//! ties of equal cost): the bound only orders the search. A planner whose targets only grow
//! keeps one such field up to date over its searches instead of a Dijkstra per search.
//! \return the path (cost = sum of the graph's weights, winding_rad = its summed turns), or
//! nothing if no route stays within the bound.
//! \throw InvalidInputError as CutGraph::shortest_path(), or if the options are invalid.
std::optional<GraphPath> winding_bounded_path(
    const CutGraph& graph, const PathQuery& query,
    const std::function<double(VertexHandle, VertexHandle, bool)>& turn,
    const WindingBoundOptions& options = {},
    const std::function<void(VertexHandle)>& settled = {},
    const std::vector<double>* cost_to_targets = nullptr);

}  // namespace vessel
