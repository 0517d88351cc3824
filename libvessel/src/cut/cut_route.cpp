#include "vessel/cut/cut_route.h"

namespace vessel {

std::shared_ptr<const CutRoutePolicy> route_policy(CutRoute route)
{
    switch (route)
    {
        case CutRoute::ShortestPath:
            return std::make_shared<ShortestPathRoute>();
        case CutRoute::Streamline:
            return std::make_shared<StreamlineRoute>();
        case CutRoute::Aligned:
            break;
    }
    return std::make_shared<AlignedRoute>();
}

}  // namespace vessel
