#pragma once

#include "vessel/check/validation.h"
#include "vessel/core/mesh.h"
#include "vessel/pipeline.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace vessel::test {

//! A flattened OBJ as vessel-flatten writes it: v = 3D input positions, vt = uv, f v/vt.
struct FlatObj
{
    std::vector<Eigen::Vector3d> v;
    std::vector<Eigen::Vector2d> vt;
    std::vector<std::array<int, 3>> f;   //!< 0-based indices into v
    std::vector<std::array<int, 3>> ft;  //!< 0-based indices into vt
};

//! Parse \p path; throws std::runtime_error on a malformed file.
FlatObj read_flat_obj(const std::string& path);

//! Independent topology and quality checks of a flat OBJ, computed from its own arrays.
struct FlatObjCheck
{
    long euler = 0;               //!< V - E + F of the (vt, ft) mesh
    int boundary_loops = 0;       //!< of the (vt, ft) mesh
    int flipped = 0;              //!< faces with non-positive signed uv area
    double area_ratio = 0;        //!< total uv area / total 3D area
    double mean_abs_log_area = 0;  //!< area-weighted
    int seam_loops_touched = 0;   //!< 3D boundary loops touched by seam vertices
    int loops_3d = 0;             //!< boundary loops of the (v, f) mesh
};

FlatObjCheck check_flat_obj(const FlatObj& obj);

//! The `int` vertex (or face) property \p name of \p mesh, indexed by `idx()`; throws
//! std::runtime_error if it is missing.
std::vector<int> int_vertex_property(const Mesh& mesh, const char* name);
std::vector<int> int_face_property(const Mesh& mesh, const char* name);

//! Whether one of \p result's notes contains \p text.
bool noted(const FlattenResult& result, const std::string& text);

//! Run a shell command; returns its exit status (0 = success).
int run(const std::string& command);

//! The JSON report of ../shared/tools/flatcheck.py (the independent check of a flattened map:
//! topology, flips, raster overlap fraction, area and angle distortion, seam alignment) on
//! \p flat_obj, flattened from \p input; written beside \p flat_obj. Throws
//! std::runtime_error if the script fails.
nlohmann::json flatcheck(const std::string& input, const std::string& flat_obj);

//! The JSON report of ../shared/tools/seamwinding.py (how far each piece of the seam between
//! junctions winds round its vessel) on \p flat_obj, flattened from \p input; written beside
//! \p flat_obj. Throws std::runtime_error if the script fails.
nlohmann::json seamwinding(const std::string& input, const std::string& flat_obj);

//! The message of the exception \p f throws, or "(no error)".
std::string error_of(const std::function<void()>& f);

//! The message with which make_tree_surface() refuses \p raw (an InvalidInputError), or "" if
//! it accepts it.
std::string refusal(const RawMesh& raw, const TreeSurfaceOptions& options = {});

//! True if \p text contains \p part.
inline bool contains(const std::string& text, const std::string& part)
{
    return text.find(part) != std::string::npos;
}

//! Path to a fresh temporary directory for one test.
std::string temp_dir(const std::string& name);

}  // namespace vessel::test
