#pragma once

#include "vessel/core/mesh.h"

#include <Eigen/Core>

#include <functional>
#include <optional>
#include <type_traits>
#include <utility>

namespace vessel {

//! \file Travel costs of the directed cut graph. A cost is any callable
//! `double(const Mesh&, SmartHalfedgeHandle) const` returning a value >= 0 for walking along
//! halfedge `h` from `h.from()` to `h.to()`. Costs are evaluated once into HalfedgeWeights, so a
//! researcher's own cost (see tools/examples/custom_cost.cpp) runs at full speed in Dijkstra.

//! E_c = 1 - <unit edge, unit z_i>: zero when the edge runs along the vessel direction z at its
//! start vertex i (z points toward the inlet, so cuts walk from the outlets toward the inlet).
struct CurvatureCost
{
    const Eigen::MatrixX3d* direction = nullptr;  //!< |V| x 3 unit z, row `v.idx()`
    double operator()(const Mesh& mesh, SmartHalfedgeHandle h) const;
};

//! E_g = edge length, in units of the mean edge length so that it blends with E_c.
struct LengthCost
{
    double unit = 1.0;  //!< divide lengths by this (the pipeline passes the mean edge length)
    double operator()(const Mesh& mesh, SmartHalfedgeHandle h) const;
};

//! E_cg = a E_c + (1 - a) E_g.
struct BlendCost
{
    CurvatureCost curvature;
    LengthCost length;
    double a = 0.5;  //!< weight of the curvature term, in [0, 1]
    double operator()(const Mesh& mesh, SmartHalfedgeHandle h) const;
};

//! Type-erased cost, for choosing a cost at run time (CLI, configuration).
using AnyCost = std::function<double(const Mesh&, SmartHalfedgeHandle)>;

//! Stage Z's per-vertex fields of the (uncut) mesh a cost is evaluated on, typed, each row
//! `v.idx()`: what a researcher's cost reads instead of looking properties up by name.
struct VesselFields
{
    const Eigen::MatrixX3d* direction = nullptr;  //!< unit vessel direction z, toward the inlet
    const Eigen::VectorXd* geodesic = nullptr;    //!< heat-method distance from the inlet
    //! harmonic longitudinal coordinate (harmonic_longitudinal() of cut_metrics.h): 0 on the
    //! inlet, on each outlet the mean geodesic distance of that loop; smooth across junctions
    const Eigen::VectorXd* longitudinal = nullptr;
    const Eigen::VectorXd* kmax = nullptr;  //!< |largest principal curvature|, 1 / mesh unit
    double mean_edge = 1.0;                 //!< mean edge length, mesh units
};

//! \brief A researcher's travel cost for CostOptions::custom (FlattenOptions::cost): any callable
//! `double(const Mesh&, SmartHalfedgeHandle, const VesselFields&) const`, or one without the
//! fields, `double(const Mesh&, SmartHalfedgeHandle) const` (as the built-in costs). It must
//! return a finite value >= 0; it is evaluated once per halfedge before the cuts are planned.
class CustomCost
{
    //! F takes the fields (else it must take the mesh and halfedge only).
    template <class F>
    static constexpr bool reads_fields =
        std::is_invocable_r_v<double, const F&, const Mesh&, SmartHalfedgeHandle,
                              const VesselFields&>;

public:
    CustomCost() = default;
    template <class F, std::enable_if_t<reads_fields<F> || std::is_invocable_r_v<
                                                               double, const F&, const Mesh&,
                                                               SmartHalfedgeHandle>,
                                        int> = 0>
    CustomCost(F cost)
    {
        if constexpr (reads_fields<F>)
            cost_ = std::move(cost);
        else
            cost_ = [cost = std::move(cost)](const Mesh& mesh, SmartHalfedgeHandle h,
                                             const VesselFields&) { return cost(mesh, h); };
    }
    explicit operator bool() const { return static_cast<bool>(cost_); }
    double operator()(const Mesh& mesh, SmartHalfedgeHandle h, const VesselFields& fields) const
    {
        return cost_(mesh, h, fields);
    }

private:
    std::function<double(const Mesh&, SmartHalfedgeHandle, const VesselFields&)> cost_;
};

//! The built-in travel costs (step 4).
enum class CostKind
{
    Curvature,  //!< E_c = 1 - <unit edge, z>
    Geodesic,   //!< E_g = edge length (in mean edge lengths)
    Blend,      //!< E_cg = a E_c + (1 - a) E_g
};

//! The travel cost flatten() puts on the cut graph's arcs (step 4).
struct CostOptions
{
    CostKind kind = CostKind::Curvature;  //!< the built-in cost (E_c: the paper's default)
    double blend = 0.5;  //!< `a` of E_cg with CostKind::Blend, in [0, 1]
    //! A researcher's own travel cost; when set it replaces `kind`. Called with the uncut mesh,
    //! each halfedge and stage Z's VesselFields (z, geodesic distance, harmonic coordinate,
    //! |k_max|, mean edge); the same fields are also the mesh's `prop::direction`,
    //! `prop::geodesic`, `prop::longitudinal` and `prop::kmax` properties.
    CustomCost custom;
    //! The camera position, if the cuts should keep behind the vessels seen from it (CLI
    //! `--viewpoint`, which also sets FarSideEndpoints): every halfedge's cost is multiplied by
    //! 1 + facing_weight x its facing (price_facing()), so that a cut runs on the far side of
    //! its vessel along its length, not only at its ends. None = costs as they are.
    std::optional<Eigen::Vector3d> viewpoint;
    //! The viewpoint taken from the mesh itself: flatten() sets `viewpoint` to
    //! face_on_viewpoint() of its input (the tree seen face-on, along its axis of least spread)
    //! and, unless CutPlanOptions::endpoints is given, FarSideEndpoints from there (CLI
    //! `--viewpoint face-on`). The cuts then lie behind the vessels in the tree's own face-on
    //! view and keep their side when the surface is remeshed; FlattenResult::viewpoint tells
    //! where it was. Not with `viewpoint`.
    bool face_on = false;
    //! How much dearer a halfedge on the wall facing the viewpoint is than one facing away,
    //! >= 0 (0 = the ends alone). The price trades the seam's far side against its winding: a
    //! smaller weight leaves cuts in front on branching trees, a larger one makes them wind
    //! more; 30 is where the real trees' cuts gained their far side and stayed natural
    //! (docs/results.md, "Cuts behind the vessels").
    double facing_weight = 30.0;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! \brief Multiply each halfedge's cost in \p weights by 1 + \p weight x its facing: the cosine of
//! the angle between the edge's normal (the mean of its faces' unit normals, outward) and the
//! direction from the edge's midpoint to \p viewpoint, 0 where the edge faces away. A cost of 0
//! stays 0. \throw InvalidInputError if \p weights has not one entry per halfedge, \p viewpoint is
//! not finite or \p weight is negative or not finite.
void price_facing(const Mesh& mesh, const Eigen::Vector3d& viewpoint, double weight,
                  HalfedgeWeights& weights);

//! \brief Evaluate a researcher's \p cost with stage Z's \p fields on every halfedge.
//! \throw InvalidInputError as evaluate_cost(), or if \p cost is empty.
HalfedgeWeights evaluate_cost(const Mesh& mesh, const CustomCost& cost, const VesselFields& fields);

//! \brief Evaluate \p cost on every halfedge (boundary halfedges included).
//! \return one weight per halfedge, indexed by `h.idx()`.
//! \throw InvalidInputError if the cost returns a negative or non-finite value.
template <class Cost>
HalfedgeWeights evaluate_cost(const Mesh& mesh, const Cost& cost);

//! \cond internal
void check_weight(double w, int halfedge);
//! \endcond

template <class Cost>
HalfedgeWeights evaluate_cost(const Mesh& mesh, const Cost& cost)
{
    static_assert(std::is_invocable_r_v<double, const Cost&, const Mesh&, SmartHalfedgeHandle>,
                  "a cut cost must be callable as double(const Mesh&, SmartHalfedgeHandle) const");
    HalfedgeWeights weights(mesh.n_halfedges());
    for (auto h : mesh.halfedges())
    {
        const double w = cost(mesh, h);
        check_weight(w, h.idx());
        weights[h.idx()] = w;
    }
    return weights;
}

}  // namespace vessel
