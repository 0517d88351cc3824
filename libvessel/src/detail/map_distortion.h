#pragma once

#include "vessel/quality/metrics.h"

namespace vessel::detail {

//! flat_quality() without the overlap search (its overlap fields stay 0): the distortion
//! measures alone, for comparisons of mean |log area| between maps of the same mesh, where the
//! exact pairwise overlap test (find_overlaps()) would cost more than the rest.
FlatQuality map_distortion(const Mesh& mesh, const Eigen::MatrixX2d& uv);

}  // namespace vessel::detail
