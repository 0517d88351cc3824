#include "flat_obj.h"

#include "vessel/core/errors.h"
#include "vessel/core/properties.h"

#include <algorithm>
#include <array>
#include <fstream>
#include <map>
#include <sstream>

namespace vessel::cli {
namespace {

[[noreturn]] void bad(const std::string& path, int line, const std::string& what)
{
    throw InvalidInputError(path + ":" + std::to_string(line) + ": " + what +
                            "; expected the seam form vessel-flatten writes (f v/vt v/vt v/vt)");
}

//! Splits the boundary cycle(s) of the cut mesh into runs of opening edges (see FlatObj::loops).
std::vector<BoundaryLoop> openings(const Mesh& mesh)
{
    OpenMesh::VPropHandleT<int> input;
    mesh.get_property_handle(input, prop::input_index);
    auto key = [&](SmartHalfedgeHandle h) {
        return std::minmax(mesh.property(input, h.from()), mesh.property(input, h.to()));
    };
    std::map<std::pair<int, int>, int> uses;
    for (auto h : mesh.halfedges())
        if (h.is_boundary())
            ++uses[key(h)];
    std::vector<char> seen(mesh.n_halfedges(), 0);
    std::vector<BoundaryLoop> loops;
    for (auto start : mesh.halfedges())
    {
        // Walk each boundary cycle from a seam edge so that no run wraps around the start.
        if (!start.is_boundary() || seen[start.idx()] || uses[key(start)] != 2)
            continue;
        BoundaryLoop run;
        for (auto h = start; !seen[h.idx()]; h = h.next())
        {
            seen[h.idx()] = 1;
            if (uses[key(h)] == 1)
            {
                run.halfedges.push_back(h);
                run.vertices.push_back(h.from());
                run.arc_length += mesh.calc_edge_length(h);
            }
            else if (!run.halfedges.empty())
            {
                loops.push_back(std::move(run));
                run = {};
            }
        }
        if (!run.halfedges.empty())
            loops.push_back(std::move(run));
    }
    for (auto& loop : loops)
    {
        for (auto v : loop.vertices)
            loop.centroid += to_eigen(mesh.point(v));
        loop.centroid /= static_cast<double>(loop.vertices.size());
    }
    std::stable_sort(loops.begin(), loops.end(), [](const BoundaryLoop& a, const BoundaryLoop& b) {
        return a.arc_length > b.arc_length;
    });
    return loops;
}

}  // namespace

FlatObj read_flat_obj(const std::string& path)
{
    std::ifstream in(path);
    if (!in)
        throw IoError("cannot open " + path);
    std::vector<Eigen::Vector3d> points;
    std::vector<Eigen::Vector2d> uvs;
    std::vector<std::array<std::pair<int, int>, 3>> faces;
    std::string line;
    for (int n = 1; std::getline(in, line); ++n)
    {
        std::istringstream s(line);
        std::string tag;
        s >> tag;
        if (tag == "v")
        {
            Eigen::Vector3d p;
            if (!(s >> p.x() >> p.y() >> p.z()))
                bad(path, n, "a v line needs 3 numbers");
            points.push_back(p);
        }
        else if (tag == "vt")
        {
            Eigen::Vector2d t;
            if (!(s >> t.x() >> t.y()))
                bad(path, n, "a vt line needs 2 numbers");
            uvs.push_back(t);
        }
        else if (tag == "f")
        {
            std::array<std::pair<int, int>, 3> f;
            std::string corner;
            int k = 0;
            for (; s >> corner; ++k)
            {
                int v = 0, t = 0;
                char slash = 0;
                std::istringstream c(corner);
                if (k >= 3 || !(c >> v >> slash >> t) || slash != '/')
                    bad(path, n, "a face must be a triangle of v/vt corners");
                f[k] = {v - 1, t - 1};
            }
            if (k != 3)
                bad(path, n, "a face must be a triangle");
            faces.push_back(f);
        }
    }
    if (faces.empty() || uvs.empty())
        bad(path, 0, "no faces or no vt lines");
    FlatObj flat;
    std::vector<int> input(uvs.size(), -1);
    for (const auto& f : faces)
        for (const auto& [v, t] : f)
        {
            if (v < 0 || v >= static_cast<int>(points.size()) || t < 0 ||
                t >= static_cast<int>(uvs.size()))
                bad(path, 0, "a face corner indexes past the v or vt lines");
            if (input[t] != -1 && input[t] != v)
                bad(path, 0, "vt " + std::to_string(t + 1) + " is used with two positions");
            input[t] = v;
        }
    auto index = OpenMesh::VProp<int>(flat.mesh, prop::input_index);
    flat.uv.resize(static_cast<Eigen::Index>(uvs.size()), 2);
    for (std::size_t t = 0; t < uvs.size(); ++t)
    {
        // An unused vt still gets a vertex so that row t of uv stays vertex t.
        const auto vh = flat.mesh.add_vertex(
            to_openmesh(input[t] >= 0 ? points[input[t]] : Eigen::Vector3d::Zero()));
        index[vh] = input[t];
        flat.uv.row(static_cast<Eigen::Index>(t)) = uvs[t].transpose();
    }
    for (const auto& f : faces)
        if (!flat.mesh
                 .add_face(VertexHandle(f[0].second), VertexHandle(f[1].second),
                           VertexHandle(f[2].second))
                 .is_valid())
            bad(path, 0, "the faces over the vt vertices are not a manifold mesh");
    flat.loops = openings(flat.mesh);
    return flat;
}

}  // namespace vessel::cli
