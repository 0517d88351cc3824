#pragma once

#include <Eigen/Core>

#include <memory>
#include <string>

typedef struct _cairo_surface cairo_surface_t;

namespace vessel::test {

//! A PNG read back with cairo; pixel() gives RGB in [0, 1].
class Png
{
public:
    //! Reads \p path; a doctest REQUIRE fails if cairo cannot.
    explicit Png(const std::string& path);
    int width() const;
    int height() const;
    Eigen::Vector3d pixel(int x, int y) const;

private:
    std::unique_ptr<cairo_surface_t, void (*)(cairo_surface_t*)> surface_;
};

//! Largest per-channel difference of two RGB colours.
double color_error(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

}  // namespace vessel::test
