#pragma once

#include "vessel/mesh.h"

#include <vector>

namespace vessel {

//! One shortest-path query on the directed cut graph (vertices = mesh vertices, arcs =
//! halfedges weighted by HalfedgeWeights).
struct PathQuery
{
    //! Start vertices. All of them are joined to one zero-cost imaginary source node, so the path
    //! starts wherever along them is cheapest (a single vertex pins the start).
    std::vector<VertexHandle> sources;
    //! |V| flags, `v.idx()`: the path ends at the first target reached (cheapest).
    std::vector<char> is_target;
    //! |V| flags, `v.idx()`: vertices the path must not pass through (empty = none).
    std::vector<char> is_blocked;
    //! |V| x 3 rows `v.idx()` (optional, may be empty): angle around the vessel gained per unit
    //! displacement at each vertex. When given, routes whose cost is within `tie_tolerance` of
    //! the optimum at each step are told apart by their accumulated winding, and the one that
    //! stays on its side of the vessel is taken.
    Eigen::MatrixX3d winding_rate;
    //! Slack per step, as a fraction of the mean arc weight, within which two routes tie.
    double tie_tolerance = 0.0;
};

//! A path found in the cut graph.
struct GraphPath
{
    std::vector<HalfedgeHandle> halfedges;  //!< from a source to the target, head to tail
    double cost = 0.0;                      //!< sum of the weights along `halfedges`
    double winding_rad = 0.0;  //!< signed angle gained around the vessel (0 without winding_rate)
};

//! \brief Dijkstra with a binary heap from the imaginary source to the cheapest target.
//! \throw InvalidInputError if sizes disagree, there are no sources, or no target is reachable
//! (the message names the source and target counts).
GraphPath shortest_path(const Mesh& mesh, const HalfedgeWeights& weights, const PathQuery& query);

}  // namespace vessel
