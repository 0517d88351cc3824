#pragma once

#include "vessel/solve/ordering.h"
#include "vessel/layout/pins.h"

#include <functional>
#include <memory>
#include <string>

namespace vessel {

//! Which minimizer runs the ARAP energy.
enum class ArapSolver
{
    Ceres,        //!< Ceres nonlinear least squares over (u, v) and one rotation angle per face
    LocalGlobal,  //!< Liu et al. 2008 local/global iterations on a prefactored Cholesky
};

class ArapFactor;

struct ArapOptions
{
    ArapSolver solver = ArapSolver::LocalGlobal;  //!< the faster to the same energy (docs/benchmarks.md)
    int max_iterations = 50;   //!< Ceres iterations, or local/global sweeps
    double tolerance = 1e-6;   //!< stop when the relative energy decrease falls below this
    //! Threads Ceres may use for residual evaluation; the local/global solver's local step,
    //! right-hand side and u/v solves use up to two (from 8192 faces), with the same bits as
    //! one thread.
    int threads = 2;
    //! Called after every iteration with its number (1, 2, ...) and the arap_energy() of the
    //! current map, e.g. for progress output or energy-against-time studies; return false to
    //! stop there (the summary then reports not converged). With the Ceres solver each call
    //! costs one energy evaluation. Null (the default) = no calls.
    std::function<bool(int iteration, double energy)> on_iteration;
    //! The local/global solver's factorization, made ahead by arap_prefactor() of the same mesh
    //! and pin vertices (e.g. on another thread while the initial map is solved; the pipeline
    //! does so). Null (the default) = arap() factors it itself. Ignored by ArapSolver::Ceres.
    std::shared_ptr<const ArapFactor> prefactored;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

struct ArapSummary
{
    int iterations = 0;
    double initial_energy = 0.0;
    double final_energy = 0.0;
    bool converged = false;
    std::string report;  //!< the solver's own one-line report
};

//! \brief ARAP energy E = sum_t area_t * ||J_t - R_t||_F^2 with R_t the closest rotation to the
//! Jacobian J_t of the map on face t.
//! \param uv |V| x 2, row `v.idx()`.
double arap_energy(const Mesh& mesh, const Eigen::MatrixX2d& uv);

//! \brief The local/global solver's prefactored Cholesky of the cotan Laplacian of \p mesh with
//! the vertices of \p pins held (their targets do not matter), for ArapOptions::prefactored.
//! Reads \p mesh only, so it may run beside other readers of it.
//! \throw InvalidInputError if the pins are invalid or a face is degenerate.
//! \throw SolverError if CHOLMOD cannot factor the Laplacian.
//! \param ordering Elimination order of the factorization: a VertexOrdering of \p mesh (the
//! pipeline passes the one its other factorizations use); null (the default) = AMD here.
std::shared_ptr<const ArapFactor> arap_prefactor(const Mesh& mesh, const Pins& pins,
                                                 const VertexOrdering* ordering = nullptr);

//! \brief Refine a disk parameterization with the as-rigid-as-possible energy
//! \cite liu_2008_local; pinned vertices stay at their targets.
//! \param mesh Disk-topology triangle mesh (not modified).
//! \param uv |V| x 2 initial (u, v), row `v.idx()`, updated in place; should have no flips.
//! \param pins Vertices held fixed (at least one; the pipeline pins the inlet loop).
//! \throw InvalidInputError if sizes disagree, options are invalid or
//! ArapOptions::prefactored was made for other pin vertices.
//! \throw SolverError if the solver reports an unusable solution.
ArapSummary arap(const Mesh& mesh, Eigen::MatrixX2d& uv, const Pins& pins,
                 const ArapOptions& options = {});

}  // namespace vessel
