#include <doctest/doctest.h>

#include "vessel/direction/curvature.h"
#include "vessel/direction/direction.h"
#include "vessel/core/errors.h"
#include "vessel/direction/geodesic.h"
#include "vessel/core/operators.h"
#include "vessel/phantom/phantom.h"

#include <cmath>
#include <limits>
#include <random>

using namespace vessel;

namespace {

Eigen::VectorXd random_function(int n, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    Eigen::VectorXd f(n);
    for (int i = 0; i < n; ++i)
        f[i] = uniform(rng);
    return f;
}

// Mean and max of |d - reference| / reference over vertices with reference > min_reference.
std::pair<double, double> relative_error(const Eigen::VectorXd& d, const Eigen::VectorXd& reference,
                                         double min_reference)
{
    double sum = 0.0, max = 0.0;
    int count = 0;
    for (Eigen::Index i = 0; i < d.size(); ++i)
        if (reference[i] > min_reference)
        {
            const double e = std::abs(d[i] - reference[i]) / reference[i];
            sum += e;
            max = std::max(max, e);
            ++count;
        }
    REQUIRE(count > 0);
    return {sum / count, max};
}

}  // namespace

TEST_CASE("operators: cotan Laplacian is symmetric, rows sum to zero, energy matches gradient")
{
    for (const Mesh& mesh : {icosphere(1.0, 3), open_cylinder(1.0, 2.0, 24, 10), torus(3, 1, 30, 12)})
    {
        const Eigen::SparseMatrix<double> L = cotan_laplacian(mesh);
        const int n = static_cast<int>(mesh.n_vertices());
        REQUIRE(L.rows() == n);
        REQUIRE(L.cols() == n);
        const Eigen::SparseMatrix<double> asym = L - Eigen::SparseMatrix<double>(L.transpose());
        CHECK(asym.norm() < 1e-12 * L.norm());
        const Eigen::VectorXd row_sums = L * Eigen::VectorXd::Ones(n);
        CHECK(row_sums.cwiseAbs().maxCoeff() < 1e-12);
        for (int i = 0; i < n; ++i)
            CHECK(L.coeff(i, i) > 0.0);

        // The Dirichlet energy two ways: u^T L u = sum_f area_f |grad u|_f^2.
        const Eigen::VectorXd u = random_function(n, 7);
        const Eigen::MatrixX3d G = face_gradient(mesh, u);
        const Eigen::VectorXd A = face_areas(mesh);
        const double energy = (A.asDiagonal() * G.rowwise().squaredNorm()).sum();
        CHECK(u.dot(L * u) == doctest::Approx(energy).epsilon(1e-10));

        const Eigen::VectorXd M = lumped_mass(mesh);
        CHECK(M.sum() == doctest::Approx(A.sum()).epsilon(1e-12));
        CHECK(M.minCoeff() > 0.0);
    }
}

TEST_CASE("operators: gradient of a linear function is exact")
{
    const Mesh plane = plane_grid(2.0, 12);
    const Eigen::MatrixX3d P = vertex_positions(plane);
    const Eigen::Vector3d a(2.0, -3.0, 0.0);
    const Eigen::VectorXd f = (P * a).array() + 1.0;
    const Eigen::MatrixX3d Gf = face_gradient(plane, f);
    const Eigen::MatrixX3d Gv = vertex_gradient(plane, f);
    CHECK((Gf.rowwise() - a.transpose()).cwiseAbs().maxCoeff() < 1e-12);
    CHECK((Gv.rowwise() - a.transpose()).cwiseAbs().maxCoeff() < 1e-12);

    // On a curved surface the face gradient of a linear function is its projection on the face.
    const Mesh sphere = icosphere(1.0, 2);
    const Eigen::Vector3d b(0.3, -1.0, 2.0);
    const Eigen::MatrixX3d Gs = face_gradient(sphere, vertex_positions(sphere) * b);
    for (auto face : sphere.faces())
    {
        const Eigen::Vector3d N = to_eigen(sphere.calc_face_normal(face)).normalized();
        const Eigen::Vector3d expected = b - b.dot(N) * N;
        CHECK((Gs.row(face.idx()).transpose() - expected).norm() < 1e-12);
    }

    CHECK_THROWS_AS(face_gradient(plane, Eigen::VectorXd::Zero(3)), InvalidInputError);
    CHECK_THROWS_AS(vertex_gradient(plane, Eigen::VectorXd::Zero(3)), InvalidInputError);
}

TEST_CASE("operators: vertex gradient is the face-area-weighted mean of the face gradients")
{
    // Exactly (the same bits): the vertex gradient is made in one pass over the faces, and the
    // cut planner's decisions depend on its last digits through the stream field.
    Mesh mesh = icosphere(1.0, 3);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.02, 0.02);
    for (auto v : mesh.vertices())
        mesh.point(v) += Mesh::Point(jitter(rng), jitter(rng), jitter(rng));
    // One degenerate face (two corners at one point): no gradient, no weight.
    const auto h = mesh.halfedge_handle(FaceHandle(0));
    mesh.point(mesh.to_vertex_handle(mesh.next_halfedge_handle(h))) =
        mesh.point(mesh.from_vertex_handle(h));
    const Eigen::VectorXd f = random_function(static_cast<int>(mesh.n_vertices()), 11);

    const Eigen::MatrixX3d Gf = face_gradient(mesh, f);
    const Eigen::VectorXd A = face_areas(mesh);
    Eigen::MatrixX3d expected = Eigen::MatrixX3d::Zero(mesh.n_vertices(), 3);
    Eigen::VectorXd weight = Eigen::VectorXd::Zero(mesh.n_vertices());
    for (auto face : mesh.faces())
        for (auto v : face.vertices())
        {
            expected.row(v.idx()) += A[face.idx()] * Gf.row(face.idx());
            weight[v.idx()] += A[face.idx()];
        }
    for (Eigen::Index i = 0; i < expected.rows(); ++i)
        if (weight[i] > 0.0)
            expected.row(i) /= weight[i];
    CHECK(A[0] == 0.0);
    CHECK(Gf.row(0).isZero(0.0));
    CHECK(vertex_gradient(mesh, f) == expected);
}

TEST_CASE("geodesic: plane grid distance matches Euclidean from the centre and a corner")
{
    const int n = 60;
    const Mesh mesh = plane_grid(1.0, n);
    const Eigen::MatrixX3d P = vertex_positions(mesh);
    for (const auto bc : {HeatBoundaryCondition::Neumann, HeatBoundaryCondition::Average})
    for (const int source : {(n / 2) * (n + 1) + n / 2, 0, n / 2})
    {
        CAPTURE(static_cast<int>(bc));
        CAPTURE(source);
        HeatGeodesicsOptions options;
        options.boundary_condition = bc;
        const HeatGeodesics solver(mesh, options);
        const Eigen::VectorXd d = solver.distance({VertexHandle(source)});
        const Eigen::VectorXd exact = (P.rowwise() - P.row(source)).rowwise().norm();
        CHECK(d[source] == doctest::Approx(0.0));
        CHECK(d.minCoeff() > -0.02);
        const auto [mean_error, max_error] = relative_error(d, exact, 0.1);
        CHECK(mean_error < 0.03);
        CHECK(max_error < 0.09);
    }
}

TEST_CASE("geodesic: icosphere distance from a pole matches the great-circle distance")
{
    const double r = 2.0;
    const Mesh mesh = icosphere(r, 4);
    const Eigen::MatrixX3d P = vertex_positions(mesh);
    const int source = 0;
    const Eigen::VectorXd d = heat_geodesic_distance(mesh, {VertexHandle(source)});
    Eigen::VectorXd exact(P.rows());
    for (Eigen::Index i = 0; i < P.rows(); ++i)
        exact[i] = r * std::acos(std::clamp(P.row(i).dot(P.row(source)) / (r * r), -1.0, 1.0));
    const auto [mean_error, max_error] = relative_error(d, exact, 0.2 * r);
    CHECK(mean_error < 0.02);
    CHECK(max_error < 0.05);
}

TEST_CASE("geodesic: factor once, query twice")
{
    const Mesh mesh = open_cylinder(1.0, 5.0, 32, 40);
    const HeatGeodesics solver(mesh);
    const std::vector<VertexHandle> a{VertexHandle(0)};
    const std::vector<VertexHandle> b{VertexHandle(static_cast<int>(mesh.n_vertices()) - 1)};
    const Eigen::VectorXd da1 = solver.distance(a);
    const Eigen::VectorXd db = solver.distance(b);
    const Eigen::VectorXd da2 = solver.distance(a);
    CHECK((da1 - da2).cwiseAbs().maxCoeff() == 0.0);
    CHECK((da1 - heat_geodesic_distance(mesh, a)).cwiseAbs().maxCoeff() < 1e-9);
    CHECK((da1 - db).cwiseAbs().maxCoeff() > 1.0);

    // Moving keeps the factorizations.
    HeatGeodesics moved = HeatGeodesics(mesh);
    moved = HeatGeodesics(mesh);
    CHECK((moved.distance(a) - da1).cwiseAbs().maxCoeff() < 1e-9);

    // Two sources: close to the pointwise minimum of the single-source distances.
    const Eigen::VectorXd dab = solver.distance({a[0], b[0]});
    const Eigen::VectorXd nearest = da1.cwiseMin(db);
    CHECK((dab - nearest).cwiseAbs().maxCoeff() < 0.1 * 5.0);
}

TEST_CASE("geodesic: distance from a cylinder rim is the height")
{
    const double length = 6.0;
    const Mesh mesh = open_cylinder(1.0, length, 48, 48);
    std::vector<VertexHandle> rim;
    for (auto v : mesh.vertices())
        if (mesh.point(v)[2] == 0.0)
            rim.push_back(v);
    for (const auto bc : {HeatBoundaryCondition::Neumann, HeatBoundaryCondition::Average})
    {
        HeatGeodesicsOptions options;
        options.boundary_condition = bc;
        const Eigen::VectorXd d = heat_geodesic_distance(mesh, rim, options);
        for (auto v : mesh.vertices())
            CHECK(d[v.idx()] == doctest::Approx(mesh.point(v)[2]).epsilon(0.01).scale(length));
    }
}

TEST_CASE("geodesic: cylinder distance from an interior vertex, both boundary conditions")
{
    const Mesh mesh = open_cylinder(1.0, 6.0, 48, 48);
    const int source = 24 * 48;
    const auto ps = mesh.point(VertexHandle(source));
    Eigen::VectorXd exact(mesh.n_vertices());
    for (auto v : mesh.vertices())
    {
        // Geodesics on the unrolled cylinder are straight lines.
        const auto p = mesh.point(v);
        const double angle = std::atan2(p[1], p[0]) - std::atan2(ps[1], ps[0]);
        exact[v.idx()] = std::hypot(std::remainder(angle, 2.0 * M_PI), p[2] - ps[2]);
    }
    for (const auto bc : {HeatBoundaryCondition::Neumann, HeatBoundaryCondition::Average})
    {
        HeatGeodesicsOptions options;
        options.boundary_condition = bc;
        const Eigen::VectorXd d = heat_geodesic_distance(mesh, {VertexHandle(source)}, options);
        const auto [mean_error, max_error] = relative_error(d, exact, 0.3);
        CHECK(mean_error < 0.03);
        CHECK(max_error < 0.1);
    }
}

TEST_CASE("geodesic: align_to_root points the cylinder axis toward the z = 0 rim")
{
    const Mesh mesh = open_cylinder(1.0, 4.0, 64, 32);
    std::vector<VertexHandle> rim;
    for (auto v : mesh.vertices())
        if (mesh.point(v)[2] == 0.0)
            rim.push_back(v);
    const Eigen::VectorXd G = heat_geodesic_distance(mesh, rim);
    const PrincipalCurvature k = principal_curvature(mesh);
    const Eigen::MatrixX3d z = align_to_root(mesh, k.min_direction, G);
    REQUIRE(z.rows() == static_cast<Eigen::Index>(mesh.n_vertices()));
    for (auto v : mesh.vertices())
    {
        CHECK(z.row(v.idx()).norm() == doctest::Approx(1.0));
        if (!v.is_boundary())
            CHECK(z(v.idx(), 2) < -0.99);
    }
    // Flipping the input signs does not change the result.
    const Eigen::MatrixX3d z2 = align_to_root(mesh, -k.min_direction, G);
    CHECK((z - z2).cwiseAbs().maxCoeff() == 0.0);

    CHECK_THROWS_AS(align_to_root(mesh, k.min_direction.topRows(3), G), InvalidInputError);
    CHECK_THROWS_AS(align_to_root(mesh, k.min_direction, G.head(3)), InvalidInputError);
}

TEST_CASE("geodesic: vertices without a path to a source are infinitely far")
{
    Mesh mesh = plane_grid(1.0, 4);
    const auto isolated = mesh.add_vertex({5.0, 5.0, 0.0});
    const Eigen::VectorXd d = heat_geodesic_distance(mesh, {VertexHandle(0)});
    CHECK(d[isolated.idx()] == std::numeric_limits<double>::infinity());
    CHECK(d.head(d.size() - 1).allFinite());
}

TEST_CASE("geodesic: invalid input throws")
{
    const Mesh mesh = plane_grid(1.0, 4);
    const HeatGeodesics solver(mesh);
    CHECK_THROWS_AS(solver.distance({}), InvalidInputError);
    CHECK_THROWS_AS(solver.distance({VertexHandle()}), InvalidInputError);
    CHECK_THROWS_AS(solver.distance({VertexHandle(static_cast<int>(mesh.n_vertices()))}),
                    InvalidInputError);
    CHECK_THROWS_AS(heat_geodesic_distance(mesh, {}), InvalidInputError);

    HeatGeodesicsOptions bad;
    bad.time_factor = 0.0;
    CHECK_THROWS_AS(bad.validate(), InvalidInputError);
    CHECK_THROWS_AS((HeatGeodesics{mesh, bad}), InvalidInputError);
    bad.time_factor = std::numeric_limits<double>::infinity();
    CHECK_THROWS_AS((HeatGeodesics{mesh, bad}), InvalidInputError);
    bad.time_factor = std::nan("");
    CHECK_THROWS_AS((HeatGeodesics{mesh, bad}), InvalidInputError);
    HeatGeodesicsOptions bad_bc;
    bad_bc.boundary_condition = static_cast<HeatBoundaryCondition>(7);
    CHECK_THROWS_AS(bad_bc.validate(), InvalidInputError);
    CHECK_THROWS_AS((HeatGeodesics{mesh, bad_bc}), InvalidInputError);

    Mesh points_only;
    points_only.add_vertex({0, 0, 0});
    CHECK_THROWS_AS(HeatGeodesics{points_only}, InvalidInputError);
    CHECK_THROWS_AS(HeatGeodesics{Mesh()}, InvalidInputError);
}
