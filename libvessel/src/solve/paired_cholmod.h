#pragma once

#include "solve/cholmod_common.h"
#include "solve/paired_symbolic.h"
#include "solve/reach_solve.h"
#include "solve/serial_openmp.h"
#include "solve/subtree_factorization.h"

#include <Eigen/Cholesky>
#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>

#include <exception>
#include <memory>
#include <thread>
#include <vector>

namespace vessel::detail {

//! Eigen's CholmodSupernodalLLT with a symbolic analysis in a given elimination order (e.g. from
//! a VertexOrdering shared by several factorizations) instead of CHOLMOD's own choice, and its
//! numeric factorization on two threads (SubtreeFactorization; the solves are CHOLMOD's).
template <int UpLo>
class OrderedCholmod : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, UpLo>
{
    using Base = Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, UpLo>;

public:
    //! Threads of factorize() (1 or 2; the same factor either way).
    void set_threads(int threads) { threads_ = threads; }

    //! Eigen's analyzePattern() (CHOLMOD's ordering), then made ready for factorize().
    void analyzePattern(const Eigen::SparseMatrix<double>& A)
    {
        Base::analyzePattern(A);
        prepare(A);
    }

    //! analyzePattern(), then factorize().
    void compute(const Eigen::SparseMatrix<double>& A)
    {
        analyzePattern(A);
        if (this->info() == Eigen::Success)
            factorize(A);
    }

    //! Numeric factorization of \p A, whose pattern analyze_given() or analyzePattern()
    //! analysed.
    //! Check info(): NumericalIssue if A is not positive definite.
    void factorize(const Eigen::SparseMatrix<double>& A)
    {
        const SerialOpenMp serial;  // one BLAS thread per factorization thread
        if (!subtree_ || !A.isCompressed())
        {
            Base::factorize(A);
            return;
        }
        cholmod_sparse view = Eigen::viewAsCholmod(A.template selfadjointView<UpLo>());
        const bool ok =
            subtree_->factorize(view, *this->m_cholmodFactor, this->cholmod(), threads_);
        this->m_info = ok ? Eigen::Success : Eigen::NumericalIssue;
        this->m_factorizationIsOk = true;
    }

    //! Symbolic analysis of \p A (the UpLo triangle, compressed) eliminating its unknowns in
    //! \p order (each once). Check info().
    void analyze_given(const Eigen::SparseMatrix<double>& A, std::vector<int> order)
    {
        cholmod_sparse view = Eigen::viewAsCholmod(A.template selfadjointView<UpLo>());
        adopt(A, analyze_in_order(view, &order, this->cholmod()));
    }

    //! \brief (A + U diag(c) U^T)^-1 b for the factorized A and a low-rank term (every c > 0)
    //! by the Woodbury identity (Hager 1989, "Updating the inverse of a matrix") on the
    //! factor's triangular halves, P A P^T = L L^T: with y = L^-1 P b and Y = L^-1 P U,
    //! x = P^T L^-T (y - Y (diag(1 / c) + Y^T Y)^-1 Y^T y). The columns of U are sparse and
    //! their forward solves run on the rows they reach (reach_forward_solve()), beside b's on a
    //! second thread where threads allow (the same bits either way); b takes one forward and
    //! one backward solve. Check info().
    Eigen::VectorXd solve_with_low_rank(const Eigen::VectorXd& b,
                                        const Eigen::SparseMatrix<double>& U,
                                        const Eigen::VectorXd& c)
    {
        const cholmod_factor* L = this->m_cholmodFactor;
        if (!L || !L->is_super || !L->is_ll || L->itype != CHOLMOD_INT ||
            L->xtype != CHOLMOD_REAL || L->dtype != CHOLMOD_DOUBLE)
        {
            this->m_info = Eigen::InvalidInput;
            return {};
        }
        // U's reach and b's forward solve read the factor only: side by side.
        Eigen::MatrixXd y = b;
        bool forward = false;
        ReachSolve reach;
        std::exception_ptr failed;  // of the second thread, rethrown here
        {
            std::thread beside;
            // Joined on leaving the scope, also by an exception.
            const struct Join
            {
                std::thread& thread;
                ~Join()
                {
                    if (thread.joinable())
                        thread.join();
                }
            } join{beside};
            if (threads_ > 1 && U.cols() > 0 && b.size() >= kBesideUnknowns)
                beside = std::thread([&] {
                    try
                    {
                        reach = reach_forward_solve(*L, U);
                    }
                    catch (...)
                    {
                        failed = std::current_exception();
                    }
                });
            else
                reach = reach_forward_solve(*L, U);
            forward = apply(CHOLMOD_P, y) && apply(CHOLMOD_L, y);
        }
        if (failed)
            std::rethrow_exception(failed);
        if (!forward)
            return {};
        const Eigen::Index m = static_cast<Eigen::Index>(reach.rows.size());
        Eigen::VectorXd at_reach(m);
        for (Eigen::Index r = 0; r < m; ++r)
            at_reach[r] = y(reach.rows[static_cast<std::size_t>(r)], 0);
        Eigen::MatrixXd S = Eigen::MatrixXd::Zero(U.cols(), U.cols());
        S.selfadjointView<Eigen::Lower>().rankUpdate(reach.Y.transpose());
        S.diagonal() += c.cwiseInverse();
        const Eigen::VectorXd z =
            S.selfadjointView<Eigen::Lower>().ldlt().solve(reach.Y.transpose() * at_reach);
        at_reach.noalias() -= reach.Y * z;
        for (Eigen::Index r = 0; r < m; ++r)
            y(reach.rows[static_cast<std::size_t>(r)], 0) = at_reach[r];
        if (!apply(CHOLMOD_Lt, y) || !apply(CHOLMOD_Pt, y))
            return {};
        return y;
    }

protected:
    //! \p symbolic (a symbolic analysis of A's pattern, owned from here on; null where it
    //! failed) as the factor for factorize(). Check info().
    void adopt(const Eigen::SparseMatrix<double>& A, cholmod_factor* symbolic)
    {
        if (this->m_cholmodFactor)
            cholmod_free_factor(&this->m_cholmodFactor, &this->cholmod());
        this->m_cholmodFactor = symbolic;
        this->m_isInitialized = true;
        this->m_info = symbolic ? Eigen::Success : Eigen::NumericalIssue;
        this->m_analysisIsOk = symbolic != nullptr;
        this->m_factorizationIsOk = false;
        prepare(A);
    }

private:
    // The fewest unknowns for which solve_with_low_rank() runs U's reach on a second thread:
    // below it (the coarse mesh's systems) a forward solve is about as short as starting a
    // thread, and those systems are solved while the other core is busy with another map.
    static constexpr Eigen::Index kBesideUnknowns = 20000;

    // B <- CHOLMOD's solve of system \p sys (CHOLMOD_L, CHOLMOD_Lt, CHOLMOD_P or CHOLMOD_Pt)
    // with the factor, column by column; sets info().
    bool apply(int sys, Eigen::MatrixXd& B)
    {
        cholmod_dense view{};
        view.nrow = view.d = static_cast<size_t>(B.rows());
        view.ncol = static_cast<size_t>(B.cols());
        view.nzmax = view.nrow * view.ncol;
        view.x = B.data();
        view.xtype = CHOLMOD_REAL;
        view.dtype = CHOLMOD_DOUBLE;
        cholmod_dense* X = cholmod_solve(sys, this->m_cholmodFactor, &view, &this->cholmod());
        const bool solved = X != nullptr;
        this->m_info = solved ? Eigen::Success : Eigen::NumericalIssue;
        if (solved)
            B = Eigen::Map<const Eigen::MatrixXd>(static_cast<double*>(X->x), B.rows(), B.cols());
        cholmod_free_dense(&X, &this->cholmod());
        return solved;
    }

    // The numeric factorization's plan for the analysed pattern of A (none for a simplicial
    // factor or a matrix not compressed: factorize() then calls CHOLMOD's).
    void prepare(const Eigen::SparseMatrix<double>& A)
    {
        subtree_.reset();
        if (this->m_cholmodFactor && this->m_cholmodFactor->is_super && A.isCompressed())
        {
            cholmod_sparse view = Eigen::viewAsCholmod(A.template selfadjointView<UpLo>());
            subtree_ = std::make_unique<SubtreeFactorization>(view, *this->m_cholmodFactor);
        }
    }

    std::unique_ptr<SubtreeFactorization> subtree_;
    int threads_ = 2;
};

//! CHOLMOD's supernodal LL' of a symmetric matrix stored as its upper triangle whose unknowns
//! come in pairs (u, v of one vertex: unknowns 2i and 2i + 1) that share their sparsity.
//! analyze_pairs() orders the vertex graph (half the unknowns, a quarter of the entries) with
//! AMD (METIS on large maps) and makes the factor's analysis from the vertex graph too
//! (paired_symbolic(): CHOLMOD's analysis of the paired order, field for field), instead of
//! AMD and the analysis on the whole matrix: the same kind of ordering for a fraction of the
//! symbolic analysis's cost, which matters where the pattern changes every iteration (SLIM's
//! scaffold), and from kMetisVertices on a factor with far fewer flops (the area polish's
//! Newton Hessian too; LSCM's single factorization keeps AMD).
class PairedCholmod : public OrderedCholmod<Eigen::Upper>
{
public:
    //! Vertex count from which the vertex graph is ordered by METIS instead of AMD. METIS's
    //! nested dissection fills less (carotid-1M, 500k vertices, SLIM: peak RSS 2752 -> 2431 MB)
    //! but costs far more to compute, and SLIM with a scaffold orders a new pattern at every
    //! new triangulation: with AMD instead, Glenn split4 (139k vertices, 225 triangulations)
    //! flattened in 191 s against 285 s, carotid-300k (150k) in 19.0 s against 20.3 s (peak
    //! RSS 876 against 810 MB), the same maps' figures (docs/benchmarks.md).
    static constexpr int kMetisVertices = 400000;

    //! Symbolic analysis of \p A (upper triangle, compressed, even size). Check info().
    //! \p metis_vertices: the vertex count from which METIS orders (a single factorization,
    //! e.g. LSCM's, is better served by AMD's cheaper ordering at every size).
    //! \p given_order: an elimination order of the pairs (each pair index once) to use instead
    //! of ordering them here.
    void analyze_pairs(const Eigen::SparseMatrix<double>& A, int metis_vertices = kMetisVertices,
                       const std::vector<int>* given_order = nullptr)
    {
        const int n = static_cast<int>(A.cols()) / 2;
        VertexGraph vertices = vertex_graph(A);
        cholmod_sparse graph = vertices.view();
        std::vector<int> vertex_order = given_order ? *given_order : std::vector<int>(n);
        // From kMetisVertices vertices on, METIS's nested dissection instead of AMD: less
        // fill and memory on large maps (docs/journal/benchmarks-2026-11.md, "Stage F at 1M");
        // below it AMD, far cheaper to compute (see kMetisVertices).
        const bool ok =
            given_order ||
            (n >= metis_vertices
                 ? cholmod_metis(&graph, nullptr, 0, 1, vertex_order.data(), &this->cholmod())
                 : cholmod_amd(&graph, nullptr, 0, vertex_order.data(), &this->cholmod()));
        if (!ok)
        {
            this->m_info = Eigen::NumericalIssue;
            return;
        }
        // The vertex graph's analysis is A's where each pair's block is whole (not LSCM's,
        // whose diagonal blocks have no (u, v) entry) and a supernodal factor is asked for
        // (Eigen's default).
        cholmod_factor* L =
            vertices.whole_blocks && this->cholmod().supernodal == CHOLMOD_SUPERNODAL
                ? paired_symbolic(graph, vertex_order, this->cholmod())
                : nullptr;
        if (L)
            adopt(A, L);
        else  // CHOLMOD's own analysis of the whole matrix
            analyze_given(A, paired(vertex_order));
    }

private:
    // Each pair's two unknowns in the pairs' order.
    static std::vector<int> paired(const std::vector<int>& pair_order)
    {
        std::vector<int> order(2 * pair_order.size());
        for (std::size_t k = 0; k < pair_order.size(); ++k)
        {
            order[2 * k] = 2 * pair_order[k];
            order[2 * k + 1] = 2 * pair_order[k] + 1;
        }
        return order;
    }
};

}  // namespace vessel::detail
