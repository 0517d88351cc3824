#include "vessel/map/arap.h"

#include "detail/arap_ceres.h"
#include "solve/cholmod_common.h"
#include "detail/face_jacobian.h"
#include "solve/serial_openmp.h"
#include "solve/subtree_factorization.h"
#include "solve/subtree_solver.h"
#include "vessel/core/errors.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

namespace vessel {

namespace detail {

std::vector<ArapFace> arap_faces(const Mesh& mesh, const char* caller)
{
    std::vector<ArapFace> faces(mesh.n_faces());
    for (auto f : mesh.faces())
    {
        ArapFace& face = faces[f.idx()];
        const auto h = f.halfedge();
        face.v[0] = h.from().idx();
        face.v[1] = h.to().idx();
        face.v[2] = h.next().to().idx();
        const Eigen::Vector3d p0 = to_eigen(mesh.point(h.from()));
        const Eigen::Vector3d e1 = to_eigen(mesh.point(h.to())) - p0;
        const Eigen::Vector3d e2 = to_eigen(mesh.point(h.next().to())) - p0;
        const double l1 = e1.norm();
        const double twice_area = e1.cross(e2).norm();
        if (!(l1 > 0.0) || !(twice_area > 1e-14 * e2.squaredNorm()) || !std::isfinite(twice_area))
            throw InvalidInputError(std::string(caller) + ": face " + std::to_string(f.idx()) +
                                    " is degenerate (area " + std::to_string(0.5 * twice_area) +
                                    "); remove degenerate triangles before parameterizing");
        face.x[0] = Eigen::Vector2d::Zero();
        face.x[1] = Eigen::Vector2d(l1, 0.0);
        face.x[2] = Eigen::Vector2d(e1.dot(e2) / l1, twice_area / l1);
        Eigen::Matrix2d X;
        X << face.x[1], face.x[2];
        face.X_inv = X.inverse();
        face.area = 0.5 * twice_area;
        for (int k = 0; k < 3; ++k)
        {
            const Eigen::Vector2d a = face.x[(k + 1) % 3] - face.x[k];
            const Eigen::Vector2d b = face.x[(k + 2) % 3] - face.x[k];
            face.cot[k] = a.dot(b) / twice_area;
        }
    }
    return faces;
}

Eigen::Matrix2d arap_jacobian(const ArapFace& face, const Eigen::MatrixX2d& uv)
{
    Eigen::Matrix2d D;
    D.col(0) = (uv.row(face.v[1]) - uv.row(face.v[0])).transpose();
    D.col(1) = (uv.row(face.v[2]) - uv.row(face.v[0])).transpose();
    return D * face.X_inv;
}

double closest_rotation_angle(const Eigen::Matrix2d& J)
{
    // tr(R(t)^T J) = cos t (J00 + J11) + sin t (J10 - J01); its maximiser is a proper rotation
    // even when J is a reflection, which is what the 2x2 SVD with det-correction would return.
    return std::atan2(J(1, 0) - J(0, 1), J(0, 0) + J(1, 1));
}

double face_energy(const ArapFace& face, const Eigen::MatrixX2d& uv, Eigen::Matrix2d& R)
{
    return jacobian_energy(face.area, arap_jacobian(face, uv), R);
}

double jacobian_energy(double area, const Eigen::Matrix2d& J, Eigen::Matrix2d& R)
{
    // The rotation of closest_rotation_angle() without the angle: (cos t, sin t) is the unit
    // vector along (J00 + J11, J10 - J01); t = 0 (atan2(0, 0)) when that vector is zero.
    const double c = J(0, 0) + J(1, 1), s = J(1, 0) - J(0, 1);
    const double length = std::sqrt(c * c + s * s);
    if (length > 0.0)
        R << c / length, -s / length, s / length, c / length;
    else
        R.setIdentity();
    return area * (J - R).squaredNorm();
}

double arap_energy(const std::vector<ArapFace>& faces, const Eigen::MatrixX2d& uv)
{
    double energy = 0.0;
    Eigen::Matrix2d R;
    for (const ArapFace& face : faces)
        energy += face_energy(face, uv, R);
    return energy;
}

}  // namespace detail

namespace {

void check_uv(const Mesh& mesh, const Eigen::MatrixX2d& uv, const char* caller)
{
    if (uv.rows() != static_cast<Eigen::Index>(mesh.n_vertices()))
        throw InvalidInputError(std::string(caller) + ": uv has " + std::to_string(uv.rows()) +
                                " rows but the mesh has " + std::to_string(mesh.n_vertices()) +
                                " vertices; pass one (u, v) row per vertex, e.g. from lscm()");
    if (!uv.allFinite())
        throw InvalidInputError(
            std::string(caller) +
            ": uv has non-finite entries; start from a valid map such as lscm()");
}

// Validates the pins; returns one flag per vertex.
std::vector<bool> pinned_vertices(const Mesh& mesh, const Pins& pins, const char* caller)
{
    if (pins.empty())
        throw InvalidInputError(std::string(caller) +
                                ": no pins; pin at least one vertex (e.g. the inlet loop) to "
                                "fix the translation");
    pin_index(mesh, pins, caller);  // validates
    std::vector<bool> is_pinned(mesh.n_vertices(), false);
    for (const auto& pin : pins)
        is_pinned[pin.vertex.idx()] = true;
    return is_pinned;
}

using detail::CholmodCommon;

}  // namespace

// Global step: minimising sum_t sum_k cot_k / 2 ||u_j - u_l - R_t (x_j - x_l)||^2 (which equals
// the documented energy) over the free u gives K_ff u_f = b(R) - K_fp u_p with K the cotan
// Laplacian (weights cot a + cot b). K does not depend on R, on the map or on the pins' targets,
// only on the mesh and on which vertices are pinned: factor it once (possibly ahead, on another
// thread: arap_prefactor()).
class ArapFactor
{
public:
    ArapFactor(const Mesh& mesh, const std::vector<bool>& is_pinned,
               std::vector<detail::ArapFace> faces, const VertexOrdering* ordering = nullptr)
        : faces_(std::move(faces)), is_pinned_(is_pinned), dof_(mesh.n_vertices(), -1)
    {
        for (auto v : mesh.vertices())
            if (!is_pinned_[v.idx()] && !mesh.is_isolated(v))
                dof_[v.idx()] = n_free_++;
        if (n_free_ == 0)
            return;
        std::vector<Eigen::Triplet<double>> triplets;
        triplets.reserve(9 * faces_.size());
        for (const auto& face : faces_)
            for (int k = 0; k < 3; ++k)
            {
                const int j = face.v[(k + 1) % 3], l = face.v[(k + 2) % 3];
                const double w = face.cot[k];
                const int fj = dof_[j], fl = dof_[l];
                if (fj >= 0)
                {
                    triplets.emplace_back(fj, fj, w);
                    if (fl >= 0)
                        triplets.emplace_back(std::max(fj, fl), std::min(fj, fl), -w);
                }
                if (fl >= 0)
                    triplets.emplace_back(fl, fl, w);
            }
        Eigen::SparseMatrix<double> K(n_free_, n_free_);
        K.setFromTriplets(triplets.begin(), triplets.end());
        // A supernodal factorization in CHOLMOD's layout (BLAS-3; carotid-300k: 0.15 s against
        // 0.5 s for CHOLMOD's simplicial one; SubtreeFactorization's numeric part), copied for
        // the solves into a SubtreeSolver, which runs them on two threads without the
        // supernodal solve's BLAS call per supernode (that cost more than its arithmetic here).
        // The given ordering, else CHOLMOD's default ordering choice (AMD here), as Eigen's
        // CholmodSupernodalLLT makes it. CHOLMOD's factor is freed once copied.
        std::vector<int> given;
        if (ordering)
            given = unknown_order(*ordering, dof_, n_free_);
        CholmodCommon common;
        common.c.supernodal = CHOLMOD_SUPERNODAL;
        const Eigen::SparseMatrix<double>& lower = K;
        cholmod_sparse view = Eigen::viewAsCholmod(lower.selfadjointView<Eigen::Lower>());
        const detail::SerialOpenMp serial;
        cholmod_factor* factor =
            detail::analyze_in_order(view, ordering ? &given : nullptr, common.c);
        // One thread: the pipeline makes this factor on its own thread beside LSCM's.
        const bool factored =
            factor != nullptr && detail::factorize_once(view, *factor, common.c, 1);
        try
        {
            if (factored)
                solver_.emplace(*factor);
        }
        catch (...)
        {
            cholmod_free_factor(&factor, &common.c);  // no destructor after a throw here
            throw;
        }
        cholmod_free_factor(&factor, &common.c);
        if (!factored)
            throw SolverError("arap: CHOLMOD could not factor the cotan Laplacian (" +
                              std::to_string(n_free_) +
                              " free vertices); every connected component needs a pin");
        // The free vertices renumbered in the factor's column order: the right-hand side is
        // gathered and the solution read in that order, with no permutation per solve.
        std::vector<int> column_of(n_free_);
        const std::vector<int>& row_of_column = solver_->permutation();
        for (int c = 0; c < n_free_; ++c)
            column_of[row_of_column[c]] = c;
        for (int& d : dof_)
            if (d >= 0)
                d = column_of[d];
        make_gather();
    }

    const std::vector<detail::ArapFace>& faces() const { return faces_; }
    const std::vector<bool>& is_pinned() const { return is_pinned_; }
    //! Per vertex its unknown, i.e. its column in solver()'s factor (solve_in_order()), or -1.
    const std::vector<int>& dof() const { return dof_; }
    int n_free() const { return n_free_; }
    //! The factor's solves; only when n_free() > 0.
    const detail::SubtreeSolver& solver() const { return *solver_; }

    //! The terms of free vertex \p i's row of the global step's right-hand side, in face order:
    //! each is 2 (3 t + k) for + term k of face t, one more for its - term.
    const int* gather_begin(int i) const { return gather_.data() + gather_start_[i]; }
    const int* gather_end(int i) const { return gather_.data() + gather_start_[i + 1]; }

private:
    // Face t's term k, cot_k R_t (x_j - x_l), is added to row j and subtracted from row l. Listing
    // each row's terms (in face order) lets two threads sum disjoint rows, with the additions
    // in the order of one thread's sweep over the faces.
    void make_gather()
    {
        gather_start_.assign(n_free_ + 1, 0);
        for (const auto& face : faces_)
            for (int k = 0; k < 3; ++k)
                for (const int vertex : {face.v[(k + 1) % 3], face.v[(k + 2) % 3]})
                    if (dof_[vertex] >= 0)
                        ++gather_start_[dof_[vertex] + 1];
        for (int i = 0; i < n_free_; ++i)
            gather_start_[i + 1] += gather_start_[i];
        gather_.resize(gather_start_[n_free_]);
        std::vector<int> next(gather_start_.begin(), gather_start_.end() - 1);
        for (std::size_t t = 0; t < faces_.size(); ++t)
            for (int k = 0; k < 3; ++k)
            {
                const int term = 2 * static_cast<int>(3 * t + k);
                const int fj = dof_[faces_[t].v[(k + 1) % 3]], fl = dof_[faces_[t].v[(k + 2) % 3]];
                if (fj >= 0)
                    gather_[next[fj]++] = term;
                if (fl >= 0)
                    gather_[next[fl]++] = term + 1;
            }
    }

    std::vector<detail::ArapFace> faces_;
    std::vector<bool> is_pinned_;
    std::vector<int> dof_;
    int n_free_ = 0;
    std::vector<int> gather_start_;
    std::vector<int> gather_;
    std::optional<detail::SubtreeSolver> solver_;
};

namespace {

ArapSummary arap_local_global(const ArapFactor& system, Eigen::MatrixX2d& uv,
                              const ArapOptions& options)
{
    const std::vector<detail::ArapFace>& faces = system.faces();
    const std::vector<int>& dof = system.dof();
    const int n = static_cast<int>(uv.rows());
    const int n_free = system.n_free();

    ArapSummary summary;
    summary.initial_energy = summary.final_energy = detail::arap_energy(faces, uv);
    if (n_free == 0)
    {
        summary.converged = true;
        summary.report = "LocalGlobal: every vertex is pinned";
        return summary;
    }
    // The pinned neighbours' share of the right-hand side: K_fp u_p.
    Eigen::MatrixX2d b_pinned = Eigen::MatrixX2d::Zero(n_free, 2);
    for (const auto& face : faces)
        for (int k = 0; k < 3; ++k)
        {
            const int j = face.v[(k + 1) % 3], l = face.v[(k + 2) % 3];
            const double w = face.cot[k];
            const int fj = dof[j], fl = dof[l];
            if (fj >= 0 && fl < 0)
                b_pinned.row(fj) += w * uv.row(l);
            if (fl >= 0 && fj < 0)
                b_pinned.row(fl) += w * uv.row(j);
        }

    // Local step: the closest rotation per face. It also yields the energy of the current map,
    // so each sweep evaluates the Jacobians once, and each face's right-hand-side terms
    // cot_k R_t (x_j - x_l) for the next global step. Per face, so on two threads for large
    // meshes; the terms are summed into b in face order, as on one thread.
    // The energy is summed in `chunks` partial sums whether or not they run on as many threads,
    // so that every thread count gives the same bits.
    const int chunks = detail::face_threads(faces.size());
    const int threads = std::min(options.threads, chunks);
    const auto over_chunks = [&](std::size_t count, const auto& body) {
        if (threads == chunks)
            detail::parallel_chunks(count, chunks, body);
        else
            for (int t = 0; t < chunks; ++t)
                body(count * t / chunks, count * (t + 1) / chunks, t);
    };
    // The map as the local step reads it, interleaved: (u, v) of unknown i at x[2i], x[2i + 1]
    // (where the global step's solve leaves them), then the other vertices' (pinned or
    // without a face), fixed. Each face's corners as positions in it.
    std::vector<int> slot(n);
    for (int i = 0, next = n_free; i < n; ++i)
        slot[i] = dof[i] >= 0 ? dof[i] : next++;
    std::vector<double> x(2 * static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i)
    {
        x[2 * static_cast<std::size_t>(slot[i])] = uv(i, 0);
        x[2 * static_cast<std::size_t>(slot[i]) + 1] = uv(i, 1);
    }
    std::vector<std::array<int, 3>> corner(faces.size());
    for (std::size_t f = 0; f < faces.size(); ++f)
        for (int k = 0; k < 3; ++k)
            corner[f][k] = 2 * slot[faces[f].v[k]];
    std::vector<Eigen::RowVector2d> rotated(3 * faces.size());
    const auto local_step = [&] {
        std::array<double, 2> partial{0.0, 0.0};
        over_chunks(faces.size(), [&](std::size_t begin, std::size_t end, int t) {
            double e = 0.0;
            Eigen::Matrix2d R, D;
            for (std::size_t f = begin; f < end; ++f)
            {
                const auto& face = faces[f];
                const double* p0 = x.data() + corner[f][0];
                const double* p1 = x.data() + corner[f][1];
                const double* p2 = x.data() + corner[f][2];
                D << p1[0] - p0[0], p2[0] - p0[0], p1[1] - p0[1], p2[1] - p0[1];
                e += detail::jacobian_energy(face.area, D * face.X_inv, R);
                for (int k = 0; k < 3; ++k)
                    rotated[3 * f + k] = face.cot[k] *
                                         (R * (face.x[(k + 1) % 3] - face.x[(k + 2) % 3])).transpose();
            }
            partial[t] = e;
        });
        return partial[0] + partial[1];
    };
    // b = b_pinned + the rotated terms, row by row (each row's terms in face order, so the sums
    // are those of one sweep over the faces), on disjoint rows per thread; row i at b[2i],
    // b[2i + 1].
    const auto gather = [&](double* b) {
        detail::parallel_chunks(static_cast<std::size_t>(n_free), threads,
                                [&](std::size_t begin, std::size_t end, int) {
            for (std::size_t i = begin; i < end; ++i)
            {
                Eigen::RowVector2d sum = b_pinned.row(i);
                for (const int* term = system.gather_begin(i); term != system.gather_end(i); ++term)
                    if (*term & 1)
                        sum -= rotated[*term >> 1];
                    else
                        sum += rotated[*term >> 1];
                b[2 * i] = sum[0];
                b[2 * i + 1] = sum[1];
            }
        });
    };
    detail::SubtreeSolver::Workspace solve_work;
    double energy = local_step();
    const auto unknowns_end = x.begin() + 2 * static_cast<std::ptrdiff_t>(n_free);
    for (int it = 1; it <= options.max_iterations; ++it)
    {
        // The right-hand side over the unknowns' positions (the local step has read them),
        // then the solve in place.
        gather(x.data());
        system.solver().solve_in_order(x.data(), threads, solve_work);
        if (!std::all_of(x.begin(), unknowns_end, [](double value) { return std::isfinite(value); }))
            throw SolverError("arap: the global step's solve is not finite in local/global iteration " +
                              std::to_string(it));
        const double previous = energy;
        energy = local_step();
        summary.iterations = it;
        if (!(previous > 0.0) || (previous - energy) < options.tolerance * previous)
        {
            summary.converged = true;
            if (options.on_iteration)
                options.on_iteration(it, energy);
            break;
        }
        if (options.on_iteration && !options.on_iteration(it, energy))
            break;
    }
    for (int i = 0; i < n; ++i)
        if (dof[i] >= 0)
            uv.row(i) << x[2 * static_cast<std::size_t>(dof[i])],
                x[2 * static_cast<std::size_t>(dof[i]) + 1];
    summary.final_energy = energy;
    std::ostringstream report;
    report << "LocalGlobal: " << summary.iterations << " iterations, energy "
           << summary.initial_energy << " -> " << summary.final_energy
           << (summary.converged                        ? ", converged"
               : summary.iterations < options.max_iterations ? ", stopped by on_iteration"
                                                             : ", iteration limit reached");
    summary.report = report.str();
    return summary;
}

}  // namespace

void ArapOptions::validate() const
{
    if (max_iterations < 1)
        throw InvalidInputError("ArapOptions::validate: max_iterations must be >= 1 (got " +
                                std::to_string(max_iterations) + "); use e.g. 50");
    if (!(tolerance >= 0.0) || !std::isfinite(tolerance))
        throw InvalidInputError("ArapOptions::validate: tolerance must be finite and >= 0 (got " +
                                std::to_string(tolerance) + "); use e.g. 1e-6");
    if (threads < 1)
        throw InvalidInputError("ArapOptions::validate: threads must be >= 1 (got " +
                                std::to_string(threads) + ")");
    if (solver != ArapSolver::Ceres && solver != ArapSolver::LocalGlobal)
        throw InvalidInputError("ArapOptions::validate: unknown solver " +
                                std::to_string(static_cast<int>(solver)) +
                                "; use ArapSolver::Ceres or ArapSolver::LocalGlobal");
}

double arap_energy(const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    check_uv(mesh, uv, "arap_energy");
    return detail::arap_energy(detail::arap_faces(mesh, "arap_energy"), uv);
}

std::shared_ptr<const ArapFactor> arap_prefactor(const Mesh& mesh, const Pins& pins,
                                                 const VertexOrdering* ordering)
{
    if (mesh.n_faces() == 0)
        throw InvalidInputError("arap_prefactor: the mesh has no faces; pass a triangulated disk");
    return std::make_shared<const ArapFactor>(mesh, pinned_vertices(mesh, pins, "arap_prefactor"),
                                              detail::arap_faces(mesh, "arap_prefactor"),
                                              ordering);
}

ArapSummary arap(const Mesh& mesh, Eigen::MatrixX2d& uv, const Pins& pins,
                 const ArapOptions& options)
{
    options.validate();
    check_uv(mesh, uv, "arap");
    if (mesh.n_faces() == 0)
        throw InvalidInputError("arap: the mesh has no faces; pass a triangulated disk");
    const std::vector<bool> is_pinned = pinned_vertices(mesh, pins, "arap");
    if (options.prefactored && options.prefactored->is_pinned() != is_pinned)
        throw InvalidInputError("arap: ArapOptions::prefactored was made for other pins or "
                                "another mesh; make it with arap_prefactor() of this mesh and "
                                "these pins, or leave it null");
    // Work on a copy so that a throwing solver leaves the caller's map untouched.
    Eigen::MatrixX2d work = uv;
    for (const auto& pin : pins)
        work.row(pin.vertex.idx()) = pin.uv.transpose();
    ArapSummary summary;
    if (options.solver == ArapSolver::Ceres)
        summary = detail::arap_ceres(mesh, detail::arap_faces(mesh, "arap"), work, is_pinned,
                                     options);
    else if (options.prefactored)
        summary = arap_local_global(*options.prefactored, work, options);
    else
        summary = arap_local_global(ArapFactor(mesh, is_pinned, detail::arap_faces(mesh, "arap")),
                                    work, options);
    uv = work;
    return summary;
}

}  // namespace vessel
