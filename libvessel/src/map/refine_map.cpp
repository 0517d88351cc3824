#include "detail/refine_map.h"

#include "vessel/map/area_polish.h"
#include "vessel/map/centre_pull.h"
#include "vessel/map/embedding.h"
#include "vessel/layout/layout_circle.h"

#include <algorithm>

namespace vessel::detail {

bool refine_map(const Mesh& mesh, Pins pins, const FlattenOptions& options,
                const std::string& crossing, std::optional<std::string> restart,
                FlattenResult& result, const LayoutInput* layout, const LayoutResult* placed,
                const RestartStart* start)
{
    if (!restart && options.refinement != Refinement::None &&
        options.arap.max_iterations > 0)
        result.arap = arap(mesh, result.uv, pins, options.arap);
    if (options.refinement != Refinement::Injective)
        return false;
    if (!restart)
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
    }
    InjectiveOptions slim = options.injective;
    if (options.polish_area && slim.scaffold_tolerance == 0.0)
        slim.scaffold_tolerance = InjectiveOptions::kPolishedScaffoldTolerance;  // the polish goes on
    if (options.polish_area && slim.scaffold_skip_gap == 0.0)
        slim.scaffold_skip_gap = InjectiveOptions::kPolishedSkipGap;
    if (restart)
    {
        // A one-to-one start: the layout circle (layout_circle.h: Tutte's circle walked so that
        // the inlet is at the bottom and each outlet near its layout bearing), or Tutte's
        // constant-speed circle. SLIM never flips a triangle of either, and with a scaffold
        // (from the start, or from the first contact of the boundary with itself) never lets
        // its boundary cross.
        const bool from_circle = layout && placed && options.restart_on_layout_circle;
        std::string note = *restart + (from_circle ? "; restarted from the layout circle"
                                                   : "; restarted from the Tutte embedding");
        result.uv = from_circle ? layout_circle_start(*layout, *placed, options.layout_circle)
                                : tutte_embedding(mesh);
        pins.clear();  // neither start can hold the pins where they were
        // The pulls' hinges are made on the circle, which has the layout's look: a start that
        // comes from elsewhere may have lost some of its margin, which they then ask back.
        if (layout && options.look_pull.weight > 0.0)
            slim.centre_pulls = look_pulls(layout->segments, result.uv, options.look_pull.weight,
                                           options.look_pull.form, options.look_pull.margin_deg,
                                           options.look_pull.hold);
        std::vector<std::string> start_notes;
        if (start && *start)
        {
            Eigen::MatrixX2d given = (*start)(options, start_notes);
            if (given.rows() == result.uv.rows())
            {
                result.uv = std::move(given);
                note += ", solved on a coarser mesh first";
            }
            else
                note += " (the start solved on a coarser mesh was not used)";
        }
        result.notes.push_back(note);
        for (const std::string& line : start_notes)
            result.notes.push_back("coarser start: " + line);
        slim.pull_steps = options.look_pull.solver_steps();
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
            polish.pull_steps = slim.pull_steps;
            result.notes.push_back(area_polish(mesh, result.uv, pins, polish).report);
        }
    }
    return restart.has_value();
}

}  // namespace vessel::detail
