#pragma once

#include "vessel/core/mesh.h"

namespace vessel {

struct SpectralConformalOptions
{
    int max_iterations = 1000;  //!< Spectra iteration limit
    double tolerance = 1e-10;   //!< Spectra convergence tolerance
    void validate() const;
};

//! \brief Free-boundary spectral conformal parameterization \cite mullen_2008_spectral: the
//! smallest non-trivial generalized eigenvector of the LSCM conformal energy against the boundary
//! mass matrix, computed with Spectra (shift-invert). The result is scaled so that its total
//! area equals the 3D area and centred at the origin.
//! \param mesh Disk-topology triangle mesh.
//! \return |V| x 2 (u, v), row `v.idx()`.
//! \throw TopologyError if the mesh has no boundary. \throw SolverError if Spectra fails.
Eigen::MatrixX2d spectral_conformal(const Mesh& mesh, const SpectralConformalOptions& options = {});

}  // namespace vessel
