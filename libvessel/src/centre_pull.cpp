#include "vessel/centre_pull.h"

#include "vessel/errors.h"
#include "detail/centre_pull.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

namespace vessel {
namespace {

Eigen::Vector2d centre(const std::vector<int>& vertices, const Eigen::VectorXd& x)
{
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (int v : vertices)
        c += x.segment<2>(2 * v);
    return c / static_cast<double>(vertices.size());
}

// Signed distance of the pull's centre from its line.
double offset(const CentrePull& pull, const Eigen::VectorXd& x)
{
    return pull.normal.dot(centre(pull.vertices, x) - pull.origin);
}

}  // namespace

void validate_centre_pulls(const std::vector<CentrePull>& pulls, const std::string& who)
{
    for (std::size_t i = 0; i < pulls.size(); ++i)
    {
        const CentrePull& pull = pulls[i];
        if (pull.vertices.empty() || !(pull.weight >= 0.0) || !std::isfinite(pull.weight) ||
            !pull.origin.allFinite() || !(std::abs(pull.normal.norm() - 1.0) < 1e-9))
            throw InvalidInputError(who + ": centre pull " + std::to_string(i) +
                                    " needs vertices, a finite weight >= 0, a finite origin "
                                    "and a unit normal");
    }
}

std::vector<CentrePull> look_pulls(const std::vector<BoundarySegment>& segments,
                                   const Eigen::MatrixX2d& uv, double weight)
{
    std::map<int, std::vector<int>> loops;  // loop index -> its vertices (0 = inlet)
    for (const BoundarySegment& seg : segments)
        for (VertexHandle v : seg.vertices)
        {
            if (v.idx() < 0 || v.idx() >= uv.rows())
                throw InvalidInputError("look_pulls: segment vertex " + std::to_string(v.idx()) +
                                        " is not a row of the map (" +
                                        std::to_string(uv.rows()) + " rows)");
            loops[seg.loop].push_back(v.idx());
        }
    if (!loops.count(0))
        throw InvalidInputError("look_pulls: no inlet segment (loop 0) among the segments");
    const auto mean = [&](const std::vector<int>& vs) {
        Eigen::Vector2d c = Eigen::Vector2d::Zero();
        for (int v : vs)
            c += uv.row(v).transpose();
        return Eigen::Vector2d(c / static_cast<double>(vs.size()));
    };
    const Eigen::Vector2d inlet = mean(loops[0]);
    std::vector<CentrePull> pulls;
    // The inlet's two halves (in walk order) held where they are: its centre and its chord's
    // direction stay, so the map cannot turn under the outlets' rays.
    const std::vector<int>& walk = loops[0];
    const std::size_t half = std::max<std::size_t>(walk.size() / 2, 1);
    for (const std::vector<int>& part :
         {std::vector<int>(walk.begin(), walk.begin() + half),
          std::vector<int>(walk.begin() + (half < walk.size() ? half : 0), walk.end())})
    {
        const Eigen::Vector2d at = mean(part);
        pulls.push_back({part, at, Eigen::Vector2d::UnitX(), weight});
        pulls.push_back({part, at, Eigen::Vector2d::UnitY(), weight});
    }
    for (const auto& [loop, vertices] : loops)
    {
        const Eigen::Vector2d ray = mean(vertices) - inlet;
        if (loop == 0 || ray.norm() == 0.0)
            continue;
        pulls.push_back({vertices, inlet, Eigen::Vector2d(-ray.y(), ray.x()).normalized(), weight});
    }
    return pulls;
}

namespace detail {

void require_centre_pull_vertices(const std::vector<CentrePull>& pulls, int n,
                                  const std::string& who)
{
    for (const CentrePull& pull : pulls)
        for (int v : pull.vertices)
            if (v < 0 || v >= n)
                throw InvalidInputError(who + ": centre pull vertex " + std::to_string(v) +
                                        " is not a vertex of the mesh (" + std::to_string(n) +
                                        ")");
}

double centre_pull_energy(const std::vector<CentrePull>& pulls, const Eigen::VectorXd& x)
{
    double e = 0.0;
    for (const CentrePull& pull : pulls)
    {
        const double r = offset(pull, x);
        e += pull.weight * r * r;
    }
    return e;
}

void add_centre_pulls(const std::vector<CentrePull>& pulls, const Eigen::VectorXd& x,
                      const std::vector<int>& diagonal, double* values, Eigen::VectorXd& rhs)
{
    // E = W r^2 with r = n . (mean(x_S) - o): dE/dx_v = 2 (W / |S|) r n. The proxy
    // sum_v (W / |S|) |y_v - (x_v - r n)|^2 has that gradient at y = x and curvature
    // W / |S| per vertex (>= the true one along any common motion of S).
    for (const CentrePull& pull : pulls)
    {
        const double w = pull.weight / static_cast<double>(pull.vertices.size());
        const Eigen::Vector2d shift = offset(pull, x) * pull.normal;
        for (int v : pull.vertices)
            for (int k = 0; k < 2; ++k)
            {
                const int i = 2 * v + k;
                values[diagonal[i]] += w;
                rhs[i] += w * (x[i] - shift[k]);
            }
    }
}

void add_centre_pull_gradient(const std::vector<CentrePull>& pulls, const Eigen::VectorXd& x,
                              const std::vector<int>& slot, double* gradient)
{
    for (const CentrePull& pull : pulls)
    {
        const double w = pull.weight / static_cast<double>(pull.vertices.size());
        const Eigen::Vector2d g = 2.0 * w * offset(pull, x) * pull.normal;
        for (int v : pull.vertices)
            if (slot[v] >= 0)
                for (int k = 0; k < 2; ++k)
                    gradient[2 * slot[v] + k] += g[k];
    }
}

void add_centre_pull_curvature(const std::vector<CentrePull>& pulls, const std::vector<int>& slot,
                               const std::vector<int>& diagonal, double* values)
{
    for (const CentrePull& pull : pulls)
    {
        // The proxy's curvature, 2 (W / |S|) per coordinate (the energy's own Hessian is
        // dense over S; this one majorizes it along any common motion of S).
        const double w = 2.0 * pull.weight / static_cast<double>(pull.vertices.size());
        for (int v : pull.vertices)
            if (slot[v] >= 0)
                for (int k = 0; k < 2; ++k)
                    values[diagonal[2 * slot[v] + k]] += w;
    }
}

}  // namespace detail
}  // namespace vessel
