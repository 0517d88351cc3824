#include <doctest/doctest.h>

#include "vessel/direction/curvature.h"
#include "vessel/core/errors.h"
#include "vessel/phantom/phantom.h"

#include <cmath>

using namespace vessel;

TEST_CASE("curvature: cylinder min direction is the axis, k_max = 1/r, k_min = 0")
{
    const double r = 2.0;
    // Edges around (2 pi r / 96 = 0.13) and along (0.125) of similar length.
    const Mesh mesh = open_cylinder(r, 6.0, 96, 48);
    const PrincipalCurvature k = principal_curvature(mesh);
    REQUIRE(k.k_min.size() == static_cast<Eigen::Index>(mesh.n_vertices()));
    int checked = 0;
    for (auto v : mesh.vertices())
    {
        const int i = v.idx();
        CHECK(k.min_direction.row(i).norm() == doctest::Approx(1.0));
        CHECK(k.max_direction.row(i).norm() == doctest::Approx(1.0));
        CHECK(std::abs(k.min_direction.row(i).dot(k.max_direction.row(i))) < 1e-9);
        if (v.is_boundary())
            continue;
        ++checked;
        CHECK(std::abs(k.min_direction(i, 2)) > 0.99);
        CHECK(k.k_max[i] == doctest::Approx(1.0 / r).epsilon(0.03));
        CHECK(std::abs(k.k_min[i]) < 0.02 / r);
        // Directions are tangent: orthogonal to the radial (normal) direction.
        const Eigen::Vector3d radial(mesh.point(v)[0], mesh.point(v)[1], 0.0);
        CHECK(std::abs(k.min_direction.row(i).dot(radial.normalized())) < 0.01);
    }
    CHECK(checked == 96 * 47);
}

TEST_CASE("curvature: torus min direction follows the major circle, k_max = 1/r")
{
    const double R = 3.0, r = 1.0;
    const Mesh mesh = torus(R, r, 160, 48);
    const PrincipalCurvature k = principal_curvature(mesh);
    for (auto v : mesh.vertices())
    {
        const int i = v.idx();
        const auto p = mesh.point(v);
        const double rho = std::hypot(p[0], p[1]);
        const Eigen::Vector3d toroidal(-p[1] / rho, p[0] / rho, 0.0);
        // cos of the minor angle, from the distance to the rotation axis.
        const double cos_w = (rho - R) / r;
        CHECK(std::abs(k.min_direction.row(i).dot(toroidal)) > 0.99);
        CHECK(k.k_max[i] == doctest::Approx(1.0 / r).epsilon(0.05));
        CHECK(k.k_min[i] == doctest::Approx(cos_w / rho).epsilon(0.05).scale(1.0));
    }
}

TEST_CASE("curvature: sphere is umbilic with k = 1/r, plane is flat")
{
    const double r = 3.0;
    const Mesh sphere = icosphere(r, 4);
    const PrincipalCurvature ks = principal_curvature(sphere);
    for (Eigen::Index i = 0; i < ks.k_min.size(); ++i)
    {
        CHECK(ks.k_min[i] == doctest::Approx(1.0 / r).epsilon(0.02));
        CHECK(ks.k_max[i] == doctest::Approx(1.0 / r).epsilon(0.02));
    }

    const Mesh plane = plane_grid(1.0, 20);
    const PrincipalCurvature kp = principal_curvature(plane);
    CHECK(kp.k_min.cwiseAbs().maxCoeff() < 1e-9);
    CHECK(kp.k_max.cwiseAbs().maxCoeff() < 1e-9);
    CHECK(kp.min_direction.col(2).cwiseAbs().maxCoeff() < 1e-9);
}

TEST_CASE("curvature: serial and parallel runs agree")
{
    const Mesh mesh = torus(3.0, 1.0, 60, 24);
    CurvatureOptions serial;
    serial.parallel = false;
    const PrincipalCurvature a = principal_curvature(mesh, serial);
    const PrincipalCurvature b = principal_curvature(mesh);
    CHECK((a.k_min - b.k_min).cwiseAbs().maxCoeff() == 0.0);
    CHECK((a.k_max - b.k_max).cwiseAbs().maxCoeff() == 0.0);
    CHECK((a.min_direction - b.min_direction).cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("curvature: small balls grow by rings to min_neighbors")
{
    // A ball smaller than one edge holds no neighbour; the ring growth must still give a fit.
    const Mesh mesh = open_cylinder(1.0, 3.0, 64, 30);
    CurvatureOptions options;
    options.scale = 0.1;
    const PrincipalCurvature k = principal_curvature(mesh, options);
    for (auto v : mesh.vertices())
        if (!v.is_boundary())
            CHECK(k.k_max[v.idx()] == doctest::Approx(1.0).epsilon(0.03));
    CHECK(k.k_min.allFinite());
    CHECK(k.min_direction.allFinite());
}

TEST_CASE("curvature: invalid input throws")
{
    const Mesh mesh = icosphere(1.0, 1);
    CurvatureOptions bad_scale;
    bad_scale.scale = 0.0;
    CHECK_THROWS_AS(principal_curvature(mesh, bad_scale), InvalidInputError);
    bad_scale.scale = std::nan("");
    CHECK_THROWS_AS(principal_curvature(mesh, bad_scale), InvalidInputError);
    CurvatureOptions bad_neighbors;
    bad_neighbors.min_neighbors = 4;
    CHECK_THROWS_AS(bad_neighbors.validate(), InvalidInputError);
    CHECK_THROWS_AS(principal_curvature(mesh, bad_neighbors), InvalidInputError);

    Mesh empty;
    CHECK_THROWS_AS(principal_curvature(empty), InvalidInputError);
    Mesh points_only;
    points_only.add_vertex({0, 0, 0});
    CHECK_THROWS_AS(principal_curvature(points_only), InvalidInputError);
}
