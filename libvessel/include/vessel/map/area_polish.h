#pragma once

#include "vessel/map/centre_pull.h"
#include "vessel/layout/pins.h"

#include <functional>
#include <string>

namespace vessel {

struct AreaPolishOptions
{
    //! lambda of the energy below, in [0, 1): the weight of the area term against the shape
    //! term. 0.5 weighs them like the untangling (untangle.h) and barely changes a SLIM map;
    //! larger values trade conformal distortion for area. The default 0.99 keeps the
    //! one-to-one maps of the tree phantoms and of the pulmonary tree within 1.5x of the
    //! unconstrained maps' area distortion, which 0.9 does not (docs/overlaps.md, "Area polish
    //! by default").
    double area_weight = 0.99;
    //! Minimize with projected Newton steps (each face's Hessian with its negative eigenvalues
    //! clamped to 0, CHOLMOD, an Armijo line search that flips no face) instead of L-BFGS.
    //! L-BFGS moves large parts of the map slowly where its boundary presses on itself
    //! (scaffold): on the pulmonary tree it stopped at 0.068 mean |log area| after 1000
    //! iterations, Newton reaches 0.0096 in 15 (docs/overlaps.md).
    bool newton = true;
    int newton_max_iterations = 100;  //!< Newton steps in all
    //! Newton steps per chunk: each chunk gets a new scaffold (when the boundary is kept simple).
    int newton_chunk_iterations = 5;
    int max_iterations = 1000;  //!< L-BFGS iterations in all (newton off)
    //! L-BFGS iterations per chunk (newton off); each chunk gets a new scaffold.
    int chunk_iterations = 50;
    //! Stop once a chunk lowers the energy by less than this fraction of its excess over the
    //! isometric minimum (2 x the surface area).
    double tolerance = 0.01;
    //! Keep a map whose boundary is simple one-to-one: the free space between its boundary and
    //! a box around it is triangulated (detail::scaffold_triangles) for each chunk and no
    //! triangle of it may flip either. Off, or when the boundary already crosses itself, only
    //! the surface's triangles are kept from flipping.
    bool keep_boundary_simple = true;
    //! The scaffold's total weight, as a fraction of the surface area, shared equally by its
    //! triangles (as InjectiveOptions::scaffold_weight).
    double scaffold_weight = 0.002;
    //! Soft pulls on vertex sets' centres (centre_pull.h) added to the energy (its gradient
    //! exact; the Newton steps take their curvature as `pull_steps` says). Empty = none. The
    //! pipeline passes SLIM's (FlattenOptions::look_pull).
    std::vector<CentrePull> centre_pulls;
    //! How the Newton steps take `centre_pulls` (PullSteps; the pipeline passes
    //! LookPullOptions::steps). With GaussNewton a hinge within one margin of turning on counts
    //! with its curvature (detail::active_pull_rows()), so that a full step does not jump past it.
    PullSteps pull_steps = PullSteps::GaussNewton;
    //! Called after every Newton step (with L-BFGS, after every chunk) with the steps (or
    //! iterations) done so far, e.g. for progress output: a Newton step of a map of 100k
    //! vertices takes about a second, a chunk several. Null (the default) = no calls.
    std::function<void(int iterations)> on_step;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

struct AreaPolishSummary
{
    int iterations = 0;  //!< Newton steps (or L-BFGS iterations) in all
    //! The energy at the start and the end (the scaffold's small share included)
    double energy_before = 0.0, energy_after = 0.0;
    bool scaffold = false;  //!< the boundary was kept simple with a scaffold
    std::string report;     //!< one line
};

//! \brief Lower the area distortion of a flip-free map, keeping it flip-free (and, with
//! keep_boundary_simple, one-to-one).
//!
//! Minimizes sum_t A_t ((1 - lambda) ||J_t||^2 / det J_t + lambda (det J_t + 1 / det J_t)) over
//! the unpinned vertices with projected Newton steps (or L-BFGS, Ceres): the eps -> 0 limit of the untangling energy of
//! Garanzha et al. 2021. Its minimum per face is an isometry and it grows without bound as a
//! face collapses; an evaluation with a non-positive det is refused, so no step flips a face.
//! SLIM's symmetric Dirichlet energy cares about shape and area alike (on the 10-outlet tree
//! phantom it differs by 1% between maps whose mean |log area| differs by 65%); with lambda near
//! 1 this energy cares mostly about area.
//! \param uv |V| x 2, row `v.idx()`, without flipped faces; updated in place.
//! \param pins vertices that must not move (may be empty).
//! \throw InvalidInputError if \p uv has a flipped face, sizes disagree or options are invalid.
//! \throw TopologyError if the mesh is not a disk.
AreaPolishSummary area_polish(const Mesh& mesh, Eigen::MatrixX2d& uv, const Pins& pins,
                              const AreaPolishOptions& options = {});

}  // namespace vessel
