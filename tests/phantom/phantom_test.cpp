#include <doctest/doctest.h>

#include "vessel/cut/boundary.h"
#include "vessel/core/errors.h"
#include "vessel/phantom/phantom.h"

#include <OpenMesh/Tools/Utils/MeshCheckerT.hh>

#include <cmath>
#include <sstream>
#include <vector>

using namespace vessel;

namespace {

int count_components(const Mesh& mesh)
{
    std::vector<int> label(mesh.n_vertices(), -1);
    int n = 0;
    for (auto v0 : mesh.vertices())
    {
        if (label[v0.idx()] >= 0)
            continue;
        std::vector<SmartVertexHandle> stack = {v0};
        label[v0.idx()] = n;
        while (!stack.empty())
        {
            auto v = stack.back();
            stack.pop_back();
            for (auto w : v.vertices())
                if (label[w.idx()] < 0)
                {
                    label[w.idx()] = n;
                    stack.push_back(w);
                }
        }
        ++n;
    }
    return n;
}

// Every vertex is a single fan: at most one outgoing boundary halfedge, none if isolated.
bool every_vertex_one_fan(const Mesh& mesh)
{
    for (auto v : mesh.vertices())
    {
        int n_boundary = 0, n_out = 0;
        for (auto h : v.outgoing_halfedges())
        {
            ++n_out;
            n_boundary += h.is_boundary() ? 1 : 0;
        }
        if (n_out == 0 || n_boundary > 1)
            return false;
    }
    return true;
}

bool every_edge_manifold(const Mesh& mesh)
{
    for (auto e : mesh.edges())
        if (e.h0().is_boundary() && e.h1().is_boundary())
            return false;
    return true;
}

// Volume enclosed after closing each boundary loop with a fan around its centroid; positive
// when the faces are wound with outward normals.
double closed_signed_volume(const Mesh& mesh)
{
    double volume = 0.0;
    for (auto f : mesh.faces())
    {
        auto h = f.halfedge();
        const Eigen::Vector3d a = to_eigen(mesh.point(h.from()));
        const Eigen::Vector3d b = to_eigen(mesh.point(h.to()));
        const Eigen::Vector3d c = to_eigen(mesh.point(h.next().to()));
        volume += a.dot(b.cross(c)) / 6.0;
    }
    for (const auto& loop : boundary_loops(mesh))
        for (auto h : loop.halfedges)
        {
            const Eigen::Vector3d a = to_eigen(mesh.point(mesh.from_vertex_handle(h)));
            const Eigen::Vector3d b = to_eigen(mesh.point(mesh.to_vertex_handle(h)));
            volume += a.dot(b.cross(loop.centroid)) / 6.0;
        }
    return volume;
}

// Checks everything a vessel phantom promises: one component, 2-manifold, genus 0, the expected
// number of boundary loops, outward orientation, no (near) zero-area face.
void check_vessel_surface(const Mesh& mesh, int expected_loops, double edge_length)
{
    REQUIRE(mesh.n_faces() > 0);
    std::ostringstream report;
    OpenMesh::Utils::MeshCheckerT<Mesh> checker(mesh);
    CHECK_MESSAGE(checker.check(OpenMesh::Utils::MeshCheckerT<Mesh>::CHECK_ALL, report),
                  report.str());
    CHECK(count_components(mesh) == 1);
    CHECK(every_vertex_one_fan(mesh));
    CHECK(every_edge_manifold(mesh));
    const auto loops = boundary_loops(mesh);
    CHECK(static_cast<int>(loops.size()) == expected_loops);
    const long chi = static_cast<long>(mesh.n_vertices()) - static_cast<long>(mesh.n_edges()) +
                     static_cast<long>(mesh.n_faces());
    CHECK(chi == 2 - expected_loops);  // genus 0: V - E + F = 2 - 2g - b
    CHECK(closed_signed_volume(mesh) > 0.0);
    const Eigen::VectorXd areas = face_areas(mesh);
    CHECK(areas.minCoeff() > 1e-3 * edge_length * edge_length);
}

bool same_mesh(const Mesh& a, const Mesh& b)
{
    if (a.n_vertices() != b.n_vertices() || a.n_faces() != b.n_faces())
        return false;
    for (auto v : a.vertices())
        if (a.point(v) != b.point(VertexHandle(v.idx())))
            return false;
    return face_indices(a) == face_indices(b);
}

// Fraction of faces whose smallest angle is below min_deg.
double fraction_below(const Mesh& mesh, double min_deg)
{
    int n_bad = 0;
    for (auto f : mesh.faces())
    {
        std::vector<Eigen::Vector3d> p;
        for (auto v : f.vertices())
            p.push_back(to_eigen(mesh.point(v)));
        double smallest = 180.0;
        for (int i = 0; i < 3; ++i)
        {
            const Eigen::Vector3d u = (p[(i + 1) % 3] - p[i]).normalized();
            const Eigen::Vector3d w = (p[(i + 2) % 3] - p[i]).normalized();
            smallest = std::min(smallest, std::acos(std::clamp(u.dot(w), -1.0, 1.0)) * 180 / M_PI);
        }
        n_bad += smallest < min_deg ? 1 : 0;
    }
    return double(n_bad) / mesh.n_faces();
}

}  // namespace

TEST_CASE("phantom: helical tube is an open outward tube with staggered rings")
{
    HelicalTubeOptions options;
    options.turns = 1.5;
    const Mesh mesh = helical_tube(options);
    const double around = 2 * M_PI * options.tube_radius / options.n_around;
    check_vessel_surface(mesh, 2, around);
    CHECK(mesh.n_vertices() % options.n_around == 0);
    CHECK(fraction_below(mesh, 30.0) == 0.0);
    CHECK(same_mesh(mesh, helical_tube(options)));

    // Every vertex lies on the tube at its nominal frame angle.
    const int n = options.n_around;
    for (auto v : mesh.vertices())
    {
        const int i = v.idx() % n, j = v.idx() / n;
        const double expected = std::remainder(2 * M_PI * (i + 0.5 * j) / n, 2 * M_PI);
        const double angle = helical_tube_angle(options, to_eigen(mesh.point(v)));
        CHECK(std::abs(std::remainder(angle - expected, 2 * M_PI)) < 1e-6);
    }
    // No edge is parallel to the centerline: every edge has a non-zero angular extent.
    for (auto e : mesh.edges())
    {
        const double a0 = helical_tube_angle(options, to_eigen(mesh.point(e.v0())));
        const double a1 = helical_tube_angle(options, to_eigen(mesh.point(e.v1())));
        CHECK(std::abs(std::remainder(a1 - a0, 2 * M_PI)) > 0.25 * 2 * M_PI / n);
    }
}

TEST_CASE("phantom: helical_tube_angle is constant along a parallel-transported line")
{
    for (double helix_radius : {4.0, 0.0})
    {
        HelicalTubeOptions options;
        options.helix_radius = helix_radius;
        options.turns = 2.0;
        for (double angle : {-3.0, -1.0, 0.0, 0.7, 2.5, 3.1})
            for (int k = 0; k <= 200; ++k)
            {
                const double u = k / 200.0;
                for (double radius : {0.5, 1.0})
                {
                    const Eigen::Vector3d p = helical_tube_point(options, u, angle, radius);
                    CHECK(std::abs(std::remainder(helical_tube_angle(options, p) - angle,
                                                  2 * M_PI)) < 1e-6);
                }
            }
    }
    // The frame is rotation-minimizing, not Frenet: its normal has no twist about the tangent.
    HelicalTubeOptions options;
    const double du = 1e-5;
    for (double u : {0.1, 0.5, 0.9})
    {
        const Eigen::Vector3d c = helical_tube_point(options, u, 0.0, 0.0);
        const Eigen::Vector3d U0 = helical_tube_point(options, u, 0.0, 1.0) - c;
        const Eigen::Vector3d V0 = helical_tube_point(options, u, M_PI / 2, 1.0) - c;
        const Eigen::Vector3d U1 = helical_tube_point(options, u + du, 0.0, 1.0) -
                                   helical_tube_point(options, u + du, 0.0, 0.0);
        CHECK(std::abs((U1 - U0).dot(V0) / du) < 1e-4);
    }
}

TEST_CASE("phantom: helical tube options are validated")
{
    HelicalTubeOptions options;
    options.tube_radius = 0.0;
    CHECK_THROWS_AS(helical_tube(options), InvalidInputError);
    options = {};
    options.n_around = 2;
    CHECK_THROWS_AS(helical_tube(options), InvalidInputError);
    options = {};
    options.turns = 0.0;
    CHECK_THROWS_AS(helical_tube(options), InvalidInputError);
    options = {};
    options.tube_radius = 5.0;  // beyond the radius of curvature
    CHECK_THROWS_AS(helical_tube(options), InvalidInputError);
    options = {};
    options.turns = 3.0;
    options.pitch = 1.5;  // coils overlap
    CHECK_THROWS_AS(helical_tube(options), InvalidInputError);
    options = {};
    options.edge_length = 0.01;
    CHECK_THROWS_AS(helical_tube(options), InvalidInputError);
}

TEST_CASE("phantom: carotid bifurcation is a valid open tree surface")
{
    for (double stenosis : {0.5, 0.7, 0.0})
    {
        CAPTURE(stenosis);
        CarotidPhantomOptions options;
        options.stenosis = stenosis;
        const Mesh mesh = carotid_phantom(options);
        check_vessel_surface(mesh, 3, options.edge_length);
        CHECK(fraction_below(mesh, 10.0) < 0.01);
        CHECK(mean_edge_length(mesh) > 0.6 * options.edge_length);
        CHECK(mean_edge_length(mesh) < 1.3 * options.edge_length);

        // Loops: the CCA inlet is the longest; each is planar and perpendicular to its vessel.
        const auto loops = boundary_loops(mesh);
        REQUIRE(loops.size() == 3);
        CHECK(loops[0].centroid.isApprox(Eigen::Vector3d(0, 0, -options.cca_length), 1e-2));
        for (const auto& loop : loops)
        {
            const double a = options.branch_angle_deg * M_PI / 180;
            const Eigen::Vector3d axis =
                loop.centroid.z() < 0 ? Eigen::Vector3d(0, 0, -1)
                                      : Eigen::Vector3d(std::copysign(std::sin(a), loop.centroid.x()),
                                                        0, std::cos(a));
            for (auto v : loop.vertices)
                CHECK(std::abs((to_eigen(mesh.point(v)) - loop.centroid).dot(axis)) < 1e-6);
        }
    }
}

TEST_CASE("phantom: carotid stenosis narrows the internal carotid")
{
    // Narrowest cross-section of the ICA: smallest distance of ICA vertices to the ICA axis
    // between the bulb and the end.
    auto throat = [](double stenosis) {
        CarotidPhantomOptions options;
        options.stenosis = stenosis;
        const Mesh mesh = carotid_phantom(options);
        const double a = options.branch_angle_deg * M_PI / 180;
        const Eigen::Vector3d axis(std::sin(a), 0, std::cos(a));
        double r = 1e9;
        for (auto v : mesh.vertices())
        {
            const Eigen::Vector3d p = to_eigen(mesh.point(v));
            const double s = p.dot(axis);
            if (s > 0.3 * options.ica_length && s < 0.9 * options.ica_length)
                r = std::min(r, (p - s * axis).norm());
        }
        return r;
    };
    const double r0 = throat(0.0), r7 = throat(0.7);
    CHECK(r0 == doctest::Approx(2.2).epsilon(0.05));
    CHECK(r7 == doctest::Approx(0.3 * 2.2).epsilon(0.1));
}

TEST_CASE("phantom: carotid is deterministic and validates its options")
{
    CHECK(same_mesh(carotid_phantom(), carotid_phantom()));
    CarotidPhantomOptions options;
    options.stenosis = 0.95;
    CHECK_THROWS_AS(carotid_phantom(options), InvalidInputError);
    options = {};
    options.edge_length = 0.0;
    CHECK_THROWS_AS(carotid_phantom(options), InvalidInputError);
    options = {};
    options.edge_length = 5.0;
    CHECK_THROWS_AS(carotid_phantom(options), InvalidInputError);
    options = {};
    options.ica_radius = -1.0;
    CHECK_THROWS_AS(carotid_phantom(options), InvalidInputError);
    options = {};
    options.branch_angle_deg = 90.0;
    CHECK_THROWS_AS(carotid_phantom(options), InvalidInputError);
    options = {};
    options.eca_length = 2.0;
    CHECK_THROWS_AS(carotid_phantom(options), InvalidInputError);
    CHECK_NOTHROW(CarotidPhantomOptions{}.validate());
}

TEST_CASE("phantom: lateral aneurysm is a valid open tube with a round sac on its side")
{
    for (double sac_radius : {3.0, 5.0})
    {
        CAPTURE(sac_radius);
        AneurysmPhantomOptions options;
        options.sac_radius = sac_radius;
        const Mesh mesh = aneurysm_phantom(options);
        check_vessel_surface(mesh, 2, options.edge_length);
        CHECK(fraction_below(mesh, 10.0) < 0.01);
        const auto loops = boundary_loops(mesh);
        REQUIRE(loops.size() == 2);
        // The loops lie in the end planes, on the parent's circle.
        for (const auto& loop : loops)
        {
            CHECK(std::abs(std::abs(loop.centroid.z()) - 0.5 * options.parent_length) < 1e-6);
            for (auto v : loop.vertices)
            {
                const Eigen::Vector3d p = to_eigen(mesh.point(v));
                CHECK(std::hypot(p.x(), p.y()) ==
                      doctest::Approx(options.parent_radius).epsilon(0.1));
            }
        }
        // The sac: the surface reaches the far side of the sphere (its dome), and away from the
        // neck its vertices lie on the sphere.
        const Eigen::Vector3d centre = aneurysm_sac_centre(options);
        double dome = 0.0;
        int on_sac = 0, on_sphere = 0;
        for (auto v : mesh.vertices())
        {
            const Eigen::Vector3d p = to_eigen(mesh.point(v));
            dome = std::max(dome, p.x());
            if (p.x() > centre.x())
            {
                ++on_sac;
                on_sphere += std::abs((p - centre).norm() - sac_radius) < 0.05 * sac_radius;
            }
        }
        CHECK(dome == doctest::Approx(centre.x() + sac_radius).epsilon(0.02));
        CHECK(on_sac > 100);
        CHECK(on_sphere == on_sac);
    }
    CHECK(same_mesh(aneurysm_phantom(), aneurysm_phantom()));
    {
        // A branch off the sac: a third loop, the shortest, in its end plane 2 parent radii
        // beyond the sphere at 45 degrees between +x and +z.
        AneurysmPhantomOptions options;
        options.branch_radius = 0.8;
        const Mesh mesh = aneurysm_phantom(options);
        check_vessel_surface(mesh, 3, options.edge_length);
        const auto loops = boundary_loops(mesh);
        REQUIRE(loops.size() == 3);
        const Eigen::Vector3d along = Eigen::Vector3d(1, 0, 1).normalized();
        const Eigen::Vector3d end = aneurysm_sac_centre(options) +
                                    (options.sac_radius + 2.0 * options.parent_radius) * along;
        CHECK((loops[2].centroid - end).norm() < 0.05);
        for (auto v : loops[2].vertices)
            CHECK(std::abs((to_eigen(mesh.point(v)) - end).dot(along)) < 1e-6);
    }
    {
        // A tapered parent: the inlet's loop is the longer by about the taper, and the inlet.
        AneurysmPhantomOptions options;
        options.taper = 0.02;
        const Mesh mesh = aneurysm_phantom(options);
        check_vessel_surface(mesh, 2, options.edge_length);
        const auto loops = boundary_loops(mesh);
        REQUIRE(loops.size() == 2);
        CHECK(loops[0].centroid.z() == doctest::Approx(-0.5 * options.parent_length));
        CHECK(loops[0].arc_length / loops[1].arc_length ==
              doctest::Approx(1.0 + options.taper).epsilon(0.005));
    }
    AneurysmPhantomOptions options;
    options.taper = -0.01;
    CHECK_THROWS_AS(aneurysm_phantom(options), InvalidInputError);
    options.taper = 0.6;
    CHECK_THROWS_AS(aneurysm_phantom(options), InvalidInputError);
    options = {};
    options.sac_radius = 10.0;
    CHECK_THROWS_AS(aneurysm_phantom(options), InvalidInputError);
    options = {};
    options.edge_length = 1.0;
    CHECK_THROWS_AS(aneurysm_phantom(options), InvalidInputError);
    options = {};
    options.parent_length = 10.0;
    CHECK_THROWS_AS(aneurysm_phantom(options), InvalidInputError);
    options = {};
    options.branch_radius = 0.5;  // below two edge lengths
    CHECK_THROWS_AS(aneurysm_phantom(options), InvalidInputError);
    options.branch_radius = 1.5;  // above 0.6 parent radii
    CHECK_THROWS_AS(aneurysm_phantom(options), InvalidInputError);
    CHECK_NOTHROW(AneurysmPhantomOptions{}.validate());
}

TEST_CASE("phantom: random trees are valid open tree surfaces")
{
    for (int outlets : {1, 3, 10, 30})
    {
        CAPTURE(outlets);
        TreePhantomOptions options;
        options.outlets = outlets;
        options.seed = 7;
        const Mesh mesh = tree_phantom(options);
        check_vessel_surface(mesh, outlets + 1, options.edge_length);
        CHECK(fraction_below(mesh, 10.0) < 0.01);
        // The inlet is the widest loop, at the root radius.
        const auto loops = boundary_loops(mesh);
        REQUIRE(!loops.empty());
        CHECK(loops[0].arc_length ==
              doctest::Approx(2 * M_PI * options.root_radius).epsilon(0.05));
    }
}

TEST_CASE("phantom: tree is deterministic per seed and validates its options")
{
    TreePhantomOptions options;
    options.outlets = 10;
    options.seed = 3;
    const Mesh a = tree_phantom(options);
    CHECK(same_mesh(a, tree_phantom(options)));
    options.seed = 4;
    CHECK_FALSE(same_mesh(a, tree_phantom(options)));

    options = {};
    options.outlets = 0;
    CHECK_THROWS_AS(tree_phantom(options), InvalidInputError);
    options.outlets = 31;
    CHECK_THROWS_AS(tree_phantom(options), InvalidInputError);
    options = {};
    options.edge_length = 2.0;
    CHECK_THROWS_AS(tree_phantom(options), InvalidInputError);
    options = {};
    options.root_radius = 0.0;
    CHECK_THROWS_AS(tree_phantom(options), InvalidInputError);
}
