#pragma once

// vessel-flatten --image / --frames: a field of the flattened result drawn with map_image.h.

#include "vessel/fields/fields.h"
#include "vessel/pipeline.h"
#include "vessel/render/map_image.h"

#include <optional>
#include <string>
#include <vector>

namespace vessel::cli {

struct ImageRequest
{
    //! --image OUT.png|svg|pdf ...: the same image in each of these files (empty: none)
    std::vector<std::string> images;
    std::string frames;  //!< --frames DIR (empty: none)
    //! --field NAME[:magnitude|x|y|z] (empty: the first point field; parse_field_choice())
    std::string field;
    std::string units;   //!< --image-units: after the colorbar title, e.g. "Pa"
    //! --image-range LO HI: the colour range of --image and --frames (empty: the field's)
    std::vector<double> range;
    Colormap colormap = Colormap::Auto;  //!< --colormap
    std::vector<int> size;               //!< --image-size W H (empty: 1200 x 800)
    double fps = 25.0;                   //!< --fps: frames per second of series time (--frames)
    bool view3d = false;  //!< --image-3d: the 3D cut mesh beside the map
    //! --image-arrows NAME: a 3-component point array drawn as arrows on the map (its part along
    //! the wall pushed through the map); --image shows it at the moment it draws, --frames its
    //! time average over the series (empty: no arrows)
    std::string arrows;
    std::string title;    //!< the colorbar title (empty: the field's, e.g. |WSS|)
    std::vector<std::string> labels;  //!< of the inlet and outlets (empty: inlet, outlet 1...)
    std::optional<double> max_color_step;  //!< MapImageOptions::max_color_step (none: default)
    //! --image-step N: the series step --image draws (0-based); none = step 0 unless `time`.
    std::optional<int> step;
    //! --image-time T: the series time (s) --image draws, linearly interpolated between the
    //! two steps around it; must lie within the series' times.
    std::optional<double> time;
    bool quiet = false;
};

//! \brief Draw the chosen point field (fields carried to the cut mesh) on the map: --image shows
//! the static field, or one moment of a series (step 0, `step`, or `time` interpolated) with the
//! colour range of the whole series; --frames renders every step of the series, interpolated in
//! time. Vectors are drawn as their magnitude.
//! \throw InvalidInputError if there is no point field to draw, the field is a cell field,
//! --frames has no series, or the step or time is not in the series (or there is no series).
void render_images(const ImageRequest& request, const FlattenResult& result,
                   const std::vector<Field>& fields, const TimeSeries& series);

//! \brief The checks of render_images() that need only the fields, made before the flattening
//! so that a request that cannot be drawn fails before any work: the field exists and is a
//! point field, the --image-arrows array is a 3-component point array, --image-step/--image-time/
//! --frames have a series, and the figure options
//! (--image-range, --image-size, --fps) are valid.
//! \throw InvalidInputError as render_images().
void check_images(const ImageRequest& request, const std::vector<Field>& fields,
                  const TimeSeries& series);

}  // namespace vessel::cli
