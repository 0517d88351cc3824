#pragma once

#include "vessel/map/centre_pull.h"
#include "vessel/layout/pins.h"

#include <functional>
#include <string>

namespace vessel {

//! \brief Tutte embedding \cite tutte_1963_draw, \cite floater_1997_parametrization: the disk's
//! boundary is placed on a circle of the same perimeter (by arc length), every interior vertex at
//! the average of its neighbours. Guaranteed free of flipped triangles (faces counter-clockwise).
//! \param mesh Disk-topology triangle mesh.
//! \return |V| x 2 (u, v), row `v.idx()`.
//! \throw TopologyError if the mesh does not have exactly one boundary loop.
//! \throw SolverError if the sparse factorization fails.
Eigen::MatrixX2d tutte_embedding(const Mesh& mesh);

//! \brief Tutte embedding with the boundary held at given positions: every interior vertex at
//! the average of its neighbours. Free of flipped triangles when \p boundary is a convex polygon
//! walked clockwise along the boundary halfedges (as on tutte_embedding()'s circle).
//! \param boundary a position for every boundary vertex (and for no other vertex).
//! \return |V| x 2, row `v.idx()`, scaled to the surface's 3D area.
//! \throw InvalidInputError if a boundary vertex has no position or an interior one has.
//! \throw SolverError if the sparse factorization fails.
Eigen::MatrixX2d tutte_embedding(const Mesh& mesh, const Pins& boundary);

struct InjectiveOptions
{
    int max_iterations = 100;  //!< SLIM iterations
    //! Stop after 3 iterations in a row decrease the energy by less (relative), unless each of
    //! them was cut short by a nearly collapsed triangle (InjectiveSummary::stalls_passed).
    double tolerance = 1e-4;
    //! Keep the map one-to-one, not only flip-free: triangulate the free space between the
    //! map's boundary and a box around it (a scaffold, Jiang et al. 2017) and let no scaffold
    //! triangle flip either, so the boundary cannot run into itself. Needs a start without
    //! overlaps (e.g. tutte_embedding).
    bool scaffold = false;
    //! Run without a scaffold, checking the map's boundary after every step; if the end map's
    //! boundary crosses itself, go back to the last iterate whose boundary was simple and go on
    //! from there with the scaffold (up to max_iterations more). The result is one-to-one, and
    //! the scaffold's cost is paid only when needed. Until the boundary's parts first touch, a
    //! step that would cross the boundary is halved (up to 6 times) until it does not, so the
    //! scaffold starts from where they touch rather than from before the step that crossed
    //! them, as the line search of \cite smith_2015_bijective stops at the boundary's first
    //! collision. Needs a start whose boundary is simple; otherwise it has no effect.
    bool scaffold_on_contact = false;
    //! With scaffold_on_contact: once the boundary has stayed crossed for this many
    //! iterations in a row, stop the unconstrained run there and go on with the scaffold (a
    //! crossing that lasts seldom comes apart; the iterations spent on it are lost).
    int crossing_patience = 5;
    //! The scaffold's total weight, as a fraction of the surface area, shared equally by its
    //! triangles. Heavier scaffolds resist the map's motion more (pulmonary tree, mean |log
    //! area|: 0.1598 at 0.1, 0.1561 at 0.02; the weight does not stall the steps).
    double scaffold_weight = 0.002;
    //! The stopping rule's `tolerance` once a scaffold is in use; 0 = automatic:
    //! kScaffoldTolerance, or kPolishedScaffoldTolerance where flatten()'s area polish follows
    //! SLIM (FlattenOptions::polish_area).
    double scaffold_tolerance = 0.0;
    //! SLIM alone: the scaffold's steps are shorter, and progress continues below 1e-4. With
    //! `momentum` 0.5, 2e-5 ends within a few percent of the mean |log area| of 1e-5 without
    //! momentum in 55-75% of the iterations; 3e-5 stops visibly early on large maps
    //! (docs/journal/benchmarks-2026-11.md, "SLIM momentum").
    static constexpr double kScaffoldTolerance = 2e-5;
    //! Before the area polish: the scaffold phase's slow tail evens out area, which the
    //! polish's Newton steps do in a few steps anyway; the end map's mean |log area| stays the
    //! same (docs/journal/benchmarks-2026-11.md, "SLIM hands over to the polish").
    static constexpr double kPolishedScaffoldTolerance = 3e-4;
    //! With scaffold_on_contact: when the boundary has crossed (crossing_patience), SLIM goes
    //! back to its last simple iterate and on with a scaffold. Where that iterate's energy is
    //! at most this fraction above the crossed iterate's, it stops there instead: the
    //! unconstrained steps had all but converged, and the scaffold phase, whose iterations
    //! cost several unconstrained ones each (a constrained Delaunay triangulation and a new
    //! symbolic factorization), could gain about that gap, which a following area polish
    //! gains anyway with its own scaffold. The map is one-to-one either way. 0 = automatic:
    //! kPolishedSkipGap where flatten()'s area polish follows SLIM, never otherwise; < 0 =
    //! never.
    double scaffold_skip_gap = 0.0;
    //! Before the area polish: a boundary that crosses late, after the energy has all but
    //! converged, skips the scaffold phase; one that crosses within the first iterations, far
    //! above the minimum (a tree from the layout circle), does not (docs/benchmarks.md, "The
    //! scaffold's skip gap").
    static constexpr double kPolishedSkipGap = 0.03;
    //! Line searches per global step in the scaffold phase: when a step stops where a scaffold
    //! triangle would collapse, the free space is triangulated again (its triangles made
    //! Delaunay by edge flips, or where none flips, anew by the CGAL mesher) and the rest of the
    //! same direction is line searched again (no new factorization), up to this many times in
    //! all. 1 = one line search per step (Jiang et al.).
    int scaffold_passes = 4;
    //! Heavy-ball momentum in [0, 1): each step also tries the SLIM direction plus this share
    //! of the last iteration's motion and keeps whichever line search ends at the lower energy
    //! (flips and, with a scaffold, crossings stay excluded: the same line search). 0 = plain
    //! SLIM. Larger values reach a crossing of the boundary sooner, after which the scaffold
    //! phase costs far more than the momentum saves (docs/journal/benchmarks-2026-11.md, "SLIM
    //! momentum").
    double momentum = 0.5;
    //! Soft pulls on vertex sets' centres (centre_pull.h), added to the energy SLIM minimizes
    //! and line searches (in the global step as `pull_steps` says; the solver's pattern is
    //! unchanged either way). Empty = none. The pipeline fills it on a restart to keep the
    //! start's look (FlattenOptions::look_pull); the summary's energies stay the surface's alone.
    std::vector<CentrePull> centre_pulls;
    //! How the global step takes `centre_pulls` (PullSteps; the pipeline passes
    //! LookPullOptions::steps).
    PullSteps pull_steps = PullSteps::GaussNewton;
    //! Called after every iteration with the current phase's iterations so far (1, 2, ...; at
    //! most max_iterations) and whether that phase uses the scaffold, e.g. for progress output.
    //! Null (the default) = no calls.
    std::function<void(int iteration, bool scaffold)> on_iteration;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

struct InjectiveSummary
{
    int iterations = 0;
    double initial_energy = 0.0;  //!< symmetric Dirichlet energy at the start (4 x area at best)
    double final_energy = 0.0;
    bool converged = false;
    //! With scaffold_on_contact: the iterate (0 = the start) the scaffold phase went on from;
    //! -1 if the boundary never crossed (no scaffold was needed).
    int scaffold_from = -1;
    int scaffold_rebuilds = 0;  //!< scaffold triangulations made by the mesher
    int scaffold_refits = 0;    //!< scaffold triangulations made Delaunay again by edge flips
    //! Symbolic factorizations of the global step: one per pattern, which a mesher
    //! triangulation makes new; edge flips keep the vertices, and their triangles are fitted to
    //! the pattern analysed before.
    int pattern_analyses = 0;
    int scaffold_passes = 0;    //!< extra line searches on a new scaffold (scaffold_passes)
    int accelerated = 0;        //!< steps that took the momentum direction (momentum)
    //! The boundary crossed and SLIM stopped at its last simple iterate (scaffold_skip_gap).
    bool scaffold_skipped = false;
    //! Steps along the proxy matrix applied to the energy's true gradient, where the proxy's
    //! own direction did not descend (weights clamped on nearly collapsed faces).
    int gradient_steps = 0;
    //! Runs of three slow iterations that did not end the run because each step was cut below
    //! a thousandth of the proxy's step (a nearly collapsed triangle in the way, far from the
    //! minimum); at most 3 per run.
    int stalls_passed = 0;
    //! With scaffold_on_contact: steps halved so that the boundary stayed simple.
    int shortened_steps = 0;
    std::string report;  //!< one line: iterations and energies
};

//! \brief Minimize the symmetric Dirichlet energy E = sum_t area_t (||J_t||^2 + ||J_t^-1||^2)
//! with SLIM \cite rabinovich_2017_scalable (reweighted local/global steps on a CHOLMOD
//! factorization whose pattern is analysed once) and a line search that never lets a triangle
//! flip \cite smith_2015_bijective: the energy grows without bound as a triangle collapses and
//! each step stops short of the first collapse, so a flip-free start stays flip-free. Its
//! minimum is an isometry, like ARAP's, but it penalizes shrinking as much as stretching, so
//! area stays close to the 3D area. The proxy's weights are computed with singular values
//! clamped at 1e-2 (nearly collapsed faces would make the global step numerically
//! indefinite); where that proxy's direction does not lower the energy, the step goes along its
//! matrix applied to the energy's true gradient instead (a descent direction; the same as the
//! proxy's wherever no weight is clamped).
//! \param uv |V| x 2 start, row `v.idx()`, with no flipped triangle; updated in place.
//! \param pins vertices held fixed (may be empty).
//! \throw InvalidInputError if \p uv has a flipped triangle or the sizes disagree.
//! \throw SolverError if the sparse factorization fails.
InjectiveSummary injective_refine(const Mesh& mesh, Eigen::MatrixX2d& uv, const Pins& pins,
                                    const InjectiveOptions& options = {});

}  // namespace vessel
