#pragma once

#include "vessel/layout/layout.h"

namespace vessel {

struct LayoutCircleOptions
{
    //! Each gap between two loops (a run of cut sides) keeps at least this fraction of the angle
    //! its length would get on Tutte's circle, when the loops are moved toward their layout
    //! bearings; in (0, 1]. 1 = Tutte's circle (loops at their arc-length positions). Small
    //! gaps squeeze the cut sides' faces, and a start of far higher symmetric Dirichlet energy
    //! than Tutte's can stall SLIM (docs/overlaps.md, "The layout circle start").
    double min_gap_fraction = 0.5;
    //! How far each loop's centre moves from its place on Tutte's constant-speed circle toward
    //! its layout target, in [0, 1]: 0 = Tutte's circle with the inlet at the bottom, 1 = the
    //! layout's bearings. Less than 1 leaves outlets below the inlet on many-outlet trees
    //! (docs/overlaps.md, "The layout circle start").
    double pull = 1.0;
    //! An outlet at layout bearing b (seen from the inlet's midpoint, the bottom of the circle)
    //! is aimed at the circle's point seen from there at b, i.e. at central angle
    //! bearing_scale x b from the top (inscribed angle: 2). 1 = central angle b.
    double bearing_scale = 2.0;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! \brief A one-to-one start map with the layout's arrangement, for the restart of a map whose
//! layout overlaps: a Tutte embedding (tutte_embedding(), injective.h) whose circle is not walked
//! at constant speed but so that the inlet is centred at the bottom and each outlet's arc is
//! centred, as near as the walk order allows, on the bearing the layout gives it (seen from the
//! inlet's midpoint; map_look.h). Loops keep their arc-length share of the circle; the cut sides
//! between them take what is left (at least LayoutCircleOptions::min_gap_fraction of their share).
//! The targets are made monotone along the boundary walk by isotonic regression (a fan layout's
//! crossing branches come out in walk order). The boundary is a convex polygon walked in order,
//! so the map has no flipped triangle and no overlap.
//! \param input the layout's input (cut mesh and its boundary segments, inlet first).
//! \param placed the layout's pins for the inlet and outlet vertices.
//! \return |V| x 2, row `v.idx()` of the cut mesh, scaled to its 3D area.
//! \throw TopologyError if the cut mesh is not a disk whose boundary walk holds the segments.
//! \throw InvalidInputError if the options are invalid or a loop vertex has no pin.
Eigen::MatrixX2d layout_circle_start(const LayoutInput& input, const LayoutResult& placed,
                                     const LayoutCircleOptions& options = {});

}  // namespace vessel
