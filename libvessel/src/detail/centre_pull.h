#pragma once

#include "vessel/map/centre_pull.h"

#include <Eigen/Core>

#include <string>
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
