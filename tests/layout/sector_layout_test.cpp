#include <doctest/doctest.h>

#include "support/meshes.h"
#include "vessel/core/errors.h"
#include "vessel/layout/layout.h"
#include "vessel/quality/overlap.h"
#include "vessel/phantom/phantom.h"
#include "vessel/pipeline.h"
#include "vessel/check/validation.h"

#include <filesystem>
#include <memory>
#include <string>

using namespace vessel;

namespace {

// Delegates to a layout and keeps what it placed, so a test sees the layout the pipeline used.
class RecordingLayout : public Layout
{
public:
    explicit RecordingLayout(std::shared_ptr<const Layout> inner) : inner_(std::move(inner)) {}
    std::string name() const override { return inner_->name(); }
    LayoutResult place(const LayoutInput& input) const override
    {
        *placed_ = inner_->place(input);
        n_paths_ = input.plan->paths.size();
        return *placed_;
    }
    const LayoutResult& placed() const { return *placed_; }
    std::size_t n_paths() const { return n_paths_; }

private:
    std::shared_ptr<const Layout> inner_;
    std::shared_ptr<LayoutResult> placed_ = std::make_shared<LayoutResult>();
    mutable std::size_t n_paths_ = 0;
};

// Pairs of strips whose interiors intersect (each strip as two triangles).
int crossing_strips(const std::vector<Strip>& strips)
{
    std::vector<Triangle2> soup;
    for (const Strip& s : strips)
    {
        soup.push_back({s[0], s[1], s[2]});
        soup.push_back({s[0], s[2], s[3]});
    }
    int crossings = 0;
    for (const auto& [f, g] : find_overlaps(soup).pairs)
        crossings += f / 2 != g / 2;
    return crossings;
}

// Runs the pipeline up to the layout (no refinement) with `layout` recorded.
std::shared_ptr<RecordingLayout> layout_of(const Mesh& mesh, std::shared_ptr<const Layout> layout)
{
    auto recorder = std::make_shared<RecordingLayout>(std::move(layout));
    FlattenOptions options;
    options.layout = recorder;
    options.refinement = Refinement::None;
    flatten(mesh, options);
    return recorder;
}

void check_sector_layout(const Mesh& mesh, const std::string& what)
{
    const auto sector = layout_of(mesh, std::make_shared<SectorLayout>());
    const auto& placed = sector->placed();
    REQUIRE(placed.strips.size() == sector->n_paths());
    CHECK_MESSAGE(crossing_strips(placed.strips) == 0, what);
    // The paper's look: inlet on the u axis, everything above it.
    for (const auto& pin : placed.inlet)
        CHECK(pin.uv.y() == doctest::Approx(0.0));
    for (const Strip& s : placed.strips)
        for (const auto& corner : s)
            CHECK(corner.y() >= -1e-9);
    const auto fan = layout_of(mesh, std::make_shared<BranchFanLayout>());
    MESSAGE(what << ": " << placed.strips.size() << " strips; crossing pairs: sector 0, fan "
                 << crossing_strips(fan->placed().strips));
}

}  // namespace

TEST_CASE("sector layout: strips never cross on seeded tree phantoms with 3 to 30 outlets")
{
    for (int outlets : {3, 5, 8, 12, 20, 30})
        for (std::uint32_t seed : {1u, 2u})
        {
            // 30 outlets need finer vessels
            const double edge = outlets < 30 ? 1.0 : 0.75;
            check_sector_layout(test::test_tree_phantom(outlets, seed, edge), "tree phantom, " +
                                                           std::to_string(outlets) +
                                                           " outlets, seed " + std::to_string(seed));
        }
}

TEST_CASE("sector layout: strips never cross on the real trees")
{
    const std::string data = VESSEL_SHARED_DATA;
    for (const char* relative :
         {"vmtk-test-data/aorta-surface-open-ends.ply", "vampy/artery-coarse.ply",
          "vmtk-old-website/aneurisk-id1-lateral-aneurysm.ply",
          "svfsi-tests/pulmonary-glenn-wall.ply", "x-ray-angio-data/coronary-phantom-tri3-coarse.ply",
          "simvascular-tests/demo-model-open.ply"})
    {
        const std::string path = data + "/" + relative;
        REQUIRE_MESSAGE(std::filesystem::exists(path), "missing shared data: " << path);
        check_sector_layout(load_tree_surface(path).mesh, relative);
    }
}

TEST_CASE("sector layout: bad parameters and names are refused")
{
    CHECK_THROWS_AS(SectorLayout(0.0), InvalidInputError);
    CHECK_THROWS_AS(SectorLayout(90.0), InvalidInputError);
    CHECK_THROWS_AS(SectorLayout(60.0, 0.5), InvalidInputError);
    CHECK(make_layout("sector")->name() == "sector");
}
