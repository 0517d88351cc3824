#pragma once

#include "prepare.h"

#include "vessel/pipeline.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace vessel::cli {

//! The `--report` JSON of one flattened mesh (timings, counts, repairs, cuts with their
//! alignment, quality, notes). \p in must be the input that was flattened into \p r.
//! \param viewpoint `--viewpoint`, if given: the quality gets `seam_far_side_fraction`.
nlohmann::json report_json(const std::string& input, const PreparedInput& in,
                           const FlattenResult& r, double read_s, double write_s,
                           const std::optional<Eigen::Vector3d>& viewpoint = std::nullopt);

}  // namespace vessel::cli
