#pragma once

#include "vessel/io.h"

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
    std::vector<std::string> notes;  //!< repairs applied, one human-readable line each
};

//! \brief Check that \p raw is a valid vessel tree surface (one connected, consistently oriented,
//! 2-manifold, genus-0 surface with at least two open ends, finite coordinates, no degenerate
//! faces) and build the mesh.
//! \throw InvalidInputError with a one-line message naming the problem (with element ids or
//! counts) and what to do about it.
TreeSurface make_tree_surface(const RawMesh& raw, const TreeSurfaceOptions& options = {});

//! read_raw_mesh() followed by make_tree_surface().
TreeSurface load_tree_surface(const std::string& path, const TreeSurfaceOptions& options = {});

}  // namespace vessel
