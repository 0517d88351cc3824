// FlattenOptions::custom_cost: a researcher's travel cost, with stage Z's fields typed.
#include <doctest/doctest.h>

#include "support/meshes.h"
#include "vessel/core/errors.h"
#include "vessel/core/properties.h"
#include "vessel/cut/boundary.h"
#include "vessel/cut/cut_cost.h"
#include "vessel/phantom/phantom.h"
#include "vessel/pipeline.h"

#include <algorithm>
#include <cmath>

using namespace vessel;
using vessel::test::test_tree_phantom;

TEST_CASE("custom cost: E_c written on the typed fields makes the default's cuts and map")
{
    const Mesh tree = test_tree_phantom(3);
    FlattenOptions options;
    options.relief.max_cuts = 0;
    const FlattenResult builtin = flatten(tree, options);
    options.cost.custom = [](const Mesh& mesh, SmartHalfedgeHandle h, const VesselFields& f) {
        return CurvatureCost{f.direction}(mesh, h);
    };
    const FlattenResult custom = flatten(tree, options);
    REQUIRE(custom.plan.paths.size() == builtin.plan.paths.size());
    for (std::size_t i = 0; i < custom.plan.paths.size(); ++i)
        CHECK(custom.plan.paths[i].halfedges == builtin.plan.paths[i].halfedges);
    CHECK(custom.uv == builtin.uv);
}

TEST_CASE("custom cost: the fields are stage Z's, row per vertex of the uncut mesh")
{
    const Mesh tree = test_tree_phantom(3);
    const std::vector<BoundaryLoop> loops = boundary_loops(tree);
    int calls = 0;
    bool checked = false;
    FlattenOptions options;
    options.relief.max_cuts = 0;
    options.cost.custom = [&](const Mesh& mesh, SmartHalfedgeHandle h, const VesselFields& f) {
        ++calls;
        if (!checked)
        {
            checked = true;
            const auto n = static_cast<Eigen::Index>(mesh.n_vertices());
            CHECK(mesh.n_vertices() == tree.n_vertices());  // uncut
            REQUIRE(f.direction->rows() == n);
            REQUIRE(f.geodesic->size() == n);
            REQUIRE(f.longitudinal->size() == n);
            REQUIRE(f.kmax->size() == n);
            CHECK(f.mean_edge == doctest::Approx(mean_edge_length(mesh)));
            CHECK(f.kmax->minCoeff() >= 0.0);
            // The same values as the named properties.
            OpenMesh::VPropHandleT<OpenMesh::Vec3d> z;
            OpenMesh::VPropHandleT<double> g;
            REQUIRE(mesh.get_property_handle(z, prop::direction));
            REQUIRE(mesh.get_property_handle(g, prop::geodesic));
            for (auto v : mesh.vertices())
            {
                CHECK(to_eigen(mesh.property(z, v)) == f.direction->row(v.idx()).transpose());
                CHECK(mesh.property(g, v) == (*f.geodesic)[v.idx()]);
            }
            // Distance and harmonic coordinate start at the inlet; on an outlet the coordinate
            // is the loop's mean distance.
            for (auto v : loops[0].vertices)
                CHECK((*f.longitudinal)[v.idx()] == doctest::Approx(0.0));
            CHECK(f.geodesic->minCoeff() == doctest::Approx(0.0));
            double mean = 0.0;
            for (auto v : loops[1].vertices)
                mean += (*f.geodesic)[v.idx()] / static_cast<double>(loops[1].vertices.size());
            CHECK(mean > 0.0);
            for (auto v : loops[1].vertices)
                CHECK((*f.longitudinal)[v.idx()] == doctest::Approx(mean));
        }
        return CurvatureCost{f.direction}(mesh, h);
    };
    flatten(tree, options);
    CHECK(checked);
    CHECK(calls == static_cast<int>(tree.n_halfedges()));
}

TEST_CASE("custom cost: a cost without the fields is taken as before")
{
    const Mesh tree = test_tree_phantom(3);
    int calls = 0;
    FlattenOptions options;
    options.relief.max_cuts = 0;
    options.cost.custom = [&](const Mesh& mesh, SmartHalfedgeHandle h) {
        ++calls;
        return mesh.calc_edge_length(h);
    };
    const FlattenResult r = flatten(tree, options);
    CHECK(calls == static_cast<int>(tree.n_halfedges()));
    CHECK(r.plan.paths.size() == 3);
}

TEST_CASE("custom cost: price_facing makes the wall facing the viewpoint dearer, the far wall not")
{
    // A straight tube along z (outward normals), seen from far out on +x: the halfedges on the
    // +x side cost up to 1 + weight times as much, those on the -x side as much as before.
    HelicalTubeOptions straight;
    straight.helix_radius = 0.0;
    const Mesh tube = helical_tube(straight);
    const HalfedgeWeights base = evaluate_cost(tube, LengthCost{1.0});
    HalfedgeWeights priced = base;
    const Eigen::Vector3d viewpoint(100.0, 0.0, 6.0);
    price_facing(tube, viewpoint, 30.0, priced);
    double front = 0.0;
    for (auto h : tube.halfedges())
    {
        const double x = 0.5 * (tube.point(h.from())[0] + tube.point(h.to())[0]);
        const double ratio = priced[h.idx()] / base[h.idx()];
        CHECK(ratio >= 1.0);
        CHECK(ratio <= 31.0 + 1e-12);
        if (x < -0.1)
            CHECK(ratio == 1.0);
        if (x > 0.9)
            front = std::max(front, ratio);
    }
    CHECK(front > 25.0);
    HalfedgeWeights free(tube.n_halfedges(), 0.0);
    price_facing(tube, viewpoint, 30.0, free);
    CHECK(*std::max_element(free.begin(), free.end()) == 0.0);

    HalfedgeWeights short_weights(3, 1.0);
    CHECK_THROWS_AS(price_facing(tube, viewpoint, 30.0, short_weights), InvalidInputError);
    CHECK_THROWS_AS(price_facing(tube, Eigen::Vector3d::Constant(NAN), 30.0, priced),
                    InvalidInputError);
    CHECK_THROWS_AS(price_facing(tube, viewpoint, -1.0, priced), InvalidInputError);
    CostOptions bad;
    bad.facing_weight = -1.0;
    CHECK_THROWS_AS(bad.validate(), InvalidInputError);
}
