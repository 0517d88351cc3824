#include <doctest/doctest.h>

#include "vessel/cut/boundary.h"
#include "vessel/direction/curvature.h"
#include "vessel/direction/direction.h"
#include "vessel/core/errors.h"
#include "vessel/direction/geodesic.h"
#include "vessel/phantom/phantom.h"

#include <cmath>

using namespace vessel;

namespace {

// A zone of the unit sphere between latitudes lo and hi (radians): open_cylinder()'s rings
// moved onto the sphere, so the faces keep their outward winding. Every point is an umbilic
// (k_min = k_max), so the minimal curvature direction is noise, while the vessel direction
// (toward the larger rim at lo, the inlet) is known: minus the latitude tangent.
Mesh sphere_zone(double lo, double hi, int n_around, int n_along)
{
    Mesh mesh = open_cylinder(1.0, 1.0, n_around, n_along);
    for (auto v : mesh.vertices())
    {
        const auto p = mesh.point(v);
        const double t = std::atan2(p[1], p[0]);
        const double phi = lo + (hi - lo) * p[2];
        mesh.set_point(v, {std::cos(phi) * std::cos(t), std::cos(phi) * std::sin(t), std::sin(phi)});
    }
    return mesh;
}

Eigen::Vector3d toward_inlet(const Mesh& mesh, VertexHandle v)
{
    const auto p = mesh.point(v);
    const double phi = std::asin(p[2]);
    const double t = std::atan2(p[1], p[0]);
    return -Eigen::Vector3d(-std::sin(phi) * std::cos(t), -std::sin(phi) * std::sin(t),
                            std::cos(phi));
}

struct Fields
{
    std::vector<BoundaryLoop> loops;
    PrincipalCurvature curvature;
    Eigen::VectorXd G;
};

Fields fields(const Mesh& mesh)
{
    Fields f;
    f.loops = boundary_loops(mesh);
    f.curvature = principal_curvature(mesh);
    f.G = heat_geodesic_distance(mesh, f.loops[0].vertices);
    return f;
}

// Mean of <z, expected> over interior vertices (1 = along the vessel toward the inlet).
template <class Expected>
double mean_agreement(const Mesh& mesh, const Eigen::MatrixX3d& z, Expected expected)
{
    double sum = 0.0;
    int n = 0;
    for (auto v : mesh.vertices())
        if (!v.is_boundary())
        {
            sum += z.row(v.idx()).dot(expected(v));
            ++n;
        }
    return sum / n;
}

}  // namespace

TEST_CASE("direction: curvature anisotropy is 1 on a cylinder and 0 on a sphere")
{
    const Mesh tube = open_cylinder(1.0, 4.0, 48, 40);
    const Eigen::VectorXd a_tube = curvature_anisotropy(principal_curvature(tube));
    const Mesh ball = icosphere(1.0, 4);
    const Eigen::VectorXd a_ball = curvature_anisotropy(principal_curvature(ball));
    double tube_min = 1.0;
    for (auto v : tube.vertices())
        if (!v.is_boundary())
            tube_min = std::min(tube_min, a_tube[v.idx()]);
    MESSAGE("anisotropy: cylinder interior min " << tube_min << ", sphere max "
                                                 << a_ball.maxCoeff());
    CHECK(tube_min > 0.95);
    CHECK(a_ball.maxCoeff() < 0.05);
    CHECK(a_ball.minCoeff() >= 0.0);
}

TEST_CASE("direction: on a sphere zone z follows the harmonic guide, not the umbilic noise")
{
    const Mesh mesh = sphere_zone(-M_PI / 6.0, M_PI / 3.0, 64, 40);
    const Fields f = fields(mesh);
    REQUIRE(f.loops.size() == 2);
    const auto expected = [&](VertexHandle v) { return toward_inlet(mesh, v); };
    DirectionOptions pure;
    pure.confident_anisotropy = 0.0;
    const Eigen::MatrixX3d z_pure = vessel_direction(mesh, f.curvature, f.loops, f.G, pure);
    DirectionOptions guided;
    guided.confident_anisotropy = 0.6;
    const Eigen::MatrixX3d z = vessel_direction(mesh, f.curvature, f.loops, f.G, guided);
    const double pure_agreement = mean_agreement(mesh, z_pure, expected);
    const double agreement = mean_agreement(mesh, z, expected);
    MESSAGE("sphere zone: mean <z, toward inlet> pure curvature " << pure_agreement
                                                                  << ", guided (0.6) "
                                                                  << agreement);
    CHECK(agreement > 0.99);
    CHECK(pure_agreement < 0.9);
    for (auto v : mesh.vertices())
        CHECK(z.row(v.idx()).norm() == doctest::Approx(1.0));
}

TEST_CASE("direction: on a cylinder the guided policy keeps the curvature direction")
{
    const Mesh mesh = open_cylinder(1.0, 4.0, 48, 40);
    const Fields f = fields(mesh);
    const Eigen::MatrixX3d z_pure = align_to_root(mesh, f.curvature.min_direction, f.G);
    DirectionOptions guided;
    guided.confident_anisotropy = 0.9;
    const Eigen::MatrixX3d z = vessel_direction(mesh, f.curvature, f.loops, f.G, guided);
    CHECK(vessel_direction(mesh, f.curvature, f.loops, f.G) == z_pure);  // the default: pure
    CHECK((z - z_pure).cwiseAbs().maxCoeff() < 1e-12);
    // Both rims are equally long; z points along the axis toward whichever is the inlet.
    const double inlet_side = mesh.point(f.loops[0].vertices.front())[2] > 2.0 ? 1.0 : -1.0;
    const Eigen::Vector3d axis(0, 0, inlet_side);
    CHECK(mean_agreement(mesh, z, [&](VertexHandle) { return axis; }) > 0.99);
}

TEST_CASE("direction: confident_direction blends by anisotropy and checks its input")
{
    Eigen::MatrixX3d z(3, 3), guide(3, 3);
    z << 1, 0, 0, 1, 0, 0, 1, 0, 0;
    guide << 0, 1, 0, 0, 1, 0, 0, 0, 0;
    Eigen::VectorXd a(3);
    a << 0.0, 0.3, 0.0;
    DirectionOptions options;
    options.confident_anisotropy = 0.6;
    const Eigen::MatrixX3d b = confident_direction(z, a, guide, options);
    CHECK(b.row(0).isApprox(Eigen::RowVector3d(0, 1, 0)));  // no anisotropy: the guide
    CHECK(b.row(1).isApprox(Eigen::RowVector3d(1, 1, 0).normalized()));  // halfway
    CHECK(b.row(2).isApprox(Eigen::RowVector3d(1, 0, 0)));  // no guide: kept
    options.confident_anisotropy = 0.0;
    CHECK(confident_direction(z, a, guide, options) == z);
    options.confident_anisotropy = 1.5;
    CHECK_THROWS_AS(confident_direction(z, a, guide, options), InvalidInputError);
    CHECK_THROWS_AS(confident_direction(z, a.head(2), guide), InvalidInputError);
}
