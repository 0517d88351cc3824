#pragma once

#include "vessel/layout.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace vessel {

//! A soft linear constraint on the centre c (mean uv) of a set of vertices: the energy
//! weight x (normal . (c - origin))^2, zero on the line through \p origin perpendicular to
//! \p normal. Quadratic in the map; injective_refine() adds it to SLIM's energy
//! (InjectiveOptions::centre_pulls).
struct CentrePull
{
    std::vector<int> vertices;  //!< vertex indices (`v.idx()`), not empty
    Eigen::Vector2d origin = Eigen::Vector2d::Zero();
    Eigen::Vector2d normal = Eigen::Vector2d::UnitX();  //!< unit length
    double weight = 0.0;  //!< >= 0; multiplies a squared length (an area)
};

//! \brief Check every pull: vertices, a weight >= 0, a finite origin and a unit normal.
//! \param who the options' name for the message.
//! \throw InvalidInputError naming the bad pull.
void validate_centre_pulls(const std::vector<CentrePull>& pulls, const std::string& who);

//! \brief The pulls that keep a map's look while SLIM runs: the inlet is held where it is in
//! \p uv (its two halves along the walk, each by two pulls, u and v: its centre and its chord's
//! direction stay) and every outlet loop's centre is pulled onto the ray from
//! the inlet's centre through where that centre is in \p uv (its bearing; a loop split by cuts
//! counts once, all its vertices). Meant for a start that has the layout's look (the layout
//! circle, layout_circle.h).
//! \param segments the cut mesh's boundary segments (BoundarySegment::loop 0 = inlet).
//! \param weight every pull's CentrePull::weight: the energy is weight x the sum of the squared
//! distances of the centres from their lines (an area, like SLIM's energy, whose minimum is
//! 4 x the surface's area).
//! \throw InvalidInputError if there is no inlet segment or a vertex is out of range.
std::vector<CentrePull> look_pulls(const std::vector<BoundarySegment>& segments,
                                   const Eigen::MatrixX2d& uv, double weight);

}  // namespace vessel
