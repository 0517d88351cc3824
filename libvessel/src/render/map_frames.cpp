#include "vessel/render/map_frames.h"

#include "vessel/core/errors.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace vessel {
namespace {

std::string frame_name(int k)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "frame_%04d.png", k);
    return buf;
}

//! Single-quote \p s for /bin/sh.
std::string shell_quote(const std::string& s)
{
    std::string q = "'";
    for (char c : s)
        q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

bool ffmpeg_available()
{
    return std::system("command -v ffmpeg >/dev/null 2>&1") == 0;
}

//! Encodes the frames with ffmpeg; GIF through a generated palette (far better colours than
//! ffmpeg's default), MP4 as H.264 yuv420p with even dimensions (what players accept).
void encode_animation(const std::string& dir, const std::string& out, double fps)
{
    std::string ext = std::filesystem::path(out).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    const std::string input = "-framerate " + std::to_string(fps) + " -i " +
                              shell_quote((std::filesystem::path(dir) / "frame_%04d.png").string());
    std::string filter;
    if (ext == ".gif")
        filter = "-filter_complex \"[0:v]split[a][b];[a]palettegen[p];[b][p]paletteuse\"";
    else
        filter = "-vf \"scale=trunc(iw/2)*2:trunc(ih/2)*2\" -c:v libx264 -pix_fmt yuv420p";
    const std::string cmd =
        "ffmpeg -y -loglevel error " + input + " " + filter + " " + shell_quote(out);
    if (std::system(cmd.c_str()) != 0)
        throw IoError("render_frames: ffmpeg failed to write " + out + " (command: " + cmd + ")");
}

}  // namespace

void FieldSeries::validate() const
{
    if (times.empty())
        throw InvalidInputError("FieldSeries: no time step; give at least one");
    if (times.size() != values.size())
        throw InvalidInputError("FieldSeries: " + std::to_string(times.size()) + " times but " +
                                std::to_string(values.size()) + " value vectors");
    for (std::size_t k = 0; k < times.size(); ++k)
    {
        if (!std::isfinite(times[k]) || (k > 0 && !(times[k] > times[k - 1])))
            throw InvalidInputError(
                "FieldSeries: times must be finite and strictly increasing "
                "(step " +
                std::to_string(k) + " is " + std::to_string(times[k]) + ")");
        if (values[k].size() != values[0].size())
            throw InvalidInputError("FieldSeries: step " + std::to_string(k) + " has " +
                                    std::to_string(values[k].size()) + " values, step 0 has " +
                                    std::to_string(values[0].size()));
    }
}

void FrameOptions::validate() const
{
    if (!(fps > 0 && fps <= 240))
        throw InvalidInputError("FrameOptions: fps must be in (0, 240] (got " +
                                std::to_string(fps) + ")");
    if (!(slowdown > 0 && std::isfinite(slowdown)))
        throw InvalidInputError("FrameOptions: slowdown must be a positive number");
    if (!animation.empty())
    {
        std::string ext = std::filesystem::path(animation).extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(),
                       [](unsigned char c) { return std::tolower(c); });
        if (ext != ".gif" && ext != ".mp4")
            throw InvalidInputError("FrameOptions: animation '" + animation +
                                    "' must end in .gif or .mp4");
    }
}

Eigen::VectorXd interpolate_series(const FieldSeries& series, double t)
{
    series.validate();
    if (!std::isfinite(t))
        throw InvalidInputError("interpolate_series: time is not finite");
    const auto& T = series.times;
    if (t <= T.front())
        return series.values.front();
    if (t >= T.back())
        return series.values.back();
    const std::size_t k =
        std::upper_bound(T.begin(), T.end(), t) - T.begin();  // T[k-1] <= t < T[k]
    const double a = (t - T[k - 1]) / (T[k] - T[k - 1]);
    return (1.0 - a) * series.values[k - 1] + a * series.values[k];
}

MapImageOptions series_range_options(const FieldSeries& series, const MapImageOptions& image)
{
    series.validate();
    image.validate();
    if (!image.auto_range)
        return image;
    // One range over every step: linear blends never leave [min, max] of their ends.
    Eigen::VectorXd all(series.values.size() * series.values[0].size());
    Eigen::Index at = 0;
    for (const auto& v : series.values)
    {
        all.segment(at, v.size()) = v;
        at += v.size();
    }
    const MapImageLayout range = map_image_range(all, image);
    MapImageOptions fixed = image;
    fixed.auto_range = false;
    fixed.range_min = range.range_min;
    fixed.range_max = range.range_max;
    fixed.colormap = range.colormap;
    return fixed;
}

std::vector<double> frame_times(const FieldSeries& series, const FrameOptions& options)
{
    series.validate();
    options.validate();
    const double dt = 1.0 / (options.fps * options.slowdown);
    const double t0 = series.times.front(), t1 = series.times.back();
    const auto n = static_cast<long>(std::floor((t1 - t0) / dt + 1e-9)) + 1;
    if (n > 100000)
        throw InvalidInputError("frame_times: " + std::to_string(n) +
                                " frames; lower fps or slowdown");
    std::vector<double> times(n);
    for (long k = 0; k < n; ++k)
        times[k] = t0 + k * dt;
    return times;
}

FramesSummary render_frames(const std::string& dir, const MapImageInput& input,
                            const FieldSeries& series, const MapImageOptions& image,
                            const FrameOptions& options)
{
    FramesSummary summary;
    summary.frame_times = frame_times(series, options);
    const MapImageOptions frame_options =
        options.fixed_range ? series_range_options(series, image) : image;
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
        throw IoError("render_frames: cannot create directory " + dir + ": " + ec.message());
    for (std::size_t k = 0; k < summary.frame_times.size(); ++k)
    {
        const Eigen::VectorXd values = interpolate_series(series, summary.frame_times[k]);
        MapImageOptions timed = frame_options;
        if (options.time_caption)
        {
            char caption[64];
            std::snprintf(caption, sizeof caption, "t = %.3f s", summary.frame_times[k]);
            timed.caption = caption;
        }
        const MapImageLayout layout = render_map_image(
            (std::filesystem::path(dir) / frame_name(static_cast<int>(k))).string(), input, values,
            timed);
        if (k == 0)
        {
            summary.range_min = layout.range_min;
            summary.range_max = layout.range_max;
        }
        ++summary.frames;
    }
    if (!options.animation.empty())
    {
        if (ffmpeg_available())
        {
            encode_animation(dir, options.animation, options.fps);
            summary.animation_written = true;
        }
        else
            summary.message =
                "ffmpeg not found on PATH; wrote the frames only, not " + options.animation;
    }
    return summary;
}

}  // namespace vessel
