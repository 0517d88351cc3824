#pragma once

#include "vessel/render/map_image.h"

#include <string>
#include <vector>

namespace vessel {

//! \file A time series of a field on the flattened map as numbered PNG frames (and, when ffmpeg
//! is installed, an animated GIF or MP4).

//! Per-vertex values at increasing times: `values[k]` holds one value per vertex at `times[k]`.
struct FieldSeries
{
    std::vector<double> times;            //!< strictly increasing, seconds
    std::vector<Eigen::VectorXd> values;  //!< one vector per time, all of the same size
    //! \throw InvalidInputError if the sizes disagree, times are not strictly increasing or
    //! there is no step.
    void validate() const;
};

//! \brief Values at time \p t: the linear blend of the two steps around \p t; times before the
//! first (after the last) step give the first (last) step's values.
//! \throw InvalidInputError if `series.validate()` fails or \p t is not finite.
Eigen::VectorXd interpolate_series(const FieldSeries& series, double t);

struct FrameOptions
{
    double fps = 25.0;  //!< frames per second of the animation
    //! Seconds of animation per second of series time (2 = twice as slow as real time).
    double slowdown = 1.0;
    //! One colour range for all frames (min/max over every step); otherwise each frame's own.
    //! Ignored when MapImageOptions fixes the range.
    bool fixed_range = true;
    //! Write each frame's series time as the image's caption ("t = 0.250 s"), so that a
    //! frame taken out of the series still says when it is.
    bool time_caption = true;
    //! Also write an animation here (`.gif` or `.mp4`) with ffmpeg when it is on PATH; empty =
    //! frames only.
    std::string animation;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

struct FramesSummary
{
    int frames = 0;                   //!< PNGs written, DIR/frame_0000.png ...
    std::vector<double> frame_times;  //!< series time of each frame
    double range_min = 0.0;           //!< range of the first frame
    double range_max = 1.0;
    bool animation_written = false;  //!< the GIF/MP4 exists
    std::string message;  //!< why no animation was written (e.g. ffmpeg not found), else empty
};

//! \brief \p image with its colour range fixed to the range of every step of \p series (what
//! render_frames() uses with `fixed_range`), so that images at different times compare; \p image
//! unchanged when it fixes the range itself (`auto_range = false`).
//! \throw InvalidInputError if `series.validate()` or `image.validate()` fails.
MapImageOptions series_range_options(const FieldSeries& series, const MapImageOptions& image);

//! Times of the frames: t0, t0 + 1 / (fps slowdown), ... up to the last step's time.
std::vector<double> frame_times(const FieldSeries& series, const FrameOptions& options);

//! \brief Render \p series as DIR/frame_0000.png, ... (the directory is created) at the times of
//! frame_times(), each interpolated with interpolate_series().
//! \throw InvalidInputError as render_map_image() and the validate() functions.
//! \throw IoError if the directory or a frame cannot be written or ffmpeg fails.
FramesSummary render_frames(const std::string& dir, const MapImageInput& input,
                            const FieldSeries& series, const MapImageOptions& image = {},
                            const FrameOptions& options = {});

}  // namespace vessel
