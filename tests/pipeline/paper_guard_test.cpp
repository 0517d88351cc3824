// The paper preset's own figures on real meshes (issue 33). `--preset paper` (LSCM at the
// layout, then ARAP with the inlet pinned; no untangling, no SLIM, overlaps kept) is the
// published method, for reproduction: its maps may have flipped triangles and overlaps, so
// "0 flips" is no requirement here. What is required is that the method stays the paper's: its
// flipped triangles and overlap fraction, as the report states them and as
// ../shared/tools/flatcheck.py measures them on the written OBJ, stay near what it gives today.
// A change that moves them (a stage shared with the default, or the preset itself) must be
// deliberate and re-baselined here.
#include <doctest/doctest.h>

#include "support/checks.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

namespace {

//! The paper map's figures on one mesh, `vessel-flatten MESH --preset paper` (deterministic).
struct PaperBaseline
{
    const char* mesh;        //!< path under ../shared/data/real
    int flipped;             //!< the report's quality.flipped_triangles
    double overlap;          //!< the report's quality.overlap_fraction (exact)
    int flatcheck_flipped;   //!< flatcheck.py's flips
    double flatcheck_overlap;  //!< flatcheck.py's overlap_fraction (raster, quarter edge)
};

//! Measured with the natural cuts of stages Z to L (the default's; CutPlanOptions::natural_cuts).
//! Re-baselining: run `vessel_tests -tc="paper: *" -s` and copy the figures of its messages;
//! say why in the commit.
constexpr PaperBaseline kPaperBaselines[] = {
    {"vampy/artery-coarse.ply", 1, 0.016535, 1, 0.016497},
    {"vampy/artery.ply", 3, 0.109763, 3, 0.120202},
    {"vmtk-test-data/aorta-surface-open-ends.ply", 2, 0.038529, 2, 0.039951},
    {"x-ray-angio-data/coronary-phantom-tri3-coarse.ply", 4, 0.075943, 4, 0.078368},
    {"x-ray-angio-data/coronary-clinical-branch-fine.ply", 0, 0.0, 0, 0.0},
    {"simvascular-tests/demo-model-open.ply", 1, 0.021781, 1, 0.022235},
};

//! A figure may move by this factor either way from its baseline, plus the absolute slack below
//! (one triangle; half a percent of the map's area, a few of the raster's pixels on these
//! meshes), so that the 0 and 1 of a coarse mesh do not make the guard a test of rounding.
constexpr double kFactor = 1.5;
constexpr double kFlipSlack = 1.0;
constexpr double kOverlapSlack = 0.005;

void check_within(const char* what, double measured, double baseline, double slack)
{
    INFO(what << ": " << measured << " against baseline " << baseline << " (x/" << kFactor
              << " - " << slack << " .. x" << kFactor << " + " << slack << ")");
    CHECK(measured <= kFactor * baseline + slack);
    CHECK(measured >= baseline / kFactor - slack);
}

}  // namespace

TEST_CASE("paper: the paper preset's flipped triangles and overlap stay at its baselines on real "
          "meshes")
{
    for (const PaperBaseline& baseline : kPaperBaselines)
    {
        const std::string mesh = baseline.mesh;
        CAPTURE(mesh);
        const std::string input = std::string(VESSEL_SHARED_DATA) + "/" + mesh;
        REQUIRE_MESSAGE(std::filesystem::exists(input), "missing shared data: " << input);
        const std::string dir =
            vessel::test::temp_dir("paper_" + std::filesystem::path(input).stem().string());
        const std::string out = dir + "/flat.obj";
        REQUIRE(vessel::test::run(std::string(VESSEL_FLATTEN_EXE) + " " + input + " -o " + out +
                                  " --report " + dir + "/report.json --preset paper -q") == 0);
        const auto report = nlohmann::json::parse(std::ifstream(dir + "/report.json"));
        const auto& q = report["quality"];
        const auto check = vessel::test::flatcheck(input, out);
        const int flipped = q["flipped_triangles"];
        const double overlap = q["overlap_fraction"];
        const int fc_flipped = check["flips"];
        const double fc_overlap = check["overlap_fraction"];
        MESSAGE(mesh << ": flipped " << flipped << ", overlap fraction " << overlap
                              << "; flatcheck flips " << fc_flipped << ", overlap fraction "
                              << fc_overlap);
        // The paper's map is the same map however it is read: the two flip counts agree.
        CHECK(flipped == fc_flipped);
        check_within("flipped triangles (report)", flipped, baseline.flipped, kFlipSlack);
        check_within("overlap fraction (report)", overlap, baseline.overlap, kOverlapSlack);
        check_within("flips (flatcheck)", fc_flipped, baseline.flatcheck_flipped, kFlipSlack);
        check_within("overlap fraction (flatcheck)", fc_overlap, baseline.flatcheck_overlap,
                     kOverlapSlack);
    }
}
