#include "vessel/quality/metrics.h"

#include "vessel/core/errors.h"
#include "vessel/quality/overlap.h"
#include "detail/map_distortion.h"
#include "detail/uv_rows.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

namespace vessel {

double signed_uv_area(const Mesh& mesh, const Eigen::MatrixX2d& uv, FaceHandle f)
{
    auto h = mesh.halfedge_handle(f);
    const int a = mesh.from_vertex_handle(h).idx();
    const int b = mesh.to_vertex_handle(h).idx();
    const int c = mesh.to_vertex_handle(mesh.next_halfedge_handle(h)).idx();
    const Eigen::Vector2d e1 = uv.row(b) - uv.row(a), e2 = uv.row(c) - uv.row(a);
    return 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
}

double signed_map_area(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    double area2 = 0.0;
    for (auto f : mesh.faces())
        area2 += signed_uv_area(mesh, uv, f);
    return area2;
}

void scale_to_surface_area(const Mesh& mesh, Eigen::MatrixX2d& uv)
{
    const double area2 = signed_map_area(mesh, uv);
    const double area3 = face_areas(mesh).sum();
    if (area2 > 0.0)
        uv *= std::sqrt(area3 / area2);
}

FlatQuality detail::map_distortion(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    detail::require_uv_rows(mesh, uv, "flat_quality");
    FlatQuality q;
    double area3 = 0.0, area2 = 0.0, log_sum = 0.0, conformal_sum = 0.0, weight = 0.0;
    std::vector<std::pair<double, double>> good;  // (A_2D, A_3D) of the non-flipped faces
    good.reserve(mesh.n_faces());
    double good2 = 0.0;
    for (auto f : mesh.faces())
    {
        auto h = f.halfedge();
        const Eigen::Vector3d p0 = to_eigen(mesh.point(h.from()));
        const Eigen::Vector3d p1 = to_eigen(mesh.point(h.to()));
        const Eigen::Vector3d p2 = to_eigen(mesh.point(h.next().to()));
        // Local orthonormal frame of the 3D triangle.
        const Eigen::Vector3d e1 = p1 - p0, e2 = p2 - p0;
        const double a3 = 0.5 * e1.cross(e2).norm();
        const double a2 = signed_uv_area(mesh, uv, f);
        area3 += a3;
        area2 += a2;
        if (a2 <= 0.0)
        {
            ++q.flipped_triangles;
            continue;
        }
        if (a3 <= 0.0)
            continue;
        const Eigen::Vector3d x = e1.normalized();
        const Eigen::Vector3d y = (e2 - e2.dot(x) * x).normalized();
        Eigen::Matrix2d P, U;  // columns: edges in the 3D frame and in the map
        P << e1.dot(x), e2.dot(x), 0.0, e2.dot(y);
        const int i0 = h.from().idx(), i1 = h.to().idx(), i2 = h.next().to().idx();
        U.col(0) = (uv.row(i1) - uv.row(i0)).transpose();
        U.col(1) = (uv.row(i2) - uv.row(i0)).transpose();
        const Eigen::Matrix2d J = U * P.inverse();
        const Eigen::Vector2d s = Eigen::JacobiSVD<Eigen::Matrix2d>(J).singularValues();
        const double conformal = s[1] > 0 ? s[0] / s[1] : INFINITY;
        log_sum += a3 * std::abs(std::log(a2 / a3));
        good.emplace_back(a2, a3);
        good2 += a2;
        conformal_sum += a3 * conformal;
        weight += a3;
        q.max_conformal = std::max(q.max_conformal, conformal);
    }
    q.area_ratio = area3 > 0 ? area2 / area3 : 0.0;
    q.mean_abs_log_area = weight > 0 ? log_sum / weight : 0.0;
    q.mean_conformal = weight > 0 ? conformal_sum / weight : 0.0;
    if (weight > 0 && good2 > 0)
    {
        const double shift = std::log(good2 / weight);  // weight = sum of the good A_3D
        q.mean_abs_log_area_normalized =
            detail::normalized_log_area_sum(good.data(), good.data() + good.size(), shift) / weight;
    }
    return q;
}

FlatQuality flat_quality(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    FlatQuality q = detail::map_distortion(mesh, uv);
    OverlapReport overlaps = find_overlaps(mesh, uv);
    q.overlapping_triangles = overlaps.overlapping_triangles();
    q.overlap_area = overlaps.overlap_area;
    q.overlap_fraction = overlaps.overlap_fraction;
    q.overlapping_faces = std::move(overlaps.triangles);
    return q;
}

std::string distortion_warning(const FlatQuality& quality)
{
    if (!(quality.mean_abs_log_area > kMaxUsefulMeanAbsLogArea))
        return {};
    std::ostringstream out;
    out.precision(3);
    out << "the map distorts areas too much to be of use (mean |log area| "
        << quality.mean_abs_log_area << ", above " << kMaxUsefulMeanAbsLogArea
        << ": a triangle's area is off by a factor " << std::exp(quality.mean_abs_log_area)
        << " on average); check the input for holes in the wall (vessel-flatten --fill-holes) "
           "or for boundary loops that are not vessel ends";
    return out.str();
}

}  // namespace vessel
