// A researcher's own cut cost, plugged into the pipeline without editing the library.
//
// The cost below prefers edges that follow the vessel direction z (like E_c) and, in addition,
// penalizes walking across high curvature (a cut that avoids sharp folds). Any callable
// double(const Mesh&, SmartHalfedgeHandle, const VesselFields&) returning a value >= 0 works
// (or one without the fields); flatten() passes stage Z's fields, typed (cut_cost.h).
//
//   custom_cost_example [MESH] [OUT.obj]
// Without arguments it flattens the built-in carotid phantom. It also makes the default's cuts
// and prints how many seam edges the two share, to show what the cost changed.
#include "vessel/io/flat_io.h"
#include "vessel/io/io.h"
#include "vessel/phantom/phantom.h"
#include "vessel/pipeline.h"
#include "vessel/check/validation.h"
#include "vessel/io/vtk_io.h"  // inputs may be .vtp/.vtk

#include <algorithm>
#include <cstdio>
#include <exception>
#include <iterator>
#include <vector>

namespace {

struct AvoidFoldsCost
{
    double fold_weight = 0.5;  //!< cost per unit of (k_max * edge length)

    double operator()(const vessel::Mesh& mesh, vessel::SmartHalfedgeHandle h,
                      const vessel::VesselFields& fields) const
    {
        const int i = h.from().idx();
        const Eigen::Vector3d e = vessel::to_eigen(mesh.point(h.to()) - mesh.point(h.from()));
        const double length = e.norm();
        const double along = length > 0 ? e.dot(fields.direction->row(i).transpose()) / length : 0.0;
        return std::max(0.0, 1.0 - along) + fold_weight * (*fields.kmax)[i] * length;
    }
};

}  // namespace

int main(int argc, char** argv)
{
    try
    {
        vessel::RawMesh raw;
        vessel::TreeSurface surface;
        if (argc > 1)
        {
            raw = vessel::read_raw_mesh(argv[1]);
            surface = vessel::make_tree_surface(raw);
        }
        else
        {
            raw = vessel::to_raw_mesh(vessel::carotid_phantom());
            surface = vessel::make_tree_surface(raw);
        }
        vessel::FlattenOptions options;
        options.cost.custom = AvoidFoldsCost{};
        const vessel::FlattenResult result = vessel::flatten(surface.mesh, options);
        for (const auto& cut : result.plan.paths)
            std::printf("cut from outlet %d: %zu edges, cost %.3f\n", cut.outlet,
                        cut.halfedges.size(), cut.cost);
        std::printf("flipped %d, area ratio %.4f, mean |log area| %.4f\n",
                    result.quality.flipped_triangles, result.quality.area_ratio,
                    result.quality.mean_abs_log_area);

        // The default's cuts on the same surface: which seam edges the custom cost moved.
        const vessel::FlattenResult by_default = vessel::flatten(surface.mesh);
        auto seam = [&](const vessel::FlattenResult& r) {
            std::vector<int> edges;
            for (const auto e : r.plan.seam_edges(surface.mesh))
                edges.push_back(e.idx());
            std::sort(edges.begin(), edges.end());
            return edges;
        };
        const std::vector<int> custom_seam = seam(result), default_seam = seam(by_default);
        std::vector<int> shared;
        std::set_intersection(custom_seam.begin(), custom_seam.end(), default_seam.begin(),
                              default_seam.end(), std::back_inserter(shared));
        std::printf("seam edges: custom cost %zu, default %zu, shared %zu; the custom cost moved "
                    "%zu of the default's seam edges\n",
                    custom_seam.size(), default_seam.size(), shared.size(),
                    default_seam.size() - shared.size());
        if (argc > 2)
            vessel::write_flat_obj(argv[2], raw.points, result.mesh, result.uv);
        return 0;
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "custom_cost_example: %s\n", e.what());
        return 1;
    }
}
