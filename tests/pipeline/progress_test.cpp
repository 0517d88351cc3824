// FlattenOptions::on_progress: what flatten() reports while it runs.
#include <doctest/doctest.h>

#include "support/meshes.h"
#include "vessel/pipeline.h"

#include <set>
#include <string>
#include <vector>

using namespace vessel;

namespace {

std::vector<Progress> run_with_progress(const Mesh& mesh, FlattenOptions options,
                                        FlattenResult& result)
{
    std::vector<Progress> seen;
    options.on_progress = [&](const Progress& p) { seen.push_back(p); };
    result = flatten(mesh, options);
    return seen;
}

}  // namespace

TEST_CASE(
    "pipeline: on_progress reports every stage's start and end and stage F's iterations "
    "and changes no map")
{
    const Mesh mesh = test::test_tree_phantom(3);
    FlattenOptions every;
    every.progress_interval_s = 0.0;
    FlattenResult with;
    const std::vector<Progress> seen = run_with_progress(mesh, every, with);
    CHECK(with.uv == flatten(mesh).uv);

    std::vector<std::string> ends;
    std::set<std::string> phases;
    std::string running;  // the stage begun and not yet ended
    for (const Progress& p : seen)
        if (p.stage_begins)
        {
            CHECK_MESSAGE(running.empty(), p.stage, " begins inside ", running);
            CHECK(p.phase.empty());
            CHECK(p.iteration == 0);
            CHECK(!p.stage_done);
            running = p.stage;
        }
        else if (p.stage_done)
        {
            CHECK_MESSAGE(running == p.stage, p.stage, " ends, but ", running, " was running");
            running.clear();
            ends.push_back(p.stage);
            CHECK(p.seconds >= 0.0);
        }
        else
        {
            CHECK(p.stage == "F");
            CHECK(running == "F");
            CHECK(p.iteration >= 1);
            CHECK(p.iteration <= p.max_iterations);
            phases.insert(p.phase);
        }
    CHECK(running.empty());
    // Z once, then GC, VC, AC, L and F for every pass (a relief cut is one more pass).
    REQUIRE(ends.size() >= 6);
    CHECK((ends.size() - 1) % 5 == 0);
    CHECK(ends.front() == "Z");
    for (std::size_t i = 1; i < ends.size(); ++i)
        CHECK(ends[i] == std::vector<std::string>{"GC", "VC", "AC", "L", "F"}[(i - 1) % 5]);
    if (with.injective.iterations > 0)
        CHECK(phases.count("slim") + phases.count("scaffold") > 0);
    if (with.arap.iterations > 0)
        CHECK(phases.count("arap") == 1);
    for (const std::string& phase : phases)
        CHECK_MESSAGE(
            (phase == "arap" || phase == "slim" || phase == "scaffold" || phase == "polish"),
            phase);
}

TEST_CASE(
    "pipeline: on_progress reports each of the paper's ARAP sweeps, and no more often than asked")
{
    const Mesh mesh = test::test_tree_phantom(3);
    FlattenOptions every = FlattenOptions::paper();
    every.progress_interval_s = 0.0;
    FlattenResult paper;
    int sweeps = 0;
    for (const Progress& p : run_with_progress(mesh, every, paper))
        if (!p.stage_done && !p.stage_begins)
        {
            CHECK(p.phase == "arap");
            CHECK(p.iteration == ++sweeps);
            CHECK(p.max_iterations == every.arap.max_iterations);
        }
    CHECK(sweeps == paper.arap.iterations);
    CHECK(sweeps > 1);

    FlattenOptions rare = every;
    rare.progress_interval_s = 1e6;
    int reports = 0;
    for (const Progress& p : run_with_progress(mesh, rare, paper))
        reports += p.stage_done || p.stage_begins ? 0 : 1;
    CHECK(reports == 1);  // the first; the next is due in 1e6 s
}
