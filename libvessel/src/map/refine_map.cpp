#include "detail/refine_map.h"

#include "vessel/map/area_polish.h"
#include "vessel/map/centre_pull.h"
#include "vessel/map/embedding.h"
#include "vessel/map/fan_start.h"
#include "vessel/layout/layout_circle.h"

#include <algorithm>

namespace vessel::detail {

bool refine_map(const Mesh& mesh, Pins pins, const FlattenOptions& options,
                const std::string& crossing, std::string restart, FlattenResult& result,
                const LayoutInput* layout, const LayoutResult* placed)
{
    Eigen::MatrixX2d before_arap;  // the initial map, kept for Prevent's fallback
    if (restart.empty() && options.refinement != Refinement::None &&
        options.arap.max_iterations > 0)
    {
        if (options.overlaps == OverlapPolicy::Prevent && options.keep_layout_look)
            before_arap = result.uv;
        result.arap = arap(mesh, result.uv, pins, options.arap);
    }
    if (options.refinement != Refinement::Injective)
        return false;
    if (restart.empty())
    {
        result.untangle = untangle(mesh, result.uv, pins, options.untangle);
        if (result.untangle.flipped_before > 0)
            result.notes.push_back(result.untangle.report);
        if (result.untangle.flipped_after > 0)
            restart = "untangling left " + std::to_string(result.untangle.flipped_after) +
                      " flipped triangles";
        else if (options.overlaps != OverlapPolicy::Keep &&
                 boundary_self_intersection(mesh, result.uv).first >= 0)
            restart = crossing;
        if (!restart.empty() && before_arap.size() > 0)
        {
            // ARAP can relax a one-to-one initial map into itself (carotid phantom: the LSCM
            // map at the layout is one-to-one, ARAP's crosses). Go on from the initial map,
            // untangled, when it is one-to-one: SLIM then keeps the layout's look.
            UntangleSummary fixed = untangle(mesh, before_arap, pins, options.untangle);
            if (fixed.flipped_after == 0 && boundary_self_intersection(mesh, before_arap).first < 0)
            {
                result.notes.push_back(restart + "; went on from the map before ARAP");
                result.uv = std::move(before_arap);
                result.untangle = fixed;
                restart.clear();
            }
        }
    }
    InjectiveOptions slim = options.injective;
    if (options.polish_area && slim.scaffold_tolerance == 0.0)
        slim.scaffold_tolerance = InjectiveOptions::kPolishedScaffoldTolerance;  // the polish goes on
    if (!restart.empty())
    {
        // A one-to-one start: the fan start (fan_start.h) keeps the layout's look (inlet at the
        // bottom, branches fanned out in order); Tutte's map of the disk onto a circle is the
        // fallback (the loops keep their order around it, the arrangement is lost). SLIM never
        // flips a triangle of either, and with a scaffold (from the start, or from the first
        // contact of the boundary with itself) never lets its boundary cross.
        bool from_fan = false;
        if (layout && options.overlaps == OverlapPolicy::Prevent && options.keep_layout_look)
        {
            FanStart start = fan_start(*layout, options.fan_start);
            from_fan = start.untangle.flipped_after == 0 &&
                       boundary_self_intersection(mesh, start.uv).first < 0;
            if (from_fan)
                result.uv = std::move(start.uv);
            else
                result.notes.push_back("fan start: " + start.untangle.report);
        }
        const bool from_circle =
            !from_fan && layout && placed && options.restart_on_layout_circle;
        result.notes.push_back(restart + (from_fan      ? "; restarted from the fan start"
                                          : from_circle ? "; restarted from the layout circle"
                                                        : "; restarted from the Tutte embedding"));
        if (from_circle)
            result.uv = layout_circle_start(*layout, *placed, options.layout_circle);
        else if (!from_fan)
            result.uv = tutte_embedding(mesh);
        pins.clear();  // neither start can hold the pins where they were
        if (layout && options.look_pull > 0.0)
            slim.centre_pulls = look_pulls(layout->segments, result.uv, options.look_pull,
                                           options.look_pull_form, options.look_margin_deg,
                                           options.look_hold);
        slim.max_iterations = std::max(slim.max_iterations, 1);
    }
    if (slim.max_iterations > 0)
    {
        slim.scaffold_on_contact = options.overlaps == OverlapPolicy::Prevent;
        result.injective = injective_refine(mesh, result.uv, pins, slim);
        if (result.injective.scaffold_from >= 0)
            result.notes.push_back(result.injective.report);
        if (options.polish_area)  // SLIM's map has no flipped face
        {
            AreaPolishOptions polish = options.area_polish;
            polish.keep_boundary_simple = options.overlaps != OverlapPolicy::Keep;
            polish.centre_pulls = slim.centre_pulls;
            result.notes.push_back(area_polish(mesh, result.uv, pins, polish).report);
        }
    }
    return !restart.empty();
}

}  // namespace vessel::detail
