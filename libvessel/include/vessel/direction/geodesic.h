#pragma once

#include "vessel/core/mesh.h"
#include "vessel/solve/ordering.h"

#include <memory>
#include <vector>

namespace vessel {

//! Boundary condition of the heat step on meshes with boundary (closed meshes ignore it).
enum class HeatBoundaryCondition
{
    //! Zero normal derivative (the default). Exact, by reflection, for sources on a straight
    //! boundary, such as the inlet rim libvessel measures from; two factorizations.
    Neumann,
    //! Mean of the Neumann and Dirichlet (u = 0 on the boundary; boundary sources keep their
    //! Neumann value) solutions, recommended by Crane et al. 2013 for sources away from the
    //! boundary; a third factorization (about +50% construction time).
    Average,
};

struct HeatGeodesicsOptions
{
    //! Diffusion time t = time_factor * h^2, h = mean edge length (Crane et al. 2013 use 1).
    double time_factor = 1.0;
    //! See HeatBoundaryCondition.
    HeatBoundaryCondition boundary_condition = HeatBoundaryCondition::Neumann;
    //! Elimination order of the factorizations, laplacian_ordering() of the same mesh, e.g. to
    //! share one with other factorizations (the pipeline does). Null (the default) = AMD here.
    std::shared_ptr<const VertexOrdering> ordering;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! \brief Heat-method geodesic distance \cite crane_2013_geodesics. The heat and Poisson systems
//! are factored once (CHOLMOD) in the constructor and reused for every query.
class HeatGeodesics
{
public:
    //! \throw SolverError if a factorization fails. \throw InvalidInputError if the mesh has no
    //! faces or the options are invalid.
    explicit HeatGeodesics(const Mesh& mesh, const HeatGeodesicsOptions& options = {});
    ~HeatGeodesics();
    HeatGeodesics(HeatGeodesics&&) noexcept;
    HeatGeodesics& operator=(HeatGeodesics&&) noexcept;

    //! Distance to the nearest of \p sources; |V| entries indexed by `v.idx()`, shifted so that
    //! the smallest value over the sources is 0 (per connected component). Vertices in components
    //! without a source (including isolated vertices) get +infinity.
    //! \throw InvalidInputError if \p sources is empty or holds an invalid handle.
    Eigen::VectorXd distance(const std::vector<VertexHandle>& sources) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

//! One-off convenience: factor and query once. Throws as the constructor and distance() do.
Eigen::VectorXd heat_geodesic_distance(const Mesh& mesh, const std::vector<VertexHandle>& sources,
                                       const HeatGeodesicsOptions& options = {});

}  // namespace vessel
