#include "vessel/cut/cut_route.h"

#include "detail/streamline_tracer.h"

namespace vessel {

namespace {

class StreamlineRouter : public CutRouter
{
public:
    explicit StreamlineRouter(const CutPlanContext& context) : tracer_(context) {}

    // The traced path from the cheapest path's start; the cheapest path where the trace does
    // not arrive.
    RoutedCut route(CutStep& step) override
    {
        const GraphPath& cheapest = step.cheapest();
        const Mesh& mesh = step.context().mesh();
        std::optional<GraphPath> along =
            tracer_.trace(step, mesh.from_vertex_handle(cheapest.halfedges.front()));
        if (along)
            return {std::move(*along), true};
        return {cheapest, false};
    }

    void added(const CutStep& step, const CutPath& cut) override { tracer_.added(step, cut); }

private:
    detail::StreamlineTracer tracer_;
};

}  // namespace

std::unique_ptr<CutRouter> StreamlineRoute::start(const CutPlanContext& context) const
{
    return std::make_unique<StreamlineRouter>(context);
}

}  // namespace vessel
