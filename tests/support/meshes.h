#pragma once

#include "vessel/core/mesh.h"
#include "vessel/cut/cut_plan.h"
#include "vessel/io/io.h"
#include "vessel/io/vtk_io.h"
#include "vessel/phantom/phantom.h"

#include <Eigen/Geometry>

#include <functional>

#include <cstdint>
#include <string>
#include <vector>

namespace vessel::test {

//! \brief Open cylinder of radius \p radius along +z, cut open along the x-z seam into a disk.
//! (n_around + 1) x (n_along + 1) vertices; vertex (i, j), i around and j along, has index
//! j * (n_around + 1) + i. Columns i = 0 and i = n_around coincide in 3D but are distinct
//! vertices, so the mesh has a single boundary loop. Faces are counter-clockwise seen from outside.
Mesh cut_cylinder(double radius, double length, int n_around, int n_along);

//! The mesh of the real tree surface \p relative (a path under ../shared/data/real, e.g.
//! "vampy/artery.ply") as load_tree_surface() makes it; throws std::invalid_argument naming the
//! file where it is missing.
Mesh shared_tree_mesh(const std::string& relative);

//! The seeded tree phantom the overlap tests share: \p outlets outlets, seed = outlets, edge
//! length 0.75 (coarser than the default 0.5, to keep the tests short).
Mesh test_tree_phantom(int outlets);
//! As test_tree_phantom(outlets), with another seed (and edge length).
Mesh test_tree_phantom(int outlets, std::uint32_t seed, double edge_length = 0.75);

//! How a cut turns round its vessel by a phantom's exact angle, degrees: \p angle (radians, of a
//! point) unwrapped along the path from the outlet.
struct PathTurn
{
    double winding_deg = 0.0;  //!< signed, first vertex to last
    double span_deg = 0.0;     //!< largest minus smallest unwrapped angle
};
PathTurn path_turn(const Mesh& mesh, const CutPath& path,
                   const std::function<double(const Eigen::Vector3d&)>& angle);

//! path_turn() round a helical_tube(), in the phantom's own frame (helical_tube_angle()).
PathTurn helix_turn(const HelicalTubeOptions& options, const Mesh& mesh, const CutPath& path);

//! \brief Flat n x n quad grid of side \p size split into triangles, mapped into 3D by \p pose
//! (a rigid motion). Vertex (i, j) has index j * (n + 1) + i and planar position
//! (size * i / n, size * j / n) before the motion.
Mesh posed_grid(double size, int n, const Eigen::Isometry3d& pose);

//! \brief posed_grid() with the identity pose and a Gaussian bump of height \p height in z at the
//! centre (a non-developable disk). Vertex (i, j) has index j * (n + 1) + i.
Mesh bumped_grid(double size, int n, double height);

//! \brief Open tube as a file would hold it: \p around x (\p along + 1) points (ring j, point i
//! at index j * around + i, rings twisted by half a step), the first ring of faces quads, the
//! others triangles. Unit radius, rings 0.4 apart.
RawMesh tube_with_quads(int around, int along);

//! \brief tube_with_quads() with arrays of every kind: point `pressure` (Float32), `velocity`
//! (Float64, 3 components), `GlobalNodeID` (Int32); cell `GlobalElementID` (Int64, values past
//! 2^32) and `thickness` (Float64).
PolyData tube_with_fields(int around, int along);

//! The (x, y) of a mesh lying in the z = 0 plane (e.g. plane_grid()) as its map: |V| x 2.
Eigen::MatrixX2d planar_uv(const Mesh& mesh);

//! Signed area of every face of the map \p uv (|V| x 2, row `v.idx()`), indexed by `f.idx()`;
//! negative means the triangle is flipped.
Eigen::VectorXd uv_signed_areas(const Mesh& mesh, const Eigen::MatrixX2d& uv);

//! Number of faces with non-positive signed area in \p uv.
int count_flips(const Mesh& mesh, const Eigen::MatrixX2d& uv);

//! Largest |l_2D / l_3D - 1| over all edges.
double max_edge_length_error(const Mesh& mesh, const Eigen::MatrixX2d& uv);

//! Vertices on a boundary loop, in index order.
std::vector<VertexHandle> boundary_vertices(const Mesh& mesh);

//! \brief open_cylinder(1, 4, 12, 6) (7 rings of 12 vertices, 144 faces) cut at its middle ring
//! (ring 3, vertices 36-47): the faces above it use copies of that ring (vertices 84-95, same
//! positions), so two pieces touch along coincident boundary loops.
RawMesh split_tube();

//! \brief A blind-ended vessel: an open tube of radius \p radius from z = 0 to \p length
//! (\p n_around x \p n_along quads), closed at the top by a hemispherical dome of \p n_cap
//! rings and a pole; its one open end (z = 0) is its only boundary loop. Normals outward.
RawMesh blind_tube(double radius, double length, int n_around, int n_along, int n_cap);

//! \brief \p mesh with every boundary loop except loop \p keep (boundary_loops() order) closed
//! by a fan around the loop's centroid, as segmentations leave caps on vessel ends.
RawMesh cap_loops_except(const Mesh& mesh, int keep);

//! \brief open_cylinder(1, n_along * 2 pi / n_around, n_around, n_along) (near-equilateral
//! triangles) with \p holes of its faces removed: each a one-triangle hole (a boundary loop of 3
//! edges) whose vertices are off the rims and off every other hole's vertices and their
//! neighbours, spread along the tube; throws std::invalid_argument if they do not fit.
RawMesh tube_with_holes(int n_around, int n_along, int holes);

//! \brief open_cylinder(1, 4, 12, 6) without two faces off the rims that share exactly one
//! vertex: two one-triangle holes touching at that vertex (a non-manifold vertex).
RawMesh tube_with_touching_holes();

//! A Moebius strip: \p n quads around a circle of radius 1, width \p width, half a twist.
RawMesh moebius_strip(int n, double width);

}  // namespace vessel::test
