#pragma once

#include "vessel/map/centre_pull.h"

#include <Eigen/Core>
#include <Eigen/Sparse>

#include <string>
#include <utility>
#include <vector>

namespace vessel::detail {

//! \brief Check that every vertex of every pull is one of the \p n vertices of the mesh.
//! \param who the caller's name for the message.
//! \throw InvalidInputError naming the first vertex out of range.
void require_centre_pull_vertices(const std::vector<CentrePull>& pulls, int n,
                                  const std::string& who);

//! Sum of the pulls' energies at the interleaved map \p x (u0 v0 u1 v1 ...).
double centre_pull_energy(const std::vector<CentrePull>& pulls, const Eigen::VectorXd& x);

//! Add the pulls to SLIM's global step at \p x as a diagonal proxy whose gradient at \p x is
//! the pulls' (each vertex of an active pull is drawn toward its place moved against the
//! residual's gradient, with weight |dr/dc|^2 / |set|: a Line pull's vertices toward their
//! places moved by the centre's offset from the line, with weight / |vertices|; so the normal
//! matrix's pattern is unchanged; hinges that hold add nothing).
//! \param diagonal value index of entry (i, i) of the normal matrix's values \p values.
void add_centre_pulls(const std::vector<CentrePull>& pulls, const Eigen::VectorXd& x,
                      const std::vector<int>& diagonal, double* values, Eigen::VectorXd& rhs);

//! A pull's residual r and its derivatives by its two centres (dr/dc, dr/dc2).
struct PullResidual
{
    double r = 0.0;
    Eigen::Vector2d by_first = Eigen::Vector2d::Zero(), by_second = Eigen::Vector2d::Zero();
    bool active = false;  //!< the energy (weight r^2) counts: a Line always, a hinge when r < 0
};

//! \brief \p pull's residual with the centre of its vertices at \p first and (PullKind::Order)
//! that of its second set at \p second, both relative to its origin.
PullResidual pull_residual(const CentrePull& pull, const Eigen::Vector2d& first,
                           const Eigen::Vector2d& second);

//! One active pull linearized at a map x (PullSteps::GaussNewton): its residual r (a hinge's
//! at most 0), weight W, and u = dr/dx as (interleaved unknown 2 v + k, value) entries.
struct PullRow
{
    double weight = 0.0;
    double r = 0.0;
    std::vector<std::pair<int, double>> entries;
};

//! \brief The pulls active at the interleaved map \p x as rows, the pulls' Gauss-Newton
//! Hessian being sum 2 W u u^T. With \p band > 0 a hinge that holds by less than \p band times
//! its margin counts too (r = 0: its curvature, no gradient), so that an exact step does not
//! jump past a hinge that it turns on.
std::vector<PullRow> active_pull_rows(const std::vector<CentrePull>& pulls,
                                      const Eigen::VectorXd& x, double band = 0.0);

//! The rows as the columns U of a low-rank term U diag(c) U^T over \p size unknowns, and c:
//! entry 2 v + k of a row at unknown 2 slot[v] + k (an entry of a vertex with slot[v] < 0 left
//! out), or at unknown 2 v + k with \p slot null; c = \p scale x each row's weight. U is sparse:
//! a pull reaches the vertices of its sets only.
struct PullColumns
{
    Eigen::SparseMatrix<double> U;
    Eigen::VectorXd c;
};
PullColumns pull_columns(const std::vector<PullRow>& rows, Eigen::Index size, double scale,
                         const std::vector<int>* slot = nullptr);

//! Add the pulls' gradient at \p x to \p gradient, whose entries 2 slot[v] + k are vertex v's
//! (slot[v] < 0: a fixed vertex, skipped).
void add_centre_pull_gradient(const std::vector<CentrePull>& pulls, const Eigen::VectorXd& x,
                              const std::vector<int>& slot, double* gradient);
//! Add each pull's per-vertex curvature at \p x, 2 weight |dr/dc|^2 / |set| (the proxy's,
//! which majorizes the pull's dense Gauss-Newton Hessian along any common motion of a set; a
//! Line pull: 2 weight / |vertices|; a hinge that holds: 0) to the values at
//! diagonal[2 slot[v] + k] of the free vertices (slot[v] >= 0).
void add_centre_pull_curvature(const std::vector<CentrePull>& pulls, const Eigen::VectorXd& x,
                               const std::vector<int>& slot, const std::vector<int>& diagonal,
                               double* values);

}  // namespace vessel::detail
