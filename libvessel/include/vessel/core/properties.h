#pragma once

//! Names of the durable mesh properties libvessel stores. Vertex properties are copied to the
//! duplicates created when the mesh is cut (see cut.h), so values computed before cutting stay
//! available afterwards.

namespace vessel::prop {

//! `int` per vertex: index in the input file of the vertex a (possibly duplicated) vertex came
//! from; set when a file is loaded (see validation.h), copied to seam duplicates.
inline constexpr const char* input_index = "vessel:input_index";
//! `int` per face: index in the input file of the polygon a triangle came from (polygons with
//! more than 3 corners are split into several triangles); set when a file is loaded (see
//! validation.h). Cutting keeps faces, so cell data follow their faces through it.
inline constexpr const char* input_face = "vessel:input_face";
//! `int` per vertex: index, in the mesh before cutting, of the vertex a (possibly duplicated)
//! vertex came from; created by cut_along_edges() (see cut.h).
inline constexpr const char* origin = "vessel:origin";
//! `double` per vertex: heat-method geodesic distance from the inlet.
inline constexpr const char* geodesic = "vessel:geodesic";
//! `OpenMesh::Vec3d` per vertex: unit vessel direction z, pointing toward the root (inlet).
inline constexpr const char* direction = "vessel:direction";
//! `double` per vertex: harmonic longitudinal coordinate (harmonic_longitudinal() of
//! cut_metrics.h: 0 on the inlet, rising along every vessel), computed once in stage Z.
inline constexpr const char* longitudinal = "vessel:longitudinal";
//! `double` per vertex: maximal principal curvature magnitude (1 / local vessel radius).
inline constexpr const char* kmax = "vessel:kmax";
//! `OpenMesh::Vec2d` per vertex: flattened (u, v) coordinates.
inline constexpr const char* uv = "vessel:uv";

}  // namespace vessel::prop
