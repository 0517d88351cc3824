#pragma once

// Implicit vessel surfaces shared by carotid_phantom() and tree_phantom(): a smooth union of
// tubes sampled by surface nets, opened at end planes and improved into a valid tree surface.

#include "vessel/core/mesh.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>
#include <utility>

namespace vessel::detail {

// Polynomial smooth minimum: exact min when |a - b| >= k, a fillet of depth k / 4 otherwise.
inline double smooth_min(double a, double b, double k)
{
    const double g = std::max(k - std::abs(a - b), 0.0) / k;
    return std::min(a, b) - 0.25 * g * g * k;
}

// A straight piece of centerline from a to b whose radius is radius(s), s = arc length from a.
struct Tube
{
    Eigen::Vector3d a, b;
    std::function<double(double)> radius;
    double max_radius = 0.0;
    Eigen::AlignedBox3d box;  // where the tube can change the field (see VesselField)

    double distance(const Eigen::Vector3d& x) const
    {
        const Eigen::Vector3d ab = b - a;
        const double len2 = ab.squaredNorm();
        const double t = std::clamp((x - a).dot(ab) / len2, 0.0, 1.0);
        return (x - a - t * ab).norm() - radius(t * std::sqrt(len2));
    }
};

// Smooth union of tubes; negative inside. Far from every tube the field saturates at `outside`.
// A tube only enters the fold where its inflated box contains x; the box is inflated so that
// outside it the tube's distance exceeds outside + blend, where smooth_min(f, d) = f exactly, so
// the field is continuous and identical whether evaluated point-wise or on the grid.
class VesselField
{
public:
    VesselField(double blend, double outside) : blend_(blend), outside_(outside) {}

    void add_tube(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                  std::function<double(double)> radius)
    {
        Tube tube{a, b, std::move(radius), 0.0, {}};
        const double len = (b - a).norm();
        for (int i = 0; i <= 256; ++i)
            tube.max_radius = std::max(tube.max_radius, tube.radius(len * i / 256.0));
        const double inflate = tube.max_radius * 1.05 + outside_ + blend_ + 1e-9;
        tube.box.extend(a);
        tube.box.extend(b);
        tube.box.min().array() -= inflate;
        tube.box.max().array() += inflate;
        tubes_.push_back(std::move(tube));
    }

    double operator()(const Eigen::Vector3d& x) const
    {
        double f = outside_;
        for (const auto& tube : tubes_)
            if (tube.box.contains(x))
                f = smooth_min(f, tube.distance(x), blend_);
        return f;
    }

    Eigen::Vector3d gradient(const Eigen::Vector3d& x, double step) const
    {
        Eigen::Vector3d g;
        for (int i = 0; i < 3; ++i)
        {
            Eigen::Vector3d e = Eigen::Vector3d::Zero();
            e[i] = step;
            g[i] = ((*this)(x + e) - (*this)(x - e)) / (2.0 * step);
        }
        return g;
    }

    const std::vector<Tube>& tubes() const { return tubes_; }
    double outside() const { return outside_; }
    double blend() const { return blend_; }

private:
    double blend_, outside_;
    std::vector<Tube> tubes_;
};

// A vessel end: the surface is cut by the plane through `center` with normal `normal` (pointing
// away from the kept vessel); everything beyond it, within the end's region, is discarded.
struct EndPlane
{
    Eigen::Vector3d center, normal;
    double radius = 0.0;  // vessel radius at the end
    double extent = 0.0;  // how far beyond the plane the (capped) implicit tube reaches

    // Signed distance beyond the plane, or nullopt-like NaN when x is not in the end's region.
    double beyond(const Eigen::Vector3d& x, double h) const
    {
        const Eigen::Vector3d d = x - center;
        const double a = d.dot(normal);
        const double radial = (d - a * normal).norm();
        if (a < -3.0 * h || a > extent + 3.0 * h || radial > 1.5 * radius + 3.0 * h)
            return std::numeric_limits<double>::quiet_NaN();
        return a;
    }
};

//! \brief Closed implicit surface -> manifold mesh -> open ends -> better triangles, retrying on a
//! shifted grid should the sampling ever produce a wrong topology.
//! \param h target edge length. \param caller names the phantom in error messages.
//! \throw TopologyError if no grid shift gives a valid tree surface with one loop per end.
Mesh vessel_surface(const VesselField& field, const std::vector<EndPlane>& ends, double h,
                    const char* caller);

}  // namespace vessel::detail
