#include <doctest/doctest.h>

#include "support/meshes.h"
#include "vessel/area_polish.h"
#include "vessel/centre_pull.h"
#include "vessel/errors.h"
#include "vessel/embedding.h"
#include "vessel/injective.h"
#include "vessel/io.h"
#include "vessel/pipeline.h"
#include "vessel/validation.h"

#include <cmath>
#include <string>

using namespace vessel;

namespace {

Eigen::Vector2d centre(const Eigen::MatrixX2d& uv, const std::vector<int>& vertices)
{
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (int v : vertices)
        c += uv.row(v).transpose();
    return c / static_cast<double>(vertices.size());
}

// A pull on the first boundary vertices' centre toward a line 3 units off where it starts.
CentrePull offset_pull(const Mesh& mesh, const Eigen::MatrixX2d& uv, double weight)
{
    CentrePull pull;
    const std::vector<VertexHandle> boundary = test::boundary_vertices(mesh);
    for (std::size_t i = 0; i < 10; ++i)
        pull.vertices.push_back(boundary[i].idx());
    pull.normal = Eigen::Vector2d(0.6, 0.8);
    pull.origin = centre(uv, pull.vertices) + 3.0 * pull.normal;
    pull.weight = weight;
    return pull;
}

double offset(const CentrePull& pull, const Eigen::MatrixX2d& uv)
{
    return pull.normal.dot(centre(uv, pull.vertices) - pull.origin);
}

}  // namespace

TEST_CASE("centre pull: SLIM moves a pulled centre onto its line at no cost in shape")
{
    // SLIM's energy does not see a rigid motion, so one pull is met by moving the map: the
    // centre ends on its line and the surface's energy is the same as without the pull.
    const Mesh mesh = test::cut_cylinder(1.0, 6.0, 32, 40);
    const Eigen::MatrixX2d start = tutte_embedding(mesh);
    InjectiveOptions options;
    options.max_iterations = 200;
    Eigen::MatrixX2d free = start;
    const InjectiveSummary plain = injective_refine(mesh, free, {}, options);
    options.centre_pulls = {offset_pull(mesh, start, 1.0)};
    const CentrePull& pull = options.centre_pulls[0];
    CHECK(std::abs(offset(pull, free)) > 2.0);  // without it, the map stays about where it was
    Eigen::MatrixX2d pulled = start;
    const InjectiveSummary with = injective_refine(mesh, pulled, {}, options);
    CHECK(std::abs(offset(pull, pulled)) < 0.05 * std::abs(offset(pull, free)));
    CHECK(test::count_flips(mesh, pulled) == 0);
    CHECK(with.final_energy == doctest::Approx(plain.final_energy).epsilon(1e-2));
}

TEST_CASE("centre pull: the area polish moves a pulled centre onto its line")
{
    const Mesh mesh = test::cut_cylinder(1.0, 6.0, 32, 40);
    Eigen::MatrixX2d uv = tutte_embedding(mesh);
    injective_refine(mesh, uv, {});
    AreaPolishOptions options;
    options.centre_pulls = {offset_pull(mesh, uv, 1.0)};
    const CentrePull& pull = options.centre_pulls[0];
    const double before = offset(pull, uv);
    area_polish(mesh, uv, {}, options);
    CHECK(std::abs(offset(pull, uv)) < 0.05 * std::abs(before));
    CHECK(test::count_flips(mesh, uv) == 0);
}

TEST_CASE("centre pull: look_pulls holds the inlet and puts each outlet on its ray")
{
    // Two segments of loop 1 count as one outlet; each half of the inlet gets two pulls (u, v).
    Eigen::MatrixX2d uv(6, 2);
    uv << -1, 0, 1, 0, 2, 2, 2, 4, -3, 3, -3, 3;
    std::vector<BoundarySegment> segments(3);
    segments[0].loop = 0;
    segments[0].vertices = {VertexHandle(0), VertexHandle(1)};
    segments[1].loop = 1;
    segments[1].vertices = {VertexHandle(2)};
    segments[2].loop = 1;
    segments[2].vertices = {VertexHandle(3)};
    const std::vector<CentrePull> pulls = look_pulls(segments, uv, 2.5);
    REQUIRE(pulls.size() == 5);  // the inlet's two halves, two pulls each
    for (const CentrePull& p : pulls)
    {
        CHECK(p.weight == 2.5);
        CHECK(p.normal.norm() == doctest::Approx(1.0));
        CHECK(p.normal.dot(centre(uv, p.vertices) - p.origin) == doctest::Approx(0.0));
    }
    CHECK(pulls[0].origin.isApprox(Eigen::Vector2d(-1, 0)));
    CHECK(pulls[2].origin.isApprox(Eigen::Vector2d(1, 0)));
    CHECK(pulls[4].vertices.size() == 2);
    CHECK(pulls[4].origin.isApprox(Eigen::Vector2d::Zero()));  // the inlet's centre
    CHECK(std::abs(pulls[4].normal.dot(Eigen::Vector2d(2, 3).normalized())) < 1e-12);
    segments[0].loop = 2;  // no inlet
    CHECK_THROWS_AS(look_pulls(segments, uv, 1.0), InvalidInputError);
}

TEST_CASE("centre pull: bad pulls are refused")
{
    InjectiveOptions options;
    options.centre_pulls = {CentrePull{}};  // no vertices
    CHECK_THROWS_AS(options.validate(), InvalidInputError);
    options.centre_pulls[0].vertices = {0};
    options.centre_pulls[0].weight = -1.0;
    CHECK_THROWS_AS(options.validate(), InvalidInputError);
    options.centre_pulls[0].weight = 1.0;
    options.centre_pulls[0].normal = Eigen::Vector2d(1, 1);
    CHECK_THROWS_AS(options.validate(), InvalidInputError);
    options.centre_pulls[0].normal = Eigen::Vector2d(0, 1);
    CHECK_NOTHROW(options.validate());
    const Mesh mesh = test::cut_cylinder(1.0, 2.0, 8, 4);
    Eigen::MatrixX2d uv = tutte_embedding(mesh);
    options.centre_pulls[0].vertices = {static_cast<int>(mesh.n_vertices())};
    CHECK_THROWS_AS(injective_refine(mesh, uv, {}, options), InvalidInputError);
}

TEST_CASE("overlaps with a look pull: the pulmonary Glenn tree keeps its outlets above the inlet "
          "and nearer the walk order, one-to-one")
{
    // Measured (docs/overlaps.md, "Look pull"): by default 1 of 20 outlets below the inlet and
    // 22 walk inversions (SLIM's scaffold phase and then the polish pull the branches into a
    // blob); --look-pull 100: 0 below, 3 inversions, mean |log area| 0.0097 -> 0.0220.
    const TreeSurface surface = load_tree_surface(std::string(VESSEL_SHARED_DATA) +
                                                  "/svfsi-tests/pulmonary-glenn-wall.ply");
    const FlattenResult plain = flatten(surface.mesh, FlattenOptions());
    FlattenOptions options;
    options.look_pull = 100.0;
    const FlattenResult pulled = flatten(surface.mesh, options);
    CHECK(pulled.quality.flipped_triangles == 0);
    CHECK(pulled.quality.overlapping_triangles == 0);
    CHECK(boundary_self_intersection(pulled.mesh, pulled.uv).first == -1);
    CHECK(pulled.look.outlets == 20);
    CHECK(pulled.look.outlets_below_inlet == 0);
    CHECK(pulled.look.area_below_inlet < 0.005);
    CHECK(3 * pulled.look.walk_inversions <= plain.look.walk_inversions);
    CHECK(pulled.look.mean_bearing_error_deg < 0.5 * plain.look.mean_bearing_error_deg);
    // The price, in area (2.3x the default's; not the default for that reason).
    CHECK(pulled.quality.mean_abs_log_area <= 3.0 * plain.quality.mean_abs_log_area);
    MESSAGE("Glenn: default " << plain.look.walk_inversions << " walk inversions, "
                              << plain.look.outlets_below_inlet << " below, mean |log area| "
                              << plain.quality.mean_abs_log_area << "; look pull 100: "
                              << pulled.look.walk_inversions << ", "
                              << pulled.look.outlets_below_inlet << ", "
                              << pulled.quality.mean_abs_log_area);
}
