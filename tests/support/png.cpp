#include "support/png.h"

#include <doctest/doctest.h>

#include <cairo.h>

#include <cstdint>
#include <cstring>

namespace vessel::test {

Png::Png(const std::string& path)
    : surface_(cairo_image_surface_create_from_png(path.c_str()), &cairo_surface_destroy)
{
    REQUIRE_MESSAGE(cairo_surface_status(surface_.get()) == CAIRO_STATUS_SUCCESS, path);
    cairo_surface_flush(surface_.get());
}

int Png::width() const
{
    return cairo_image_surface_get_width(surface_.get());
}

int Png::height() const
{
    return cairo_image_surface_get_height(surface_.get());
}

Eigen::Vector3d Png::pixel(int x, int y) const
{
    const unsigned char* row = cairo_image_surface_get_data(surface_.get()) +
                               y * cairo_image_surface_get_stride(surface_.get());
    std::uint32_t p;
    std::memcpy(&p, row + 4 * x, 4);
    return Eigen::Vector3d((p >> 16) & 0xff, (p >> 8) & 0xff, p & 0xff) / 255.0;
}

double color_error(const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
    return (a - b).cwiseAbs().maxCoeff();
}

}  // namespace vessel::test
