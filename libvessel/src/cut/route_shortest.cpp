#include "vessel/cut/cut_route.h"

namespace vessel {

namespace {

class ShortestPathRouter : public CutRouter
{
public:
    RoutedCut route(CutStep& step) override { return {step.cheapest(), false}; }
};

}  // namespace

std::unique_ptr<CutRouter> ShortestPathRoute::start(const CutPlanContext&) const
{
    return std::make_unique<ShortestPathRouter>();
}

}  // namespace vessel
