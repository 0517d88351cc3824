#include "vessel/map/lscm.h"
#include "vessel/core/errors.h"
#include "vessel/phantom/phantom.h"

#include "support/meshes.h"

#include <doctest/doctest.h>

#include <complex>

using namespace vessel;

namespace {

using Complex = std::complex<double>;

Complex at(const Eigen::MatrixX2d& uv, int i)
{
    return {uv(i, 0), uv(i, 1)};
}

// Planar position of grid vertex i before posed_grid's rigid motion.
Complex grid_position(double size, int n, int i)
{
    return {size * (i % (n + 1)) / n, size * (i / (n + 1)) / n};
}

}  // namespace

TEST_CASE("lscm: a tilted planar grid is reproduced up to a similarity")
{
    const double size = 2.0;
    const int n = 12;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.rotate(Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, 2, 3).normalized()));
    pose.pretranslate(Eigen::Vector3d(0.5, -1.0, 3.0));
    const Mesh mesh = test::posed_grid(size, n, pose);
    const int last = static_cast<int>(mesh.n_vertices()) - 1;

    const Pins pins = {{VertexHandle(0), {0.3, -0.2}}, {VertexHandle(last), {-1.0, 2.5}}};
    const Eigen::MatrixX2d uv = lscm(mesh, pins);

    // The similarity z -> a w + b through the two pins must map every vertex.
    const Complex w0 = grid_position(size, n, 0), w1 = grid_position(size, n, last);
    const Complex a = (at(uv, last) - at(uv, 0)) / (w1 - w0), b = at(uv, 0) - a * w0;
    double worst = 0.0;
    for (int i = 0; i <= last; ++i)
        worst = std::max(worst, std::abs(at(uv, i) - (a * grid_position(size, n, i) + b)));
    CHECK(worst < 1e-8);
    CHECK(at(uv, 0) == Complex(0.3, -0.2));
    CHECK(at(uv, last) == Complex(-1.0, 2.5));
    CHECK(test::count_flips(mesh, uv) == 0);
    CHECK(conformal_energy(mesh, uv) < 1e-12);
}

TEST_CASE("lscm: pinning every boundary vertex of a flat grid reproduces the interior")
{
    const double size = 3.0;
    const int n = 10;
    const Mesh mesh = test::posed_grid(size, n, Eigen::Isometry3d::Identity());
    // Targets: a rotated, scaled, shifted copy of the grid (still conformal).
    const Complex a = std::polar(1.7, 0.4), b(-2.0, 1.0);
    Pins pins;
    for (auto v : test::boundary_vertices(mesh))
    {
        const Complex z = a * grid_position(size, n, v.idx()) + b;
        pins.push_back({v, {z.real(), z.imag()}});
    }
    REQUIRE(pins.size() == static_cast<std::size_t>(4 * n));

    const Eigen::MatrixX2d uv = lscm(mesh, pins);
    double worst = 0.0;
    for (auto v : mesh.vertices())
        worst =
            std::max(worst, std::abs(at(uv, v.idx()) - (a * grid_position(size, n, v.idx()) + b)));
    CHECK(worst < 1e-10);
}

TEST_CASE("lscm: conformal energy agrees per triangle and as a quadratic form")
{
    const Mesh mesh = test::cut_cylinder(1.0, 3.0, 24, 12);
    const int n = static_cast<int>(mesh.n_vertices());
    const int top_corner = n - 1;  // vertex (n_around, n_along)
    const Eigen::MatrixX2d uv =
        lscm(mesh, {{VertexHandle(0), {0.0, 0.0}}, {VertexHandle(top_corner), {6.0, 3.0}}});
    CHECK(test::count_flips(mesh, uv) == 0);

    const Eigen::SparseMatrix<double> L = lscm_energy_matrix(mesh);
    Eigen::VectorXd x(2 * n);
    x << uv.col(0), uv.col(1);
    const double quadratic = 0.5 * x.dot(L * x);
    const double per_triangle = conformal_energy(mesh, uv);
    CHECK(per_triangle > 0.0);
    CHECK(quadratic == doctest::Approx(per_triangle).epsilon(1e-9));

    // L_C is symmetric, annihilates translations, and is positive semi-definite.
    CHECK((Eigen::SparseMatrix<double>(L.transpose()) - L).norm() < 1e-12);
    Eigen::VectorXd t = Eigen::VectorXd::Zero(2 * n);
    t.head(n).setOnes();
    CHECK((L * t).norm() < 1e-10);
    CHECK(conformal_energy(mesh, Eigen::MatrixX2d::Random(n, 2)) >= 0.0);
}

TEST_CASE("lscm: pins at a plausible but inexact layout give an unflipped map")
{
    const int n_around = 32, n_along = 16;
    const Mesh mesh = test::cut_cylinder(1.0, 4.0, n_around, n_along);
    const double width = 2.0 * M_PI;
    Pins pins;  // the two rims, stretched by 10% against the true length
    for (int i = 0; i <= n_around; ++i)
    {
        const double u = width * i / n_around;
        pins.push_back({VertexHandle(i), {u, 0.0}});
        pins.push_back({VertexHandle(n_along * (n_around + 1) + i), {1.1 * u, 4.4}});
    }
    const Eigen::MatrixX2d uv = lscm(mesh, pins);
    CHECK(test::count_flips(mesh, uv) == 0);
    for (const Pin& p : pins)
        CHECK((uv.row(p.vertex.idx()).transpose() - p.uv).norm() == 0.0);
}

TEST_CASE("lscm: invalid input is rejected")
{
    const Mesh mesh = test::posed_grid(1.0, 4, Eigen::Isometry3d::Identity());
    const VertexHandle a(0), b(24);
    CHECK_THROWS_AS(lscm(mesh, {}), InvalidInputError);
    CHECK_THROWS_AS(lscm(mesh, {{a, {0, 0}}}), InvalidInputError);
    CHECK_THROWS_AS(lscm(mesh, {{a, {0, 0}}, {VertexHandle(), {1, 0}}}), InvalidInputError);
    CHECK_THROWS_AS(lscm(mesh, {{a, {0, 0}}, {VertexHandle(25), {1, 0}}}), InvalidInputError);
    CHECK_THROWS_AS(lscm(mesh, {{a, {0, 0}}, {a, {1, 0}}}), InvalidInputError);
    CHECK_THROWS_AS(lscm(mesh, {{a, {1, 1}}, {b, {1, 1}}}), InvalidInputError);
    CHECK_THROWS_AS(lscm(mesh, {{a, {0, 0}}, {b, {NAN, 0}}}), InvalidInputError);
    CHECK_THROWS_AS(lscm(Mesh(), {{a, {0, 0}}, {b, {1, 0}}}), InvalidInputError);
    CHECK_THROWS_AS(conformal_energy(mesh, Eigen::MatrixX2d::Zero(3, 2)), InvalidInputError);
}

TEST_CASE("lscm: a singular system falls back to a regularised solve instead of failing")
{
    // Two separate flat grids, pins on the first only: the second's block of the conformal
    // system is singular (its similarities cost nothing), so CHOLMOD's LLT cannot factor it.
    const double size = 2.0;
    const int n = 6;
    const Mesh a = test::posed_grid(size, n, Eigen::Isometry3d::Identity());
    Mesh mesh = a;
    const int na = static_cast<int>(a.n_vertices());
    for (auto v : a.vertices())
        mesh.add_vertex(a.point(v) + Mesh::Point(5.0, 0.0, 0.0));
    for (auto f : a.faces())
    {
        std::vector<VertexHandle> corners;
        for (auto v : a.fv_range(f))
            corners.push_back(VertexHandle(v.idx() + na));
        mesh.add_face(corners);
    }
    const int last = na - 1;
    const Pins pins = {{VertexHandle(0), {0.0, 0.0}}, {VertexHandle(last), {size, size}}};
    Eigen::MatrixX2d uv;
    REQUIRE_NOTHROW(uv = lscm(mesh, pins));
    CHECK(uv.allFinite());
    double worst = 0.0;  // the pinned grid is still reproduced exactly
    for (int i = 0; i < na; ++i)
        worst = std::max(worst, std::abs(at(uv, i) - grid_position(size, n, i)));
    CHECK(worst < 1e-8);
}
