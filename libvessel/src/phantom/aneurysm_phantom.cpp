#include "vessel/phantom/phantom.h"

#include "detail/implicit_vessel.h"
#include "vessel/core/errors.h"

#include <cmath>
#include <string>
#include <vector>

namespace vessel {

void AneurysmPhantomOptions::validate() const
{
    auto fail = [](const std::string& what) {
        throw InvalidInputError("AneurysmPhantomOptions: " + what);
    };
    if (!(parent_radius > 0.0) || !std::isfinite(parent_radius))
        fail("parent_radius must be finite and > 0");
    if (!(sac_radius >= 0.75 * parent_radius && sac_radius <= 3.0 * parent_radius))
        fail("sac_radius must be in [0.75, 3] x parent_radius (" +
             std::to_string(0.75 * parent_radius) + " to " + std::to_string(3.0 * parent_radius) +
             "), got " + std::to_string(sac_radius));
    if (!(edge_length > 0.0 && edge_length <= parent_radius / 3.0))
        fail("edge_length must be in (0, parent_radius / 3 = " +
             std::to_string(parent_radius / 3.0) + "], got " + std::to_string(edge_length));
    if (!(branch_radius == 0.0 ||
          (branch_radius >= 2.0 * edge_length && branch_radius <= 0.6 * parent_radius)))
        fail("branch_radius must be 0 (no branch) or in [2 edge_length, 0.6 parent_radius] (" +
             std::to_string(2.0 * edge_length) + " to " + std::to_string(0.6 * parent_radius) +
             "), got " + std::to_string(branch_radius));
    if (!(taper >= 0.0 && taper <= 0.5))
        fail("taper must be in [0, 0.5] (a fraction of parent_radius), got " +
             std::to_string(taper));
    // The sac and its fillet must end well before the end planes.
    const double min_length = 2.0 * (sac_radius + 2.0 * parent_radius) + 4.0 * edge_length;
    if (!(parent_length >= min_length) || !std::isfinite(parent_length))
        fail("parent_length must be >= 2 (sac_radius + 2 parent_radius) + 4 edge_length (" +
             std::to_string(min_length) + "), got " + std::to_string(parent_length));
}

Eigen::Vector3d aneurysm_sac_centre(const AneurysmPhantomOptions& options)
{
    return {options.parent_radius + 0.8 * options.sac_radius, 0.0, 0.0};
}

Mesh aneurysm_phantom(const AneurysmPhantomOptions& options)
{
    options.validate();
    const double r = options.parent_radius, R = options.sac_radius, h = options.edge_length;
    const double blend = 0.5 * r;
    detail::VesselField field(blend, 3.0 * h + blend);
    const Eigen::Vector3d z(0, 0, 1), x(1, 0, 0);
    const double half = 0.5 * options.parent_length, overshoot = r + 3.0 * h;
    // The parent's radius at height z: r (1 - taper z / length), r at the sac's level.
    const double taper = options.taper, length = options.parent_length;
    const auto parent = [r, taper, length](double z) { return r * (1.0 - taper * z / length); };
    field.add_tube(-(half + overshoot) * z, (half + overshoot) * z,
                   [parent, half, overshoot](double s) { return parent(s - half - overshoot); });
    // The sac: a tube far shorter than the edge length is a sphere to the field's precision
    // (the distance to its axis segment, less its radius).
    const Eigen::Vector3d centre = aneurysm_sac_centre(options);
    const double tiny = 1e-6 * R;
    field.add_tube(centre - tiny * x, centre + tiny * x, [R](double) { return R; });
    std::vector<detail::EndPlane> ends;
    ends.push_back({-half * z, -z, parent(-half), overshoot + parent(-half)});
    ends.push_back({half * z, z, parent(half), overshoot + parent(half)});
    if (options.branch_radius > 0.0)
    {
        const double b = options.branch_radius, b_overshoot = b + 3.0 * h;
        const Eigen::Vector3d along = Eigen::Vector3d(1, 0, 1).normalized();
        const Eigen::Vector3d end = centre + (R + 2.0 * r) * along;
        field.add_tube(centre, end + b_overshoot * along, [b](double) { return b; });
        ends.push_back({end, along, b, b_overshoot + b});
    }
    return detail::vessel_surface(field, ends, h, "aneurysm_phantom");
}

}  // namespace vessel
