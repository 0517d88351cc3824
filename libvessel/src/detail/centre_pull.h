#pragma once

#include "vessel/centre_pull.h"

#include <Eigen/Core>

#include <vector>

namespace vessel::detail {

//! Sum of the pulls' energies at the interleaved map \p x (u0 v0 u1 v1 ...).
double centre_pull_energy(const std::vector<CentrePull>& pulls, const Eigen::VectorXd& x);

//! Add the pulls to SLIM's global step at \p x as a diagonal proxy whose gradient at \p x is
//! the pulls' (each vertex of a pull is drawn toward its place moved by the centre's offset
//! from the line, with weight / |vertices|; so the normal matrix's pattern is unchanged).
//! \param diagonal value index of entry (i, i) of the normal matrix's values \p values.
void add_centre_pulls(const std::vector<CentrePull>& pulls, const Eigen::VectorXd& x,
                      const std::vector<int>& diagonal, double* values, Eigen::VectorXd& rhs);

//! Add the pulls' gradient at \p x to \p gradient, whose entries 2 slot[v] + k are vertex v's
//! (slot[v] < 0: a fixed vertex, skipped); and, if \p diagonal is given, each pull's per-vertex
//! curvature weight / |vertices| to the values at diagonal[2 slot[v] + k] (as add_centre_pulls).
void add_centre_pull_gradient(const std::vector<CentrePull>& pulls, const Eigen::VectorXd& x,
                              const std::vector<int>& slot, double* gradient);
void add_centre_pull_curvature(const std::vector<CentrePull>& pulls, const std::vector<int>& slot,
                               const std::vector<int>& diagonal, double* values);

}  // namespace vessel::detail
