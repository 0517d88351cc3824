// vessel-flatten --batch over every mesh in ../shared/data/real (valid trees and bad inputs),
// interrupted half-way and resumed. Labelled `slow` (it flattens the 277k-triangle tree twice);
// scripts/test.sh runs it.
#include <doctest/doctest.h>

#include "support/checks.h"

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <string>

namespace fs = std::filesystem;
namespace vt = vessel::test;

namespace {

const std::string kFlatten = VESSEL_FLATTEN_EXE;
const std::string kData = VESSEL_SHARED_DATA;

std::string read_file(const fs::path& path)
{
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

nlohmann::json summary_of(const std::string& dir)
{
    return nlohmann::json::parse(read_file(dir + "/summary.json"));
}

// The per-mesh report without its timings (which differ from run to run).
nlohmann::json report_without_timings(const fs::path& path)
{
    nlohmann::json j = nlohmann::json::parse(read_file(path));
    j.erase("timings");
    return j;
}

// The first words of the documented message (docs/bad-input.md) for each bad real mesh.
const std::map<std::string, std::string> kRefusals = {
    {"aorta-surface.ply", "the surface is closed (no open ends)"},
    {"aorta-surface.vtp", "the surface is closed (no open ends)"},
    {"aorta-surface-subdiv-207k.vtp", "the surface is closed (no open ends)"},
    {"demo-model-capped.vtp", "the surface is closed (no open ends)"},
    {"aorta-surface-branch-split.vtp",
     "coincident boundary loops: 344 boundary vertices lie exactly on other boundary vertices"},
    {"aorta-surface-subdiv-207k.ply", "the surface is closed (no open ends)"},
    {"demo-model-capped.ply", "the surface is closed (no open ends)"},
    {"carotid-bif-capped.ply", "the surface is closed (no open ends)"},
    {"carotid-bif-capped.stl", "the surface is closed (no open ends)"},
    {"aorta-surface-branch-split.ply",
     "coincident boundary loops: 344 boundary vertices lie exactly on other boundary vertices"},
    {"aneurysm3d.ply", "1 duplicate face (same three vertices as another face)"},
    {"aneurysm3d.stl", "1 duplicate face (same three vertices as another face)"},
};

}  // namespace

TEST_SUITE("slow")
{
TEST_CASE("batch: every real mesh gets a row and an interrupted then resumed run gives the same outputs")
{
    REQUIRE(fs::is_directory(kData));
    // The sanitizer build (scripts/sanitize.sh) sets VESSEL_BATCH_MAX_BYTES to leave out the
    // largest files (several minutes each under ASan); the normal build takes them all.
    const char* max_bytes_env = std::getenv("VESSEL_BATCH_MAX_BYTES");
    const std::uintmax_t max_bytes =
        max_bytes_env ? std::stoull(max_bytes_env) : std::numeric_limits<std::uintmax_t>::max();
    const std::string dir = vt::temp_dir("batch_real");
    std::set<std::string> meshes;  // file names of the inputs the batch must take
    std::ofstream list(dir + "/inputs.txt");
    for (const auto& e : fs::recursive_directory_iterator(kData))
    {
        const std::string ext = e.path().extension().string();
        if (e.is_regular_file() && (ext == ".ply" || ext == ".stl" || ext == ".obj" ||
                                    ext == ".off" || ext == ".vtp" || ext == ".vtk"))
        {
            if (fs::file_size(e.path()) > max_bytes)
                continue;
            meshes.insert(e.path().filename().string());
            list << fs::absolute(e.path()).string() << "\n";
        }
    }
    list.close();
    auto refusals = kRefusals;
    if (max_bytes_env)
    {
        MESSAGE("VESSEL_BATCH_MAX_BYTES=" << max_bytes << ": " << meshes.size() << " files");
        for (auto it = refusals.begin(); it != refusals.end();)
            it = meshes.count(it->first) ? std::next(it) : refusals.erase(it);
        REQUIRE(meshes.size() >= 10);
    }
    else
        REQUIRE(meshes.size() >= 27);
    const std::string inputs = max_bytes_env ? dir + "/inputs.txt" : kData;
    const std::string batch = kFlatten + " --batch " + inputs + " --jobs 2 --quiet -o ";

    // 1. Uninterrupted.
    CHECK(vt::run(batch + dir + "/fresh 2> " + dir + "/fresh.err") == 1);  // some are refused
    const nlohmann::json fresh = summary_of(dir + "/fresh");
    REQUIRE(fresh["files"].size() == meshes.size());
    int lines = 0;
    {
        std::ifstream csv(dir + "/fresh/summary.csv");
        for (std::string line; std::getline(csv, line);)
            ++lines;
    }
    CHECK(lines == static_cast<int>(meshes.size()) + 1);  // header + one row per file
    std::map<std::string, std::string> output_of;         // file name -> output base name
    for (const auto& row : fresh["files"])
    {
        const fs::path file = row["file"].get<std::string>();
        const std::string name = file.filename().string();
        CAPTURE(name);
        CHECK(meshes.count(name) == 1);
        const auto refusal = refusals.find(name);
        if (refusal == refusals.end())
        {
            CHECK(row["status"] == "ok");
            CHECK(row["flipped"] == 0);
            // Same-stem inputs (x.ply, x.stl) are named by file name.
            const std::string base = fs::exists(dir + "/fresh/" + name + ".obj")
                                         ? name
                                         : file.stem().string();
            output_of[name] = base;
            const auto c = vt::check_flat_obj(vt::read_flat_obj(dir + "/fresh/" + base + ".obj"));
            CHECK(c.euler == 1);
            CHECK(c.flipped == 0);
        }
        else
        {
            CHECK(row["status"] == "refused");
            CHECK_MESSAGE(row["message"].get<std::string>().find(refusal->second) !=
                              std::string::npos,
                          row["message"]);
        }
    }
    CHECK(fresh["ok"] == static_cast<int>(meshes.size() - refusals.size()));
    CHECK(fresh["refused"] == static_cast<int>(refusals.size()));

    // 2. Interrupted (SIGINT) once 4 meshes are written, then resumed.
    const std::string out = dir + "/out";
    fs::create_directories(out);
    const int status =
        vt::run("sh -c '" + batch + out + " 2> " + dir + "/out.err & pid=$!; "
            "while kill -0 $pid 2>/dev/null && [ $(ls " + out + " | grep -c \"\\.obj$\") -lt 4 ]; "
            "do sleep 0.1; done; kill -INT $pid; wait $pid'");
    CHECK(status == 130);
    const nlohmann::json interrupted = summary_of(out);
    CHECK(interrupted["interrupted"].get<int>() > 0);
    CHECK(interrupted["ok"].get<int>() >= 4);
    for (const auto& e : fs::directory_iterator(out))
        CHECK_MESSAGE(e.path().extension() != ".tmp", e.path());
    CHECK(vt::run(batch + out + " --resume 2> " + dir + "/resume.err") == 1);
    const nlohmann::json resumed = summary_of(out);
    CHECK(resumed["ok"] == fresh["ok"]);
    CHECK(resumed["refused"] == fresh["refused"]);
    CHECK(resumed["interrupted"] == 0);
    int kept = 0;
    for (const auto& row : resumed["files"])
        kept += row["resumed"].get<bool>();
    CHECK(kept == interrupted["ok"].get<int>());
    for (const auto& [name, base] : output_of)
    {
        CAPTURE(name);
        const std::string a = read_file(dir + "/fresh/" + base + ".obj");
        CHECK(!a.empty());
        CHECK(a == read_file(out + "/" + base + ".obj"));
        CHECK(report_without_timings(dir + "/fresh/" + base + ".json") ==
              report_without_timings(out + "/" + base + ".json"));
    }
}
}
