// vessel-flatten's presets, help, --config and progress lines; FlattenOptions::paper().
#include <doctest/doctest.h>

#include "support/files.h"
#include "support/checks.h"
#include "support/meshes.h"
#include "vessel/pipeline.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

using namespace vessel;
using vessel::test::read_bytes;
using vessel::test::run;
using vessel::test::temp_dir;

namespace {

const std::string kFlatten = VESSEL_FLATTEN_EXE;
const std::string kArtery = std::string(VESSEL_SHARED_DATA) + "/vampy/artery-coarse.ply";

// Runs vessel-flatten with \p args; its stdout and stderr together, and its exit status.
std::pair<int, std::string> flatten_cli(const std::string& dir, const std::string& args)
{
    const std::string log = dir + "/log.txt";
    const int status = run(kFlatten + " " + args + " > " + log + " 2>&1");
    return {status, read_bytes(log)};
}

int count_lines(const std::string& text)
{
    return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
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
    CHECK(paper.arap.iterations > 0);        // the paper's ARAP ran ...
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
    const std::string preset = read_bytes(dir + "/preset.obj");
    CHECK(preset.size() > 1000);
    CHECK(preset == read_bytes(dir + "/flags.obj"));
    REQUIRE(flatten_cli(dir, kArtery + " -o " + dir + "/default.obj").first == 0);
    CHECK(preset != read_bytes(dir + "/default.obj"));
    // A flag after the preset changes it: the paper's method with SLIM is another map.
    const std::string changed = " -o " + dir + "/changed.obj --preset paper --refine injective";
    REQUIRE(flatten_cli(dir, kArtery + changed).first == 0);
    CHECK(preset != read_bytes(dir + "/changed.obj"));
}

TEST_CASE("cli: --config reads a JSON set of options and the command line wins over it")
{
    const std::string dir = temp_dir("config");
    REQUIRE(flatten_cli(dir, kArtery + " -o " + dir + "/preset.obj --preset paper").first == 0);
    const std::string preset = read_bytes(dir + "/preset.obj");

    std::ofstream(dir + "/paper.json") << R"({"preset": "paper", "quiet": true})";
    const auto [status, log] =
        flatten_cli(dir, kArtery + " -o " + dir + "/config.obj --config " + dir + "/paper.json");
    REQUIRE_MESSAGE(status == 0, log);
    CHECK(log.empty());  // "quiet": true
    CHECK(read_bytes(dir + "/config.obj") == preset);

    // The file asks for 5 relief cuts and SLIM; the command line for the paper's none and ARAP.
    std::ofstream(dir + "/more.json")
        << R"({"preset": "paper", "relief-cuts": 5, "refine": "injective"})";
    REQUIRE(flatten_cli(dir, kArtery + " -o " + dir + "/wins.obj --config " + dir +
                                 "/more.json --relief-cuts 0 --refine arap")
                .first == 0);
    CHECK(read_bytes(dir + "/wins.obj") == preset);

    std::ofstream(dir + "/typo.json") << R"({"relief-cut": 1})";
    const auto [typo_status, typo_log] =
        flatten_cli(dir, kArtery + " -o " + dir + "/typo.obj --config " + dir + "/typo.json");
    CHECK(typo_status == 1);
    CHECK(typo_log.find("relief-cut") != std::string::npos);
    std::ofstream(dir + "/broken.json") << R"({"preset": )";
    const auto [broken_status, broken_log] =
        flatten_cli(dir, kArtery + " -o " + dir + "/broken.obj --config " + dir + "/broken.json");
    CHECK(broken_status == 1);
    CHECK(broken_log.find("JSON") != std::string::npos);
}

TEST_CASE("cli: --help fits one screen in groups, --help-all adds the tuning options, --version")
{
    const std::string dir = temp_dir("help");
    const auto [status, help] = flatten_cli(dir, "--help");
    CHECK(status == 0);
    CHECK(count_lines(help) <= 40);
    for (const char* shown : {"Input and output:", "Fields and images:", "Cut:", "Map:", "--preset",
                              "--config", "--image", "--viewpoint", "--quiet"})
        CHECK_MESSAGE(help.find(shown) != std::string::npos, shown);
    CHECK(help.find("--slim-iterations") == std::string::npos);

    const auto [all_status, all] = flatten_cli(dir, "--help-all");
    CHECK(all_status == 0);
    CHECK(count_lines(all) > count_lines(help));
    for (const char* shown : {"--slim-iterations", "--join", "--repair", "--image-time"})
        CHECK_MESSAGE(all.find(shown) != std::string::npos, shown);

    const auto [version_status, version] = flatten_cli(dir, "--version");
    CHECK(version_status == 0);
    CHECK(version.find(VESSEL_VERSION) != std::string::npos);
}

TEST_CASE(
    "cli: progress is drawn on a terminal (each step named while it runs) but not in a pipe "
    "and --quiet silences it")
{
    const std::string dir = temp_dir("progress");
    const std::string mesh = std::string(VESSEL_SHARED_DATA) + "/vampy/artery.ply";
    // script(1) runs the command on a pseudo-terminal and copies what it writes to stdout.
    const auto on_terminal = [&](const std::string& args) {
        const std::string log = dir + "/tty.txt";
        const int status = run("script -qec '" + kFlatten + " " + args + "' /dev/null > " + log +
                               " 2>&1 < /dev/null");
        return std::make_pair(status, read_bytes(log));
    };
    const std::string redraw = "\r\033[K";  // the live line is redrawn in place
    const auto [tty_status, tty] = on_terminal(mesh + " -o " + dir + "/tty.obj");
    REQUIRE_MESSAGE(tty_status == 0, tty);
    CHECK(tty.find(redraw) != std::string::npos);
    CHECK(tty.find("[F ] ") != std::string::npos);
    const bool iterations_shown = tty.find(" arap ") != std::string::npos ||
                                  tty.find(" slim ") != std::string::npos ||
                                  tty.find(" polish ") != std::string::npos;
    CHECK(iterations_shown);
    // Each step is named on the status line as it starts, before the line that ends it: the
    // reading, and every stage, also those that report no iterations (stage Z).
    const auto named_before = [&](const std::string& status, const std::string& done) {
        const std::size_t at = tty.find(redraw + status + " 0.0 s");
        CHECK_MESSAGE(at != std::string::npos, status);
        CHECK_MESSAGE(at < tty.find(done), status);
    };
    named_before("[  ] reading artery.ply", "[  ] read ");
    for (const char* stage :
         {"[Z ] curvature, geodesic distance, alignment", "[GC] cut graph costs", "[VC] cut paths",
          "[AC] applying the cuts", "[L ] layout", "[F ] initial map + refinement"})
        named_before(stage, std::string(stage) + "  ");

    const auto [pipe_status, pipe] = flatten_cli(dir, mesh + " -o " + dir + "/pipe.obj");
    REQUIRE(pipe_status == 0);
    CHECK(pipe.find("\r") == std::string::npos);
    CHECK(pipe.find("[F ] ") != std::string::npos);  // one line per stage, as ever
    CHECK(read_bytes(dir + "/pipe.obj") == read_bytes(dir + "/tty.obj"));

    const auto [quiet_status, quiet] = on_terminal(mesh + " -o " + dir + "/quiet.obj --quiet");
    REQUIRE(quiet_status == 0);
    CHECK(quiet.find("[F ") == std::string::npos);
    CHECK(quiet.find(redraw) == std::string::npos);

    // A batch names the mesh running on the status line before the line that ends it.
    std::filesystem::create_directories(dir + "/in");
    std::filesystem::copy_file(mesh, dir + "/in/a.ply");
    const auto [batch_status, batch] = on_terminal("--batch " + dir + "/in -o " + dir + "/out");
    REQUIRE_MESSAGE(batch_status == 0, batch);
    const std::size_t named = batch.find(redraw + "[0/1] running " + dir + "/in/a.ply");
    CHECK(named != std::string::npos);
    CHECK(named < batch.find("[1/1] " + dir + "/in/a.ply: ok"));
}
