#pragma once

// Plane geometry shared by the layout policies (layout.cpp, sector_layout.cpp).

#include "vessel/layout/layout.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace vessel::detail {

inline Eigen::Vector2d rotate(const Eigen::Vector2d& d, double angle)
{
    const double c = std::cos(angle), s = std::sin(angle);
    return {c * d.x() - s * d.y(), s * d.x() + c * d.y()};
}

inline Eigen::Vector2d left_normal(const Eigen::Vector2d& d) { return {-d.y(), d.x()}; }

//! Index into `input.segments` of every loop's segment (loops are indexed as `*input.loops`).
//! \throw TopologyError naming \p caller if a loop is opened in several places or not at all.
std::vector<int> segment_of_loop(const LayoutInput& input, const std::string& caller);

//! Pins \p seg as a straight line of its own arc length, centred at \p centre, perpendicular to
//! \p direction, running from the left to the right of the direction (clockwise boundary).
void pin_segment(const BoundarySegment& seg, const Eigen::Vector2d& centre,
                 const Eigen::Vector2d& direction, Pins& pins);

//! The strip of a segment: from \p base (width \p base_width) along unit \p direction for
//! \p height to the outlet (width \p top_width); corners base-left, base-right, top-right, top-left.
Strip make_strip(const Eigen::Vector2d& base, const Eigen::Vector2d& direction, double height,
                 double base_width, double top_width);

//! 3D length of a cut path.
double path_length(const Mesh& mesh, const CutPath& path);

}  // namespace vessel::detail
