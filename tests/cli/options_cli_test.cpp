// vessel-flatten's presets; FlattenOptions::paper().
#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/meshes.h"
#include "vessel/pipeline.h"

#include <fstream>
#include <iterator>
#include <string>

using namespace vessel;
using vessel::test::run;
using vessel::test::temp_dir;

namespace {

const std::string kFlatten = VESSEL_FLATTEN_EXE;
const std::string kArtery = std::string(VESSEL_SHARED_DATA) + "/vampy/artery-coarse.ply";

std::string read_text(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

// Runs vessel-flatten with \p args; its stdout and stderr together, and its exit status.
std::pair<int, std::string> flatten_cli(const std::string& dir, const std::string& args)
{
    const std::string log = dir + "/log.txt";
    const int status = run(kFlatten + " " + args + " > " + log + " 2>&1");
    return {status, read_text(log)};
}

}  // namespace

TEST_CASE("pipeline: FlattenOptions::paper() is the paper's options set one by one")
{
    const Mesh mesh = test::test_tree_phantom(3);
    FlattenOptions explicit_options;
    explicit_options.refinement = Refinement::Arap;
    explicit_options.overlaps = OverlapPolicy::Keep;
    explicit_options.relief.max_cuts = 0;
    const FlattenResult paper = flatten(mesh, FlattenOptions::paper());
    const FlattenResult by_hand = flatten(mesh, explicit_options);
    CHECK(paper.uv == by_hand.uv);
    CHECK(paper.arap.iterations > 0);       // the paper's ARAP ran ...
    CHECK(paper.injective.iterations == 0);  // ... and no SLIM after it
    CHECK(paper.plan.relief.empty());
    CHECK(paper.uv != flatten(mesh).uv);  // the default is another method
}

TEST_CASE("cli: --preset paper writes the same OBJ bytes as the paper's options given one by one")
{
    const std::string dir = temp_dir("preset_paper");
    const auto [preset_status, preset_log] =
        flatten_cli(dir, kArtery + " -o " + dir + "/preset.obj --preset paper");
    REQUIRE_MESSAGE(preset_status == 0, preset_log);
    const auto [flags_status, flags_log] = flatten_cli(
        dir, kArtery + " -o " + dir + "/flags.obj --refine arap --overlaps keep --relief-cuts 0");
    REQUIRE_MESSAGE(flags_status == 0, flags_log);
    const std::string preset = read_text(dir + "/preset.obj");
    CHECK(preset.size() > 1000);
    CHECK(preset == read_text(dir + "/flags.obj"));
    REQUIRE(flatten_cli(dir, kArtery + " -o " + dir + "/default.obj").first == 0);
    CHECK(preset != read_text(dir + "/default.obj"));
    // A flag after the preset changes it: the paper's method with SLIM is another map.
    REQUIRE(flatten_cli(dir, kArtery + " -o " + dir + "/changed.obj --preset paper --refine "
                             "injective").first == 0);
    CHECK(preset != read_text(dir + "/changed.obj"));
}
