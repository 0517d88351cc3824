#pragma once

#include "vessel/layout/layout.h"
#include "vessel/map/untangle.h"

namespace vessel {

struct FanStartOptions
{
    //! Half-angle of the fan around the vertical, seen from its centre below the inlet's
    //! midpoint: the inlet's ends are seen at 90 -/+ this, and the rest of the boundary lies
    //! between those two rays. In [30, 89].
    double spread_deg = 80.0;
    //! Angular weight of a cut-side edge relative to a loop edge of the same length and radius,
    //! in (0, 1]: small values make both sides of a cut nearly radial (strips fanned out).
    double cut_weight = 0.1;
    //! Removes the flips of the harmonic map (boundary held). More epsilon steps than the
    //! default: with the boundary fixed, the crotch slivers open slowly (3-outlet tree phantom:
    //! 56 flips left after 30 steps, 1 after 200).
    UntangleOptions untangle = [] {
        UntangleOptions o;
        o.max_epsilon_steps = 200;
        return o;
    }();
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

struct FanStart
{
    Eigen::MatrixX2d uv;       //!< |V| x 2, row `v.idx()`, scaled to the 3D area
    //! The flip removal. The map is one-to-one iff flipped_after == 0 and its boundary is
    //! simple (boundary_self_intersection(), embedding.h): the caller checks both.
    UntangleSummary untangle;
};

//! \brief A one-to-one start map with the layout's look, for a refinement that must not
//! overlap (used where the map at the layout crosses itself, instead of a Tutte circle).
//!
//! The cut mesh's boundary is laid out as a polygon that is star-shaped around a centre above
//! the inlet, hence simple: the inlet straight at the bottom (3D length), every other boundary
//! vertex at radius (inlet-end radius + its geodesic distance from the inlet), at an angle that
//! decreases monotonically along the boundary walk (edges of outlet loops weighted by length /
//! radius, cut sides by cut_weight times that). So each branch is a wedge pointing away from the
//! inlet, branches in their walk (left-to-right) order. The interior is the cotangent-harmonic
//! map onto that polygon (LSCM with the whole boundary pinned); triangles with all three corners
//! on the polygon that it inverts are first opened (the boundary run between their corners laid
//! on an arc across their chord). Its flips, where the polygon is not convex, are removed with
//! the boundary held (untangle.h); flips left over (crotch notches of the polygon) once more with
//! only the inlet held, which can make the boundary cross. A flip-free map with a simple
//! boundary is one-to-one.
//! \param input the layout's input (cut mesh, loops, segments, geodesic distance, origins).
//! \throw InvalidInputError if the options are invalid.
//! \throw TopologyError if the cut mesh is not a disk whose boundary holds the inlet segment.
FanStart fan_start(const LayoutInput& input, const FanStartOptions& options = {});

}  // namespace vessel
