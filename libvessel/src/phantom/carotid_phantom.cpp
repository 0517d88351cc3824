#include "vessel/phantom/phantom.h"

#include "detail/implicit_vessel.h"
#include "vessel/core/errors.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace vessel {

using detail::EndPlane;
using detail::VesselField;
using detail::vessel_surface;

void CarotidPhantomOptions::validate() const
{
    auto fail = [](const std::string& what) {
        throw InvalidInputError("CarotidPhantomOptions: " + what);
    };
    if (!(cca_radius > 0.0) || !(ica_radius > 0.0) || !(eca_radius > 0.0))
        fail("cca_radius, ica_radius and eca_radius must be > 0");
    if (ica_radius > cca_radius || eca_radius > cca_radius)
        fail("the branches (ica_radius, eca_radius) must not be wider than cca_radius");
    if (!(branch_angle_deg >= 10.0 && branch_angle_deg <= 60.0))
        fail("branch_angle_deg must be in [10, 60] (got " + std::to_string(branch_angle_deg) +
             ")");
    if (!(stenosis >= 0.0 && stenosis <= 0.8))
        fail("stenosis must be in [0, 0.8] (got " + std::to_string(stenosis) + ")");
    if (!(edge_length > 0.0))
        fail("edge_length must be > 0");
    if (edge_length > 0.6 * std::min(ica_radius, eca_radius))
        fail("edge_length must be <= 0.6 * min(ica_radius, eca_radius) (" +
             std::to_string(0.6 * std::min(ica_radius, eca_radius)) +
             ") so that each vessel gets at least ~10 edges around");
    const double min_length = 3.0 * cca_radius + 2.0 * edge_length;
    if (!(cca_length >= min_length) || !(ica_length >= min_length) ||
        !(eca_length >= min_length))
        fail("cca_length, ica_length and eca_length must be >= 3 * cca_radius + 2 * "
             "edge_length (" + std::to_string(min_length) + ")");
}

Mesh carotid_phantom(const CarotidPhantomOptions& options)
{
    options.validate();
    const CarotidPhantomOptions o = options;
    // ICA profile: sinus bulb just past the bifurcation, then a Gaussian narrowing whose throat
    // has (1 - stenosis) times the local diameter.
    const double bulb_at = 0.2 * o.ica_length, bulb_width = 0.12 * o.ica_length;
    const double stenosis_at = 0.45 * o.ica_length, stenosis_width = 0.1 * o.ica_length;
    auto ica_radius = [o, bulb_at, bulb_width, stenosis_at, stenosis_width](double s) {
        const double bulb = 0.3 * std::exp(-std::pow((s - bulb_at) / bulb_width, 2));
        const double narrowing =
            o.stenosis * std::exp(-std::pow((s - stenosis_at) / stenosis_width, 2));
        return o.ica_radius * (1.0 + bulb) * (1.0 - narrowing);
    };
    const double r_min = std::min(o.eca_radius, o.ica_radius * (1.0 - o.stenosis));
    const double h = std::min(o.edge_length, r_min / 1.6);
    const double blend = 0.6 * std::min(o.ica_radius, o.eca_radius);
    VesselField field(blend, 3.0 * h + blend);

    // CCA along +z ending at the bifurcation (origin); branches in the x-z plane.
    const double angle = o.branch_angle_deg * M_PI / 180.0;
    const Eigen::Vector3d z(0, 0, 1);
    const Eigen::Vector3d ica_dir(std::sin(angle), 0, std::cos(angle));
    const Eigen::Vector3d eca_dir(-std::sin(angle), 0, std::cos(angle));
    auto extension = [h](double r) { return r + 3.0 * h; };  // capped overshoot past each end
    const double cca_r = o.cca_radius, eca_r = o.eca_radius;
    field.add_tube(-(o.cca_length + extension(cca_r)) * z, Eigen::Vector3d::Zero(),
                   [cca_r](double) { return cca_r; });
    field.add_tube(Eigen::Vector3d::Zero(), (o.ica_length + extension(o.ica_radius)) * ica_dir,
                   ica_radius);
    field.add_tube(Eigen::Vector3d::Zero(), (o.eca_length + extension(eca_r)) * eca_dir,
                   [eca_r](double) { return eca_r; });

    std::vector<EndPlane> ends;
    ends.push_back({-o.cca_length * z, -z, cca_r, extension(cca_r) + cca_r});
    ends.push_back({o.ica_length * ica_dir, ica_dir, ica_radius(o.ica_length),
                    extension(o.ica_radius) + o.ica_radius});
    ends.push_back({o.eca_length * eca_dir, eca_dir, eca_r, extension(eca_r) + eca_r});
    return vessel_surface(field, ends, h, "carotid_phantom");
}

}  // namespace vessel
