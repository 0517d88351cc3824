#include "support/checks.h"

#include "vessel/core/errors.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

namespace vessel::test {

FlatObj read_flat_obj(const std::string& path)
{
    std::ifstream in(path);
    if (!in)
        throw std::runtime_error("cannot open " + path);
    FlatObj obj;
    std::string line;
    while (std::getline(in, line))
    {
        std::istringstream s(line);
        std::string tag;
        s >> tag;
        if (tag == "v")
        {
            Eigen::Vector3d p;
            s >> p.x() >> p.y() >> p.z();
            obj.v.push_back(p);
        }
        else if (tag == "vt")
        {
            Eigen::Vector2d p;
            s >> p.x() >> p.y();
            obj.vt.push_back(p);
        }
        else if (tag == "f")
        {
            std::array<int, 3> f{}, ft{};
            for (int k = 0; k < 3; ++k)
            {
                std::string corner;
                s >> corner;
                const auto slash = corner.find('/');
                if (slash == std::string::npos)
                    throw std::runtime_error("face corner without vt in " + path);
                f[k] = std::stoi(corner.substr(0, slash)) - 1;
                ft[k] = std::stoi(corner.substr(slash + 1)) - 1;
            }
            obj.f.push_back(f);
            obj.ft.push_back(ft);
        }
    }
    return obj;
}

namespace {

// Boundary edges (directed as in their face) of a triangle list.
std::vector<std::pair<int, int>> boundary_edges(const std::vector<std::array<int, 3>>& faces)
{
    std::map<std::pair<int, int>, int> count;
    for (const auto& f : faces)
        for (int k = 0; k < 3; ++k)
            ++count[{std::min(f[k], f[(k + 1) % 3]), std::max(f[k], f[(k + 1) % 3])}];
    std::vector<std::pair<int, int>> out;
    for (const auto& f : faces)
        for (int k = 0; k < 3; ++k)
            if (count[{std::min(f[k], f[(k + 1) % 3]), std::max(f[k], f[(k + 1) % 3])}] == 1)
                out.emplace_back(f[k], f[(k + 1) % 3]);
    return out;
}

// Loops of a set of directed boundary edges, as vertex sets.
std::vector<std::set<int>> loops_of(const std::vector<std::pair<int, int>>& edges)
{
    std::map<int, int> next;
    for (auto [a, b] : edges)
        next[a] = b;
    std::set<int> seen;
    std::vector<std::set<int>> loops;
    for (auto [a, b] : edges)
    {
        if (seen.count(a))
            continue;
        std::set<int>& loop = loops.emplace_back();
        int v = a;
        while (!seen.count(v) && next.count(v))
        {
            seen.insert(v);
            loop.insert(v);
            v = next[v];
        }
    }
    return loops;
}

}  // namespace

FlatObjCheck check_flat_obj(const FlatObj& obj)
{
    FlatObjCheck c;
    std::set<std::pair<int, int>> edges;
    for (const auto& f : obj.ft)
        for (int k = 0; k < 3; ++k)
            edges.insert({std::min(f[k], f[(k + 1) % 3]), std::max(f[k], f[(k + 1) % 3])});
    std::set<int> used;
    for (const auto& f : obj.ft)
        used.insert(f.begin(), f.end());
    c.euler = static_cast<long>(used.size()) - static_cast<long>(edges.size()) +
              static_cast<long>(obj.ft.size());
    c.boundary_loops = static_cast<int>(loops_of(boundary_edges(obj.ft)).size());

    double a3 = 0, a2 = 0, log_sum = 0;
    for (std::size_t i = 0; i < obj.f.size(); ++i)
    {
        const auto& f = obj.f[i];
        const auto& t = obj.ft[i];
        const double area3 =
            0.5 * (obj.v[f[1]] - obj.v[f[0]]).cross(obj.v[f[2]] - obj.v[f[0]]).norm();
        const Eigen::Vector2d e1 = obj.vt[t[1]] - obj.vt[t[0]], e2 = obj.vt[t[2]] - obj.vt[t[0]];
        const double area2 = 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
        a3 += area3;
        a2 += area2;
        if (area2 <= 0)
            ++c.flipped;
        else
            log_sum += area3 * std::abs(std::log(area2 / area3));
    }
    c.area_ratio = a2 / a3;
    c.mean_abs_log_area = log_sum / a3;

    // Seam vertices: 3D vertices used with more than one vt.
    std::map<int, std::set<int>> uvs_of;
    for (std::size_t i = 0; i < obj.f.size(); ++i)
        for (int k = 0; k < 3; ++k)
            uvs_of[obj.f[i][k]].insert(obj.ft[i][k]);
    const auto loops3 = loops_of(boundary_edges(obj.f));
    c.loops_3d = static_cast<int>(loops3.size());
    for (const auto& loop : loops3)
        for (int v : loop)
            if (uvs_of[v].size() > 1)
            {
                ++c.seam_loops_touched;
                break;
            }
    return c;
}

bool noted(const FlattenResult& result, const std::string& text)
{
    return std::any_of(result.notes.begin(), result.notes.end(), [&](const std::string& note) {
        return note.find(text) != std::string::npos;
    });
}

int run(const std::string& command)
{
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

namespace {

// The JSON that ../shared/tools/<tool>.py prints for \p flat_obj (from \p input), written beside
// it.
nlohmann::json shared_tool(const std::string& tool, const std::string& input,
                           const std::string& flat_obj, const std::string& flags)
{
    const std::string out = flat_obj + "." + tool + ".json";
    if (run("/usr/bin/python3 " + std::string(VESSEL_SHARED_TOOLS) + "/" + tool + ".py " + input +
            " " + flat_obj + flags + " > " + out) != 0)
        throw std::runtime_error(tool + ".py failed on " + flat_obj + " (from " + input + ")");
    return nlohmann::json::parse(std::ifstream(out));
}

}  // namespace

nlohmann::json flatcheck(const std::string& input, const std::string& flat_obj)
{
    return shared_tool("flatcheck", input, flat_obj, " --json");
}

nlohmann::json seamwinding(const std::string& input, const std::string& flat_obj)
{
    return shared_tool("seamwinding", input, flat_obj, "");
}

std::string temp_dir(const std::string& name)
{
    // Per process: several checkouts of the project run their suites on one machine, and a
    // shared /tmp/vessel_test_<name> let one run's batch outputs be compared with another's.
    const auto dir = std::filesystem::temp_directory_path() /
                     ("vessel_test_" + std::to_string(::getpid()) + "_" + name);
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir.string();
}

namespace {

template <class Handle, class Range>
std::vector<int> int_property(const Mesh& mesh, const char* name, Range elements)
{
    typename OpenMesh::HandleToPropHandle<Handle, int>::type h;
    if (!mesh.get_property_handle(h, name))
        throw std::runtime_error(std::string("mesh has no property ") + name);
    std::vector<int> out;
    for (auto e : elements)
        out.push_back(mesh.property(h, e));
    return out;
}

}  // namespace

std::vector<int> int_vertex_property(const Mesh& mesh, const char* name)
{
    return int_property<OpenMesh::VertexHandle>(mesh, name, mesh.vertices());
}

std::vector<int> int_face_property(const Mesh& mesh, const char* name)
{
    return int_property<OpenMesh::FaceHandle>(mesh, name, mesh.faces());
}

std::string error_of(const std::function<void()>& f)
{
    try
    {
        f();
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
    return "(no error)";
}

std::string refusal(const RawMesh& raw, const TreeSurfaceOptions& options)
{
    try
    {
        make_tree_surface(raw, options);
    }
    catch (const InvalidInputError& e)
    {
        return e.what();
    }
    return "";
}

}  // namespace vessel::test
