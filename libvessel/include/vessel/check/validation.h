#pragma once

#include "vessel/io/io.h"

#include <string>
#include <vector>

namespace vessel {

struct TreeSurfaceOptions
{
    //! Split faces with more than 3 corners into triangle fans (noted); otherwise refuse them.
    bool triangulate_polygons = true;
    //! Reverse the winding of a surface wound inward (normals into the lumen, common in vmtk
    //! output) so that normals point out of the lumen (noted); otherwise keep it as read.
    bool orient_outward = true;
    //! Reverse the winding of faces that disagree with their neighbours (in each connected
    //! piece the winding most faces have is kept; noted, TreeSurface::reoriented_faces);
    //! otherwise refuse inconsistent orientation. A non-orientable surface is always refused.
    bool orient_consistently = true;
    //! Keep only the largest connected component (by faces) and drop the others (noted);
    //! otherwise refuse a surface in several pieces.
    bool keep_largest_component = false;
    //! Remove the flat caps that close the vessel ends (noted, TreeSurface::removed_caps), so
    //! that a capped model (SimVascular's, a segmentation closed by planes) opens at its inlet
    //! and outlets: each planar patch that is a disk and meets the wall at a sharp rim (a
    //! crease of at least 30 degrees everywhere and 60 on average) is dropped; its interior
    //! vertices are then unused, and the others keep their input indices, so point and cell
    //! data still match. Curved caps are not found: the surface is then refused as closed.
    bool remove_flat_caps = false;
    //! Faces whose area is below `degenerate_area_factor * (mean edge length)^2` are degenerate.
    double degenerate_area_factor = 1e-10;
    //! A vertex farther than `far_vertex_factor` times the median distance of the vertices from
    //! their (coordinate-wise) median point is refused as a corrupt coordinate (e.g. one vertex
    //! at 1e38: it would otherwise make every other face look degenerate, or overflow the areas).
    //! Real trees stay within 10 times; 0 turns the check off.
    double far_vertex_factor = 1000.0;
    //! A boundary loop of at most `hole_max_edges` edges whose perimeter is below
    //! `hole_perimeter_fraction` of the largest loop's is a hole in the wall, not a vessel end,
    //! and is refused (each loop would be cut to as an outlet: a useless map, and minutes of
    //! work per hole). Fill such holes first (RepairOptions::fill_holes_below, vessel-flatten
    //! --fill-holes). A one-triangle hole has 3 edges, the star of a vertex about 6; the vessel
    //! ends of the real trees have 10 or more (docs/bad-input.md). 0 accepts every loop.
    int hole_max_edges = 6;
    //! See hole_max_edges: loops as long as this fraction of the largest are never holes, so a
    //! coarse tube whose ends have few edges stays valid.
    double hole_perimeter_fraction = 0.5;
};

//! A validated vessel tree surface.
struct TreeSurface
{
    //! Triangle mesh of the used input vertices; `int` vertex property `prop::input_index` gives
    //! each vertex's index in the input file, `int` face property `prop::input_face` each
    //! triangle's polygon in the input file.
    Mesh mesh;
    int input_vertices = 0;          //!< vertices in the file (including unused ones)
    //! Faces whose winding was reversed to agree with their neighbours (orient_consistently);
    //! not counting a reversal of all faces by orient_outward.
    int reoriented_faces = 0;
    int removed_caps = 0;            //!< flat caps removed (TreeSurfaceOptions::remove_flat_caps)
    std::vector<std::string> notes;  //!< repairs applied, one human-readable line each
};

//! \brief Check that \p raw is a valid vessel tree surface (one connected, consistently oriented,
//! 2-manifold, genus-0 surface with at least one open end, finite coordinates, no degenerate
//! or duplicate faces, no boundary loops lying on each other) and build the mesh. One open end
//! makes a disk, which flatten() maps without cuts. Checks run in this order: coordinates, face
//! corners, far vertices, zero area, duplicates, orientation (fixed, see orient_consistently; a
//! non-orientable surface is refused), non-manifold edge, orientation (only without
//! orient_consistently), non-manifold vertex, coincident boundary loops, components, then
//! (with remove_flat_caps) the flat caps are removed, then closed, genus.
//! \throw InvalidInputError with a one-line message naming the problem (with element ids or
//! counts) and what to do about it.
TreeSurface make_tree_surface(const RawMesh& raw, const TreeSurfaceOptions& options = {});

//! read_raw_mesh() followed by make_tree_surface().
TreeSurface load_tree_surface(const std::string& path, const TreeSurfaceOptions& options = {});

}  // namespace vessel
