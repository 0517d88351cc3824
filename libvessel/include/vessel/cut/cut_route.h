#pragma once
// Cut routing (step 4 of the method): how each cut runs from its outlet to its end. A policy
// like Layout: CutPlanOptions::router holds any subclass; the built-in CutRoute values are the
// three below (route_shortest.cpp, route_streamline.cpp, route_aligned.cpp).

#include "vessel/cut/cut_step.h"

#include <memory>
#include <string>

namespace vessel {

//! One cut's route as a router found it.
struct RoutedCut
{
    //! Consecutive halfedges from one of CutStep::query()'s sources to one of its targets,
    //! through no blocked vertex and no other target (plan_cuts() checks the ends and refuses a
    //! broken chain, naming the policy).
    GraphPath path;
    bool traced = false;  //!< CutPath::traced: taken along a streamline
};

//! \brief The router of one plan: asked for every cut in turn (largest outlet first), told of
//! each cut once it is in the plan. Made by CutRoutePolicy::start() for one plan_cuts() call,
//! so it may keep per-plan state (a field grown as cuts are added, scratch arrays).
class CutRouter
{
public:
    virtual ~CutRouter() = default;
    //! \throw InvalidInputError if the outlet cannot reach a target.
    virtual RoutedCut route(CutStep& step) = 0;
    //! \p cut (the route's path, as made into the plan) is now part of the cut tree.
    virtual void added(const CutStep& step, const CutPath& cut)
    {
        (void)step;
        (void)cut;
    }
};

//! \brief A cut-route policy (stateless: one object may serve many plans at once).
class CutRoutePolicy
{
public:
    virtual ~CutRoutePolicy() = default;
    virtual std::string name() const = 0;
    //! Whether the routes read CutPlanContext::stream_field (flatten() computes it only then).
    virtual bool needs_stream_field() const { return false; }
    virtual std::unique_ptr<CutRouter> start(const CutPlanContext& context) const = 0;
};

//! CutRoute::ShortestPath: the paper's rule, CutStep::cheapest().
class ShortestPathRoute : public CutRoutePolicy
{
public:
    std::string name() const override { return "shortest"; }
    std::unique_ptr<CutRouter> start(const CutPlanContext& context) const override;
};

//! CutRoute::Streamline: the cheapest path inside a band around a streamline of the stream
//! field from the cheapest path's start (CutPlanOptions::band_rings, join_rings); the cheapest
//! path where the streamline does not arrive.
class StreamlineRoute : public CutRoutePolicy
{
public:
    std::string name() const override { return "streamline"; }
    bool needs_stream_field() const override { return true; }
    std::unique_ptr<CutRouter> start(const CutPlanContext& context) const override;
};

//! CutRoute::Aligned (the default): per cut, the cheapest and the traced path, keeping the one
//! that winds less or is better aligned, then a steered search for a cut that still winds
//! (CutPlanOptions::aligned_min_gain, winding_* and natural_cuts).
class AlignedRoute : public CutRoutePolicy
{
public:
    std::string name() const override { return "aligned"; }
    bool needs_stream_field() const override { return true; }
    std::unique_ptr<CutRouter> start(const CutPlanContext& context) const override;
};

//! The built-in policy of \p route.
std::shared_ptr<const CutRoutePolicy> route_policy(CutRoute route);

}  // namespace vessel
