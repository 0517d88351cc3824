#pragma once

// vessel-flatten --html with fields: the carried point fields as viewer fields.

#include "vessel/fields/fields.h"
#include "vessel/render/viewer.h"

#include <vector>

namespace vessel::cli {

//! Every point field of \p fields (static) and of \p series (over time), rows on the cut mesh,
//! as viewer fields: scalars as they are, vectors as their length (named |NAME|). Cell fields
//! are left out: the viewer colours vertices.
std::vector<ViewerField> viewer_fields(const std::vector<Field>& fields, const TimeSeries& series);

}  // namespace vessel::cli
