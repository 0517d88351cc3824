#pragma once
// Coarse-grid corrections of relax_area() (multilevel.h): the two-grid step of a multigrid
// solver, with the projected Newton system of the fine map restricted to the coarser level's
// map (Galerkin: P^T H P, P the interpolation of the coarse level's vertices by their map; the
// coarse mesh's own Hessian is no substitute: its needles along the kept boundary make it
// nearly singular).
// Gauss-Seidel sweeps remove the error of short wavelength quickly and that of long wavelength
// slowly; a coarse step removes the latter (Briggs, Henson and McCormick 2000, "A multigrid
// tutorial", ch. 3 and 6). The step is line searched on the energy with no face flipping, and
// where it would bring two boundary parts nearer than the guard's clearance, the coarse
// vertices around that place are held and the step solved again (an active set), so the
// relaxation's guarantees stay: no flip, the boundary simple and its parts apart.

#include "detail/boundary_guard.h"
#include "detail/face_jacobian.h"
#include "detail/polish_hessian.h"
#include "detail/vertex_newton.h"
#include "solve/paired_cholmod.h"
#include "vessel/core/mesh.h"

#include <Eigen/Sparse>

#include <functional>
#include <vector>

namespace vessel::detail {

//! The interpolation of a coarse level's map onto the fine level: row v holds the barycentric
//! weights of the fine vertex v's place in \p fine_uv within the coarse triangle of
//! \p coarse_uv that holds it (the nearest one, weights clamped, where none does; a vertex the
//! coarse level kept takes its own coarse vertex). Interleaved: (2|V_fine|) x (2|V_coarse|), the
//! same weights for u and v.
Eigen::SparseMatrix<double> coarse_interpolation(const Mesh& coarse, const std::vector<int>& coarse_of,
                                                 const Eigen::MatrixX2d& coarse_uv,
                                                 const Eigen::MatrixX2d& fine_uv);

//! The Galerkin operator P^T H P (upper triangle, 2|V_coarse| square) of the projected Hessian H
//! of \p faces' energy (polish_hessian.h) at the map \p x, over the fine vertices with
//! slot[v] >= 0, for an interpolation P given by rows (\p interpolation, as
//! coarse_interpolation(): the same weights for u and v). Computed by 2 x 2 blocks without
//! forming H or a sparse product: H's blocks summed per fine vertex and neighbour, then each
//! coarse column gathered from the fine vertices it interpolates and their neighbours
//! (Gustavson 1978, "Two fast algorithms for sparse matrices: multiplication and permuted
//! transposition"), the columns on two threads on large meshes (the same bits as on one).
//! Equal to the product up to rounding.
Eigen::SparseMatrix<double> galerkin_operator(
    const std::vector<FaceOperator>& faces, const std::vector<int>& slot, const double* x,
    double lambda, const Eigen::SparseMatrix<double, Eigen::RowMajor>& interpolation);

//! The upper triangle of P^T C P for a symmetric C given by its upper triangle (2|V| square,
//! compressed) and an interpolation \p interpolation by rows with the same weights for u and v
//! (as coarse_interpolation()): the level below's operator of the iterative corrections. By
//! 2 x 2 blocks as galerkin_operator(), its columns on \p threads threads (1 or 2; the same
//! bits either way). Equal to the product up to rounding.
Eigen::SparseMatrix<double> galerkin_of_operator(
    const Eigen::SparseMatrix<double>& upper,
    const Eigen::SparseMatrix<double, Eigen::RowMajor>& interpolation, int threads);

//! The coarse step's system C d = -P^T g (C the Galerkin operator, some unknowns held at 0) is
//! solved either by a sparse Cholesky factorization of C, made again whenever a step holds more
//! unknowns, or, given the interpolation P2 of a level below the coarse one, iteratively:
//! conjugate gradients over the free unknowns, preconditioned by a V-cycle (symmetric
//! Gauss-Seidel sweeps on C, on two threads hybrid: Gauss-Seidel within each half of the
//! unknowns, Jacobi between the halves; around an exact solve of P2^T C P2 with a stiff spring on
//! each held unknown; Briggs, Henson and McCormick 2000, "A multigrid tutorial", ch. 3 and 10). A
//! factorization's fill grows faster than C, so on the largest meshes it dominates the
//! relaxation; the iterative solve costs a few sweeps over C's entries plus the factorization of
//! an operator a quarter as large, and holding more unknowns refactorizes only that one
//! (docs/benchmarks.md "Coarse-to-fine").
class CoarseCorrection
{
public:
    //! \p faces: the fine mesh's; \p interpolation from coarse_interpolation(); \p pinned per
    //! fine vertex (>= 0: held). \p below: empty, or the interpolation of a level below the
    //! coarse one (coarse_interpolation() of that level into the coarse level's map; 2|V_coarse|
    //! rows): the system is then solved iteratively.
    CoarseCorrection(const std::vector<FaceOperator>& faces, Eigen::SparseMatrix<double> interpolation,
                     const std::vector<int>& pinned, double lambda,
                     Eigen::SparseMatrix<double> below = {});

    //! One correction of the map x (interleaved), whose energy is \p current (updated).
    //! Returns the energy lowered (0: no admissible step; x unchanged). \p guard null: the
    //! boundary is not kept simple (no coarse vertex held).
    //! \p extra, if set: more energy of the map beside the faces' (the look pulls; in
    //! \p current too), which the line search counts.
    double step(const VertexEnergy& energy, Eigen::VectorXd& x, BoundaryGuard* guard, double& current,
                const std::function<double(const Eigen::VectorXd&)>& extra = {});

private:
    const std::vector<FaceOperator>& faces_;
    Eigen::SparseMatrix<double> P_;
    Eigen::SparseMatrix<double, Eigen::RowMajor> rows_;  // P by rows: a fine vertex's coarse vertices
    std::vector<int> slot_;  // per fine vertex: its index, -1 if pinned
    // Per thread of the gradient's sum: slot_ on the thread's half of the vertices, -1 elsewhere.
    std::vector<std::vector<int>> owned_slot_;
    std::vector<double> per_face_;  // the line search's energies of the faces
    double lambda_;
    PairedCholmod solver_;
    // Holds the coarse unknowns that interpolate fine vertex v; returns how many were not yet.
    int hold_around(int v, std::vector<char>& held) const;
    // Factorizes the coarse operator with the held unknowns fixed (the direct solve), or, with
    // a level below, that level's operator with the held unknowns' springs.
    void factorize();
    // The coarse step for the right-hand side \p rhs (held entries 0).
    Eigen::VectorXd solve(const Eigen::VectorXd& rhs);
    // One V-cycle on C d = rhs from d = 0.
    Eigen::VectorXd v_cycle(const Eigen::VectorXd& rhs);
    // Sets the held unknowns' entries of \p y (2|V_coarse|) to 0.
    void zero_held(Eigen::VectorXd& y) const;
    // A Gauss-Seidel sweep on full_ d = rhs, over the unknowns in increasing or decreasing
    // order; on two threads (full_threads()), over each half of them (Jacobi between them).
    void sweep(const Eigen::VectorXd& rhs, Eigen::VectorXd& d, bool forward) const;
    // C y, on full_threads() threads.
    Eigen::VectorXd times_full(const Eigen::VectorXd& y) const;
    // Threads of the sweeps and products over full_: threads_, but one below 8192 unknowns (as
    // face_threads() keeps small meshes on one).
    int full_threads() const { return full_.cols() < 8192 ? 1 : threads_; }

    Eigen::SparseMatrix<double> coarse_;  // the coarse operator (upper triangle), once computed
    Eigen::SparseMatrix<double> system_;  // coarse_ with the held unknowns' rows made identity
    double mean_diagonal_ = 1.0;
    std::vector<char> held_;  // per coarse unknown
    bool analysed_ = false;
    // The V-cycle's: the interpolation from the level below, C stored whole (both triangles,
    // for the sweeps), and the level below's operator P2^T C P2 (upper triangle).
    Eigen::SparseMatrix<double> below_;
    Eigen::SparseMatrix<double, Eigen::RowMajor> below_rows_;  // below_ by rows (the springs)
    Eigen::SparseMatrix<double> full_;
    Eigen::SparseMatrix<double> below_base_;      // P2^T C P2 (upper), without the springs
    Eigen::SparseMatrix<double> below_operator_;  // with the held unknowns' springs
    int threads_ = 1;  // of the sweeps and products (face_threads() of the fine faces)
    mutable Eigen::VectorXd before_;  // a two-thread sweep's d as it began
};

}  // namespace vessel::detail
