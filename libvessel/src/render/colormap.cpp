// Colour tables and the value range of map images (map_image.h).
#include "detail/colormap_tables.h"
#include "vessel/core/errors.h"
#include "vessel/render/map_image.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vessel {

void MapImageOptions::validate() const
{
    auto fail = [](const std::string& what) {
        throw InvalidInputError("MapImageOptions: " + what);
    };
    if (width_px < 64 || height_px < 64 || width_px > 16384 || height_px > 16384)
        fail("width_px and height_px must be in [64, 16384] (got " + std::to_string(width_px) +
             " x " + std::to_string(height_px) + ")");
    if (margin_px < 0 || 4 * margin_px >= std::min(width_px, height_px))
        fail("margin_px must be >= 0 and below a quarter of the image size");
    if (!auto_range &&
        !(std::isfinite(range_min) && std::isfinite(range_max) && range_min < range_max))
        fail("a fixed range needs finite range_min < range_max (got " + std::to_string(range_min) +
             ", " + std::to_string(range_max) + ")");
    if (!(outline_width_px > 0 && outline_width_px < 50))
        fail("outline_width_px must be in (0, 50)");
    if (!(font_size_px >= 4 && font_size_px <= 200))
        fail("font_size_px must be in [4, 200]");
    if (!(max_color_step > 0 && max_color_step <= 1) ||
        !(vector_max_color_step > 0 && vector_max_color_step <= 1))
        fail("max_color_step and vector_max_color_step must be in (0, 1]");
    if (!(arrow_spacing_px >= 4 && arrow_spacing_px <= 1000))
        fail("arrow_spacing_px must be in [4, 1000] (got " + std::to_string(arrow_spacing_px) + ")");
    for (const Eigen::Vector3d* c : {&background, &nan_color})
        if (!(c->minCoeff() >= 0 && c->maxCoeff() <= 1))
            fail("background and nan_color are RGB in [0, 1]");
    if (!view_direction.allFinite() || !view_up.allFinite())
        fail("view_direction and view_up must be finite (zero = automatic)");
    if (view_direction.norm() > 0 && view_up.norm() > 0 &&
        view_direction.normalized().cross(view_up.normalized()).norm() < 1e-6)
        fail("view_up must not be parallel to view_direction");
}

Eigen::Vector3d colormap_rgb(Colormap map, double t)
{
    const auto& table = map == Colormap::Diverging ? detail::kCoolwarm : detail::kViridis;
    if (!std::isfinite(t))
        t = 0.0;
    const double x = std::clamp(t, 0.0, 1.0) * 255.0;
    const int i = std::min(static_cast<int>(x), 254);
    const double a = x - i;
    Eigen::Vector3d c;
    for (int k = 0; k < 3; ++k)
        c[k] = (1.0 - a) * table[i][k] + a * table[i + 1][k];
    return c;
}

MapImageLayout map_image_range(const Eigen::VectorXd& values, const MapImageOptions& options)
{
    options.validate();
    MapImageLayout layout;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (double x : values)
        if (std::isfinite(x))
        {
            lo = std::min(lo, x);
            hi = std::max(hi, x);
        }
    if (!options.auto_range)
    {
        lo = options.range_min;
        hi = options.range_max;
    }
    else if (!(lo <= hi))
        throw InvalidInputError("map_image_range: none of the " + std::to_string(values.size()) +
                                " values is finite; pass a field with data or a fixed range");
    const bool straddles = lo < 0 && hi > 0;
    layout.colormap = options.colormap;
    if (layout.colormap == Colormap::Auto)
        layout.colormap = straddles ? Colormap::Diverging : Colormap::Viridis;
    if (options.auto_range && layout.colormap == Colormap::Diverging && straddles)
    {
        // A diverging map means "sign": its neutral middle must sit at 0.
        const double m = std::max(-lo, hi);
        lo = -m;
        hi = m;
    }
    if (lo == hi)
    {
        // A constant field still needs a non-empty range; centre it on the value.
        const double half = lo != 0 ? 0.1 * std::abs(lo) : 1.0;
        lo -= half;
        hi += half;
    }
    layout.range_min = lo;
    layout.range_max = hi;
    return layout;
}

}  // namespace vessel
