#include "vessel/fields/map_vectors.h"

#include "detail/uv_rows.h"
#include "vessel/core/errors.h"
#include "vessel/quality/metrics.h"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <limits>

namespace vessel {

namespace {

struct FaceFrame
{
    Eigen::Vector3d p0, e1, e2;  // corner 0 and the edges to corners 1 and 2
    Eigen::Vector2d q0, d1, d2;  // the same in the map
};

FaceFrame frame(const Mesh& mesh, const Eigen::MatrixX2d& uv, FaceHandle f)
{
    FaceFrame fr;
    int k = 0;
    Eigen::Vector3d p[3];
    Eigen::Vector2d q[3];
    for (auto v : mesh.fv_range(f))
    {
        p[k] = to_eigen(mesh.point(v));
        q[k] = uv.row(v.idx()).transpose();
        ++k;
    }
    fr.p0 = p[0];
    fr.e1 = p[1] - p[0];
    fr.e2 = p[2] - p[0];
    fr.q0 = q[0];
    fr.d1 = q[1] - q[0];
    fr.d2 = q[2] - q[0];
    return fr;
}

}  // namespace

std::vector<MapJacobian> face_map_jacobians(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    detail::require_uv_rows(mesh, uv, "face_map_jacobians");
    std::vector<MapJacobian> out(mesh.n_faces(), MapJacobian::Zero());
    for (auto f : mesh.faces())
    {
        const FaceFrame fr = frame(mesh, uv, f);
        Eigen::Matrix<double, 3, 2> E;
        E << fr.e1, fr.e2;
        const Eigen::Matrix2d G = E.transpose() * E;
        if (!(std::abs(G.determinant()) > 0.0))
            continue;
        Eigen::Matrix2d Q;
        Q << fr.d1, fr.d2;
        // J E = Q with J's rows in the plane of E: J = Q (E^T E)^-1 E^T.
        out[f.idx()] = Q * G.inverse() * E.transpose();
    }
    return out;
}

VertexMapJacobians vertex_map_jacobians(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    const std::vector<MapJacobian> faces = face_map_jacobians(mesh, uv);
    VertexMapJacobians out;
    out.normal.assign(mesh.n_vertices(), Eigen::Vector3d::Zero());
    out.jacobian.assign(mesh.n_vertices(), MapJacobian::Zero());
    std::vector<double> weight(mesh.n_vertices(), 0.0);
    for (auto f : mesh.faces())
    {
        const FaceFrame fr = frame(mesh, uv, f);
        const Eigen::Vector3d area_normal = 0.5 * fr.e1.cross(fr.e2);  // length = area
        const double area = area_normal.norm();
        for (auto v : mesh.fv_range(f))
        {
            out.normal[v.idx()] += area_normal;
            out.jacobian[v.idx()] += area * faces[f.idx()];
            weight[v.idx()] += area;
        }
    }
    for (std::size_t v = 0; v < weight.size(); ++v)
    {
        const double length = out.normal[v].norm();
        if (!(weight[v] > 0.0) || !(length > 0.0))
        {
            out.jacobian[v].setZero();
            continue;
        }
        out.normal[v] /= length;
        out.jacobian[v] = out.jacobian[v] / weight[v] *
                          (Eigen::Matrix3d::Identity() - out.normal[v] * out.normal[v].transpose());
    }
    return out;
}

std::vector<Field> map_fields(const std::vector<Field>& fields, const Mesh& mesh,
                              const Eigen::MatrixX2d& uv)
{
    const bool any_vector =
        std::any_of(fields.begin(), fields.end(), [](const Field& f) { return f.components() == 3; });
    if (!any_vector)
        return fields;
    const VertexMapJacobians vertices = vertex_map_jacobians(mesh, uv);
    const std::vector<MapJacobian> faces = face_map_jacobians(mesh, uv);
    std::vector<Field> out = fields;
    for (auto& f : out)
    {
        if (f.components() != 3)
            continue;
        const bool point = f.location == FieldLocation::Point;
        const std::size_t rows = point ? vertices.jacobian.size() : faces.size();
        if (f.rows() != static_cast<Eigen::Index>(rows))
            throw InvalidInputError("map_fields: " + std::string(point ? "point" : "cell") +
                                    " field '" + f.name + "' has " + std::to_string(f.rows()) +
                                    " rows but the mesh has " + std::to_string(rows) +
                                    "; carry it onto the cut mesh first (transfer_fields())");
        for (Eigen::Index i = 0; i < f.rows(); ++i)
        {
            const MapJacobian& J = point ? vertices.jacobian[i] : faces[i];
            const Eigen::Vector2d m = J * f.values.row(i).transpose();
            f.values.row(i) << m.x(), m.y(), 0.0;
        }
        if (f.type != FieldType::Float32)
            f.type = FieldType::Float64;  // integer vectors have no integer image
    }
    return out;
}

std::vector<Field> distortion_fields(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    const std::vector<MapJacobian> faces = face_map_jacobians(mesh, uv);
    const auto nf = static_cast<Eigen::Index>(mesh.n_faces());
    Field log_area{log_area_ratio_array, FieldLocation::Cell, FieldType::Float64,
                   Eigen::MatrixXd(nf, 1)};
    Field conformal{conformal_array, FieldLocation::Cell, FieldType::Float64,
                    Eigen::MatrixXd(nf, 1)};
    for (auto f : mesh.faces())
    {
        const FaceFrame fr = frame(mesh, uv, f);
        const double area_3d = 0.5 * fr.e1.cross(fr.e2).norm();
        const double area_2d = signed_uv_area(mesh, uv, f);
        log_area.values(f.idx(), 0) = area_2d > 0.0 && area_3d > 0.0
                                          ? std::log(area_2d / area_3d)
                                          : std::numeric_limits<double>::quiet_NaN();
        const Eigen::JacobiSVD<MapJacobian> svd(faces[f.idx()]);
        const Eigen::Vector2d s = svd.singularValues();
        conformal.values(f.idx(), 0) =
            s(1) > 0.0 ? s(0) / s(1) : std::numeric_limits<double>::infinity();
    }
    return {log_area, conformal};
}

}  // namespace vessel
