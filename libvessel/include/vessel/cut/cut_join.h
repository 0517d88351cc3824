#pragma once
// Where later cuts join the cut tree (step 4 of the method; docs/design.md, "Where later cuts
// join"). A policy like Layout: CutPlanOptions::joiner holds any subclass; the built-in CutJoin
// values are the three below (cut_join.cpp, join_closest.cpp, join_approach.cpp).

#include "vessel/cut/cut_step.h"

#include <memory>
#include <string>
#include <vector>

namespace vessel {

//! \brief The joiner of one plan, asked about every later cut (not the first, which ends on the
//! inlet). Made by CutJoinPolicy::start() for one plan_cuts() call, so it may keep per-plan
//! state (a distance to the tree grown as cuts are added).
class CutJoiner
{
public:
    virtual ~CutJoiner() = default;
    //! The cut-tree vertices (targets of CutStep::query()) the cheapest path may end on;
    //! empty (the default) = all of them.
    virtual std::vector<VertexHandle> ends(const CutStep& step)
    {
        (void)step;
        return {};
    }
    //! \brief A path found to the tree, changed where the policy wants it to join elsewhere;
    //! it must stay a chain from the same start to a target (the default keeps \p path).
    virtual GraphPath finish(const CutStep& step, GraphPath path)
    {
        (void)step;
        return path;
    }
    //! \brief finish() of a path held to one side of its vessel (a winding-bounded route,
    //! CutPlanOptions::natural_cuts): it cannot turn toward the tree where it comes near it on
    //! another side, so it runs on beside it instead. The finish must be one that \p keeps
    //! accepts (the route's caller passes its winding bound: a bridge to the tree may turn
    //! round the vessel); where none is, \p path as found. The default: finish() if \p keeps
    //! accepts it.
    virtual GraphPath finish_held(const CutStep& step, GraphPath path, const PathTest& keeps)
    {
        GraphPath finished = finish(step, path);
        return keeps(finished) ? finished : path;
    }
    //! \p cut (first or later) is now part of the cut tree.
    virtual void added(const CutStep& step, const CutPath& cut)
    {
        (void)step;
        (void)cut;
    }
};

//! \brief A join policy (stateless: one object may serve many plans at once).
class CutJoinPolicy
{
public:
    virtual ~CutJoinPolicy() = default;
    virtual std::string name() const = 0;
    //! \brief Whether the joiners' ends() narrow where later cuts end. A route that searches
    //! again itself (AlignedRoute's steering) then keeps CutStep::cheapest(), whose end the
    //! policy chose; this holds for the whole plan, the first cut included.
    virtual bool narrows_ends() const { return false; }
    virtual std::unique_ptr<CutJoiner> start(const CutPlanContext& context) const = 0;
};

//! CutJoin::Cheapest: wherever the cheapest path reaches the tree (the paper, read literally).
class CheapestJoin : public CutJoinPolicy
{
public:
    std::string name() const override { return "cheapest"; }
    std::unique_ptr<CutJoiner> start(const CutPlanContext& context) const override;
};

//! CutJoin::Closest: on a tree vertex close to the outlet (CutPlanOptions::join_slack).
class ClosestJoin : public CutJoinPolicy
{
public:
    std::string name() const override { return "closest"; }
    bool narrows_ends() const override { return true; }
    std::unique_ptr<CutJoiner> start(const CutPlanContext& context) const override;
};

//! CutJoin::Approach (the default): the path cut back where it starts to run beside the tree
//! and bridged to it (CutPlanOptions::join_reach, join_excess; join_held_excess for a path held
//! to one side of its vessel).
class ApproachJoin : public CutJoinPolicy
{
public:
    std::string name() const override { return "approach"; }
    std::unique_ptr<CutJoiner> start(const CutPlanContext& context) const override;
};

//! The built-in policy of \p join.
std::shared_ptr<const CutJoinPolicy> join_policy(CutJoin join);

}  // namespace vessel
