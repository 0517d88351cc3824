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
    //! Fill every boundary loop whose perimeter (mesh units) is below this with CGAL's
    //! triangulate_refine_and_fair_hole() (new faces and vertices at the mesh's density, faired
    //! to the wall around), after the repairs above; holes in the wall, not vessel ends
    //! (TreeSurfaceOptions::hole_max_edges). 0 fills nothing. Only on a triangle mesh.
    double fill_holes_below = 0.0;
    //! Throws InvalidInputError if fill_holes_below is negative or not finite.
    void validate() const;
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
    std::size_t filled_holes = 0;      //!< boundary loops filled (RepairOptions::fill_holes_below)
    double longest_filled_hole = 0.0;  //!< the longest perimeter among them
    std::size_t hole_faces = 0;        //!< faces added to fill them
    std::size_t hole_vertices = 0;     //!< vertices added inside them (appended after the others)
    //! Holes below fill_holes_below left open because CGAL found no triangulation of them.
    std::size_t unfilled_holes = 0;

    //! One human-readable line per repair that changed something (empty if none did).
    std::vector<std::string> notes() const;
};

//! A repaired mesh and what was done to it.
struct RepairedMesh
{
    RawMesh mesh;  //!< vertices keep their input order (removed ones left out, hole vertices appended)
    RepairSummary summary;
};

//! \brief Apply the safe repairs of CGAL's Polygon_mesh_processing to \p raw: remove degenerate
//! and duplicate faces, orient the faces consistently (splitting non-manifold vertices, as CGAL's
//! orient_polygon_soup() does), stitch coincident borders. The result still has to pass
//! make_tree_surface(); repairs that do not apply (e.g. degenerate faces of a polygon mesh) are
//! left to its refusals. A mesh with non-finite coordinates or corner indices out of range is
//! returned unchanged, for make_tree_surface() to report.
//! \throw InvalidInputError if \p options are invalid (RepairOptions::validate()).
RepairedMesh repair_raw_mesh(const RawMesh& raw, const RepairOptions& options = {});

}  // namespace vessel
