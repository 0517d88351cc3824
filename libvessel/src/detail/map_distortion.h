#pragma once

#include "vessel/quality/metrics.h"

#include <cmath>
#include <utility>

namespace vessel::detail {

//! flat_quality() without the overlap search (its overlap fields stay 0): the distortion
//! measures alone, for comparisons of mean |log area| between maps of the same mesh, where the
//! exact pairwise overlap test (find_overlaps()) would cost more than the rest.
FlatQuality map_distortion(const Mesh& mesh, const Eigen::MatrixX2d& uv);

//! The faces [begin, end) given as (map area a2, surface area a3), both > 0: the sum of
//! a3 |log(a2 / a3) - shift|, with shift = log(sum a2 / sum a3) over all the map's faces. Divided
//! by sum a3 it is FlatQuality::mean_abs_log_area_normalized (the map scaled to the surface's
//! area); a sum over parts of the faces adds up to it.
inline double normalized_log_area_sum(const std::pair<double, double>* begin,
                                      const std::pair<double, double>* end, double shift)
{
    double sum = 0.0;
    for (const auto* face = begin; face != end; ++face)
        sum += face->second * std::abs(std::log(face->first / face->second) - shift);
    return sum;
}

}  // namespace vessel::detail
