#pragma once

#include "vessel/mesh.h"

#include <memory>
#include <vector>

namespace vessel {

struct HeatGeodesicsOptions
{
    //! Diffusion time t = time_factor * h^2, h = mean edge length (Crane et al. 2013 use 1).
    double time_factor = 1.0;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! \brief Heat-method geodesic distance \cite crane_2013_geodesics. The heat and Poisson systems
//! are factored once (CHOLMOD) in the constructor and reused for every query.
class HeatGeodesics
{
public:
    //! \throw SolverError if a factorization fails. \throw InvalidInputError on an empty mesh.
    explicit HeatGeodesics(const Mesh& mesh, const HeatGeodesicsOptions& options = {});
    ~HeatGeodesics();
    HeatGeodesics(HeatGeodesics&&) noexcept;
    HeatGeodesics& operator=(HeatGeodesics&&) noexcept;

    //! Distance to the nearest of \p sources; |V| entries indexed by `v.idx()`, 0 at the sources.
    //! \throw InvalidInputError if \p sources is empty or holds an invalid handle.
    Eigen::VectorXd distance(const std::vector<VertexHandle>& sources) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

//! One-off convenience: factor and query once.
Eigen::VectorXd heat_geodesic_distance(const Mesh& mesh, const std::vector<VertexHandle>& sources,
                                       const HeatGeodesicsOptions& options = {});

}  // namespace vessel
