// flatten() of a surface with one open end (issue 6: "flatten without cuts, it is a disk
// already"). The tree pipeline pins the cut-open inlet along a line; a closed loop cannot lie on
// a segment, so here the map starts from the Tutte embedding (the loop on a circle, one-to-one;
// or the spectral conformal map with --init spectral), both scaled to the surface's area, and is
// refined as the options ask holding one loop vertex (ARAP, untangling, SLIM: each is invariant
// to rotation, so one pin fixes the map). A free-boundary LSCM start was tried first: on the
// carotid phantom with both outlets capped it compressed the capped branches so much that the
// refined map crossed itself (mean |log area| 15 after the fallback, 0.81 from Tutte).
// With Refinement::Injective, as in the tree pipeline, when untangling leaves flips or (unless
// OverlapPolicy::Keep) the boundary crosses itself, the map restarts from Tutte and SLIM runs
// unpinned.
#include "detail/disk_flatten.h"

#include "detail/refine_map.h"
#include "detail/solve_map.h"
#include "detail/stage_clock.h"
#include "vessel/cut/cut.h"
#include "vessel/map/embedding.h"
#include "vessel/core/errors.h"
#include "vessel/core/properties.h"
#include "vessel/map/spectral.h"


namespace vessel::detail {

namespace {

// The start of the map: Tutte's (the loop on a circle) unless the options ask for the spectral
// conformal map; the tree's layout LSCM has no layout to pin here. Both come scaled to the 3D area.
Eigen::MatrixX2d initial_map(const Mesh& mesh, Initialization initialization)
{
    return initialization == Initialization::SpectralConformal ? spectral_conformal(mesh)
                                                               : tutte_embedding(mesh);
}

}  // namespace

FlattenResult flatten_disk(Mesh mesh, const FlattenOptions& options)
{
    FlattenResult result;
    StageClock clock(options, "Z");
    result.loops = boundary_loops(mesh);
    if (result.loops.size() != 1)
        throw InvalidInputError("flatten_disk: the mesh has " +
                                std::to_string(result.loops.size()) +
                                " boundary loops; expected exactly one (a disk)");
    result.notes.push_back(disk_note);

    // Z: only the geodesic distance from the inlet (viewer and outputs); no cut needs the
    // curvature directions.
    const HeatGeodesics heat(mesh, options.geodesic);
    const Eigen::VectorXd G = heat.distance(result.loops[0].vertices);
    auto geodesic = OpenMesh::VProp<double>(mesh, prop::geodesic);
    for (const auto v : mesh.vertices())
        geodesic[v] = G[v.idx()];
    result.timings.Z = clock.lap("Z", "GC");
    result.timings.GC = clock.lap("GC", "VC");
    result.timings.VC = clock.lap("VC", "AC");

    // AC: no seam; this only adds the identity `prop::origin` the writers expect.
    cut_along_edges(mesh, {});
    result.timings.AC = clock.lap("AC", "L");

    result.timings.L = clock.lap("L", "F");  // no layout: nothing to place

    result.uv = initial_map(mesh, options.initialization);
    const VertexHandle held = result.loops[0].vertices.front();
    const Pins pins = {{held, result.uv.row(held.idx()).transpose()}};
    if (options.refiner)
        refine_by_policy(mesh, nullptr, nullptr, *options.refiner, pins, false, result);
    else
        refine_map(mesh, pins, options, "the map overlaps itself (its boundary crosses)", "",
                   result);
    auto uv = OpenMesh::VProp<OpenMesh::Vec2d>(mesh, prop::uv);
    for (const auto v : mesh.vertices())
        uv[v] = OpenMesh::Vec2d(result.uv(v.idx(), 0), result.uv(v.idx(), 1));
    result.timings.F = clock.lap("F");

    result.quality = flat_quality(mesh, result.uv);
    result.mesh = std::move(mesh);
    return result;
}

}  // namespace vessel::detail
