#include "report.h"

#include "common/blas_kernels.h"
#include "common/huge_pages.h"
#include "common/quality_json.h"

#include "vessel/cut/cut_metrics.h"
#include "vessel/cut/cut_winding.h"
#include "vessel/direction/direction.h"
#include "vessel/quality/metrics.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace vessel::cli {

namespace {

// Each cut (then each relief cut) measured on the uncut surface: its alignment with the
// harmonic longitudinal direction and its winding (cut_metrics.h, cut_winding.h).
struct CutFigures
{
    std::vector<PathAlignment> aligned;
    std::vector<PathWinding> winding;
    std::vector<OpenStretch> open;  // the vessel cuts' only
};

CutFigures cut_figures(const Mesh& uncut, const FlattenResult& r)
{
    CutFigures figures;
    if (r.plan.paths.empty())  // one open end: a disk flattened without cuts
        return figures;
    const Eigen::VectorXd H = uncut_longitudinal(r, uncut.n_vertices());
    const Eigen::MatrixX3d reference = descent_direction(uncut, H);
    const WindingMeter meter(uncut, H);
    for (const auto* list : {&r.plan.paths, &r.plan.relief})
        for (const auto& path : *list)
        {
            figures.aligned.push_back(path_alignment(uncut, path, reference));
            OpenStretch* open = list == &r.plan.paths ? &figures.open.emplace_back() : nullptr;
            figures.winding.push_back(meter.measure(path, open));
        }
    return figures;
}

}  // namespace

nlohmann::json report_json(const std::string& input, const PreparedInput& in,
                           const FlattenResult& r, double read_s, double write_s)
{
    const TreeSurface& surface = in.surface;
    nlohmann::json j;
    j["input"] = input;
    if (in.repairs)
    {
        const RepairSummary& s = *in.repairs;
        j["repairs"] = {{"degenerate_faces_removed", s.degenerate_faces},
                        {"duplicate_faces_removed", s.duplicate_faces},
                        {"faces_reoriented", s.reoriented_faces},
                        {"vertices_split", s.split_vertices},
                        {"edges_stitched", s.stitched_edges},
                        {"vertices_removed", s.removed_vertices},
                        {"holes_filled", s.filled_holes},
                        {"longest_filled_hole", s.longest_filled_hole},
                        {"hole_faces_added", s.hole_faces},
                        {"hole_vertices_added", s.hole_vertices},
                        {"holes_left_unfilled", s.unfilled_holes}};
    }
    if (surface.removed_caps > 0)
        j["flat_caps_removed"] = surface.removed_caps;
    const auto& t = r.timings;
    j["timings"] = {{"read", read_s}, {"Z", t.Z},   {"GC", t.GC}, {"VC", t.VC},      {"AC", t.AC},
                    {"L", t.L},       {"F", t.F},   {"total", t.total()}, {"write", write_s},
                    {"huge_pages", asks_huge_pages(environ)}};
    j["blas_kernels"] = running_blas_kernels();
    nlohmann::json loops = nlohmann::json::array();
    for (std::size_t l = 0; l < r.loops.size(); ++l)
        loops.push_back({{"role", l == 0 ? "inlet" : "outlet"},
                         {"arc_length", r.loops[l].arc_length},
                         {"vertices", r.loops[l].vertices.size()}});
    j["counts"] = {{"input_vertices", surface.input_vertices},
                   {"vertices", surface.mesh.n_vertices()},
                   {"faces", surface.mesh.n_faces()},
                   {"boundary_loops", loops},
                   {"cut_vertices", r.mesh.n_vertices()},
                   {"seam_edges", r.seam_edges},
                   {"duplicated_vertices", r.duplicated_vertices}};
    const CutFigures figures = cut_figures(surface.mesh, r);
    const std::vector<PathAlignment>& aligned = figures.aligned;
    const std::size_t n_paths = r.plan.paths.size();
    const SeamWinding winding = seam_winding(std::vector<PathWinding>(
        figures.winding.begin(), figures.winding.begin() + static_cast<std::ptrdiff_t>(n_paths)));
    // The vessel cuts' figure, and the whole seam's (relief cuts too, as flatcheck sees it).
    const PathAlignment seam = seam_alignment(
        std::vector<PathAlignment>(aligned.begin(),
                                   aligned.begin() + static_cast<std::ptrdiff_t>(n_paths)));
    const PathAlignment whole = seam_alignment(aligned);
    nlohmann::json cuts = nlohmann::json::array();
    // beside_length within the default join reach (outlet radii), whatever --join-reach was.
    const double beside_reach = CutPlanOptions{}.join_reach;
    std::vector<double> reach;
    for (const CutPath& c : r.plan.paths)
        reach.push_back(beside_reach * r.loops[static_cast<std::size_t>(c.outlet)].arc_length /
                        (2.0 * M_PI));
    const std::vector<double> beside = beside_lengths(surface.mesh, r.plan, reach);
    for (std::size_t i = 0; i < r.plan.paths.size(); ++i)
    {
        const CutPath& c = r.plan.paths[i];
        cuts.push_back(
            {{"outlet", c.outlet},
             {"ends_on", c.parent < 0 ? std::string("inlet") : "cut " + std::to_string(c.parent)},
             {"edges", c.halfedges.size()},
             {"cost", c.cost},
             {"winding_deg", figures.winding[i].winding_deg},
             {"winding_span_deg", figures.winding[i].span_deg},
             {"winding_measured_fraction", static_cast<double>(figures.winding[i].measured) /
                                               std::max(1, figures.winding[i].vertices)},
             {"winding_open_length", figures.open[i].length},
             {"winding_open_turn_deg", figures.open[i].turn_deg},
             {"traced", c.traced},
             {"length", aligned[i].length},
             {"alignment", aligned[i].mean},
             {"beside_length", beside[i]}});
    }
    j["cuts"] = cuts;
    nlohmann::json relief = nlohmann::json::array();
    for (std::size_t i = 0; i < r.plan.relief.size(); ++i)
    {
        const CutPath& c = r.plan.relief[i];
        relief.push_back({{"ends_on", c.parent < 0 ? std::string("loop or relief cut")
                                                   : "cut " + std::to_string(c.parent)},
                          {"edges", c.halfedges.size()},
                          {"alignment", aligned[n_paths + i].mean},
                          {"length", c.cost}});
    }
    j["relief_cuts"] = relief;
    const auto& q = r.quality;
    j["quality"] = quality_json(q);
    j["quality"].update({{"seam_alignment", seam.mean},
                         {"seam_low_alignment_fraction", seam.low_fraction},
                         {"seam_alignment_with_relief", whole.mean},
                         {"seam_mean_abs_winding_deg", winding.mean_abs_deg},
                         {"seam_max_abs_winding_deg", winding.max_abs_deg}});
    if (const std::optional<Eigen::Vector3d>& viewpoint = r.viewpoint)
    {
        j["cuts_viewpoint"] = {viewpoint->x(), viewpoint->y(), viewpoint->z()};
        j["quality"]["seam_far_side_fraction"] = far_side_fraction(surface.mesh, r.plan, *viewpoint);
    }
    const MapLook& look = r.look;  // map_look.h; bearings 0 = up, +90 = right
    auto outlet_looks = nlohmann::json::array();
    for (const OutletLook& o : look.outlet_looks)
        outlet_looks.push_back({{"loop", o.loop},
                                {"layout_bearing_deg", o.layout_bearing_deg},
                                {"map_bearing_deg", o.map_bearing_deg},
                                {"below_inlet", o.below_inlet},
                                {"walk_rank", o.walk_rank}});
    j["quality"]["look"] = {{"area_below_inlet", look.area_below_inlet},
                            {"outlets", look.outlets},
                            {"outlets_below_inlet", look.outlets_below_inlet},
                            {"fan_inversions", look.fan_inversions},
                            {"fan_kendall_tau", look.fan_kendall_tau},
                            {"walk_inversions", look.walk_inversions},
                            {"mean_bearing_error_deg", look.mean_bearing_error_deg},
                            {"max_bearing_error_deg", look.max_bearing_error_deg},
                            {"outlet_looks", outlet_looks}};
    const LookRetrySummary& retry = r.look_retry;  // look_retry.h
    j["look_retry"] = {{"tried", retry.tried},
                       {"kept", retry.kept},
                       {"default_area", retry.default_area},
                       {"pulled_area", retry.pulled_area},
                       {"keep_area", retry.keep_area},
                       {"default_outlets_below_inlet", retry.default_look.outlets_below_inlet},
                       {"default_walk_inversions", retry.default_look.walk_inversions}};
    // Face ids index the f lines of the flat OBJ (cutting never adds or reorders faces); the
    // pipeline's quality measure found them already (flat_quality).
    j["overlaps"] = {{"triangles", q.overlapping_faces},
                     {"area_kind", "sum of pairwise intersection areas"}};
    j["arap"] = {{"iterations", r.arap.iterations},
                 {"initial_energy", r.arap.initial_energy},
                 {"final_energy", r.arap.final_energy},
                 {"converged", r.arap.converged},
                 {"report", r.arap.report}};
    j["untangle"] = {{"flipped_before", r.untangle.flipped_before},
                     {"flipped_after", r.untangle.flipped_after},
                     {"rounds", r.untangle.rounds},
                     {"free_vertices", r.untangle.free_vertices}};
    j["slim"] = {{"iterations", r.injective.iterations},
                 {"initial_energy", r.injective.initial_energy},
                 {"final_energy", r.injective.final_energy},
                 {"converged", r.injective.converged},
                 {"report", r.injective.report}};
    nlohmann::json notes = surface.notes;
    for (const auto& note : r.notes)
        notes.push_back(note);
    if (const std::string warning = distortion_warning(q); !warning.empty())
        notes.push_back("warning: " + warning);
    j["notes"] = notes;
    return j;
}

}  // namespace vessel::cli
