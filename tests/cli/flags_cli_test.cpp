// The custom-cost example's cuts against the default's.
#include <doctest/doctest.h>

#include "support/files.h"
#include "support/checks.h"
#include "support/png.h"
#include "vessel/io/io.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

using vessel::test::contains;
using vessel::test::read_bytes;
using vessel::test::run;
using vessel::test::temp_dir;

namespace {

const std::string kFlatten = VESSEL_FLATTEN_EXE;
const std::string kData = VESSEL_SHARED_DATA;
const std::string kArtery = kData + "/vampy/artery-coarse.ply";

// The seam of a flat OBJ: the 3D edges (vertex pairs, smaller first) whose two faces give them
// different uv corners, read from the file's own arrays.
std::set<std::pair<int, int>> seam_edges(const vessel::test::FlatObj& obj)
{
    std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> corners;
    for (std::size_t f = 0; f < obj.f.size(); ++f)
        for (int k = 0; k < 3; ++k)
        {
            int a = obj.f[f][k], b = obj.f[f][(k + 1) % 3];
            int ta = obj.ft[f][k], tb = obj.ft[f][(k + 1) % 3];
            if (a > b)
            {
                std::swap(a, b);
                std::swap(ta, tb);
            }
            corners[{a, b}].emplace_back(ta, tb);
        }
    std::set<std::pair<int, int>> seam;
    for (const auto& [edge, uv] : corners)
        if (uv.size() == 2 && uv[0] != uv[1])
            seam.insert(edge);
    return seam;
}

double seam_length(const vessel::test::FlatObj& obj, const std::set<std::pair<int, int>>& seam)
{
    double length = 0.0;
    for (const auto& [a, b] : seam)
        length += (obj.v[a] - obj.v[b]).norm();
    return length;
}

}  // namespace

TEST_CASE("cli: the custom-cost example's cuts differ from the default's on a real artery")
{
    // tools/examples/custom_cost.cpp: a direction term plus a penalty for crossing high
    // curvature, given as FlattenOptions::custom_cost.
    // Its own printout counts the default seam edges it moved; here the two seams are read from
    // the written OBJs (the example's, and vessel-flatten's with default options) and compared.
    const std::string dir = temp_dir("custom_cost_example");
    const std::string custom_obj = dir + "/custom.obj", default_obj = dir + "/default.obj";
    REQUIRE(run(std::string(VESSEL_CUSTOM_COST_EXE) + " " + kArtery + " " + custom_obj + " > " +
                dir + "/out.txt") == 0);
    REQUIRE(run(kFlatten + " " + kArtery + " -o " + default_obj + " -q --refine none") == 0);
    const auto custom = vessel::test::read_flat_obj(custom_obj);
    const auto by_default = vessel::test::read_flat_obj(default_obj);
    for (const auto* obj : {&custom, &by_default})
    {
        const auto c = vessel::test::check_flat_obj(*obj);
        CHECK(c.euler == 1);  // a disk, cut open to the inlet and both outlets
        CHECK(c.boundary_loops == 1);
        CHECK(c.seam_loops_touched == 3);
    }
    const auto custom_seam = seam_edges(custom), default_seam = seam_edges(by_default);
    std::vector<std::pair<int, int>> shared;
    std::set_intersection(custom_seam.begin(), custom_seam.end(), default_seam.begin(),
                          default_seam.end(), std::back_inserter(shared));
    const std::size_t moved = default_seam.size() - shared.size();
    MESSAGE("seam edges: custom " << custom_seam.size() << " (" << seam_length(custom, custom_seam)
                                  << " mm), default " << default_seam.size() << " ("
                                  << seam_length(by_default, default_seam) << " mm), shared "
                                  << shared.size());
    REQUIRE(!default_seam.empty());
    // The cost changed the cuts, not one edge of them: at least a quarter of the default's
    // seam edges are not in the custom seam.
    CHECK(moved * 4 >= default_seam.size());
    // The example's own count is this one (its default cuts are vessel-flatten's).
    const std::string out = read_bytes(dir + "/out.txt");
    std::smatch m;
    REQUIRE(std::regex_search(out, m, std::regex("default (\\d+), shared (\\d+); the custom cost "
                                                 "moved (\\d+) of the default's seam edges")));
    CHECK(std::stoul(m[1]) == default_seam.size());
    CHECK(std::stoul(m[2]) == shared.size());
    CHECK(std::stoul(m[3]) == moved);
}
