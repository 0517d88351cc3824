// sample_map_arrows(): point location of grid centres in the map's faces through a bucket grid
// of the faces' bounding boxes (each face visits the cells its box covers).
#include "vessel/render/map_arrows.h"

#include "detail/segments.h"
#include "vessel/core/errors.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace vessel {

std::vector<MapArrow> sample_map_arrows(const Mesh& mesh, const Eigen::MatrixX2d& uv,
                                        const Eigen::MatrixX2d& vectors, double spacing)
{
    const auto n = static_cast<Eigen::Index>(mesh.n_vertices());
    if (uv.rows() != n || vectors.rows() != n)
        throw InvalidInputError("sample_map_arrows: the mesh has " + std::to_string(n) +
                                " vertices but uv has " + std::to_string(uv.rows()) +
                                " rows and vectors " + std::to_string(vectors.rows()) +
                                "; give one row per cut-mesh vertex");
    if (!uv.allFinite() || !vectors.allFinite())
        throw InvalidInputError("sample_map_arrows: uv or vectors has a non-finite entry");
    if (n == 0)
        return {};
    if (!(spacing > 0.0))
        throw InvalidInputError("sample_map_arrows: spacing must be > 0, got " +
                                std::to_string(spacing));
    const Eigen::Vector2d lo = uv.colwise().minCoeff().transpose();
    const Eigen::Vector2d hi = uv.colwise().maxCoeff().transpose();
    const double nx_real = std::floor((hi.x() - lo.x()) / spacing) + 1;
    const double ny_real = std::floor((hi.y() - lo.y()) / spacing) + 1;
    if (nx_real * ny_real > 1e7)
        throw InvalidInputError("sample_map_arrows: spacing " + std::to_string(spacing) +
                                " leaves more than 10^7 grid cells on the map; give a larger one");
    const int nx = static_cast<int>(nx_real), ny = static_cast<int>(ny_real);
    // The grid is centred on the map's box: the same margin on both sides.
    const Eigen::Vector2d origin =
        0.5 * (lo + hi) - 0.5 * spacing * Eigen::Vector2d(nx - 1, ny - 1);
    const auto centre = [&](int i, int j) {
        return Eigen::Vector2d(origin.x() + i * spacing, origin.y() + j * spacing);
    };
    // Per grid point, the first face (index order) that holds it.
    std::vector<int> holder(static_cast<std::size_t>(nx) * ny, -1);
    std::vector<Eigen::Vector3d> weights(holder.size());
    for (auto f : mesh.faces())
    {
        int c[3], k = 0;
        for (auto v : f.vertices())
            c[k++] = v.idx();
        const Eigen::Vector2d a = uv.row(c[0]), b = uv.row(c[1]), d = uv.row(c[2]);
        if (!(std::abs(detail::orient(a, b, d)) > 0.0))
            continue;  // a degenerate face holds no point
        const Eigen::Vector2d fmin = a.cwiseMin(b).cwiseMin(d), fmax = a.cwiseMax(b).cwiseMax(d);
        const int i0 = std::max(0, static_cast<int>(std::ceil((fmin.x() - origin.x()) / spacing)));
        const int i1 = std::min(nx - 1, static_cast<int>(std::floor((fmax.x() - origin.x()) / spacing)));
        const int j0 = std::max(0, static_cast<int>(std::ceil((fmin.y() - origin.y()) / spacing)));
        const int j1 = std::min(ny - 1, static_cast<int>(std::floor((fmax.y() - origin.y()) / spacing)));
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i)
            {
                const std::size_t cell = static_cast<std::size_t>(j) * nx + i;
                if (holder[cell] >= 0)
                    continue;
                // A point on an edge belongs to the first of its faces.
                Eigen::Vector3d w;
                if (!detail::barycentric(centre(i, j), a, b, d, w) || w.minCoeff() < 0.0)
                    continue;
                holder[cell] = f.idx();
                weights[cell] = w;
            }
    }
    std::vector<MapArrow> arrows;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
        {
            const std::size_t cell = static_cast<std::size_t>(j) * nx + i;
            if (holder[cell] < 0)
                continue;
            Eigen::Vector2d value = Eigen::Vector2d::Zero();
            int k = 0;
            for (auto v : mesh.fv_range(mesh.face_handle(holder[cell])))
                value += weights[cell][k++] * vectors.row(v.idx()).transpose();
            arrows.push_back({centre(i, j), value});
        }
    return arrows;
}

}  // namespace vessel
