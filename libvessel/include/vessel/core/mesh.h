#pragma once

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Utils/PropertyManager.hh>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <vector>

namespace vessel {

//! OpenMesh traits: double precision points and normals, 2D texture coordinates.
struct MeshTraits : public OpenMesh::DefaultTraits
{
    using Point = OpenMesh::Vec3d;
    using Normal = OpenMesh::Vec3d;
    using TexCoord2D = OpenMesh::Vec2d;
};

//! The triangle mesh type used everywhere in libvessel.
using Mesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

using OpenMesh::EdgeHandle;
using OpenMesh::FaceHandle;
using OpenMesh::HalfedgeHandle;
using OpenMesh::SmartEdgeHandle;
using OpenMesh::SmartFaceHandle;
using OpenMesh::SmartHalfedgeHandle;
using OpenMesh::SmartVertexHandle;
using OpenMesh::VertexHandle;

//! One value per halfedge, indexed by `h.idx()`.
using HalfedgeWeights = std::vector<double>;

inline Eigen::Vector3d to_eigen(const OpenMesh::Vec3d& p) { return {p[0], p[1], p[2]}; }
inline OpenMesh::Vec3d to_openmesh(const Eigen::Vector3d& p) { return {p[0], p[1], p[2]}; }

//! Vertex positions as a |V| x 3 matrix, row `v.idx()`.
Eigen::MatrixX3d vertex_positions(const Mesh& mesh);

//! Face corner indices as a |F| x 3 matrix, row `f.idx()`, counter-clockwise.
Eigen::MatrixX3i face_indices(const Mesh& mesh);

//! Mean edge length (0 for a mesh without edges).
double mean_edge_length(const Mesh& mesh);

//! Area of every face, indexed by `f.idx()`.
Eigen::VectorXd face_areas(const Mesh& mesh);

}  // namespace vessel
