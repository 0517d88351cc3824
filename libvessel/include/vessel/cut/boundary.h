#pragma once

#include "vessel/core/mesh.h"

#include <cmath>
#include <vector>

namespace vessel {

//! One closed boundary loop (an inlet or outlet opening).
struct BoundaryLoop
{
    //! Boundary halfedges in loop order; each `h` has `mesh.is_boundary(h)` and
    //! `to(halfedges[i]) == from(halfedges[i + 1])`, i.e. the order induced by the face winding.
    std::vector<HalfedgeHandle> halfedges;
    //! `vertices[i] = from(halfedges[i])`.
    std::vector<VertexHandle> vertices;
    double arc_length = 0.0;  //!< perimeter, in mesh units
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  //!< arc-length weighted centre

    //! The radius of the circle as long as the loop: the vessel's radius at an open end cut
    //! across it, and the scale of the distances measured from it.
    double radius() const { return arc_length / (2.0 * M_PI); }
};

//! \brief All boundary loops, sorted by arc length, longest first: `loops[0]` is the inlet, the
//! rest are the outlets in the order the cuts are made.
std::vector<BoundaryLoop> boundary_loops(const Mesh& mesh);

}  // namespace vessel
