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

}  // namespace vessel::detail
