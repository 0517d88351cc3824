#include "vessel/map/spectral.h"

#include "vessel/core/errors.h"
#include "vessel/map/lscm.h"
#include "vessel/quality/metrics.h"

#include <Spectra/SymGEigsShiftSolver.h>
#include <Eigen/CholmodSupport>

#include <cmath>
#include <string>

namespace vessel {

namespace {

// The shift-invert operator y = P (L_C - sigma B)^{-1} P^T z of Spectra's ShiftInvert mode
// (Spectra passes z = B x). P is the B-orthogonal projector that removes the two translations
// (constant u, constant v): they are in the null space of L_C, so without deflation they would
// be the dominant eigenvectors nu = -1 / sigma, and on a flat mesh they would mix with the
// (equally zero) embedding itself. With P they map to nu = 0 and never get selected.
class DeflatedShiftInvert
{
public:
    using Scalar = double;

    DeflatedShiftInvert(const Eigen::SparseMatrix<double>& L, const Eigen::VectorXd& mass)
        : L_(L), mass_(mass), n_(mass.size() / 2), mass_sum_(mass.head(n_).sum())
    {}

    Eigen::Index rows() const { return L_.rows(); }
    Eigen::Index cols() const { return L_.cols(); }

    void set_shift(double sigma)
    {
        Eigen::SparseMatrix<double> A = L_;
        A.diagonal() -= sigma * mass_;
        solver_.compute(A);
        if (solver_.info() != Eigen::Success)
            throw SolverError("spectral_conformal: CHOLMOD could not factor L_C - sigma B (" +
                              std::to_string(A.rows()) +
                              " unknowns); the mesh must be connected without degenerate "
                              "triangles");
    }

    void perform_op(const double* z_in, double* y_out) const
    {
        Eigen::VectorXd z = Eigen::Map<const Eigen::VectorXd>(z_in, rows());
        for (int c = 0; c < 2; ++c)  // P^T z: remove B T (T^T B T)^{-1} T^T z
            z.segment(c * n_, n_) -=
                (z.segment(c * n_, n_).sum() / mass_sum_) * mass_.segment(c * n_, n_);
        Eigen::Map<Eigen::VectorXd> y(y_out, rows());
        y = solver_.solve(z);
        deflate(y);
    }

    //! P y: subtract the B-weighted mean of u and of v.
    void deflate(Eigen::Ref<Eigen::VectorXd> y) const
    {
        for (int c = 0; c < 2; ++c)
        {
            auto part = y.segment(c * n_, n_);
            part.array() -= part.dot(mass_.segment(c * n_, n_)) / mass_sum_;
        }
    }

private:
    const Eigen::SparseMatrix<double>& L_;
    const Eigen::VectorXd& mass_;
    Eigen::Index n_;
    double mass_sum_;
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver_;
};

// y = B x for the diagonal boundary mass matrix B.
class DiagonalProduct
{
public:
    using Scalar = double;
    explicit DiagonalProduct(const Eigen::VectorXd& diagonal) : diagonal_(diagonal) {}
    Eigen::Index rows() const { return diagonal_.size(); }
    Eigen::Index cols() const { return diagonal_.size(); }
    void perform_op(const double* x_in, double* y_out) const
    {
        Eigen::Map<Eigen::VectorXd>(y_out, rows()) =
            diagonal_.cwiseProduct(Eigen::Map<const Eigen::VectorXd>(x_in, rows()));
    }

private:
    const Eigen::VectorXd& diagonal_;
};

}  // namespace

void SpectralConformalOptions::validate() const
{
    if (max_iterations < 1)
        throw InvalidInputError(
            "SpectralConformalOptions::validate: max_iterations must be >= 1 (got " +
            std::to_string(max_iterations) + "); use e.g. 1000");
    if (!(tolerance > 0.0) || !std::isfinite(tolerance))
        throw InvalidInputError(
            "SpectralConformalOptions::validate: tolerance must be finite and > 0 (got " +
            std::to_string(tolerance) + "); use e.g. 1e-10");
}

Eigen::MatrixX2d spectral_conformal(const Mesh& mesh, const SpectralConformalOptions& options)
{
    options.validate();
    const int n = static_cast<int>(mesh.n_vertices());
    if (mesh.n_faces() == 0)
        throw InvalidInputError(
            "spectral_conformal: the mesh has no faces; pass a triangulated "
            "disk");
    for (auto v : mesh.vertices())
        if (mesh.is_isolated(v))
            throw InvalidInputError("spectral_conformal: vertex " + std::to_string(v.idx()) +
                                    " has no faces; remove isolated vertices first");

    // Boundary mass matrix B: each boundary vertex gets half its two boundary edges' lengths,
    // the same for the u and the v block.
    Eigen::VectorXd mass = Eigen::VectorXd::Zero(2 * n);
    for (auto h : mesh.halfedges())
        if (h.is_boundary())
        {
            const double half = 0.5 * mesh.calc_edge_length(h);
            for (int c = 0; c < 2; ++c)
            {
                mass[c * n + h.from().idx()] += half;
                mass[c * n + h.to().idx()] += half;
            }
        }
    const double perimeter = 0.5 * mass.head(n).sum();
    if (!(perimeter > 0.0))
        throw TopologyError("spectral_conformal: the mesh has no boundary (" +
                            std::to_string(mesh.n_faces()) +
                            " faces); cut it into a disk before flattening");

    const Eigen::SparseMatrix<double> L = lscm_energy_matrix(mesh);
    DeflatedShiftInvert op(L, mass);
    DiagonalProduct bop(mass);
    // Generalised eigenvalues scale like 1 / length, so the shift does too. A small negative
    // shift keeps L_C - sigma B positive definite (as libigl's eigs does) while the wanted
    // eigenvalue, 0 on developable meshes, stays far better separated than the next ones.
    const double sigma = -1e-6 / perimeter;
    // The smallest non-trivial eigenvalue is double (x and its 90 degree rotation have the same
    // energy), so ask for the pair.
    const Eigen::Index nev = 2;
    const Eigen::Index ncv = std::min<Eigen::Index>(2 * n, 12);
    if (ncv <= nev + 1)
        throw InvalidInputError("spectral_conformal: the mesh has only " + std::to_string(n) +
                                " vertices; need at least 3");
    Spectra::SymGEigsShiftSolver<DeflatedShiftInvert, DiagonalProduct,
                                 Spectra::GEigsMode::ShiftInvert>
        eigs(op, bop, nev, ncv, sigma);
    // Start inside the range of the operator (B-orthogonal to the translations, interior values
    // consistent with the boundary), since B is only semi-definite.
    Eigen::VectorXd start = Eigen::VectorXd::LinSpaced(2 * n, 1.0, 2.0).array().sin();
    Eigen::VectorXd range_start(2 * n);
    Eigen::VectorXd b_start = mass.cwiseProduct(start);
    op.perform_op(b_start.data(), range_start.data());
    eigs.init(range_start.data());
    eigs.compute(Spectra::SortRule::LargestMagn, options.max_iterations, options.tolerance,
                 Spectra::SortRule::SmallestAlge);
    if (eigs.info() != Spectra::CompInfo::Successful)
        throw SolverError(std::string("spectral_conformal: Spectra did not converge (") +
                          (eigs.info() == Spectra::CompInfo::NotConverging    ? "not converging"
                           : eigs.info() == Spectra::CompInfo::NumericalIssue ? "numerical issue"
                                                                              : "not computed") +
                          " after " + std::to_string(eigs.num_iterations()) +
                          " restarts); raise max_iterations or tolerance");
    // One step of inverse iteration with the same shift (Golub and Van Loan, Matrix
    // Computations, 4th ed., 7.6.1): Spectra stops when the Ritz values settle to its tolerance,
    // while the Ritz vector can still hold a part of the next eigenvectors of the order of the
    // square root of it; one more solve divides that part by (lambda_3 - sigma) / (lambda_1 -
    // sigma), large for the small shift sigma, and stays in the wanted pair's plane (their
    // shifted eigenvalues are equal).
    Eigen::VectorXd x(2 * n);
    {
        const Eigen::VectorXd b_ritz = mass.cwiseProduct(eigs.eigenvectors().col(0));
        op.perform_op(b_ritz.data(), x.data());
    }

    Eigen::MatrixX2d uv(n, 2);
    uv.col(0) = x.head(n);
    uv.col(1) = x.tail(n);
    // Scale to the 3D area and centre. The area of a conformal minimiser is positive; a negative
    // one would be a mirror image, so reflect it.
    const double area_2d = signed_map_area(mesh, uv);
    if (!(std::abs(area_2d) > 0.0) || !std::isfinite(area_2d))
        throw SolverError(
            "spectral_conformal: the eigenvector has zero area; the mesh may be "
            "degenerate");
    if (area_2d < 0.0)
        uv.col(1) *= -1.0;
    scale_to_surface_area(mesh, uv);
    uv.rowwise() -= uv.colwise().mean();
    return uv;
}

}  // namespace vessel
