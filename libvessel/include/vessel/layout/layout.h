#pragma once

#include "vessel/cut/boundary.h"
#include "vessel/cut/cut_plan.h"
#include "vessel/layout/pins.h"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace vessel {

//! A run of the cut mesh's (single) boundary that comes from one original boundary loop.
struct BoundarySegment
{
    int loop = -1;                        //!< index into the original loops (0 = inlet)
    std::vector<VertexHandle> vertices;   //!< cut-mesh vertices in boundary order (both ends included)
    std::vector<double> arc_length;       //!< cumulative 3D length at each vertex, from 0
};

//! \brief Split the boundary of a cut (disk) mesh into the runs that lie on original boundary
//! loops, in the order met when walking the boundary halfedges (clockwise in a positively
//! oriented map), starting with the inlet (loop 0).
//! \param origin pre-cut index of every cut-mesh vertex (`prop::origin`), indexed by `v.idx()`.
//! \param loop_of_origin loop index of every pre-cut vertex (-1 if not on a loop).
//! \throw TopologyError if the mesh has no boundary or the inlet is not on it.
std::vector<BoundarySegment> boundary_segments(const Mesh& mesh, const std::vector<int>& origin,
                                               const std::vector<int>& loop_of_origin);

//! What a layout policy sees (step 6 of the method). All per-vertex arrays are indexed by the
//! pre-cut vertex index (`prop::origin`).
struct LayoutInput
{
    const Mesh* mesh = nullptr;                     //!< the cut (disk) mesh
    const std::vector<BoundaryLoop>* loops = nullptr;  //!< pre-cut loops, loops[0] = inlet
    const CutPlan* plan = nullptr;                  //!< the cuts, in the order made
    const Eigen::VectorXd* geodesic = nullptr;      //!< pre-cut geodesic distance from the inlet
    std::vector<int> origin;                        //!< pre-cut index of each cut-mesh vertex
    std::vector<BoundarySegment> segments;          //!< boundary_segments() of the cut mesh
};

//! A vessel segment's strip in the plane: corners base-left, base-right, top-right, top-left
//! (counter-clockwise), the top edge being where the outlet is pinned.
using Strip = std::array<Eigen::Vector2d, 4>;

//! Positions the layout assigns to the loops' vertices.
struct LayoutResult
{
    Pins inlet;    //!< every vertex of the inlet segment
    Pins outlets;  //!< every vertex of every outlet segment
    //! The strip the layout means for each cut path, indexed like `plan->paths` (its outlet
    //! pinned on the top edge; the root's base edge is the inlet). For inspection and tests.
    std::vector<Strip> strips;
};

//! \brief A layout policy: where the inlet and outlet loops go in the plane before the map is
//! computed (like OpenMesh's Decimater modules, chosen at run time by name).
class Layout
{
public:
    virtual ~Layout() = default;
    virtual std::string name() const = 0;
    //! \throw TopologyError if the input does not have one segment per loop.
    virtual LayoutResult place(const LayoutInput& input) const = 0;
};

//! The paper's layout: every loop unrolled as a straight segment (3D arc length kept), the inlet
//! on the u axis centred at 0, each outlet at the height its cut climbs in geodesic distance;
//! each branch's frame is its parent's rotated by +alpha (left of the parent cut) or -alpha
//! (right), composed down the tree (a transform hierarchy).
class BranchFanLayout : public Layout
{
public:
    explicit BranchFanLayout(double alpha_deg = 45.0);
    std::string name() const override { return "fan"; }
    LayoutResult place(const LayoutInput& input) const override;

private:
    double alpha_deg_;
};

//! \brief The overlap-aware layout: the paper's look (inlet at the bottom, outlets fanned out in
//! their 3D left/right order, each loop a straight segment of its own length), but every subtree of
//! cuts gets its own angular sector, sized by the total outlet perimeter in it, and every branch's
//! strip (width = its loop length) starts far enough from its parent's strip to fit its sector.
//!
//! Guarantee (by construction, see docs/overlaps.md): the strips of `LayoutResult::strips` have
//! pairwise disjoint interiors, so no two pinned segments cross. The cost is branches placed
//! further out than their 3D length when sectors are narrow (many outlets).
class SectorLayout : public Layout
{
public:
    //! \param spread_deg half-angle of the whole fan around the inlet's normal, in (0, 85].
    //! \param gap fraction of each branch's sector left empty on either side, in [0, 0.45].
    //! \throw InvalidInputError if a parameter is out of range.
    explicit SectorLayout(double spread_deg = 75.0, double gap = 0.1);
    std::string name() const override { return "sector"; }
    LayoutResult place(const LayoutInput& input) const override;

private:
    double spread_deg_;
    double gap_;
};

//! \brief The layout called \p name ("fan" or "sector"), with branch angle \p alpha_deg (fan).
//! \throw InvalidInputError listing the valid names if \p name is unknown.
std::unique_ptr<Layout> make_layout(const std::string& name, double alpha_deg = 45.0);

}  // namespace vessel
