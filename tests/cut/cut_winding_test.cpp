#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/meshes.h"

#include "vessel/cut/boundary.h"
#include "vessel/cut/cut_cost.h"
#include "vessel/cut/cut_plan.h"
#include "vessel/cut/cut_metrics.h"
#include "vessel/cut/cut_winding.h"
#include "vessel/cut/endpoints.h"
#include "vessel/direction/curvature.h"
#include "vessel/direction/direction.h"
#include "vessel/core/errors.h"
#include "vessel/direction/geodesic.h"
#include "vessel/phantom/phantom.h"
#include "vessel/pipeline.h"
#include "vessel/core/properties.h"
#include "vessel/io/io.h"
#include "vessel/check/validation.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

using namespace vessel;

namespace {

Eigen::VectorXd longitudinal(const Mesh& mesh)
{
    const auto loops = boundary_loops(mesh);
    return harmonic_longitudinal(mesh, loops, heat_geodesic_distance(mesh, loops[0].vertices));
}

// A path up a tube whose ring j holds vertices j * around .. j * around + around - 1, ring by
// ring, through the vertex of the next ring whose frame
// angle (angle_of(point)) is closest to target(fraction of the tube done).
template <class Angle, class Target>
std::vector<VertexHandle> ring_path(int around, const Mesh& mesh, Angle angle_of, Target target)
{
    const int rings = static_cast<int>(mesh.n_vertices()) / around;  // n_rings + 1
    const auto angle_gap = [&](VertexHandle v, double wanted) {
        return std::abs(std::remainder(
            angle_of(to_eigen(mesh.point(v))) - wanted, 2.0 * M_PI));
    };
    VertexHandle at(0);
    for (int i = 1; i < around; ++i)
        if (angle_gap(VertexHandle(i), target(0.0)) < angle_gap(at, target(0.0)))
            at = VertexHandle(i);
    std::vector<VertexHandle> path{at};
    for (int j = 1; j < rings; ++j)
    {
        const double wanted = target(static_cast<double>(j) / (rings - 1));
        VertexHandle best;
        for (auto w : mesh.vv_range(at))
            if (w.idx() / around == j && (!best.is_valid() || angle_gap(w, wanted) <
                                                                  angle_gap(best, wanted)))
                best = w;
        REQUIRE(best.is_valid());
        path.push_back(best);
        at = best;
    }
    return path;
}

template <class Target>
std::vector<VertexHandle> helix_path(const HelicalTubeOptions& options, const Mesh& mesh,
                                     Target target)
{
    const auto angle = [&](const Eigen::Vector3d& p) { return helical_tube_angle(options, p); };
    return ring_path(options.n_around, mesh, angle, target);
}

// Unwrapped change of the frame angle (helical_tube_angle) along \p path, in degrees: the true
// winding in the tube's rotation-minimizing frame.
double true_winding_deg(const HelicalTubeOptions& options, const Mesh& mesh,
                        const std::vector<VertexHandle>& path)
{
    double total = 0.0;
    double previous = helical_tube_angle(options, to_eigen(mesh.point(path.front())));
    for (auto v : path)
    {
        const double a = helical_tube_angle(options, to_eigen(mesh.point(v)));
        total += std::remainder(a - previous, 2.0 * M_PI);
        previous = a;
    }
    return total * 180.0 / M_PI;
}

// |measured - truth| up to the sense of rotation (the meter's axis runs inlet to outlet).
double error_deg(const PathWinding& measured, double truth)
{
    return std::min(std::abs(measured.winding_deg - truth), std::abs(measured.winding_deg + truth));
}

}  // namespace

TEST_CASE("cut_winding: on a helical tube a rotation-minimizing line measures ~0, a turn ~360")
{
    for (int n_around : {24, 32, 48})
    {
        CAPTURE(n_around);
        HelicalTubeOptions options;
        options.n_around = n_around;
        options.turns = 1.0;
        const Mesh mesh = helical_tube(options);
        const WindingMeter meter(mesh, longitudinal(mesh));
        for (double a0 : {0.0, 1.0, 2.5, -2.0})
        {
            CAPTURE(a0);
            // The kept line zig-zags by half a step around (consecutive rings are staggered), so
            // its own end-to-end angle is up to 180 / n_around degrees.
            const auto keep = helix_path(options, mesh, [&](double) { return a0; });
            const PathWinding still = meter.measure(keep);
            const double still_truth = true_winding_deg(options, mesh, keep);
            const auto turn =
                helix_path(options, mesh, [&](double s) { return a0 + 2.0 * M_PI * s; });
            const PathWinding turning = meter.measure(turn);
            const double turn_truth = true_winding_deg(options, mesh, turn);
            MESSAGE("helical tube " << n_around << " around, start angle " << a0
                                    << ": kept line " << still.winding_deg << " deg (true "
                                    << still_truth << ", " << still.measured << "/"
                                    << still.vertices << " measured), one turn "
                                    << turning.winding_deg << " deg (true " << turn_truth << ")");
            // A tube has no junction: every vertex lies on a clean ring. The meter agrees with
            // the true angle within 5 degrees (measured: 3.1 on one helical turn, n = 24-48).
            CHECK(still.measured == still.vertices);
            CHECK(error_deg(still, still_truth) < 5.0);
            CHECK(error_deg(turning, turn_truth) < 5.0);
            if (n_around >= 32)
                CHECK(std::abs(still.winding_deg) < 5.0);
            CHECK(std::abs(std::abs(turning.winding_deg) - 360.0) < 20.0);
            CHECK(turning.span_deg >= std::abs(turning.winding_deg) - 1e-9);
        }
    }
}

TEST_CASE("cut_winding: on a torus piece every line along the tube measures ~0")
{
    // Half a torus: a helical tube of (almost) no pitch, half a turn (major radius 4, minor 1).
    // Its rotation-minimizing frame is the torus' own: the angle around the tube is measured
    // from the equatorial plane.
    HelicalTubeOptions options;
    options.pitch = 1e-6;
    options.turns = 0.5;
    options.n_around = 48;
    const Mesh mesh = helical_tube(options);
    REQUIRE(boundary_loops(mesh).size() == 2);
    const auto angle = [&](const Eigen::Vector3d& p) {
        return std::atan2(p.z(), std::hypot(p.x(), p.y()) - options.helix_radius);
    };
    const auto truth = [&](const std::vector<VertexHandle>& path) {
        double total = 0.0;
        for (std::size_t i = 1; i < path.size(); ++i)
            total += std::remainder(angle(to_eigen(mesh.point(path[i]))) -
                                        angle(to_eigen(mesh.point(path[i - 1]))),
                                    2.0 * M_PI);
        return total * 180.0 / M_PI;
    };
    const WindingMeter meter(mesh, longitudinal(mesh));
    for (double a0 = -M_PI; a0 < M_PI; a0 += M_PI / 4.0)  // inner and outer equator, top, ...
    {
        CAPTURE(a0);
        const auto line = ring_path(options.n_around, mesh, angle, [&](double) { return a0; });
        const PathWinding w = meter.measure(line);
        CHECK(w.measured == w.vertices);
        CHECK(std::abs(w.winding_deg) < 5.0);
        CHECK(error_deg(w, truth(line)) < 2.0);
    }
    // A line that goes once around the tube as it runs along.
    const auto spiral =
        ring_path(options.n_around, mesh, angle, [&](double s) { return 2.0 * M_PI * s; });
    CHECK(std::abs(std::abs(meter.measure(spiral).winding_deg) - 360.0) < 20.0);
}

// The three meters plan_cuts() and the report may build on one helical tube: over OpenMesh's
// circulators, over a CutGraph's arcs, and over the arcs with the axes given (minus the
// harmonic stream field).
struct MeterVariants
{
    HelicalTubeOptions options;
    Mesh mesh = helical_tube(options);
    Eigen::VectorXd u = longitudinal(mesh);
    HalfedgeWeights weights = HalfedgeWeights(mesh.n_halfedges(), 1.0);
    CutGraph graph{mesh, weights};
    double mean_edge = mean_edge_length(mesh);

    // Calls check(a, b) with both meters' figures for a straight, a half-turn and a one-turn
    // path up the tube.
    template <class Check>
    void compare(const WindingMeter& first, const WindingMeter& second, Check check) const
    {
        const auto angle = [&](const Eigen::Vector3d& p) {
            return std::atan2(p.z(), std::hypot(p.x(), p.y()) - options.helix_radius);
        };
        for (double turns : {0.0, 0.5, 1.0})
        {
            CAPTURE(turns);
            const auto path = ring_path(options.n_around, mesh, angle,
                                        [&](double s) { return 2.0 * M_PI * turns * s; });
            const PathWinding a = first.measure(path), b = second.measure(path);
            CHECK(a.measured > 0);
            CHECK(a.measured == b.measured);
            check(a, b);
        }
    }
};

TEST_CASE("cut_winding: the meter over a CutGraph's arcs gives the same figures")
{
    // plan_cuts() builds its meter on the cut graph (rings walked over the arcs, the mean edge
    // passed in); the cuts it picks by winding must be the ones the circulator meter picks.
    const MeterVariants t;
    const WindingMeter by_mesh(t.mesh, t.u);
    const WindingMeter by_graph(t.graph, t.u, t.mean_edge);
    t.compare(by_mesh, by_graph, [](const PathWinding& a, const PathWinding& b) {
        CHECK(a.winding_deg == b.winding_deg);  // bit for bit: the same rings in the same order
        CHECK(a.span_deg == b.span_deg);
    });
    CHECK_THROWS_AS(WindingMeter(t.graph, t.u, -1.0), InvalidInputError);
}

TEST_CASE("cut_winding: the meter given the stream field's axes agrees to rounding")
{
    // plan_cuts() hands its meter minus the harmonic stream field (descent_direction of u)
    // instead of letting it recompute the gradient of u at every vertex its rings reach.
    const MeterVariants t;
    const WindingMeter own(t.graph, t.u, t.mean_edge);
    const WindingMeter given(t.graph, t.u, t.mean_edge, -descent_direction(t.mesh, t.u));
    t.compare(own, given, [](const PathWinding& a, const PathWinding& b) {
        CHECK(std::abs(a.winding_deg - b.winding_deg) < 1e-6);
        CHECK(std::abs(a.span_deg - b.span_deg) < 1e-6);
    });
    CHECK_THROWS_AS(WindingMeter(t.graph, t.u, t.mean_edge, Eigen::MatrixX3d::Zero(3, 3)),
                    InvalidInputError);
}

TEST_CASE("cut_winding: bad input is refused with what to fix")
{
    const Mesh mesh = helical_tube();
    const Eigen::VectorXd u = longitudinal(mesh);
    WindingOptions bad;
    bad.band = 0.0;
    CHECK_THROWS_AS(WindingMeter(mesh, u, bad), InvalidInputError);
    CHECK_THROWS_AS(WindingMeter(mesh, Eigen::VectorXd::Zero(3)), InvalidInputError);
    const WindingMeter meter(mesh, u);
    CHECK_THROWS_AS(meter.measure(std::vector<VertexHandle>{
                        VertexHandle(static_cast<int>(mesh.n_vertices()))}),
                    InvalidInputError);
    // Seam figures: length-weighted mean and max of |winding|.
    PathWinding a, b;
    a.winding_deg = -30.0;
    a.length = 1.0;
    b.winding_deg = 10.0;
    b.length = 3.0;
    const SeamWinding seam = seam_winding({a, b});
    CHECK(seam.mean_abs_deg == doctest::Approx(15.0));
    CHECK(seam.max_abs_deg == doctest::Approx(30.0));
}

TEST_CASE("cut_winding: the default route keeps the SimVascular demo's cuts on one side")
{
    // Measured (docs/results.md): with the paper's cheapest path the two cuts wind 72 and 180
    // degrees (the branch cut turns half around its vessel); choosing per cut by winding, 6 and
    // 36. 60 lies between: the cheapest path's cuts fail it, the default's pass.
    const TreeSurface surface =
        load_tree_surface(std::string(VESSEL_SHARED_DATA) + "/simvascular-tests/demo-model-open.ply");
    const auto windings = [&](const FlattenOptions& options) {
        const FlattenResult r = flatten(surface.mesh, options);
        OpenMesh::VPropHandleT<double> handle;
        REQUIRE(r.mesh.get_property_handle(handle, prop::longitudinal));
        Eigen::VectorXd u(static_cast<Eigen::Index>(surface.mesh.n_vertices()));
        for (auto v : surface.mesh.vertices())
            u[v.idx()] = r.mesh.property(handle, v);
        const WindingMeter meter(surface.mesh, u);
        std::vector<PathWinding> result;
        for (const auto& path : r.plan.paths)
            result.push_back(meter.measure(path));
        return result;
    };
    const std::vector<PathWinding> chosen = windings(FlattenOptions{});
    REQUIRE(chosen.size() == 2);
    for (const auto& w : chosen)
    {
        MESSAGE("default route: cut of " << w.length << " mm winds " << w.winding_deg << " deg ("
                                         << w.measured << "/" << w.vertices << " measured)");
        CHECK(std::abs(w.winding_deg) < 60.0);
        CHECK(w.measured * 4 > w.vertices);  // the figure rests on at least a quarter of the cut
    }
    FlattenOptions paper;
    paper.cuts.route = CutRoute::ShortestPath;
    double worst = 0.0;
    for (const auto& w : windings(paper))
        worst = std::max(worst, std::abs(w.winding_deg));
    MESSAGE("cheapest-path route: worst cut winds " << worst << " deg");
    CHECK(worst > 60.0);
}

namespace {

// Every triangle of \p raw split 1 -> 4 at its edge midpoints: the same surface (flat
// sub-triangles) at twice the resolution, as ../shared/data/real's split4 meshes are made.
RawMesh split4(const RawMesh& raw)
{
    RawMesh fine;
    fine.points = raw.points;
    std::map<std::pair<int, int>, int> middle;
    const auto mid = [&](int a, int b) {
        const auto key = std::minmax(a, b);
        const auto [it, added] = middle.try_emplace(key, static_cast<int>(fine.points.size()));
        if (added)
            fine.points.push_back(0.5 * (raw.points[a] + raw.points[b]));
        return it->second;
    };
    for (const auto& f : raw.faces)
    {
        const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
        fine.faces.push_back({f[0], ab, ca});
        fine.faces.push_back({ab, f[1], bc});
        fine.faces.push_back({ca, bc, f[2]});
        fine.faces.push_back({ab, bc, ca});
    }
    return fine;
}

// Stage Z and the cut plan as flatten() makes them (no map: only the cuts are asked), with
// default options but \p cuts; \p longitudinal receives stage Z's coordinate.
// The pipeline's cut plan with the default options but \p cuts; with \p viewpoint the travel
// costs priced by facing as `--viewpoint` prices them (CostOptions::viewpoint).
CutPlan default_plan(const Mesh& mesh, const CutPlanOptions& cuts, Eigen::VectorXd& longitudinal,
                     const Eigen::Vector3d* viewpoint = nullptr)
{
    const FlattenOptions options;
    const auto loops = boundary_loops(mesh);
    const PrincipalCurvature curvature = principal_curvature(mesh, options.curvature);
    const Eigen::VectorXd G = heat_geodesic_distance(mesh, loops[0].vertices);
    longitudinal = harmonic_longitudinal(mesh, loops, G);
    const Eigen::MatrixX3d z =
        vessel_direction_guided(mesh, curvature, G, longitudinal, options.direction);
    HalfedgeWeights weights = evaluate_cost(mesh, CurvatureCost{&z});
    if (viewpoint)
        price_facing(mesh, *viewpoint, options.cost.facing_weight, weights);
    return plan_cuts(mesh, loops, weights, winding_rate(mesh, z, curvature.k_max.cwiseAbs()),
                     cuts, descent_direction(mesh, longitudinal), longitudinal);
}

// The default plan's windings by the library's meter: each cut's, and each piece's between
// joins (each cut split at the vertices where later cuts end on it: the paths the shared
// yardstick seamwinding.py measures).
struct DefaultWindings
{
    std::vector<PathWinding> cuts, pieces;
};

DefaultWindings default_windings(const Mesh& mesh)
{
    Eigen::VectorXd H;
    const CutPlan plan = default_plan(mesh, FlattenOptions().cuts, H);
    const WindingMeter meter(mesh, H);
    std::vector<char> join(mesh.n_vertices(), 0);
    for (std::size_t k = 1; k < plan.paths.size(); ++k)
        join[plan.paths[k].end.idx()] = 1;
    DefaultWindings windings;
    for (const auto& path : plan.paths)
    {
        windings.cuts.push_back(meter.measure(path));
        std::vector<VertexHandle> piece{path.start};
        for (auto h : path.halfedges)
        {
            const VertexHandle v = mesh.to_vertex_handle(h);
            piece.push_back(v);
            if (join[v.idx()] && v != path.end)
            {
                windings.pieces.push_back(meter.measure(piece));
                piece.assign(1, v);
            }
        }
        windings.pieces.push_back(meter.measure(piece));
    }
    return windings;
}

// Each cut's winding by the library's meter, default options.
std::vector<PathWinding> default_cut_windings(const Mesh& mesh)
{
    return default_windings(mesh).cuts;
}

// How far apart, around their vessels, the cuts of two meshes of the same surface lie. Per
// vertex of a cut of \p fine, the angle around its vessel (WindingMeter::step() on \p fine,
// with \p fine_longitudinal) from the nearest vertex of the same outlet's cut of \p coarse,
// taken at its nearest vertex of \p fine; per cut the length-weighted mean (degrees) over the
// measured vertices, and the measured length over the whole.
struct SideApart
{
    int outlet = -1;
    double mean_deg = 0.0, measured_fraction = 0.0;
};

std::vector<SideApart> sides_apart(const Mesh& coarse, const CutPlan& coarse_plan,
                                   const Mesh& fine, const CutPlan& fine_plan,
                                   const Eigen::VectorXd& fine_longitudinal)
{
    REQUIRE(coarse_plan.paths.size() == fine_plan.paths.size());
    const auto nearest_fine = [&](const Eigen::Vector3d& p) {
        VertexHandle best;
        double closest = INFINITY;
        for (VertexHandle v : fine.vertices())
        {
            const double d = (to_eigen(fine.point(v)) - p).squaredNorm();
            if (d < closest)
            {
                closest = d;
                best = v;
            }
        }
        return best;
    };
    const WindingMeter meter(fine, fine_longitudinal);
    std::vector<SideApart> apart;
    for (const CutPath& path : fine_plan.paths)
    {
        const auto twin = std::find_if(coarse_plan.paths.begin(), coarse_plan.paths.end(),
                                       [&](const CutPath& p) { return p.outlet == path.outlet; });
        REQUIRE(twin != coarse_plan.paths.end());
        // The coarse cut's vertices, each at its nearest vertex of the fine mesh.
        std::vector<VertexHandle> others{nearest_fine(to_eigen(coarse.point(twin->start)))};
        for (HalfedgeHandle h : twin->halfedges)
            others.push_back(nearest_fine(to_eigen(coarse.point(coarse.to_vertex_handle(h)))));
        double weighted = 0.0, measured = 0.0, total = 0.0;
        VertexHandle previous = path.start;
        for (HalfedgeHandle h : path.halfedges)
        {
            const VertexHandle w = fine.to_vertex_handle(h);
            const Eigen::Vector3d p = to_eigen(fine.point(w));
            const double step = (p - to_eigen(fine.point(previous))).norm();
            previous = w;
            total += step;
            const VertexHandle nearest = *std::min_element(
                others.begin(), others.end(), [&](VertexHandle a, VertexHandle b) {
                    return (to_eigen(fine.point(a)) - p).squaredNorm() <
                           (to_eigen(fine.point(b)) - p).squaredNorm();
                });
            const double angle = meter.step(nearest, w, false);
            if (!std::isfinite(angle))
                continue;
            weighted += std::abs(angle) * 180.0 / M_PI * step;
            measured += step;
        }
        // No vertex measured (a short cut across a junction or a sac): no side to compare.
        apart.push_back({path.outlet, measured > 0.0 ? weighted / measured : NAN,
                         measured / total});
    }
    return apart;
}

// The cut plan as `vessel-flatten` makes it with \p cuts, or with \p face_on as
// `--viewpoint face-on` does: behind the vessels seen from the mesh's own
// face_on_viewpoint().
CutPlan plan_of(const Mesh& mesh, const CutPlanOptions& cuts, bool face_on,
                Eigen::VectorXd& longitudinal)
{
    if (!face_on)
        return default_plan(mesh, cuts, longitudinal);
    const Eigen::Vector3d viewpoint = face_on_viewpoint(mesh);
    CutPlanOptions behind = cuts;
    behind.endpoints = std::make_shared<FarSideEndpoints>(viewpoint);
    return default_plan(mesh, behind, longitudinal, &viewpoint);
}

// sides_apart() between a real tree and the same surface split 1 -> 4 (the same shape; each
// native vertex is a vertex of the split mesh).
std::vector<SideApart> sides_apart_at_two_resolutions(const std::string& name,
                                                     const CutPlanOptions& cuts = FlattenOptions().cuts,
                                                     bool face_on = false)
{
    const RawMesh raw = read_raw_mesh(std::string(VESSEL_SHARED_DATA) + "/" + name);
    const TreeSurface native = make_tree_surface(raw);
    const TreeSurface fine = make_tree_surface(split4(raw));
    Eigen::VectorXd H, H_native;
    const CutPlan coarse_plan = plan_of(native.mesh, cuts, face_on, H_native);
    const CutPlan fine_plan = plan_of(fine.mesh, cuts, face_on, H);
    return sides_apart(native.mesh, coarse_plan, fine.mesh, fine_plan, H);
}

}  // namespace

TEST_CASE("cut_winding: --viewpoint puts the cuts on the far side of the vessels")
{
    // Two viewpoints per tree, each two bounding-box diagonals from the centre of the points
    // (toward -y and toward +x), as `--viewpoint` plans the cuts: FarSideEndpoints and the
    // travel costs priced by facing (docs/results.md "Cuts behind the vessels"). The end fixed
    // on a loop must not make the route walk along the loop (AneuRisk: a boundary edge in the
    // seam, refused by the cut, before the cut graph weighed such arcs infinity), and the cuts
    // must stay natural (issue 32's 45 degrees).
    double sum = 0.0;
    int views = 0;
    for (const std::string name : {"vmtk-test-data/aorta-surface-open-ends.ply",
                                   "simvascular-tests/demo-model-open.ply",
                                   "x-ray-angio-data/coronary-phantom-tri3-coarse.ply",
                                   "vmtk-old-website/aneurisk-id1-lateral-aneurysm.ply"})
    {
        CAPTURE(name);
        const TreeSurface surface = load_tree_surface(std::string(VESSEL_SHARED_DATA) + "/" + name);
        const Mesh& mesh = surface.mesh;
        Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo,
                        centre = Eigen::Vector3d::Zero();
        for (auto v : mesh.vertices())
        {
            const Eigen::Vector3d p = to_eigen(mesh.point(v));
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
            centre += p;
        }
        centre /= static_cast<double>(mesh.n_vertices());
        const double diagonal = (hi - lo).norm();
        Eigen::VectorXd H;
        const CutPlan plain = default_plan(mesh, FlattenOptions().cuts, H);
        for (const Eigen::Vector3d axis : {Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(1, 0, 0)})
        {
            const Eigen::Vector3d viewpoint = centre + 2.0 * diagonal * axis;
            CutPlanOptions cuts = FlattenOptions().cuts;
            cuts.endpoints = std::make_shared<FarSideEndpoints>(viewpoint);
            Eigen::VectorXd H_behind;
            const CutPlan behind = default_plan(mesh, cuts, H_behind, &viewpoint);
            const WindingMeter meter(mesh, H_behind);
            for (const CutPath& path : behind.paths)
                CHECK(std::abs(meter.measure(path).winding_deg) <= 45.0);
            int on_boundary = 0;
            for (const CutPath& path : behind.paths)
                for (const HalfedgeHandle h : path.halfedges)
                    on_boundary += mesh.is_boundary(mesh.edge_handle(h)) ? 1 : 0;
            CHECK(on_boundary == 0);
            const double before = far_side_fraction(mesh, plain, viewpoint);
            const double after = far_side_fraction(mesh, behind, viewpoint);
            MESSAGE(name << " from " << viewpoint.transpose() << ": far side " << before
                         << " -> " << after);
            CHECK(after > before);
            CHECK(after >= 0.8);
            sum += after;
            ++views;
        }
    }
    CHECK(sum / views >= 0.92);
}

TEST_CASE("cut_winding: natural cuts on the SimVascular demo at its resolution and split 1 -> 4")
{
    // Issue 32's targets (every cut <= 45 degrees around its vessel, length-weighted mean <= 20)
    // on one real tree at two resolutions of the same surface; the split adds no new shape, so
    // a cut that winds on one resolution only is the graph's doing, not the anatomy's.
    const RawMesh raw = read_raw_mesh(std::string(VESSEL_SHARED_DATA) +
                                      "/simvascular-tests/demo-model-open.ply");
    const std::vector<std::pair<std::string, RawMesh>> resolutions = {{"native", raw},
                                                                      {"split 1->4", split4(raw)}};
    for (const auto& [name, input] : resolutions)
    {
        const TreeSurface surface = make_tree_surface(input);
        const std::vector<PathWinding> windings = default_cut_windings(surface.mesh);
        REQUIRE(windings.size() == 2);
        for (const auto& w : windings)
        {
            MESSAGE(name << ": cut of " << w.length << " cm winds " << w.winding_deg << " deg ("
                         << w.measured << "/" << w.vertices << " measured)");
            CHECK(std::abs(w.winding_deg) <= 45.0);
            CHECK(w.measured * 4 > w.vertices);  // the figure rests on at least a quarter of it
        }
        CHECK(seam_winding(windings).mean_abs_deg <= 20.0);
    }
}

TEST_CASE("cut_winding: the VaMPy artery's aligned-route cuts stay on the same side of their "
          "vessels at two resolutions")
{
    // Issue 32's resolution target: the surface split 1 -> 4 is cut on the same side of each
    // vessel as at its own resolution. With the aligned route alone (natural_cuts off), measured
    // 6.3 and 5.5 degrees apart (57% and 72% of each cut measured). Not met on other real trees
    // nor by the default (docs/results.md "Cuts at two resolutions"): with the aligned route the
    // SimVascular demo's cuts lie 59 and 85 degrees apart, the vmtk aorta's 59 and 35; by
    // default (natural cuts) the demo's 9 and 6, the aorta's 21 and 39, and the artery's second
    // cut, a winding-bounded route at both resolutions, 18.
    CutPlanOptions aligned = FlattenOptions().cuts;
    aligned.natural_cuts = false;
    for (const SideApart& cut : sides_apart_at_two_resolutions("vampy/artery.ply", aligned))
    {
        CAPTURE(cut.outlet);
        MESSAGE("outlet " << cut.outlet << ": " << cut.mean_deg << " degrees apart, "
                          << cut.measured_fraction << " of it measured");
        CHECK(cut.mean_deg <= 10.0);
        CHECK(cut.measured_fraction >= 0.5);
    }
}

TEST_CASE("cut_winding: --viewpoint face-on cuts each vessel on the same half at two resolutions")
{
    // Issue 32's resolution target with the side set by the shape and the mesh's frame
    // (face_on_viewpoint(), which the split leaves where it was): per cut the mean angle apart
    // around its vessel between the tree and the same surface split 1 -> 4. Measured 0.3-62
    // degrees per cut (mean 11 over the 16 cuts of six trees); by default, where the cheapest
    // point of each loop sets the side, 4-157 (mean 68; docs/results.md "Cuts at two
    // resolutions"). Held here: every measured cut on the same half of its vessel, and the
    // mean within 20 degrees.
    double sum = 0.0;
    int cuts = 0;
    for (const std::string name : {"vampy/artery.ply", "simvascular-tests/demo-model-open.ply",
                                   "vmtk-test-data/aorta-surface-open-ends.ply",
                                   "vmtk-old-website/aneurisk-id1-lateral-aneurysm.ply",
                                   "x-ray-angio-data/coronary-clinical-branch-fine.ply",
                                   "x-ray-angio-data/coronary-phantom-tri3-coarse.ply"})
        for (const SideApart& cut :
             sides_apart_at_two_resolutions(name, FlattenOptions().cuts, true))
        {
            CAPTURE(name);
            CAPTURE(cut.outlet);
            MESSAGE(name << " outlet " << cut.outlet << ": " << cut.mean_deg
                         << " degrees apart, " << cut.measured_fraction << " of it measured");
            if (cut.measured_fraction == 0.0)
                continue;  // no side to compare (a short cut across a junction or a sac)
            CHECK(cut.mean_deg < 90.0);
            sum += cut.mean_deg;
            ++cuts;
        }
    REQUIRE(cuts >= 15);  // 16 measured
    CHECK(sum / cuts <= 20.0);
}

TEST_CASE(
    "cut_winding: --viewpoint face-on cuts the carotid phantom on the same side from 5k to "
    "300k triangles")
{
    // Issue 32's resolution target on a surface meshed anew at each resolution (dual
    // contouring: no vertex shared, unlike a split), over the range the issue names: the
    // carotid phantom at edge lengths 0.8, 0.4, 0.26 and 0.1013 mm (about 5k, 13k, 45k and
    // 300k triangles), each coarser one's cuts against the 45k and the 300k ones'. By default
    // the cheapest point of each loop sets the side, and on this symmetric shape the edges'
    // directions break the ties: 79-144 degrees apart from the 300k plan (docs/results.md
    // "Cuts at two resolutions"). Face-on, measured 3.7-18.7 from it (mean 10.4 over the six
    // cuts) and 3.8-13.3 from the 45k plan.
    constexpr int kMeshes = 4;
    const double edges[kMeshes] = {0.8, 0.4, 0.26, 0.1013};  // finer and finer
    std::vector<Mesh> meshes;
    std::vector<CutPlan> plans;
    std::vector<Eigen::VectorXd> longitudinals(kMeshes);
    for (int k = 0; k < kMeshes; ++k)
    {
        CarotidPhantomOptions phantom;
        phantom.edge_length = edges[k];
        meshes.push_back(carotid_phantom(phantom));
        plans.push_back(plan_of(meshes[k], FlattenOptions().cuts, true, longitudinals[k]));
    }
    REQUIRE(meshes.back().n_faces() > 250000);
    for (int fine : {2, 3})
    {
        double sum = 0.0;
        int cuts = 0;
        for (int coarse = 0; coarse < fine; ++coarse)
            for (const SideApart& cut : sides_apart(meshes[coarse], plans[coarse], meshes[fine],
                                                    plans[fine], longitudinals[fine]))
            {
                CAPTURE(edges[coarse]);
                CAPTURE(edges[fine]);
                CAPTURE(cut.outlet);
                MESSAGE("edge " << edges[coarse] << " against " << edges[fine] << ", outlet "
                                << cut.outlet << ": " << cut.mean_deg << " degrees apart, "
                                << cut.measured_fraction << " of it measured");
                // The ICA's sinus bulb and stenosis and the bifurcation are no round rings: at
                // 45k 40% of its cut is measured, at 300k nine tenths.
                CHECK(cut.measured_fraction >= 0.3);
                // Every cut on the same side of its vessel: within the quarter of its
                // circumference that the far-side ends and the facing price keep it to.
                CHECK(cut.mean_deg <= (fine == 2 ? 20.0 : 25.0));
                sum += cut.mean_deg;
                ++cuts;
            }
        CHECK(sum / cuts <= 15.0);
    }
}

TEST_CASE("cut_winding: where a vessel turns round the face-on view, the inlet's end is freed "
          "and the cut stays natural")
{
    // The helical phantom seen face-on: "behind" moves round the tube along its length, and
    // with both ends on the far side its one cut wound 116 degrees (no natural route joins
    // them). plan_cuts() plans it again with the inlet's end free: 11 degrees by this meter
    // (span 33), 19 in the report (span 35).
    const Mesh mesh = helical_tube();
    FlattenOptions options;
    options.cost.face_on = true;
    options.relief.max_cuts = 0;
    const FlattenResult result = flatten(mesh, options);
    REQUIRE(result.viewpoint);
    REQUIRE(result.plan.paths.size() == 1);
    const CutPath& cut = result.plan.paths.front();
    const Eigen::VectorXd G = heat_geodesic_distance(mesh, result.loops[0].vertices);
    const WindingMeter meter(mesh, harmonic_longitudinal(mesh, result.loops, G));
    const PathWinding w = meter.measure(cut);
    MESSAGE("face-on helix: winds " << w.winding_deg << " degrees, spans " << w.span_deg);
    CHECK(std::abs(w.winding_deg) <= 45.0);
    CHECK(w.span_deg <= 45.0);
    // The outlet's end is still the far side's.
    CHECK(cut.start == FarSideEndpoints(*result.viewpoint).allowed(mesh, result.loops[1], 1)[0]);
    CHECK(result.quality.flipped_triangles == 0);
}

TEST_CASE(
    "cut_winding: by default the 1.5-turn helical tube's cut keeps to one side within "
    "issue 32's targets")
{
    // Issue 32 asks of the helical phantom at most 15 degrees end to end and 30 of span. The
    // streamline of the discrete harmonic coordinate drifts about one column round the coarse
    // tube (span 32); the vessel direction's streamline, the aligned route's second trace for a
    // natural cut that spans more than twice the target, does not. The phantom's own frame
    // (helical_tube_angle()) is a second meter beside the library's.
    for (int n_around : {24, 32, 48})
    {
        CAPTURE(n_around);
        HelicalTubeOptions tube;
        tube.turns = 1.5;
        tube.n_around = n_around;
        const Mesh mesh = helical_tube(tube);
        const FlattenResult result = flatten(mesh, FlattenOptions{});
        REQUIRE(result.plan.paths.size() == 1);
        const CutPath& cut = result.plan.paths.front();
        const Eigen::VectorXd G = heat_geodesic_distance(mesh, result.loops[0].vertices);
        const WindingMeter meter(mesh, harmonic_longitudinal(mesh, result.loops, G));
        const PathWinding w = meter.measure(cut);
        const test::PathTurn exact = test::helix_turn(tube, mesh, cut);
        MESSAGE("1.5-turn helix, " << n_around << " around: the meter " << w.winding_deg
                                   << " degrees end to end, span " << w.span_deg
                                   << "; the phantom's frame: " << exact.winding_deg << ", span "
                                   << exact.span_deg);
        CHECK(std::abs(w.winding_deg) <= 15.0);
        CHECK(w.span_deg <= 30.0);
        CHECK(std::abs(exact.winding_deg) <= 15.0);
        CHECK(exact.span_deg <= 30.0);
        CHECK(result.quality.flipped_triangles == 0);
    }
}

TEST_CASE(
    "cut_winding: on a lateral aneurysm the default cut keeps off the sac, on one side of the "
    "parent")
{
    // Issue 32: where "around the vessel" is undefined (a sac) the cut takes the short natural
    // passage. On a straight parent with a round sac on its side no cut needs to cross the sac:
    // the natural one runs along the parent, clear of the sac and its neck, so that the sac
    // lies whole in the map. The parent's axis is z, so atan2(y, x) is the exact angle
    // around it, a meter beside the library's. Sacs of 1.5 and 2.5 parent radii (AneuRisk's
    // is about 2.5).
    for (double sac_radius : {3.0, 5.0})
    {
        CAPTURE(sac_radius);
        AneurysmPhantomOptions phantom;
        phantom.sac_radius = sac_radius;
        const Mesh mesh = aneurysm_phantom(phantom);
        const FlattenResult result = flatten(mesh, FlattenOptions{});
        REQUIRE(result.plan.paths.size() == 1);
        const CutPath& cut = result.plan.paths.front();
        const Eigen::Vector3d centre = aneurysm_sac_centre(phantom);
        double nearest = (to_eigen(mesh.point(cut.start)) - centre).norm();
        for (auto h : cut.halfedges)
            nearest =
                std::min(nearest, (to_eigen(mesh.point(mesh.to_vertex_handle(h))) - centre).norm());
        const double span_deg = test::path_turn(mesh, cut, [](const Eigen::Vector3d& p) {
                                    return std::atan2(p.y(), p.x());
                                }).span_deg;
        MESSAGE("aneurysm phantom, sac radius " << sac_radius << ": cut " << nearest
                                                << " from the sac's centre, span " << span_deg
                                                << " degrees round the parent");
        // Clear of the sac and of the neck's fillet.
        CHECK(nearest > sac_radius + phantom.parent_radius);
        CHECK(span_deg <= 30.0);
        const Eigen::VectorXd G = heat_geodesic_distance(mesh, result.loops[0].vertices);
        const WindingMeter meter(mesh, harmonic_longitudinal(mesh, result.loops, G));
        OpenStretch open;
        const PathWinding w = meter.measure(cut, &open);
        CHECK(std::abs(w.winding_deg) <= 15.0);
        CHECK(result.quality.flipped_triangles == 0);
        CHECK(result.quality.mean_abs_log_area_normalized <= 0.03);
        // Where "around the vessel" is undefined the meter says so: at the neck the band
        // through the cut's vertex passes the ring test but leaves an arc round its axis
        // empty, and the angle measure() reads there swings with the band's centroid (a span
        // of about 37 degrees at sac radius 3). measure()'s `open` puts the meter's excess
        // over the exact span down to that short stretch.
        MESSAGE("the meter's span " << w.span_deg << ", of it " << open.turn_deg << " degrees over "
                                    << open.length << " mm of open bands");
        CHECK(open.length > 0.0);
        CHECK(open.length < 0.2 * w.length);
        CHECK(open.turn_deg >= 0.5 * (w.span_deg - span_deg));
    }
}

TEST_CASE("cut_winding: on a tube of regular rings no band is open round the vessel")
{
    // The other side of measure()'s `open` (the lateral aneurysm test above): where every band
    // closes, at any resolution, nothing of a cut's reading is put down to open bands.
    for (int n_around : {12, 24, 48})
    {
        CAPTURE(n_around);
        HelicalTubeOptions tube;
        tube.n_around = n_around;
        const Mesh mesh = helical_tube(tube);
        const FlattenResult result = flatten(mesh, FlattenOptions{});
        REQUIRE(result.plan.paths.size() == 1);
        const WindingMeter meter(mesh, longitudinal(mesh));
        OpenStretch open;
        meter.measure(result.plan.paths.front(), &open);
        CHECK(open.length == 0.0);
        CHECK(open.turn_deg == 0.0);
    }
}

namespace {

// The lateral-aneurysm phantom at \p sac_radius with a branch of radius 0.8 off its sac.
AneurysmPhantomOptions branch_phantom(double sac_radius)
{
    AneurysmPhantomOptions phantom;
    phantom.sac_radius = sac_radius;
    phantom.branch_radius = 0.8;
    return phantom;
}

// aneurysm_phantom(\p phantom) with its inlet end widened by 2% over its last millimetre: the
// straight parent's two end loops are otherwise equally long but for rounding, so that which
// one is the inlet is left to the rounding.
Mesh widened_inlet(const AneurysmPhantomOptions& phantom)
{
    Mesh mesh = aneurysm_phantom(phantom);
    const double inlet_z = -0.5 * phantom.parent_length;
    for (auto v : mesh.vertices())
    {
        auto p = mesh.point(v);
        const double widen = 1.0 + 0.02 * std::max(0.0, (inlet_z + 1.0) - p[2]);
        p[0] *= widen;
        p[1] *= widen;
        mesh.set_point(v, p);
    }
    return mesh;
}

// The default plan's cut of the branch (loop 2) against the shortest edge path from the
// branch's loop to the first cut, by a Dijkstra of its own; checks that it is at most
// \p max_ratio times that path, natural by the library's meter, and the map has no flip.
void check_branch_cut_short(const Mesh& mesh, double max_ratio, const std::string& what,
                            double sac_radius)
{
    const FlattenResult result = flatten(mesh, FlattenOptions{});
    REQUIRE(result.loops.size() == 3);
    REQUIRE(result.plan.paths.size() == 2);
    const CutPath& first = result.plan.paths[0];
    const CutPath& branch = result.plan.paths[1];
    REQUIRE(mesh.from_vertex_handle(branch.halfedges.front()) == branch.start);

    HalfedgeWeights lengths(mesh.n_halfedges());
    for (auto h : mesh.halfedges())
        lengths[static_cast<std::size_t>(h.idx())] = mesh.calc_edge_length(h);
    PathQuery query;
    query.sources = result.loops[2].vertices;  // the branch's loop (the shortest)
    query.is_target.assign(mesh.n_vertices(), 0);
    for (auto h : first.halfedges)
        if (!mesh.is_boundary(mesh.to_vertex_handle(h)))
            query.is_target[static_cast<std::size_t>(mesh.to_vertex_handle(h).idx())] = 1;
    double shortest = 0.0;
    for (auto h : shortest_path(mesh, lengths, query).halfedges)
        shortest += lengths[static_cast<std::size_t>(h.idx())];
    double length = 0.0;
    for (auto h : branch.halfedges)
        length += lengths[static_cast<std::size_t>(h.idx())];

    const Eigen::VectorXd G = heat_geodesic_distance(mesh, result.loops[0].vertices);
    const WindingMeter meter(mesh, harmonic_longitudinal(mesh, result.loops, G));
    const PathWinding w = meter.measure(branch);
    MESSAGE(what << ", sac radius " << sac_radius << ": the branch's cut " << length
                 << " mm, the shortest edge path " << shortest << " (" << length / shortest
                 << "x), winding " << w.winding_deg << " degrees, span " << w.span_deg);
    CHECK(length <= max_ratio * shortest);
    CHECK(std::abs(w.winding_deg) <= 45.0);
    CHECK(w.span_deg <= 45.0);
    CHECK(result.quality.flipped_triangles == 0);
}

}  // namespace

TEST_CASE(
    "cut_winding: a branch off a lateral aneurysm's sac is cut across the sac by a short "
    "passage")
{
    // Issue 32: where a sac makes "around the vessel" undefined, the cut takes the shortest
    // natural passage across it. The branch off the sac must reach the first cut, which runs
    // along the parent, so its cut crosses the sac. At sac radius 3 the harmonic streamline
    // followed u's meanders over the sac, 20.4 mm against 13.2 for the shortest path along the
    // edges (1.55x); the aligned route now offers a streamline that crosses a sac the shortest
    // passage (route_aligned.cpp, keep_passage()). The yardstick: that shortest edge path
    // from the branch's loop to the first cut (check_branch_cut_short()).
    for (double sac_radius : {3.0, 4.0, 5.0})
    {
        CAPTURE(sac_radius);
        check_branch_cut_short(aneurysm_phantom(branch_phantom(sac_radius)), 1.25, "as made",
                               sac_radius);
    }
}

TEST_CASE(
    "cut_winding: a branch off a sac is cut by a short passage also where the parent tapers a "
    "little")
{
    // Issue 32 asks for a plan that holds where the anatomy changes a little. With the parent
    // narrowing by 2% of its radius from inlet to outlet (a new mesh: the sampling grid moves),
    // the branch's route bounded in winding came near the first cut on the parent's far side,
    // and its cut back there bridged round the parent past the bound, so the whole route was
    // kept, running on beside the first cut (at sac radius 5 38.0 mm, 18.9 of it beside the
    // first cut; 2.2-2.4x the shortest passage). A held route is now cut back at the first
    // place whose bridge keeps it within the bound (CutJoiner::finish_held()), and the cut is
    // a short passage: the bound on its winding leaves it a little longer than on the phantom
    // as made (1.26x at sac radius 5, where the held route still runs 2.4 mm beside the first
    // cut before its bridge), so the check is at 1.3x.
    for (double sac_radius : {3.0, 4.0, 5.0})
    {
        CAPTURE(sac_radius);
        AneurysmPhantomOptions phantom = branch_phantom(sac_radius);
        phantom.taper = 0.02;
        check_branch_cut_short(aneurysm_phantom(phantom), 1.3, "parent tapered 2%", sac_radius);
    }
}

TEST_CASE(
    "cut_winding: the meter and seamwinding.py read a branch off a sac alike from the "
    "same inlet")
{
    // Issue 32 asks the winding targets of both meters. On the lateral-aneurysm phantom with a
    // branch, seamwinding.py read the branch's cut at 107-124 degrees where the library read
    // 15-19: the straight parent's two end loops are equally long but for rounding, and the
    // yardstick took the other end for the inlet, so that its longitudinal coordinate ran the
    // other way (docs/results.md, "Sacs: the lateral-aneurysm phantom"). Here the phantom's
    // inlet end is widened by 2% over its last millimetre, so that both take it, and the cut
    // that is one piece of the seam (the branch's, which ends on the first cut) must then read
    // the same winding and span to a degree by both.
    for (double sac_radius : {3.0, 4.0, 5.0})
    {
        CAPTURE(sac_radius);
        const AneurysmPhantomOptions phantom = branch_phantom(sac_radius);
        const Mesh mesh = widened_inlet(phantom);
        const double inlet_z = -0.5 * phantom.parent_length;
        const auto loops = boundary_loops(mesh);
        REQUIRE(loops.size() == 3);
        REQUIRE(std::abs(loops[0].centroid.z() - inlet_z) < 1e-6);
        REQUIRE(loops[0].arc_length > 1.01 * loops[1].arc_length);  // no tie left to rounding

        const std::string dir = test::temp_dir("sac_yardstick");
        const std::string input = dir + "/sac.ply", flat = dir + "/flat.obj";
        write_mesh(mesh, input);
        REQUIRE(test::run(std::string(VESSEL_FLATTEN_EXE) + " " + input + " -o " + flat +
                          " --report " + dir + "/report.json -q") == 0);
        const auto report = nlohmann::json::parse(std::ifstream(dir + "/report.json"));
        const auto yardstick = test::seamwinding(input, flat);
        int compared = 0;
        for (const auto& cut : report["cuts"])
            for (const auto& piece : yardstick["paths"])
            {
                // seamwinding.py rounds lengths to a micrometre.
                if (std::abs(piece["length"].get<double>() - cut["length"].get<double>()) > 0.01)
                    continue;
                const double ours = std::abs(cut["winding_deg"].get<double>());
                const double span = cut["winding_span_deg"].get<double>();
                MESSAGE("sac radius " << sac_radius << ", the cut from outlet " << cut["outlet"]
                                      << ": winding / span " << ours << " / " << span
                                      << ", seamwinding.py " << piece["winding_deg"] << " / "
                                      << piece["span_deg"]);
                CHECK(std::abs(ours - piece["winding_deg"].get<double>()) <= 1.0);
                CHECK(std::abs(span - piece["span_deg"].get<double>()) <= 1.0);
                CHECK(ours <= 45.0);
                ++compared;
            }
        CHECK(compared >= 1);  // the branch's cut, whole
    }
}

TEST_CASE("cut_winding: by default every cut of every valid real tree is held to the bound")
{
    // Issue 32's targets by the library's meter (CutPlanOptions::natural_cuts, the default):
    // every cut winds at most 45 degrees around its vessel end to end and spans at most 45
    // (which bounds each piece between two joins, the paths seamwinding.py measures),
    // length-weighted mean at most 20.
    // With the aligned route alone (--no-natural-cuts) the vmtk aorta's first cut winds 63
    // degrees (every route a multiplier can reach winds about +-80), the Glenn tree's up to 66
    // with spans to 83, the AneuRisk side branch's 101 (docs/results.md).
    const char* trees[] = {"vmtk-test-data/aorta-surface-open-ends.ply",
                           "vampy/artery.ply",
                           "vampy/artery-coarse.ply",
                           "vmtk-old-website/aneurisk-id1-lateral-aneurysm.ply",
                           "svfsi-tests/pulmonary-glenn-wall.ply",
                           "x-ray-angio-data/coronary-phantom-tri3-coarse.ply",
                           "x-ray-angio-data/coronary-clinical-branch-fine.ply",
                           "simvascular-tests/demo-model-open.ply"};
    for (const char* name : trees)
    {
        CAPTURE(name);
        const TreeSurface surface =
            load_tree_surface(std::string(VESSEL_SHARED_DATA) + "/" + name);
        const DefaultWindings measured = default_windings(surface.mesh);
        const std::vector<PathWinding>& windings = measured.cuts;
        REQUIRE(windings.size() + 1 == boundary_loops(surface.mesh).size());
        double worst = 0.0, widest = 0.0;
        for (const auto& w : windings)
        {
            CHECK(std::abs(w.winding_deg) <= 45.0);
            CHECK(w.span_deg <= 45.0);
            worst = std::max(worst, std::abs(w.winding_deg));
            widest = std::max(widest, w.span_deg);
        }
        const double mean = seam_winding(windings).mean_abs_deg;
        // The same targets on the pieces between joins, as the yardstick reads the seam: a cut
        // within the bound end to end may still turn a third of the way round between two
        // joins and back (AneuRisk's first cut, 34 degrees from the inlet to its first join,
        // before the planner tried the target again with the meter's own steps).
        const std::vector<PathWinding>& pieces = measured.pieces;
        REQUIRE(pieces.size() >= windings.size());
        double worst_piece = 0.0;
        for (const auto& w : pieces)
        {
            CHECK(std::abs(w.winding_deg) <= 45.0);
            worst_piece = std::max(worst_piece, std::abs(w.winding_deg));
        }
        const double piece_mean = seam_winding(pieces).mean_abs_deg;
        MESSAGE(std::string(name) << ": " << windings.size() << " cuts, mean " << mean << " deg, largest "
                     << worst << ", widest span " << widest << "; " << pieces.size()
                     << " pieces between joins, mean " << piece_mean << ", largest "
                     << worst_piece);
        CHECK(mean <= 20.0);
        CHECK(piece_mean <= 20.0);
    }
}

TEST_CASE("cut_winding: a natural streamline cut gives way only to a natural one that winds "
          "clearly less or within the target")
{
    // A cut taken along a streamline that winds more than the 15 degrees the steered search
    // aims at but is natural (winds and spans at most winding_limit_deg, 45) is searched
    // again, and replaced only by a natural route that winds less by winding_min_gain_deg
    // (15), or within the target, and is as well aligned (winding_max_alignment_loss). Steered
    // without that gain or the target,
    // such a cut on the 10-outlet tree phantom (outlet 5, 23 degrees) moved to the top of its
    // vessel, outlet 6's cut joined it there, and the fan layout swung outlet 6 past outlet 1
    // (map_look_test's 10-outlet case); never searched again, the carotid phantom at edge
    // 0.44 kept an ECA streamline of 32 degrees (seam mean 21.7, over issue 32's 20).
    // Asserted on tree phantoms: while the plans with and without the steered search agree, a
    // natural traced cut is the same cut in both or its replacement winds clearly less. On
    // these phantoms (seeds 1-8 tried) no traced cut is replaced; the carotid at edge 0.44,
    // whose first cut is searched again too, is held by the next test case.
    const CutPlanOptions defaults = FlattenOptions().cuts;
    int kept = 0, replaced = 0;
    const auto compare = [&](const Mesh& mesh) {
        CutPlanOptions unsteered = defaults;
        unsteered.winding_target_deg = 0.0;
        Eigen::VectorXd H;
        const CutPlan before = default_plan(mesh, unsteered, H);
        const CutPlan after = default_plan(mesh, defaults, H);
        const WindingMeter meter(mesh, H);
        REQUIRE(before.paths.size() == after.paths.size());
        const double limit = defaults.winding_limit_deg;
        for (std::size_t k = 0; k < before.paths.size(); ++k)
        {
            const CutPath& cut = before.paths[k];
            const bool same = cut.halfedges == after.paths[k].halfedges;
            const PathWinding wound = meter.measure(cut);
            CAPTURE(cut.outlet);
            CAPTURE(wound.winding_deg);
            if (cut.traced && std::abs(wound.winding_deg) <= limit && wound.span_deg <= limit)
            {
                if (same)
                    kept += std::abs(wound.winding_deg) > defaults.winding_target_deg;
                else
                {
                    const PathWinding now = meter.measure(after.paths[k]);
                    CAPTURE(now.winding_deg);
                    CHECK(std::abs(now.winding_deg) <= limit);
                    CHECK(now.span_deg <= limit);
                    CHECK((std::abs(now.winding_deg) <
                               std::abs(wound.winding_deg) - defaults.winding_min_gain_deg ||
                           std::abs(now.winding_deg) <= defaults.winding_target_deg));
                    ++replaced;
                }
            }
            if (!same)
                break;  // later cuts join a different tree
        }
    };
    for (int outlets : {4, 6, 10})
        for (std::uint32_t seed : {1u, 2u, 3u})
        {
            CAPTURE(outlets);
            CAPTURE(seed);
            compare(test::test_tree_phantom(outlets, seed));
        }
    CHECK(kept >= 1);  // the case is exercised: a traced cut over the target was kept
    MESSAGE(kept << " traced cuts over the target kept, " << replaced << " replaced");
}

TEST_CASE("cut_winding: by default the carotid phantom's cuts meet the targets from 4k to 60k "
          "triangles")
{
    // Issue 32's targets by the library's meter on the benchmark phantom meshed anew at each
    // resolution: every cut winds at most 45 degrees end to end, the length-weighted mean at
    // most 20. Edge 0.44 kept an ECA streamline of 32 degrees before traced cuts were searched
    // again (mean 21.7); edge 0.28 a natural first cut of 35 whose bridged bounded route reads
    // 19.7 by the meter (mean 27.7) before the target was tried with the meter's own steps;
    // edge 0.22 a natural first cut of 28.5 whose steered route within the target (14.6)
    // gained less than winding_min_gain_deg (mean 21.6) before such a route was taken.
    for (double edge : {0.8, 0.5, 0.44, 0.35, 0.28, 0.263, 0.22})
    {
        CAPTURE(edge);
        CarotidPhantomOptions phantom;
        phantom.edge_length = edge;
        const std::vector<PathWinding> windings = default_cut_windings(carotid_phantom(phantom));
        REQUIRE(windings.size() == 2);
        for (const auto& w : windings)
            CHECK(std::abs(w.winding_deg) <= 45.0);
        const double mean = seam_winding(windings).mean_abs_deg;
        MESSAGE("carotid phantom, edge " << edge << ": mean " << mean << " deg, cuts "
                                         << windings[0].winding_deg << " and "
                                         << windings[1].winding_deg);
        CHECK(mean <= 20.0);
    }
}
