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
    //! Faces whose area is below `degenerate_area_factor * (mean edge length)^2` are degenerate.
    double degenerate_area_factor = 1e-10;
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
    std::vector<std::string> notes;  //!< repairs applied, one human-readable line each
};

//! \brief Check that \p raw is a valid vessel tree surface (one connected, consistently oriented,
//! 2-manifold, genus-0 surface with at least one open end, finite coordinates, no degenerate
//! or duplicate faces, no boundary loops lying on each other) and build the mesh. One open end
//! makes a disk, which flatten() maps without cuts. Checks run in this order: coordinates, face
//! corners, zero area, duplicates, orientation (fixed, see orient_consistently; a
//! non-orientable surface is refused), non-manifold edge, orientation (only without
//! orient_consistently), non-manifold vertex, coincident boundary loops, components, closed,
//! genus.
//! \throw InvalidInputError with a one-line message naming the problem (with element ids or
//! counts) and what to do about it.
TreeSurface make_tree_surface(const RawMesh& raw, const TreeSurfaceOptions& options = {});

//! read_raw_mesh() followed by make_tree_surface().
TreeSurface load_tree_surface(const std::string& path, const TreeSurfaceOptions& options = {});

}  // namespace vessel
