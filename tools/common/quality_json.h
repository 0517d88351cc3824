#pragma once

// The map-quality keys of every JSON the project writes (vessel-flatten --report, --batch,
// vessel-bench-table for ours and for the CGAL peer): one serializer, so a key means the same
// thing everywhere. Field meanings: vessel/quality/metrics.h (FlatQuality).

#include "vessel/quality/metrics.h"

#include <nlohmann/json.hpp>

namespace vessel::cli {

inline nlohmann::json quality_json(const FlatQuality& q)
{
    return {{"flipped_triangles", q.flipped_triangles},
            {"area_ratio", q.area_ratio},
            {"mean_abs_log_area_ratio", q.mean_abs_log_area},
            {"mean_abs_log_area_normalized", q.mean_abs_log_area_normalized},
            {"mean_conformal_distortion", q.mean_conformal},
            {"max_conformal_distortion", q.max_conformal},
            {"overlapping_triangles", q.overlapping_triangles},
            {"overlap_area", q.overlap_area},
            {"overlap_fraction", q.overlap_fraction}};
}

}  // namespace vessel::cli
