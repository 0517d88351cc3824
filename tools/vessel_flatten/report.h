#pragma once

#include "prepare.h"

#include "vessel/pipeline.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace vessel::cli {

//! The `--report` JSON of one flattened mesh (timings, counts, repairs, cuts with their
//! alignment, quality, notes). \p in must be the input that was flattened into \p r.
//! With a viewpoint (FlattenResult::viewpoint, `--viewpoint`) the report gets it as
//! `cuts_viewpoint` and the quality `seam_far_side_fraction`.
nlohmann::json report_json(const std::string& input, const PreparedInput& in,
                           const FlattenResult& r, double read_s, double write_s);

}  // namespace vessel::cli
