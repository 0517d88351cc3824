#include <doctest/doctest.h>

#include "vessel/check/validation.h"
#include "vessel/core/errors.h"
#include "vessel/fields/map_vectors.h"
#include "vessel/io/flat_vtk.h"
#include "vessel/phantom/phantom.h"
#include "vessel/pipeline.h"
#include "vessel/quality/metrics.h"

#include <cmath>

using namespace vessel;

namespace {

FlattenResult flat_carotid()
{
    CarotidPhantomOptions carotid;
    carotid.edge_length = 1.0;
    FlattenOptions options;
    options.refinement = Refinement::None;
    return flatten(make_tree_surface(to_raw_mesh(carotid_phantom(carotid))).mesh, options);
}

Eigen::Vector3d face_normal(const Mesh& mesh, FaceHandle f)
{
    std::vector<Eigen::Vector3d> p;
    for (auto v : mesh.fv_range(f))
        p.push_back(to_eigen(mesh.point(v)));
    return (p[1] - p[0]).cross(p[2] - p[0]).normalized();
}

}  // namespace

TEST_CASE("map vectors: a face's edge vector plus any normal part maps to the edge on the map")
{
    const FlattenResult r = flat_carotid();
    const Mesh& mesh = r.mesh;
    const auto nf = static_cast<Eigen::Index>(mesh.n_faces());
    // Per face: the edge from its first to its second corner, plus 3 x the face normal.
    Field edge{"Edge", FieldLocation::Cell, FieldType::Float64, Eigen::MatrixXd(nf, 3)};
    Eigen::MatrixXd expected(nf, 2);
    for (auto f : mesh.faces())
    {
        std::vector<VertexHandle> c;
        for (auto v : mesh.fv_range(f))
            c.push_back(v);
        const Eigen::Vector3d w =
            to_eigen(mesh.point(c[1])) - to_eigen(mesh.point(c[0])) + 3.0 * face_normal(mesh, f);
        edge.values.row(f.idx()) = w.transpose();
        expected.row(f.idx()) = r.uv.row(c[1].idx()) - r.uv.row(c[0].idx());
    }
    const std::vector<Field> mapped = map_fields({edge}, mesh, r.uv);
    REQUIRE(mapped.size() == 1);
    REQUIRE(mapped[0].components() == 3);
    const double scale = expected.rowwise().norm().maxCoeff();
    CHECK((mapped[0].values.leftCols(2) - expected).cwiseAbs().maxCoeff() < 1e-9 * scale);
    CHECK(mapped[0].values.col(2).cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("map vectors: point vectors lie in the map plane and pull back to their tangential part")
{
    const FlattenResult r = flat_carotid();
    const Mesh& mesh = r.mesh;
    const auto nv = static_cast<Eigen::Index>(mesh.n_vertices());
    Field wss{"WSS", FieldLocation::Point, FieldType::Float32, Eigen::MatrixXd(nv, 3)};
    Field pressure{"Pressure", FieldLocation::Point, FieldType::Float64, Eigen::MatrixXd(nv, 1)};
    for (auto v : mesh.vertices())
    {
        const Eigen::Vector3d p = to_eigen(mesh.point(v));
        wss.values.row(v.idx()) << std::sin(0.3 * p.y()) + 1.0, std::cos(0.2 * p.z()), 0.1 * p.x();
        pressure.values(v.idx(), 0) = p.x();
    }
    const std::vector<Field> mapped = map_fields({wss, pressure}, mesh, r.uv);
    REQUIRE(mapped.size() == 2);
    CHECK(mapped[1].values == pressure.values);  // scalars unchanged
    CHECK(mapped[0].type == FieldType::Float32);
    CHECK(mapped[0].values.col(2).cwiseAbs().maxCoeff() == 0.0);

    const VertexMapJacobians J = vertex_map_jacobians(mesh, r.uv);
    double worst = 0.0;
    int checked = 0;
    for (auto v : mesh.vertices())
    {
        const Eigen::Vector3d n = J.normal[v.idx()];
        REQUIRE(std::abs(n.norm() - 1.0) < 1e-12);
        // A basis of the tangent plane; the Jacobian restricted to it, inverted.
        const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
        Eigen::Matrix<double, 3, 2> T;
        T << e1, e2;
        const Eigen::Matrix2d M = J.jacobian[v.idx()] * T;
        REQUIRE(std::abs(M.determinant()) > 1e-6);
        const Eigen::Vector3d back = T * M.inverse() * mapped[0].values.row(v.idx()).head<2>().transpose();
        const Eigen::Vector3d w = wss.values.row(v.idx()).transpose();
        const Eigen::Vector3d tangential = w - n * n.dot(w);
        worst = std::max(worst, (back - tangential).norm() / std::max(1.0, w.norm()));
        ++checked;
    }
    CHECK(checked == nv);
    CHECK(worst < 1e-9);
    // The vertex Jacobian is a local mean of its faces': a face's map of its own edge agrees
    // with it to first order (the map is smooth, so within a few percent of the edge).
    const std::vector<MapJacobian> faces = face_map_jacobians(mesh, r.uv);
    double mean_rel = 0.0;
    for (auto f : mesh.faces())
        for (auto v : mesh.fv_range(f))
            mean_rel += (J.jacobian[v.idx()] - faces[f.idx()] *
                                                   (Eigen::Matrix3d::Identity() -
                                                    J.normal[v.idx()] * J.normal[v.idx()].transpose()))
                            .norm() /
                        faces[f.idx()].norm() / (3.0 * mesh.n_faces());
    CHECK(mean_rel < 0.2);
}

TEST_CASE("map vectors: the per-face distortion arrays average to flat_quality()'s numbers")
{
    const FlattenResult r = flat_carotid();
    const std::vector<Field> d = distortion_fields(r.mesh, r.uv);
    REQUIRE(d.size() == 2);
    CHECK(d[0].name == std::string(log_area_ratio_array));
    CHECK(d[1].name == std::string(conformal_array));
    const FlatQuality q = flat_quality(r.mesh, r.uv);
    REQUIRE(q.flipped_triangles == 0);
    double area = 0.0, log_area = 0.0, conformal = 0.0;
    for (auto f : r.mesh.faces())
    {
        const double a = r.mesh.calc_face_area(f);
        area += a;
        log_area += a * std::abs(d[0].values(f.idx(), 0));
        conformal += a * d[1].values(f.idx(), 0);
    }
    CHECK(log_area / area == doctest::Approx(q.mean_abs_log_area).epsilon(1e-9));
    CHECK(conformal / area == doctest::Approx(q.mean_conformal).epsilon(1e-9));
    CHECK(d[1].values.maxCoeff() == doctest::Approx(q.max_conformal).epsilon(1e-9));

    // On the written map: the distortion arrays as cells, a vector field flat.
    const auto nv = static_cast<Eigen::Index>(r.mesh.n_vertices());
    Field up{"Up", FieldLocation::Point, FieldType::Float64, Eigen::MatrixXd::Zero(nv, 3)};
    up.values.col(2).setOnes();
    const PolyData map = flat_polydata(r.mesh, r.uv, {up}, true);
    const PolyData cut = flat_polydata(r.mesh, r.uv, {up}, false);
    CHECK(find_field(map.cell_data, log_area_ratio_array).values == d[0].values);
    CHECK(find_field(map.point_data, "Up").values.col(2).cwiseAbs().maxCoeff() == 0.0);
    CHECK(find_field(cut.point_data, "Up").values == up.values);  // 3D vectors stay 3D
    CHECK_THROWS_AS(find_field(cut.cell_data, log_area_ratio_array), InvalidInputError);
}
