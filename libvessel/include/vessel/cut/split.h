#pragma once

#include "vessel/io/io.h"

#include <vector>

namespace vessel {

//! \file Split a vessel tree into several trees at chosen branches, so that each can be
//! flattened as its own map (when one patch would distort or overlap too much).

struct SplitOptions
{
    //! How far past the branch point the cutting ring lies, in mean outlet radii of the subtree
    //! (radius = loop length / 2 pi), capped at half the way to the subtree's next branch point.
    double offset_radii = 1.0;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! One tree after splitting.
struct TreePiece
{
    RawMesh mesh;  //!< triangles; a valid tree surface (check it with make_tree_surface())
    //! Loops of the input it keeps (indices into boundary_loops(input); 0 = the inlet), sorted;
    //! every other loop of the piece is a ring made by the split.
    std::vector<int> loops;
    double level = 0.0;  //!< geodesic distance from the inlet of the ring that cut it off (0: none)
};

//! \brief Cut off the subtrees of \p mesh that carry each set of outlets in \p subtrees, along a
//! level set of the heat-geodesic distance from the inlet just past the branch point where the
//! set joins the rest of the tree.
//!
//! The branch point of a set S is found on the merge tree of the distance's superlevel sets
//! (walking down from the outlets, S's components join one another before they meet any other
//! loop). The mesh is sliced exactly along the level set (new vertices on the crossed edges) and
//! the component of the superlevel set holding S becomes a piece whose inlet is the new ring.
//! Sets are applied in order to what is left; the last piece returned is the rest (with the
//! input's inlet), the others follow \p subtrees' order.
//! \param mesh a valid tree surface (boundary_loops(mesh)[0] is the inlet).
//! \param subtrees outlet sets, indices into boundary_loops(mesh) (1 = largest outlet), disjoint.
//! \throw InvalidInputError if an index is not an outlet, sets overlap, a set would take every
//! outlet left, or a set is not a subtree (the message names the smallest subtree holding it).
//! \throw TopologyError if the ring does not split the mesh into two pieces.
std::vector<TreePiece> split_tree(const Mesh& mesh, const std::vector<std::vector<int>>& subtrees,
                                  const SplitOptions& options = {});

}  // namespace vessel
