// FlattenOptions::refiner: a researcher's solver in place of the built-in refinements.
#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/meshes.h"
#include "vessel/core/errors.h"
#include "vessel/map/refiner.h"
#include "vessel/pipeline.h"

#include <string>

using namespace vessel;
using vessel::test::test_tree_phantom;

namespace {

// Keeps the initial map and records what it was given.
class RecordingRefiner : public MapRefiner
{
public:
    mutable int calls = 0;
    mutable std::size_t vertices = 0, pins = 0;
    mutable bool had_layout = false;
    std::string name() const override { return "recording"; }
    void refine(const RefineInput& input, Eigen::MatrixX2d& uv,
                std::vector<std::string>& notes) const override
    {
        ++calls;
        vertices = input.mesh->n_vertices();
        pins = input.pins.size();
        had_layout = input.layout != nullptr && input.placed != nullptr &&
                     !input.placed->outlets.empty();
        CHECK(uv.rows() == static_cast<Eigen::Index>(vertices));
        notes.push_back("recording refiner saw " + std::to_string(vertices) + " vertices");
    }
};

// Breaks the contract: drops a row of the map.
class ShrinkingRefiner : public MapRefiner
{
public:
    std::string name() const override { return "shrinking"; }
    void refine(const RefineInput&, Eigen::MatrixX2d& uv,
                std::vector<std::string>&) const override
    {
        uv.conservativeResize(uv.rows() - 1, 2);
    }
};

FlattenOptions paper_cuts_only()
{
    FlattenOptions options = FlattenOptions::paper();
    options.relief.max_cuts = 0;
    return options;
}

}  // namespace

TEST_CASE("refiner: the paper's ARAP as a policy gives Refinement::Arap's map")
{
    const Mesh tree = test_tree_phantom(3);
    const FlattenOptions builtin = paper_cuts_only();
    FlattenOptions policy = builtin;
    policy.refiner = std::make_shared<ArapRefiner>(builtin.arap);
    const FlattenResult a = flatten(tree, builtin);
    const FlattenResult b = flatten(tree, policy);
    REQUIRE(a.uv.rows() == b.uv.rows());
    // Equal up to rounding: the pipeline factors its ARAP system in the elimination order it
    // shares with LSCM, the refiner in AMD's own.
    const double size = (a.uv.colwise().maxCoeff() - a.uv.colwise().minCoeff()).norm();
    CHECK((a.uv - b.uv).cwiseAbs().maxCoeff() <= 1e-9 * size);
    MESSAGE("largest difference " << (a.uv - b.uv).cwiseAbs().maxCoeff() << " on a map of size "
                                  << size);
    CHECK(b.arap.iterations == 0);  // the built-in ARAP did not run
    bool noted = false;
    for (const std::string& note : b.notes)
        noted = noted || note.rfind("arap refiner: ", 0) == 0;
    CHECK(noted);
}

TEST_CASE("refiner: a researcher's refiner replaces the built-in one and its map is the result")
{
    const Mesh tree = test_tree_phantom(3);
    FlattenOptions options;  // the default would untangle, run SLIM and polish
    options.relief.max_cuts = 0;
    const auto refiner = std::make_shared<RecordingRefiner>();
    options.refiner = refiner;
    const FlattenResult r = flatten(tree, options);
    CHECK(refiner->calls == 1);
    CHECK(refiner->vertices == r.mesh.n_vertices());
    CHECK(refiner->pins > 0);
    CHECK(refiner->had_layout);
    // Keeping the initial map is Refinement::None's result: the same LSCM map at the layout.
    FlattenOptions none = options;
    none.refiner = nullptr;
    none.refinement = Refinement::None;
    const FlattenResult unrefined = flatten(tree, none);
    REQUIRE(unrefined.uv.rows() == r.uv.rows());
    CHECK(unrefined.uv == r.uv);
    CHECK(r.injective.iterations == 0);
    CHECK(r.notes.front() == "recording refiner saw " + std::to_string(r.mesh.n_vertices()) +
                                 " vertices");
}

TEST_CASE("refiner: relief cuts solve the map again with the researcher's refiner")
{
    const Mesh tree = test_tree_phantom(3);
    FlattenOptions options;
    options.relief.max_cuts = 1;
    options.relief.target_mean_abs_log_area = 0.0;  // every map asks for a relief cut
    const auto refiner = std::make_shared<RecordingRefiner>();
    options.refiner = refiner;
    flatten(tree, options);
    CHECK(refiner->calls == 2);
}

TEST_CASE("refiner: a map of the wrong shape is refused, naming the refiner")
{
    FlattenOptions options;
    options.refiner = std::make_shared<ShrinkingRefiner>();
    const auto run = [&] { flatten(test_tree_phantom(3), options); };
    CHECK_THROWS_AS(run(), InvalidInputError);
    const std::string message = test::error_of(run);
    CHECK_MESSAGE(message.find("the refiner 'shrinking' returned") != std::string::npos, message);
    CHECK_MESSAGE(message.find("one row per cut-mesh vertex") != std::string::npos, message);
}
