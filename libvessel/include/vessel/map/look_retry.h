#pragma once

#include "vessel/map/map_look.h"

#include <string>

namespace vessel {

//! When the pipeline redoes a restarted map with the look pull (LookRetryOptions).
enum class LookRetry
{
    Off,   //!< never: the default map as it comes
    Auto,  //!< when the default map's look is broken (LookRetryOptions::look_broken())
    Force  //!< whenever the map restarted, broken or not (the acceptance test still applies)
};

//! \brief The adaptive look of issue 7: after a restarted map (no fixed look pull:
//! `FlattenOptions::look_pull.weight` 0), if its look is broken, redo the restart, SLIM and the
//! polish with the hinge pull and keep that map only if it is one-to-one, its look is better (fewer
//! outlets below the inlet, or as many and fewer walk inversions) and its area distortion is within
//! the bound; trees whose look holds are untouched (docs/overlaps.md, "The adaptive look").
struct LookRetryOptions
{
    //! CLI `--look-retry auto|off|force`.
    LookRetry mode = LookRetry::Auto;
    //! The redo's hinge weight (LookPullOptions::weight; the other fields of
    //! FlattenOptions::look_pull apply, its steps too: by default the hinges' exact
    //! Gauss-Newton terms). With coarse-to-fine a kept pulled map is carried up with its pulls
    //! at this weight, as a map pulled from the start (docs/overlaps.md, "The steps and the
    //! carry"). Fitted on the pulmonary trees' natural cuts: a weight that keeps Glenn split4's
    //! map free of walk inversions within the area bound, where a lower one does not
    //! (docs/overlaps.md, "The adaptive look"). CLI `--look-retry-pull`.
    double pull = 400.0;
    //! The look is broken when an outlet is below the inlet or the walk inversions exceed this
    //! fraction of the outlet pairs: above what the tree phantoms' restarted maps show, below
    //! what the maps whose fan is visibly scrambled show (docs/overlaps.md, "The adaptive
    //! look"). CLI `--look-retry-inversions`.
    double max_walk_inversion_fraction = 0.05;
    //! The pulled map is kept only if its mean |log area| (both FlatQuality measures) is at
    //! most this factor times that of the unconstrained map (`--overlaps keep`, computed for the
    //! test when the pulled map's area is above the default map's): issue 7's 1.5x-keep bound,
    //! less a margin. With coarse-to-fine (multilevel.h) the retry runs and the bound is held
    //! on the coarse mesh; carried up with its pulls, the kept map's area at full resolution
    //! is not the coarse mesh's (docs/overlaps.md, "The steps and the carry", has both).
    //! CLI `--look-retry-area`.
    double max_area_over_keep = 1.45;
    //! \brief Whether \p look is broken by the rule above.
    bool look_broken(const MapLook& look) const;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! What the look retry did (FlattenResult::look_retry).
struct LookRetrySummary
{
    bool tried = false;          //!< the restart was redone with the pull
    bool kept = false;           //!< the pulled map replaced the default one
    double default_area = 0.0;   //!< default map's mean |log area| (normalized)
    //! pulled map's, when tried; after coarse-to-fine, on the coarse mesh, where the bound
    //! was checked (as keep_area)
    double pulled_area = 0.0;
    //! the `keep` map's, when it was computed (else 0); after coarse-to-fine, on the coarse
    //! mesh
    double keep_area = 0.0;
    MapLook default_look;        //!< the default map's look, when tried
    std::string report;          //!< one line, also in FlattenResult::notes
};

}  // namespace vessel
