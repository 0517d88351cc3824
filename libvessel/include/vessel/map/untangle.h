#pragma once

#include "vessel/layout/pins.h"

#include <string>

namespace vessel {

struct UntangleOptions
{
    int rings = 4;             //!< first region: the flipped triangles' vertices grown by this many rings
    int max_rounds = 5;        //!< each failed round doubles the rings; the last one frees every vertex
    int max_iterations = 300;  //!< L-BFGS iterations per epsilon step
    int max_epsilon_steps = 30;  //!< epsilon updates per round
    int polish_steps = 1;      //!< epsilon steps run after the last flip is gone (shapes up thin faces)
    double area_weight = 0.5;  //!< lambda: weight of the area term against the shape term, in [0, 1)
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

struct UntangleSummary
{
    int flipped_before = 0;  //!< triangles with det J <= 0 at the start
    int flipped_after = 0;   //!< ... at the end (0 on success)
    int rounds = 0;          //!< regions tried
    int free_vertices = 0;   //!< vertices moved in the last round
    std::string report;      //!< one line
};

//! \brief Remove flipped triangles from a map by moving only the vertices near them.
//!
//! Minimizes the regularized distortion energy of Garanzha et al. 2021 ("Foldover-free maps in 50
//! lines of code") with L-BFGS (Ceres' gradient solver): per face, (1 - lambda) tr(J^T J) / chi +
//! lambda (det J^2 + 1) / chi with chi(D, eps) = (D + sqrt(eps^2 + D^2)) / 2, which is finite for
//! inverted faces and, as eps shrinks, grows without bound as a face approaches inversion; eps is
//! decreased by the paper's rule until no face is inverted. Only a region around the flipped
//! faces moves (the rest and every pin stay fixed), grown until it succeeds, so a map that is
//! right almost everywhere (LSCM or ARAP at the paper's layout) keeps its shape.
//! \param uv |V| x 2, row `v.idx()`, updated in place.
//! \param pins vertices that must not move.
//! \return counts; `flipped_after > 0` if even the whole-mesh round left flips.
//! \throw InvalidInputError if sizes disagree or options are invalid.
UntangleSummary untangle(const Mesh& mesh, Eigen::MatrixX2d& uv, const Pins& pins,
                         const UntangleOptions& options = {});

}  // namespace vessel
