#pragma once
// Boundary-point choice (step 4 of the method): where on its loop a cut may start or end.

#include "vessel/cut/boundary.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace vessel {

//! \brief A boundary-point policy: the vertices of a boundary loop at which a cut may leave its
//! outlet (or, for the inlet, end). plan_cuts() joins the returned vertices to an imaginary
//! zero-cost node, as the paper joins the whole loop \cite eulzer_2021_automatic, so the cut
//! starts at the cheapest of them and passes no other vertex of its loop; a policy that returns
//! one vertex fixes the cut's end there.
//! Later cuts end on earlier cuts, not on a loop, so only the inlet and the outlets are asked.
//! Chosen like Layout: CutPlanOptions::endpoints holds any subclass.
class EndpointPolicy
{
public:
    virtual ~EndpointPolicy() = default;
    virtual std::string name() const = 0;
    //! \param loop_index index of \p loop in the loops passed to plan_cuts() (0 = the inlet,
    //! 1 = the largest outlet, ...).
    //! \return a non-empty subset of `loop.vertices` (plan_cuts() refuses anything else,
    //! naming the policy).
    virtual std::vector<VertexHandle> allowed(const Mesh& mesh, const BoundaryLoop& loop,
                                              std::size_t loop_index) const = 0;
};

//! The paper's choice (the default): every loop vertex, i.e. the cheapest point of the loop.
class ImaginaryNodeEndpoints : public EndpointPolicy
{
public:
    std::string name() const override { return "imaginary-node"; }
    std::vector<VertexHandle> allowed(const Mesh& mesh, const BoundaryLoop& loop,
                                      std::size_t loop_index) const override;
};

//! The loop vertex nearest a point: the cuts start and end on the side of each loop that faces
//! it, so that in a view from there the seams lie in front of the vessels (FarSideEndpoints
//! puts them behind).
class NearestPointEndpoints : public EndpointPolicy
{
public:
    //! \throw InvalidInputError if \p point is not finite.
    explicit NearestPointEndpoints(const Eigen::Vector3d& point);
    std::string name() const override { return "nearest-point"; }
    std::vector<VertexHandle> allowed(const Mesh& mesh, const BoundaryLoop& loop,
                                      std::size_t loop_index) const override;
    const Eigen::Vector3d& point() const { return point_; }

private:
    Eigen::Vector3d point_;
};

//! The loop vertex farthest from a point (the camera position, CLI `--viewpoint X Y Z`): the
//! cuts start and end on the side of each loop away from it, so that in a view from there the
//! seams lie behind the vessels and the wall in view is uncut in the map. The cut between its
//! ends follows the travel cost; far_side_fraction() (cut_metrics.h) measures how much of it
//! stays behind.
class FarSideEndpoints : public EndpointPolicy
{
public:
    //! \throw InvalidInputError if \p point is not finite.
    explicit FarSideEndpoints(const Eigen::Vector3d& point);
    std::string name() const override { return "far-side"; }
    std::vector<VertexHandle> allowed(const Mesh& mesh, const BoundaryLoop& loop,
                                      std::size_t loop_index) const override;
    const Eigen::Vector3d& point() const { return point_; }

private:
    Eigen::Vector3d point_;
};

//! A viewpoint from which \p mesh is seen face-on (CLI `--viewpoint face-on`,
//! CostOptions::face_on): on the axis of least spread of its surface (the eigenvector of the
//! area-weighted covariance of the face centroids with the least eigenvalue), two bounding-box
//! diagonals from the centroid, on the side where the axis's largest coordinate is positive
//! (the mesh's frame decides the side, as a mirror-symmetric surface has none of its own). It
//! depends on the shape and the frame, not on the triangulation, so cuts planned behind the
//! vessels from it (FarSideEndpoints) keep their side when the surface is remeshed, where the
//! cheapest point of a loop (ImaginaryNodeEndpoints) is decided by cost differences that on a
//! tube are noise (docs/results.md, "Cuts at two resolutions"). A surface whose two smallest
//! spreads are nearly equal (a straight tube) has no face-on axis of its own.
//! \throw InvalidInputError if the mesh has no face of positive area.
Eigen::Vector3d face_on_viewpoint(const Mesh& mesh);

}  // namespace vessel
