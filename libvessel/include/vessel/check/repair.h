#pragma once

#include "vessel/io/io.h"

#include <cstddef>
#include <string>
#include <vector>

namespace vessel {

//! Which safe repairs repair_raw_mesh() applies (all by default).
struct RepairOptions
{
    bool remove_duplicate_faces = true;   //!< faces with the same corners as another (either winding)
    bool orient = true;                   //!< make the winding consistent across every edge
    bool stitch_borders = true;           //!< merge boundary edges lying exactly on each other
    bool remove_degenerate_faces = true;  //!< faces with a repeated corner or collinear corners
};

//! What repair_raw_mesh() changed; every count is 0 when nothing needed repair.
struct RepairSummary
{
    std::size_t degenerate_faces = 0;  //!< removed: repeated corners, or collinear corners
    std::size_t duplicate_faces = 0;   //!< removed (the first copy is kept)
    std::size_t reoriented_faces = 0;  //!< whose winding was reversed to agree with neighbours
    std::size_t split_vertices = 0;    //!< copies made to separate non-manifold fans or edges
    std::size_t stitched_edges = 0;    //!< pairs of coincident boundary edges merged into one
    std::size_t removed_vertices = 0;  //!< vertices merged by stitching or left unused

    //! One human-readable line per repair that changed something (empty if none did).
    std::vector<std::string> notes() const;
};

//! A repaired mesh and what was done to it.
struct RepairedMesh
{
    RawMesh mesh;  //!< vertices keep their input order (removed ones left out)
    RepairSummary summary;
};

//! \brief Apply the safe repairs of CGAL's Polygon_mesh_processing to \p raw: remove degenerate
//! and duplicate faces, orient the faces consistently (splitting non-manifold vertices, as CGAL's
//! orient_polygon_soup() does), stitch coincident borders. The result still has to pass
//! make_tree_surface(); repairs that do not apply (e.g. degenerate faces of a polygon mesh) are
//! left to its refusals. A mesh with non-finite coordinates or corner indices out of range is
//! returned unchanged, for make_tree_surface() to report.
RepairedMesh repair_raw_mesh(const RawMesh& raw, const RepairOptions& options = {});

}  // namespace vessel
