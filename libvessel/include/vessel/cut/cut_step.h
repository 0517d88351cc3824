#pragma once
// What the cut policies (cut_route.h, cut_join.h) see while plan_cuts() makes the cuts of one
// mesh: the plan's fixed inputs (CutPlanContext) and, per cut, its search (CutStep).

#include "vessel/cut/cut_graph.h"
#include "vessel/cut/cut_plan.h"

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <vector>

namespace vessel {

//! The inputs of one plan_cuts() call, fixed while it runs. The pointers are never null and
//! stay valid until plan_cuts() returns.
struct CutPlanContext
{
    CutGraph* graph = nullptr;  //!< the directed cut graph (one search at a time)
    const std::vector<BoundaryLoop>* loops = nullptr;  //!< loops[0] is the inlet
    //! |V|, `v.idx()`: index into `loops` of the loop through v, or -1 for an interior vertex.
    const std::vector<int>* loop_of = nullptr;
    const CutPlanOptions* options = nullptr;
    //! |V| x 3 winding_rate() (angle around the vessel per unit displacement), or empty
    //! (no winding control); pass it to CutGraph::shortest_path().
    const Eigen::MatrixX3d* winding_rate = nullptr;
    //! |V| x 3 field toward the root that streamline routes trace (StreamField); empty unless
    //! the route policy asks for it (CutRoutePolicy::needs_stream_field()).
    const Eigen::MatrixX3d* stream_field = nullptr;
    //! |V| harmonic_longitudinal() values (the winding meter's axis), or empty.
    const Eigen::VectorXd* longitudinal = nullptr;
    //! |V| x 3 vessel direction z toward the root (vessel_direction_guided()), or empty:
    //! CutRoute::Aligned's second trace (CutPlanOptions::route).
    const Eigen::MatrixX3d* direction = nullptr;

    const Mesh& mesh() const { return graph->mesh(); }
};

//! A test that a path finished by the join policy must pass (CutJoiner::finish_held(): the
//! winding bound of the route that found it).
using PathTest = std::function<bool(const GraphPath&)>;

//! \brief The search for one cut, as plan_cuts() poses it to the policies: the cut from loop
//! outlet() to the inlet (the first cut, outlet() == 1) or to a vertex of an earlier cut (every
//! later one). Valid during one CutRouter::route() or CutJoiner call.
class CutStep
{
public:
    virtual ~CutStep() = default;

    virtual const CutPlanContext& context() const = 0;
    //! Index into the loops of the outlet whose cut is made (>= 1; 1 = the largest outlet).
    virtual std::size_t outlet() const = 0;
    bool first() const { return outlet() == 1; }  //!< the cut to the inlet
    //! \brief The query every route must answer: `sources` = where the cut may start on its
    //! outlet (EndpointPolicy); `is_target` = where it may end: the inlet's allowed vertices
    //! for the first cut, every interior vertex of the earlier cuts for a later one;
    //! `is_blocked` = the other loops' vertices (a cut opens each loop at one vertex only).
    //! `tie_tolerance` is CutPlanOptions::tie_tolerance.
    virtual const PathQuery& query() const = 0;
    virtual const CutPlan& plan() const = 0;  //!< the cuts made so far, in order

    //! \brief The cheapest path of query() (with its winding tie break), ending where the join
    //! policy lets a later cut end (CutJoiner::ends()) and finished by it (CutJoiner::finish());
    //! the first cut is the plain cheapest path to the inlet. Computed once per step.
    //! \throw InvalidInputError if no target can be reached.
    virtual const GraphPath& cheapest() = 0;
    //! \brief The join policy's finish of a path a route found itself (a later cut; the
    //! first cut's \p path is returned as is).
    virtual GraphPath join(GraphPath path) = 0;
    //! As join(), for a path held to one side of its vessel: a finish that \p keeps accepts,
    //! or \p path as found (CutJoiner::finish_held()).
    virtual GraphPath join_held(GraphPath path, const PathTest& keeps) = 0;
    //! CutJoinPolicy::narrows_ends() of the plan's join policy.
    virtual bool join_narrows_ends() const = 0;
};

}  // namespace vessel
