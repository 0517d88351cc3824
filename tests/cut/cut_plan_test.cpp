#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/meshes.h"

#include "vessel/cut/boundary.h"
#include "vessel/direction/curvature.h"
#include "vessel/cut/cut_cost.h"
#include "vessel/cut/cut_metrics.h"
#include "vessel/cut/cut_plan.h"
#include "vessel/direction/direction.h"
#include "vessel/core/errors.h"
#include "vessel/direction/geodesic.h"
#include "vessel/phantom/phantom.h"

#include <cmath>

using namespace vessel;

namespace {

DirectionOptions guided(double confident_anisotropy)
{
    DirectionOptions options;
    options.confident_anisotropy = confident_anisotropy;
    return options;
}

// The paper's cheapest-path route: the cases below that pass no stream field test it.
CutPlanOptions paper_route()
{
    CutPlanOptions options;
    options.route = CutRoute::ShortestPath;
    return options;
}

struct Prepared
{
    Mesh mesh;
    std::vector<BoundaryLoop> loops;
    Eigen::MatrixX3d z;
    Eigen::MatrixX3d rate;
};

// z as flatten() makes it; `confident_anisotropy = 0` is the paper's pure curvature field.
Prepared prepare(Mesh mesh, const DirectionOptions& direction = guided(0.0))
{
    Prepared p;
    p.loops = boundary_loops(mesh);
    const auto curvature = principal_curvature(mesh);
    const Eigen::VectorXd G = heat_geodesic_distance(mesh, p.loops[0].vertices);
    p.z = vessel_direction(mesh, curvature, p.loops, G, direction);
    p.rate = winding_rate(mesh, p.z, curvature.k_max.cwiseAbs());
    p.mesh = std::move(mesh);
    return p;
}

// The demo carotid phantom with the E_c weights, planned with the paper's route and \p join.
struct CarotidJoin
{
    Prepared p = prepare(carotid_phantom());
    HalfedgeWeights w = evaluate_cost(p.mesh, CurvatureCost{&p.z});
    CutPlan plan(CutJoin join, double join_excess = CutPlanOptions{}.join_excess) const
    {
        CutPlanOptions options = paper_route();
        options.join = join;
        options.join_excess = join_excess;
        return plan_cuts(p.mesh, p.loops, w, p.rate, options);
    }
};

}  // namespace

TEST_CASE("cut_plan: the E_c cut of a twisted helical tube stays on one side")
{
    // The paper's pure curvature field (the default) and the guided direction policy.
    for (const DirectionOptions& direction : {guided(0.0), guided(0.6), guided(1.0)})
    for (int n_around : {24, 32, 48})
    {
        CAPTURE(n_around);
        CAPTURE(direction.confident_anisotropy);
        HelicalTubeOptions options;
        options.tube_radius = 1.0;
        options.helix_radius = 4.0;
        options.pitch = 12.0;
        options.turns = 1.5;
        options.n_around = n_around;
        const Prepared p = prepare(helical_tube(options), direction);
        const HalfedgeWeights w = evaluate_cost(p.mesh, CurvatureCost{&p.z});
        const CutPlan plan = plan_cuts(p.mesh, p.loops, w, p.rate, paper_route());
        REQUIRE(plan.paths.size() == 1);
        const double winding =
            std::abs(test::helix_turn(options, p.mesh, plan.paths[0]).winding_deg);
        // The trap: the plain shortest path drifts around the tube at (almost) no extra cost.
        CutPlanOptions plain = paper_route();
        plain.tie_tolerance = 0.0;
        const CutPlan drifting = plan_cuts(p.mesh, p.loops, w, p.rate, plain);
        const double drift =
            std::abs(test::helix_turn(options, p.mesh, drifting.paths[0]).winding_deg);
        MESSAGE("helical tube (" << n_around << " around, confident_anisotropy "
                                 << direction.confident_anisotropy << ") E_c cut winds " << winding
                                 << " degrees; plain Dijkstra " << drift << " degrees");
        CHECK(winding < 30.0);
        CHECK(drift > winding);
    }
}

TEST_CASE("cut_plan: the streamline and aligned routes keep the helical tube's cut on one side")
{
    for (StreamField field : {StreamField::Harmonic, StreamField::Direction})
    for (int n_around : {24, 32, 48})
    {
        CAPTURE(n_around);
        CAPTURE(static_cast<int>(field));
        HelicalTubeOptions options;
        options.turns = 1.5;
        options.n_around = n_around;
        const Prepared p = prepare(helical_tube(options));
        const HalfedgeWeights w = evaluate_cost(p.mesh, CurvatureCost{&p.z});
        // The field flatten() traces: the harmonic longitudinal descent, or z itself.
        const Eigen::MatrixX3d stream =
            field == StreamField::Direction
                ? p.z
                : descent_direction(p.mesh,
                                    harmonic_longitudinal(p.mesh, p.loops,
                                                          heat_geodesic_distance(
                                                              p.mesh, p.loops[0].vertices)));
        for (CutRoute kind : {CutRoute::Streamline, CutRoute::Aligned})
        {
            CAPTURE(static_cast<int>(kind));
            CutPlanOptions route;
            route.route = kind;
            route.stream_field = field;
            const CutPlan plan = plan_cuts(p.mesh, p.loops, w, p.rate, route, stream);
            REQUIRE(plan.paths.size() == 1);
            if (kind == CutRoute::Streamline)
                CHECK(plan.paths[0].traced);
            const double winding =
                std::abs(test::helix_turn(options, p.mesh, plan.paths[0]).winding_deg);
            MESSAGE("helical tube (" << n_around << " around) "
                                     << (kind == CutRoute::Aligned ? "aligned" : "streamline")
                                     << "-route cut winds " << winding << " degrees");
            CHECK(winding < 30.0);
            // Still a cut from rim to rim.
            CHECK(plan.paths[0].parent == -1);
            CHECK(plan.paths[0].end != plan.paths[0].start);
        }
    }
    // The route needs its field.
    const Prepared p = prepare(helical_tube());
    CutPlanOptions route;
    route.route = CutRoute::Streamline;
    CHECK_THROWS_AS(plan_cuts(p.mesh, p.loops, evaluate_cost(p.mesh, CurvatureCost{&p.z}), p.rate,
                              route),
                    InvalidInputError);
    // A vessel direction of another mesh is refused, not read past its end.
    CutPlanOptions aligned;
    CHECK_THROWS_AS(
        plan_cuts(p.mesh, p.loops, evaluate_cost(p.mesh, CurvatureCost{&p.z}), p.rate, aligned, p.z,
                  Eigen::VectorXd(), Eigen::MatrixX3d(p.z.topRows(p.z.rows() - 1))),
        InvalidInputError);
    route.band_rings = -1;
    CHECK_THROWS_AS(route.validate(), InvalidInputError);
}

TEST_CASE("cut_plan: the cut of a helical tube runs from the outlet rim to the inlet rim")
{
    HelicalTubeOptions options;
    const Prepared p = prepare(helical_tube(options));
    const HalfedgeWeights w = evaluate_cost(p.mesh, CurvatureCost{&p.z});
    const CutPlan plan = plan_cuts(p.mesh, p.loops, w, p.rate, paper_route());
    REQUIRE(plan.paths.size() == 1);
    const CutPath& cut = plan.paths[0];
    CHECK(cut.parent == -1);
    // It runs from one rim to the other.
    bool starts_on_outlet = false, ends_on_inlet = false;
    for (auto v : p.loops[1].vertices)
        starts_on_outlet |= v == cut.start;
    for (auto v : p.loops[0].vertices)
        ends_on_inlet |= v == cut.end;
    CHECK(starts_on_outlet);
    CHECK(ends_on_inlet);
}

TEST_CASE("cut_plan: viewpoint endpoints start and end at the loop vertices nearest the point")
{
    const Prepared p = prepare(open_cylinder(1.0, 6.0, 24, 24));
    const HalfedgeWeights w = evaluate_cost(p.mesh, CurvatureCost{&p.z});
    CutPlanOptions options = paper_route();
    // looking at the +y side
    options.endpoints = std::make_shared<NearestPointEndpoints>(Eigen::Vector3d(0.0, 10.0, 3.0));
    const CutPlan plan = plan_cuts(p.mesh, p.loops, w, p.rate, options);
    REQUIRE(plan.paths.size() == 1);
    const auto start = p.mesh.point(plan.paths[0].start);
    const auto end = p.mesh.point(plan.paths[0].end);
    CHECK(start[1] == doctest::Approx(1.0));
    CHECK(end[1] == doctest::Approx(1.0));
    // On a cylinder with axial edges the E_c cut is the straight generator line.
    for (auto h : plan.paths[0].halfedges)
        CHECK(p.mesh.point(p.mesh.to_vertex_handle(h))[1] == doctest::Approx(1.0));
    // In front of the cylinder for the viewer at +y, wholly behind it for one at -y.
    CHECK(far_side_fraction(p.mesh, plan, Eigen::Vector3d(0.0, 10.0, 3.0)) == 0.0);
    CHECK(far_side_fraction(p.mesh, plan, Eigen::Vector3d(0.0, -10.0, 3.0)) == 1.0);
    CHECK(far_side_fraction(p.mesh, CutPlan{}, Eigen::Vector3d(0.0, 10.0, 3.0)) == 0.0);
    CHECK_THROWS_AS(far_side_fraction(p.mesh, plan, Eigen::Vector3d(0.0, std::nan(""), 0.0)),
                    InvalidInputError);
}

TEST_CASE("cut_plan: far-side endpoints put the cut on the side away from the point")
{
    const Prepared p = prepare(open_cylinder(1.0, 6.0, 24, 24));
    const HalfedgeWeights w = evaluate_cost(p.mesh, CurvatureCost{&p.z});
    CutPlanOptions options = paper_route();
    const Eigen::Vector3d viewpoint(0.0, 10.0, 3.0);
    options.endpoints = std::make_shared<FarSideEndpoints>(viewpoint);
    const CutPlan plan = plan_cuts(p.mesh, p.loops, w, p.rate, options);
    REQUIRE(plan.paths.size() == 1);
    CHECK(p.mesh.point(plan.paths[0].start)[1] == doctest::Approx(-1.0));
    CHECK(p.mesh.point(plan.paths[0].end)[1] == doctest::Approx(-1.0));
    CHECK(far_side_fraction(p.mesh, plan, viewpoint) == 1.0);
    CHECK_THROWS_AS(FarSideEndpoints(Eigen::Vector3d(0.0, 0.0, std::nan(""))), InvalidInputError);
}

namespace {

// A researcher's boundary-point choice: on every loop, the vertex with the largest x (the
// side of the vessel away from a viewer at -x), recording which loops it was asked about.
class LargestXEndpoints : public EndpointPolicy
{
public:
    mutable std::vector<std::size_t> asked;
    std::string name() const override { return "largest-x"; }
    std::vector<VertexHandle> allowed(const Mesh& mesh, const BoundaryLoop& loop,
                                      std::size_t loop_index) const override
    {
        asked.push_back(loop_index);
        VertexHandle best = loop.vertices.front();
        for (auto v : loop.vertices)
            if (mesh.point(v)[0] > mesh.point(best)[0])
                best = v;
        return {best};
    }
};

// A policy that breaks the contract: it hands back another loop's vertex, or none.
class WrongLoopEndpoints : public EndpointPolicy
{
public:
    const std::vector<BoundaryLoop>* loops = nullptr;
    bool none = false;
    std::string name() const override { return none ? "nothing" : "wrong-loop"; }
    std::vector<VertexHandle> allowed(const Mesh&, const BoundaryLoop&,
                                      std::size_t loop_index) const override
    {
        if (none)
            return {};
        return {(*loops)[(loop_index + 1) % loops->size()].vertices.front()};
    }
};

}  // namespace

TEST_CASE("cut_plan: a researcher's endpoint policy places every cut end on the tree")
{
    const Prepared p = prepare(Mesh(tree_phantom({3, 3.0, 0.6, 7})));
    REQUIRE(p.loops.size() == 4);
    const HalfedgeWeights w = evaluate_cost(p.mesh, CurvatureCost{&p.z});
    CutPlanOptions options = paper_route();
    const auto policy = std::make_shared<LargestXEndpoints>();
    options.endpoints = policy;
    const CutPlan plan = plan_cuts(p.mesh, p.loops, w, p.rate, options);
    REQUIRE(plan.paths.size() == 3);
    // Asked once per loop a cut leaves or meets: the inlet, then each outlet.
    CHECK(policy->asked == std::vector<std::size_t>{0, 1, 2, 3});
    for (const CutPath& path : plan.paths)
    {
        const auto chosen = LargestXEndpoints().allowed(p.mesh, p.loops[path.outlet], 0);
        CHECK(path.start == chosen.front());
        if (path.parent < 0)
            CHECK(path.end == LargestXEndpoints().allowed(p.mesh, p.loops[0], 0).front());
    }
    // The default (the whole loop) starts the first cut elsewhere on this tree: the policy
    // changed the plan.
    const CutPlan cheapest = plan_cuts(p.mesh, p.loops, w, p.rate, paper_route());
    bool differs = false;
    for (std::size_t i = 0; i < plan.paths.size(); ++i)
        differs = differs || plan.paths[i].start != cheapest.paths[i].start;
    CHECK(differs);
}

TEST_CASE("cut_plan: an endpoint policy that returns no vertex or another loop's is refused")
{
    const Prepared p = prepare(Mesh(tree_phantom({3, 3.0, 0.6, 7})));
    const HalfedgeWeights w = evaluate_cost(p.mesh, CurvatureCost{&p.z});
    CutPlanOptions options = paper_route();
    auto policy = std::make_shared<WrongLoopEndpoints>();
    policy->loops = &p.loops;
    options.endpoints = policy;
    const auto plan = [&] { plan_cuts(p.mesh, p.loops, w, p.rate, options); };
    CHECK_THROWS_AS(plan(), InvalidInputError);
    std::string message = test::error_of(plan);
    CHECK_MESSAGE(message.find("endpoint policy 'wrong-loop' returned vertex") !=
                      std::string::npos, message);
    CHECK_MESSAGE(message.find("not on loop 0") != std::string::npos, message);
    policy->none = true;
    message = test::error_of(plan);
    CHECK_MESSAGE(message.find("endpoint policy 'nothing' allows no vertex of loop 0") !=
                      std::string::npos, message);
}

TEST_CASE("cut_plan: branches end on interior cut vertices, largest outlet first")
{
    const Mesh tree = tree_phantom({4, 3.0, 0.6, 7});
    const Prepared p = prepare(Mesh(tree));
    REQUIRE(p.loops.size() == 5);
    const HalfedgeWeights w = evaluate_cost(p.mesh, CurvatureCost{&p.z});
    const CutPlan plan = plan_cuts(p.mesh, p.loops, w, p.rate, paper_route());
    REQUIRE(plan.paths.size() == 4);
    std::vector<int> loop_of(p.mesh.n_vertices(), -1);
    for (std::size_t l = 0; l < p.loops.size(); ++l)
        for (auto v : p.loops[l].vertices)
            loop_of[v.idx()] = static_cast<int>(l);
    std::vector<int> on_cut(p.mesh.n_vertices(), -1);
    for (std::size_t k = 0; k < plan.paths.size(); ++k)
    {
        const CutPath& cut = plan.paths[k];
        CHECK(cut.outlet == static_cast<int>(k) + 1);  // largest to smallest
        CHECK(loop_of[cut.start.idx()] == cut.outlet);
        if (k == 0)
            CHECK(loop_of[cut.end.idx()] == 0);
        else
        {
            CHECK(loop_of[cut.end.idx()] == -1);
            REQUIRE(on_cut[cut.end.idx()] >= 0);
            CHECK(cut.parent == on_cut[cut.end.idx()]);
        }
        // No vertex but the end is shared with an earlier cut (cuts never cross), and no vertex
        // but the start and (for the first cut) the end lies on a boundary loop.
        for (std::size_t i = 0; i < cut.halfedges.size(); ++i)
        {
            const auto v = p.mesh.to_vertex_handle(cut.halfedges[i]);
            if (i + 1 < cut.halfedges.size())
            {
                CHECK(on_cut[v.idx()] < 0);
                CHECK(loop_of[v.idx()] < 0);
            }
        }
        on_cut[cut.start.idx()] = static_cast<int>(k);
        for (auto h : cut.halfedges)
            if (on_cut[p.mesh.to_vertex_handle(h).idx()] < 0)
                on_cut[p.mesh.to_vertex_handle(h).idx()] = static_cast<int>(k);
    }
    const auto seam = plan.seam_edges(p.mesh);
    std::size_t total = 0;
    for (const auto& cut : plan.paths)
        total += cut.halfedges.size();
    CHECK(seam.size() == total);
}

TEST_CASE("cut_plan: invalid options and too few loops are refused")
{
    CutPlanOptions bad;
    bad.tie_tolerance = -1.0;
    CHECK_THROWS_AS(bad.validate(), InvalidInputError);
    const Mesh sphere = icosphere(1.0, 1);
    CHECK_THROWS_AS(plan_cuts(sphere, {}, HalfedgeWeights(sphere.n_halfedges(), 1.0),
                              Eigen::MatrixX3d()),
                    InvalidInputError);
}

TEST_CASE("cut_plan: CutJoin::Closest ends a branch's cut at its bifurcation, not beside the parent")
{
    // Demo carotid phantom: with the cheapest join the ECA cut runs down the CCA beside the
    // first cut and joins it near the inlet; the closest join ends it near the bifurcation.
    const CarotidJoin c;
    const Prepared& p = c.p;
    REQUIRE(p.loops.size() == 3);
    const CutPlan a = c.plan(CutJoin::Cheapest);
    const CutPlan b = c.plan(CutJoin::Closest);
    REQUIRE(a.paths.size() == 2);
    REQUIRE(b.paths.size() == 2);
    CHECK(a.paths[0].halfedges == b.paths[0].halfedges);  // the first cut does not change
    const auto length = [&](const CutPath& cut) {
        double total = 0.0;
        for (auto h : cut.halfedges)
            total += p.mesh.calc_edge_length(h);
        return total;
    };
    // Geodesic distance from the inlet of the two ends: the closest join ends far up the CCA.
    const Eigen::VectorXd G = heat_geodesic_distance(p.mesh, p.loops[0].vertices);
    const double cca = CarotidPhantomOptions{}.cca_length;
    CHECK(G[b.paths[1].end.idx()] > 0.6 * cca);
    CHECK(G[a.paths[1].end.idx()] < 0.4 * cca);
    CHECK(length(b.paths[1]) < 0.75 * length(a.paths[1]));
    CHECK(b.paths[1].parent == 0);
}

TEST_CASE("cut_plan: CutJoin::Approach stops a branch's cut where it would run beside the parent")
{
    // Demo carotid phantom: the cheapest path of the ECA cut runs down the CCA beside the first
    // cut; the default join cuts it back near the bifurcation and bridges to the first cut.
    const CarotidJoin c;
    const Prepared& p = c.p;
    REQUIRE(p.loops.size() == 3);
    REQUIRE(CutPlanOptions{}.join == CutJoin::Approach);  // the default
    const CutPlan a = c.plan(CutJoin::Cheapest);
    const CutPlan b = c.plan(CutJoin::Approach);
    REQUIRE(a.paths.size() == 2);
    REQUIRE(b.paths.size() == 2);
    CHECK(a.paths[0].halfedges == b.paths[0].halfedges);  // the first cut does not change
    const CutPath& before = a.paths[1];
    const CutPath& after = b.paths[1];
    CHECK(after.parent == 0);
    CHECK(after.start == before.start);
    // The branch part is the cheapest path's; only its tail is replaced.
    std::size_t shared = 0;
    while (shared < after.halfedges.size() && shared < before.halfedges.size() &&
           after.halfedges[shared] == before.halfedges[shared])
        ++shared;
    CHECK(shared > after.halfedges.size() / 2);
    CHECK(shared < before.halfedges.size());
    // The end moves up the CCA to the bifurcation; the cut no longer runs beside cut 0.
    const Eigen::VectorXd G = heat_geodesic_distance(p.mesh, p.loops[0].vertices);
    const double cca = CarotidPhantomOptions{}.cca_length;
    CHECK(G[before.end.idx()] < 0.4 * cca);
    CHECK(G[after.end.idx()] > 0.6 * cca);
    const double radius = p.loops[2].arc_length / (2.0 * M_PI);
    const double beside_before = beside_length(p.mesh, a, 1, radius);
    const double beside_after = beside_length(p.mesh, b, 1, radius);
    CHECK(beside_before > 0.25 * cca);
    CHECK(beside_after < 0.25 * beside_before);
    CHECK(beside_length(p.mesh, b, 0, radius) == 0.0);  // nothing before the first cut
    // With an excess no run reaches, the cheapest path is kept.
    CHECK(c.plan(CutJoin::Approach, 1e6).paths[1].halfedges == before.halfedges);
    CutPlanOptions bad;
    bad.join_excess = -1.0;
    CHECK_THROWS_AS(bad.validate(), InvalidInputError);
}
