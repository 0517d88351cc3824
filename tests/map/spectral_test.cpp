#include "vessel/map/spectral.h"
#include "vessel/core/errors.h"
#include "vessel/map/lscm.h"
#include "vessel/phantom/phantom.h"

#include "support/meshes.h"

#include <doctest/doctest.h>

#include <cmath>

using namespace vessel;

namespace {

double area_ratio(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    return test::uv_signed_areas(mesh, uv).sum() / face_areas(mesh).sum();
}

}  // namespace

TEST_CASE("spectral: a tilted flat grid maps to a congruent copy")
{
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.rotate(Eigen::AngleAxisd(1.1, Eigen::Vector3d(-1, 2, 0.5).normalized()));
    pose.pretranslate(Eigen::Vector3d(4, 0, -2));
    const Mesh mesh = test::posed_grid(2.0, 14, pose);
    const Eigen::MatrixX2d uv = spectral_conformal(mesh);

    REQUIRE(uv.rows() == static_cast<Eigen::Index>(mesh.n_vertices()));
    CHECK(test::count_flips(mesh, uv) == 0);
    CHECK(area_ratio(mesh, uv) == doctest::Approx(1.0).epsilon(1e-10));
    CHECK(conformal_energy(mesh, uv) < 1e-10 * face_areas(mesh).sum());
    // Conformal with the right area on a flat mesh means isometric.
    CHECK(test::max_edge_length_error(mesh, uv) < 1e-6);
    CHECK(uv.colwise().mean().norm() < 1e-12);
}

TEST_CASE("spectral: a cut cylinder unrolls without flips and with its area")
{
    const Mesh mesh = test::cut_cylinder(1.0, 3.0, 32, 12);
    const Eigen::MatrixX2d uv = spectral_conformal(mesh);
    CHECK(test::count_flips(mesh, uv) == 0);
    CHECK(area_ratio(mesh, uv) == doctest::Approx(1.0).epsilon(1e-10));
    // The triangulated prism is developable: the unrolling is an isometry.
    CHECK(conformal_energy(mesh, uv) < 1e-8 * face_areas(mesh).sum());
    CHECK(test::max_edge_length_error(mesh, uv) < 1e-4);
}

TEST_CASE("spectral: a non-developable disk maps without flips")
{
    const Mesh mesh = test::bumped_grid(2.0, 16, 0.6);
    const Eigen::MatrixX2d uv = spectral_conformal(mesh);
    CHECK(test::count_flips(mesh, uv) == 0);
    CHECK(area_ratio(mesh, uv) == doctest::Approx(1.0).epsilon(1e-10));
    const double energy = conformal_energy(mesh, uv);
    CHECK(energy > 0.0);
    CHECK(energy < 0.05 * face_areas(mesh).sum());
}

TEST_CASE("spectral: invalid input is rejected")
{
    CHECK_THROWS_AS(spectral_conformal(icosphere(1.0, 1)), TopologyError);
    CHECK_THROWS_AS(spectral_conformal(Mesh()), InvalidInputError);
    const Mesh grid = test::posed_grid(1.0, 4, Eigen::Isometry3d::Identity());
    SpectralConformalOptions bad;
    bad.max_iterations = 0;
    CHECK_THROWS_AS(spectral_conformal(grid, bad), InvalidInputError);
    bad = SpectralConformalOptions{};
    bad.tolerance = 0.0;
    CHECK_THROWS_AS(bad.validate(), InvalidInputError);
    bad.tolerance = NAN;
    CHECK_THROWS_AS(bad.validate(), InvalidInputError);
    CHECK_NOTHROW(SpectralConformalOptions{}.validate());
}
