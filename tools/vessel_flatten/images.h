#pragma once

// vessel-flatten --image / --frames: a field of the flattened result drawn with map_image.h.

#include "vessel/fields.h"
#include "vessel/pipeline.h"

#include <string>
#include <vector>

namespace vessel::cli {

struct ImageRequest
{
    std::string image;   //!< --image OUT.png|svg|pdf (empty: none)
    std::string frames;  //!< --frames DIR (empty: none)
    std::string field;   //!< --field NAME (empty: the first point field)
    bool quiet = false;
};

//! \brief Draw the chosen point field (fields carried to the cut mesh) on the map: --image shows
//! the static field, or step 0 of a series; --frames renders every step of the series,
//! interpolated in time. Vectors are drawn as their magnitude.
//! \throw InvalidInputError if there is no point field to draw, the field is a cell field, or
//! --frames has no series.
void render_images(const ImageRequest& request, const FlattenResult& result,
                   const std::vector<Field>& fields, const TimeSeries& series);

}  // namespace vessel::cli
