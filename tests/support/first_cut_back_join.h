#pragma once
// A join policy for tests whose input is a particular cut plan: CutJoin::Approach as it finished
// a route held to its side of the vessel before CutJoiner::finish_held() was given the route's
// bound, i.e. cut back only at the first point near the tree, and the route kept whole where
// that cut back leaves the bound. The tests that need a plan of that rule (a SLIM stall, a
// stalled carry) use it to keep their input; it also shows a researcher's joiner built on a
// built-in one through cut_join.h.

#include "vessel/cut/cut_join.h"

#include <memory>
#include <string>
#include <utility>

namespace vessel::test {

class FirstCutBackJoin : public CutJoinPolicy
{
public:
    std::string name() const override { return "first cut back"; }
    std::unique_ptr<CutJoiner> start(const CutPlanContext& context) const override
    {
        return std::make_unique<Joiner>(join_policy(CutJoin::Approach)->start(context));
    }

private:
    class Joiner : public CutJoiner
    {
    public:
        explicit Joiner(std::unique_ptr<CutJoiner> approach) : approach_(std::move(approach)) {}
        GraphPath finish(const CutStep& step, GraphPath path) override
        {
            return approach_->finish(step, std::move(path));
        }
        GraphPath finish_held(const CutStep& step, GraphPath path, const PathTest& keeps) override
        {
            GraphPath first =
                approach_->finish_held(step, path, [](const GraphPath&) { return true; });
            return keeps(first) ? first : path;
        }
        void added(const CutStep& step, const CutPath& cut) override
        {
            approach_->added(step, cut);
        }

    private:
        std::unique_ptr<CutJoiner> approach_;
    };
};

}  // namespace vessel::test
