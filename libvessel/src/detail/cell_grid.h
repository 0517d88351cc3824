#pragma once
// CellGrid: the cell arithmetic of a uniform grid over the plane, shared by the grids of a map's
// boundary edges (detail::BoundaryGuard, prolongate()'s boundary in multilevel.cpp).

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace vessel::detail {

//! nx x ny square cells of side `cell` from `origin`, numbered i * ny + j (i along u, j along
//! v). A point outside the grid counts in the nearest border cell, for entries and queries
//! alike, so that two segments that meet always share a cell. Each owner keeps its own entries
//! (a static sorted list, or lists that grow), as its queries need.
struct CellGrid
{
    Eigen::Vector2d origin = Eigen::Vector2d::Zero();
    double cell = 1.0;
    int nx = 1, ny = 1;

    std::size_t size() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }

    //! Calls visit(index) for each cell that the box [lo, hi] grown by \p grow on every side
    //! meets, i outer, j inner.
    template <class Visit>
    void for_cells(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double grow,
                   const Visit& visit) const
    {
        const auto index = [&](double value, double start, int n) {
            return std::clamp(static_cast<int>(std::floor((value - start) / cell)), 0, n - 1);
        };
        const int x0 = index(lo.x() - grow, origin.x(), nx);
        const int x1 = index(hi.x() + grow, origin.x(), nx);
        const int y0 = index(lo.y() - grow, origin.y(), ny);
        const int y1 = index(hi.y() + grow, origin.y(), ny);
        for (int i = x0; i <= x1; ++i)
            for (int j = y0; j <= y1; ++j)
                visit(static_cast<std::size_t>(i) * static_cast<std::size_t>(ny) +
                      static_cast<std::size_t>(j));
    }
};

}  // namespace vessel::detail
