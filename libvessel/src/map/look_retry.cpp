#include "detail/look_retry.h"

#include "detail/map_distortion.h"
#include "detail/refine_map.h"
#include "vessel/map/embedding.h"
#include "vessel/core/errors.h"
#include "vessel/quality/metrics.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>

namespace vessel {

bool LookRetryOptions::look_broken(const MapLook& look) const
{
    const double pairs = 0.5 * look.outlets * (look.outlets - 1);
    return look.outlets_below_inlet > 0 ||
           look.walk_inversions > max_walk_inversion_fraction * pairs;
}

void LookRetryOptions::validate() const
{
    if (!(pull > 0.0 && std::isfinite(pull)))
        throw InvalidInputError("LookRetryOptions: pull must be > 0 and finite, got " +
                                std::to_string(pull));
    if (!(max_walk_inversion_fraction >= 0.0 && max_walk_inversion_fraction <= 1.0))
        throw InvalidInputError(
            "LookRetryOptions: max_walk_inversion_fraction must be in [0, 1], got " +
            std::to_string(max_walk_inversion_fraction));
    if (!(max_area_over_keep >= 1.0 && std::isfinite(max_area_over_keep)))
        throw InvalidInputError("LookRetryOptions: max_area_over_keep must be >= 1 and finite, got " +
                                std::to_string(max_area_over_keep));
}

namespace detail {

namespace {

std::string look_line(const MapLook& look)
{
    return std::to_string(look.outlets_below_inlet) + " of " + std::to_string(look.outlets) +
           " outlets below the inlet, " + std::to_string(look.walk_inversions) +
           " walk inversions";
}

// Fewer outlets below the inlet, or as many and fewer walk inversions.
bool look_better(const MapLook& look, const MapLook& than)
{
    return look.outlets_below_inlet < than.outlets_below_inlet ||
           (look.outlets_below_inlet == than.outlets_below_inlet &&
            look.walk_inversions < than.walk_inversions);
}

}  // namespace

FlatQuality keep_quality(const Mesh& mesh, const Pins& pins, const Eigen::MatrixX2d& initial,
                         const FlattenOptions& options, const LayoutInput& layout,
                         const LayoutResult& placed, const std::atomic<bool>* cancel)
{
    FlattenOptions keep = cancellable(options, cancel);
    keep.overlaps = OverlapPolicy::Keep;
    FlattenResult unconstrained;
    unconstrained.uv = initial;
    refine_map(mesh, pins, keep, "", std::nullopt, unconstrained, &layout, &placed);
    return map_distortion(mesh, unconstrained.uv);
}

bool within_area_bound(const FlatQuality& map, const FlatQuality& keep,
                       const LookRetryOptions& retry)
{
    return map.mean_abs_log_area_normalized <=
               retry.max_area_over_keep * keep.mean_abs_log_area_normalized &&
           map.mean_abs_log_area <= retry.max_area_over_keep * keep.mean_abs_log_area;
}

bool may_retry_look(const FlattenOptions& options)
{
    return options.look_retry.mode != LookRetry::Off && options.look_pull.weight == 0.0 &&
           options.overlaps != OverlapPolicy::Keep;  // `keep` is the retry's own reference
}

namespace {

// Thrown from a solver's iteration callback once a cancel flag is set (cancellable()).
struct Cancelled
{
};

// \p caller (which may be empty) behind a check of \p cancel: it throws Cancelled once the
// flag is set, else calls \p caller (returning \p otherwise where that is empty).
template <class R, class... Args>
std::function<R(Args...)> behind(const std::atomic<bool>* cancel,
                                 std::function<R(Args...)> caller, R otherwise = R())
{
    return [cancel, caller = std::move(caller), otherwise](Args... args) -> R {
        if (cancel->load())
            throw Cancelled{};
        if (caller)
            return caller(args...);
        return otherwise;
    };
}

template <class... Args>
std::function<void(Args...)> behind(const std::atomic<bool>* cancel,
                                    std::function<void(Args...)> caller)
{
    return [cancel, caller = std::move(caller)](Args... args) {
        if (cancel->load())
            throw Cancelled{};
        if (caller)
            caller(args...);
    };
}

}  // namespace

FlattenOptions cancellable(const FlattenOptions& options, const std::atomic<bool>* cancel)
{
    if (!cancel)
        return options;
    FlattenOptions wired = options;
    // Ceres' ARAP would pay an energy evaluation per call: it runs to its end.
    if (options.arap.solver == ArapSolver::LocalGlobal)
        wired.arap.on_iteration = behind(cancel, options.arap.on_iteration, true);
    wired.injective.on_iteration = behind(cancel, options.injective.on_iteration);
    wired.area_polish.on_step = behind(cancel, options.area_polish.on_step);
    return wired;
}

FlattenResult pulled_map(const Mesh& mesh, const Pins& pins, const FlattenOptions& options,
                         const LayoutInput& layout, const LayoutResult& placed,
                         const std::atomic<bool>* cancel)
{
    FlattenOptions pulled = cancellable(options, cancel);
    pulled.look_pull.weight = options.look_retry.pull;
    FlattenResult trial;
    refine_map(mesh, pins, pulled, "", "look retry", trial, &layout, &placed);
    return trial;
}

void retry_look(const Mesh& mesh, const Pins& pins, const Eigen::MatrixX2d& initial,
                const FlattenOptions& options, FlattenResult& result, const LayoutInput& layout,
                const LayoutResult& placed, std::future<FlattenResult>* ahead)
{
    const LookRetryOptions& retry = options.look_retry;
    if (!may_retry_look(options))
        return;
    LookRetrySummary& summary = result.look_retry;
    summary.default_look = map_look(mesh, result.uv, layout.segments, placed);
    if (summary.default_look.outlets == 0 ||
        (retry.mode == LookRetry::Auto && !retry.look_broken(summary.default_look)))
        return;
    summary.tried = true;
    // While the pulled map made ahead is still being solved on the second core, this thread
    // would wait for it: it solves the `keep` map the area bound may need meanwhile (the same
    // map as after the fact; used only where the bound needs it).
    std::optional<FlatQuality> keep_ahead;
    if (ahead && ahead->valid() &&
        ahead->wait_for(std::chrono::seconds(0)) != std::future_status::ready)
        keep_ahead = keep_quality(mesh, pins, initial, options, layout, placed);
    const FlatQuality before = map_distortion(mesh, result.uv);
    summary.default_area = before.mean_abs_log_area_normalized;

    FlattenResult trial = ahead && ahead->valid()
                              ? ahead->get()
                              : pulled_map(mesh, pins, options, layout, placed);
    const FlatQuality quality = flat_quality(mesh, trial.uv);
    summary.pulled_area = quality.mean_abs_log_area_normalized;
    const MapLook look = map_look(mesh, trial.uv, layout.segments, placed);

    std::string verdict;
    const MapLook& was = summary.default_look;
    if (quality.flipped_triangles > 0 || quality.overlapping_triangles > 0 ||
        boundary_self_intersection(mesh, trial.uv).first >= 0)
        verdict = "not one-to-one";
    else if (!look_better(look, was))
        verdict = "look not better";
    else if (summary.pulled_area > summary.default_area ||
             quality.mean_abs_log_area > before.mean_abs_log_area)
    {
        const FlatQuality keep =
            keep_ahead ? *keep_ahead : keep_quality(mesh, pins, initial, options, layout, placed);
        summary.keep_area = keep.mean_abs_log_area_normalized;
        if (!within_area_bound(quality, keep, retry))
            verdict = "area above the bound";
    }
    summary.kept = verdict.empty();
    char areas[160];
    std::snprintf(areas, sizeof areas, "look retry (pull %g): ", retry.pull);
    std::string line = areas + look_line(summary.default_look) + " -> " + look_line(look);
    std::snprintf(areas, sizeof areas, "; mean |log area| %.4f -> %.4f", summary.default_area,
                  summary.pulled_area);
    line += areas;
    if (summary.keep_area > 0.0)
    {
        std::snprintf(areas, sizeof areas, " (keep %.4f)", summary.keep_area);
        line += areas;
    }
    summary.report = line +
                     (summary.kept ? "; kept the pulled map"
                                   : "; " + verdict + ", kept the default map");
    result.notes.push_back(summary.report);
    if (summary.kept)
    {
        result.uv = std::move(trial.uv);
        result.injective = trial.injective;
    }
}

}  // namespace detail

}  // namespace vessel
