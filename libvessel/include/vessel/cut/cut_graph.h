#pragma once

#include "vessel/core/mesh.h"

#include <functional>
#include <utility>
#include <vector>

namespace vessel {

//! One shortest-path query on the directed cut graph (vertices = mesh vertices, arcs =
//! halfedges weighted by HalfedgeWeights; those along the boundary weigh infinity).
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
    //! Optional steering (empty = none): the signed angle around the vessel gained per unit
    //! displacement at a vertex index (e.g. WindingMeter::angular_rate()). Each arc v -> w then
    //! weighs max(w + steer_weight * steer_rate(v) . (p_w - p_v), 0.1 w): a Lagrange multiplier
    //! on the path's signed winding (Ahuja, Magnanti, Orlin, "Network Flows", 1993, ch. 16), so
    //! that a search can trade cost for staying on its side of the vessel. The reported cost
    //! stays the sum of the unsteered weights.
    std::function<Eigen::Vector3d(int)> steer_rate;
    double steer_weight = 0.0;  //!< the multiplier, cost per radian (either sign)
};

//! A path found in the cut graph.
struct GraphPath
{
    std::vector<HalfedgeHandle> halfedges;  //!< from a source to the target, head to tail
    double cost = 0.0;                      //!< sum of the weights along `halfedges`
    double winding_rad = 0.0;  //!< signed angle gained around the vessel (0 without winding_rate)
};

//! \brief The directed cut graph built once for many queries (plan_cuts() runs one per outlet):
//! each vertex's outgoing arcs stored contiguously (CSR) with their weights, in OpenMesh's
//! outgoing-halfedge order, and scratch arrays kept between queries, so a query costs only the
//! vertices it settles. Keeps references to \p mesh and \p weights, which must outlive the graph
//! and not change. Not thread-safe (one query at a time).
class CutGraph
{
public:
    //! \throw InvalidInputError if \p weights does not have one entry per halfedge.
    CutGraph(const Mesh& mesh, const HalfedgeWeights& weights);

    //! \brief Dijkstra (4-ary heap with decrease-key) from the imaginary source to the cheapest
    //! target; the same path as shortest_path(mesh, weights, query).
    //! \throw InvalidInputError as shortest_path().
    GraphPath shortest_path(const PathQuery& query);

    //! \brief shortest_path(\p query) with \p winding_rate read in place of
    //! `query.winding_rate` (which is ignored): a caller that keeps the |V| x 3 field
    //! elsewhere need not copy it into every query.
    //! \throw InvalidInputError as shortest_path().
    GraphPath shortest_path(const PathQuery& query, const Eigen::MatrixX3d& winding_rate);

    const Mesh& mesh() const { return mesh_; }  //!< the mesh the graph was built on

    //! An arc: one halfedge of the mesh with its weight.
    struct Arc
    {
        int to = -1;        //!< head vertex index
        int halfedge = -1;  //!< halfedge index
        double weight = 0.0;
    };

    //! \brief The arcs leaving vertex index \p v, as [first, last), in the order voh_range()
    //! visits them (clockwise from the vertex's halfedge). An arc along the boundary weighs
    //! infinity (a seam is made of interior edges); weight() gives its HalfedgeWeights value.
    std::pair<const Arc*, const Arc*> arcs(int v) const
    {
        return {arcs_.data() + first_[v], arcs_.data() + first_[v + 1]};
    }

    //! The weight of the arc along halfedge \p h.
    double weight(HalfedgeHandle h) const { return weights_[static_cast<std::size_t>(h.idx())]; }

    //! \brief A given route as a GraphPath: its halfedges and the sum of their weights.
    //! \param halfedges consecutive halfedges, head to tail.
    GraphPath path_of(std::vector<HalfedgeHandle> halfedges) const;

private:
    void relax(int v, double d, int parent);  // d < dist_[v]: lower it, place v in the heap
    int pop_min();                           // remove and return the closest vertex in the heap

    const Mesh& mesh_;
    const HalfedgeWeights& weights_;
    double mean_weight_ = 0.0;
    std::vector<int> first_;        // |V|+1: arcs of vertex v are [first_[v], first_[v+1])
    std::vector<Arc> arcs_;  // together, so a search reads one cache line per arc
    // Scratch, valid for the vertices in touched_ only; reset at the start of each query.
    std::vector<double> dist_;
    std::vector<int> parent_;  // halfedge entering the vertex on the Dijkstra tree
    std::vector<char> state_;  // bit 1: settled, bit 2: source
    std::vector<int> touched_;
    std::vector<int> slot_;  // place in heap_, -1 if not there
    std::vector<std::pair<double, int>> heap_;  // 4-ary min-heap of (distance, vertex)
};

//! \brief Dijkstra from the imaginary source to the cheapest target (a one-off CutGraph).
//! \throw InvalidInputError if sizes disagree, there are no sources, or no target is reachable
//! (the message names the source and target counts).
GraphPath shortest_path(const Mesh& mesh, const HalfedgeWeights& weights, const PathQuery& query);

}  // namespace vessel
