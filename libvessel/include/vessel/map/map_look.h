#pragma once

#include "vessel/layout/layout.h"

#include <vector>

namespace vessel {

//! Where one outlet loop ended up in the map, against where the layout meant it to go.
//! Bearings are seen from the inlet's midpoint, in degrees: 0 = straight up (away from the
//! inlet, on the side the map lies), +90 = right, -90 = left, +-180 = straight down.
struct OutletLook
{
    int loop = -1;                  //!< index into the loops (1.. = outlets)
    double layout_bearing_deg = 0;  //!< bearing of the loop's centre in the layout
    double map_bearing_deg = 0;     //!< bearing of the loop's centre in the map
    bool below_inlet = false;       //!< the loop's centre is below the inlet's line in the map
    int walk_rank = 0;              //!< 0-based rank among the outlets along the boundary walk
};

//! How much of the paper's look a map keeps (issue 7): the inlet at the bottom, the branches
//! fanned out in the layout's left/right order. Both the map and the layout are read in the
//! frame of their own inlet chord (left end -> right end = +u, the map above it = +v), so a
//! rotation, translation or uniform scale of either does not change any figure.
struct MapLook
{
    //! Fraction of the map's area (sum of |face areas|) whose face centroids lie below the inlet's
    //! line: 0 = the whole map above its inlet.
    double area_below_inlet = 0.0;
    int outlets = 0;              //!< outlet loops measured
    int outlets_below_inlet = 0;  //!< outlet centres below the inlet's line in the map
    //! Outlet pairs whose left-to-right order (by bearing) in the map is the reverse of the
    //! layout's. 0 = the layout's fan order.
    int fan_inversions = 0;
    //! Kendall's tau of the outlets' bearings, map against layout (pairs tied in the layout
    //! left out): 1 = same order, -1 = mirrored. 1 with fewer than two outlets.
    double fan_kendall_tau = 1.0;
    //! Outlet pairs whose left-to-right order in the map (by bearing) is the reverse of their
    //! order along the boundary walk from the inlet (the 3D left/right order the layouts fan
    //! out; the fan layout itself may break it where its branches cross). 0 = walk order.
    int walk_inversions = 0;
    double mean_bearing_error_deg = 0.0;  //!< mean |map - layout bearing| over the outlets
    double max_bearing_error_deg = 0.0;   //!< worst |map - layout bearing|
    std::vector<OutletLook> outlet_looks;  //!< one per outlet loop, by loop index
};

//! \brief Measure how the map \p uv keeps the look of \p layout (see MapLook).
//! \param mesh the cut (disk) mesh the map and the layout belong to.
//! \param uv |V| x 2, row `v.idx()` of \p mesh.
//! \param segments boundary_segments() of \p mesh: which boundary vertices form which loop
//! (the inlet's first vertex is its right end, its last its left end, in the map as in the layout).
//! \param layout the layout's pins (`LayoutResult::inlet` and `::outlets`) for those vertices.
//! A loop's centre is the mean of its vertices' positions. The walk order is the order of
//! \p segments (boundary_segments() gives it from the inlet on).
//! \throw InvalidInputError if \p uv does not have one row per vertex, there is no inlet
//! segment, the inlet's ends coincide, or a loop vertex has no layout pin.
MapLook map_look(const Mesh& mesh, const Eigen::MatrixX2d& uv,
                 const std::vector<BoundarySegment>& segments, const LayoutResult& layout);

//! \brief The layout's own bearing of every outlet loop (OutletLook::layout_bearing_deg without
//! a map): the loop's centre seen from the middle of the layout's inlet chord, in degrees
//! (0 = up, +90 = right). Parameters as map_look().
//! \return one value per loop index (entry 0, the inlet, and loops without a segment are 0).
//! \throw InvalidInputError as map_look().
std::vector<double> layout_bearings(const Mesh& mesh,
                                    const std::vector<BoundarySegment>& segments,
                                    const LayoutResult& layout);

}  // namespace vessel
