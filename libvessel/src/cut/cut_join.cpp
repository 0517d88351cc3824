#include "vessel/cut/cut_join.h"

namespace vessel {

std::unique_ptr<CutJoiner> CheapestJoin::start(const CutPlanContext&) const
{
    return std::make_unique<CutJoiner>();  // the base: every tree vertex, the path as found
}

std::shared_ptr<const CutJoinPolicy> join_policy(CutJoin join)
{
    switch (join)
    {
        case CutJoin::Cheapest:
            return std::make_shared<CheapestJoin>();
        case CutJoin::Closest:
            return std::make_shared<ClosestJoin>();
        case CutJoin::Approach:
            break;
    }
    return std::make_shared<ApproachJoin>();
}

}  // namespace vessel
