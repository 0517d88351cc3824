#include <doctest/doctest.h>

#include "detail/boundary_guard.h"
#include "detail/coarse_correction.h"
#include "detail/face_jacobian.h"
#include "detail/polish_hessian.h"
#include "detail/refine_map.h"
#include "support/checks.h"
#include "support/first_cut_back_join.h"
#include "support/meshes.h"
#include "vessel/check/validation.h"
#include "vessel/core/errors.h"
#include "vessel/map/embedding.h"
#include "vessel/map/injective.h"
#include "vessel/map/multilevel.h"
#include "vessel/pipeline.h"
#include "vessel/quality/metrics.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <limits>
#include <memory>
#include <numeric>
#include <set>
#include <string>
#include <tuple>

using namespace vessel;

namespace {

// The boundary of a disk mesh, walked from its first boundary halfedge: vertex indices in order.
std::vector<int> boundary_walk(const Mesh& mesh)
{
    std::vector<int> walk;
    for (auto start : mesh.halfedges())
        if (start.is_boundary())
        {
            auto h = start;
            do
            {
                walk.push_back(h.from().idx());
                h = h.next();
            } while (h != start);
            break;
        }
    return walk;
}

// A flip-free map of the coarse mesh: SLIM from Tutte's, as the pipeline's restart makes it.
Eigen::MatrixX2d coarse_map(const Mesh& mesh)
{
    Eigen::MatrixX2d uv = tutte_embedding(mesh);
    InjectiveOptions options;
    options.max_iterations = 30;
    injective_refine(mesh, uv, {}, options);
    return uv;
}

using test::noted;

// The energy / minimum before and after of every relaxation note of \p r that is \p prefix and
// then its sweeps ("coarse-to-fine: N relaxation sweeps, ..., energy / minimum A -> B"), in
// order.
std::vector<std::pair<double, double>> relaxed_ratios(const FlattenResult& r,
                                                       const std::string& prefix)
{
    std::vector<std::pair<double, double>> ratios;
    for (const std::string& note : r.notes)
    {
        const std::size_t at = note.find("energy / minimum ");
        if (note.rfind(prefix, 0) != 0 || at == std::string::npos || note.size() <= prefix.size() ||
            !std::isdigit(static_cast<unsigned char>(note[prefix.size()])))
            continue;
        double before = 0.0, after = 0.0;
        REQUIRE(std::sscanf(note.c_str() + at, "energy / minimum %lf -> %lf", &before, &after) ==
                2);
        ratios.emplace_back(before, after);
    }
    return ratios;
}

// The carried map was kept (no fallback noted), one-to-one.
void check_carry_kept(const FlattenResult& r)
{
    CHECK_FALSE(noted(r, "times its minimum (more than"));
    CHECK_FALSE(noted(r, "tried again with the whole boundary"));
    CHECK_FALSE(noted(r, "solved again at full resolution"));
    CHECK(r.quality.flipped_triangles == 0);
    CHECK(r.quality.overlapping_triangles == 0);
}

// \p blocks (an operator by blocks, upper triangle) against \p product, the sparse product it
// replaces: equal up to rounding, upper triangle only, every diagonal entry stored (the
// corrections shift it).
void check_upper_equals(const Eigen::SparseMatrix<double>& blocks,
                        const Eigen::SparseMatrix<double>& product, const char* what)
{
    REQUIRE(blocks.rows() == product.rows());
    REQUIRE(blocks.cols() == product.cols());
    const Eigen::MatrixXd difference = Eigen::MatrixXd(blocks) - Eigen::MatrixXd(product);
    MESSAGE(what << " " << blocks.rows() << " x " << blocks.cols() << ", " << blocks.nonZeros()
                 << " entries; largest difference " << difference.cwiseAbs().maxCoeff() << " of "
                 << Eigen::MatrixXd(product).cwiseAbs().maxCoeff());
    CHECK(difference.norm() <= 1e-12 * Eigen::MatrixXd(product).norm());
    CHECK(Eigen::MatrixXd(product).norm() > 0.0);
    for (Eigen::Index c = 0; c < blocks.outerSize(); ++c)
    {
        bool diagonal = false;
        for (Eigen::SparseMatrix<double>::InnerIterator it(blocks, c); it; ++it)
        {
            CHECK(it.row() <= c);
            diagonal = diagonal || it.row() == c;
        }
        CHECK(diagonal);
    }
}

}  // namespace

TEST_CASE("multilevel: coarsen keeps a disk, the kept vertices and the boundary's order")
{
    const Mesh fine = test::cut_cylinder(1.0, 6.0, 32, 40);
    const std::vector<VertexHandle> boundary = test::boundary_vertices(fine);
    const std::vector<VertexHandle> keep = {boundary[0], boundary[boundary.size() / 2]};
    const CoarseMesh coarse = coarsen(fine, 200, keep);

    const Mesh& m = coarse.mesh;
    CHECK(m.n_vertices() <= 220);
    CHECK(m.n_vertices() >= 150);
    CHECK(static_cast<int>(m.n_vertices()) - static_cast<int>(m.n_edges()) +
              static_cast<int>(m.n_faces()) == 1);  // still a disk
    for (auto v : keep)
        CHECK(coarse.coarse_of[v.idx()] >= 0);
    for (std::size_t c = 0; c < coarse.fine_of.size(); ++c)
    {
        CHECK(coarse.coarse_of[coarse.fine_of[c]] == static_cast<int>(c));
        // Kept vertices stay where they were.
        CHECK((m.point(VertexHandle(static_cast<int>(c))) -
               fine.point(VertexHandle(coarse.fine_of[c]))).norm() == 0.0);
    }
    // The coarse boundary is the fine one with vertices left out, in the same cyclic order.
    const std::vector<int> fine_walk = boundary_walk(fine);
    std::vector<int> coarse_walk;
    for (int c : boundary_walk(m))
        coarse_walk.push_back(coarse.fine_of[c]);
    REQUIRE(!coarse_walk.empty());
    std::vector<int> kept_in_fine_order;
    for (int v : fine_walk)
        if (coarse.coarse_of[v] >= 0)
            kept_in_fine_order.push_back(v);
    REQUIRE(kept_in_fine_order.size() == coarse_walk.size());
    const auto at = std::find(kept_in_fine_order.begin(), kept_in_fine_order.end(),
                              coarse_walk.front());
    REQUIRE(at != kept_in_fine_order.end());
    std::rotate(kept_in_fine_order.begin(), at, kept_in_fine_order.end());
    CHECK(kept_in_fine_order == coarse_walk);
    CHECK(coarse.collapses.size() == fine.n_vertices() - m.n_vertices());
}

TEST_CASE("multilevel: coarsen's collapses replay on OpenMesh's half-edge mesh to the same level")
{
    // coarsen() decimates on arrays but keeps OpenMesh's halfedge numbering and circulation
    // order, so that its levels are those OpenMesh's collapse() and garbage_collection() make
    // on a copy built face by face (multilevel.h). Replayed on such a copy, every recorded
    // collapse is one OpenMesh allows, its star listed as OpenMesh circulates it, each round's
    // collapses in the order of (edge length, OpenMesh halfedge index), and the compacted copy
    // is the coarse mesh, vertex for vertex and face for face, corner for corner.
    FlattenOptions cut_only;
    cut_only.refinement = Refinement::None;
    const Mesh tree = flatten(test::test_tree_phantom(10), cut_only).mesh;
    const Mesh cylinder = test::cut_cylinder(1.0, 6.0, 48, 60);
    for (const auto& [fine, no_new_chords, keep_boundary] :
         {std::tuple<const Mesh&, bool, bool>{tree, true, true}, {tree, false, false},
          {cylinder, false, true}})
    {
        std::vector<VertexHandle> keep;
        if (keep_boundary)
            keep = test::boundary_vertices(fine);
        const CoarseMesh coarse =
            coarsen(fine, static_cast<int>(fine.n_vertices() / 4), keep, no_new_chords);
        REQUIRE(coarse.collapses.size() > 100);

        OpenMesh::TriMesh_ArrayKernelT<> copy;
        copy.request_vertex_status();
        copy.request_edge_status();
        copy.request_face_status();
        for (auto v : fine.vertices())
            copy.add_vertex(OpenMesh::vector_cast<OpenMesh::Vec3f>(fine.point(v)));
        for (auto f : fine.faces())
        {
            auto h = f.halfedge();
            copy.add_face(OpenMesh::VertexHandle(h.from().idx()),
                          OpenMesh::VertexHandle(h.to().idx()),
                          OpenMesh::VertexHandle(h.next().to().idx()));
        }
        const auto length = [&](int a, int b) {
            return (fine.point(VertexHandle(a)) - fine.point(VertexHandle(b))).sqrnorm();
        };
        std::size_t round = 0, out_of_order = 0, unlike = 0;
        std::pair<double, int> last{-1.0, -1};
        for (std::size_t c = 0; c < coarse.collapses.size(); ++c)
        {
            if (round < coarse.rounds.size() && coarse.rounds[round] == c)
            {
                ++round;
                last = {-1.0, -1};
            }
            const Collapse& collapse = coarse.collapses[c];
            const auto h = OpenMesh::make_smart(
                copy.find_halfedge(OpenMesh::VertexHandle(collapse.v0),
                                   OpenMesh::VertexHandle(collapse.v1)),
                copy);
            REQUIRE(h.is_valid());
            REQUIRE(copy.is_collapse_ok(h));
            std::vector<std::array<int, 2>> star;
            int across = -1;
            for (auto out : h.from().outgoing_halfedges())
            {
                if (!out.is_boundary())
                    star.push_back({out.to().idx(), out.next().to().idx()});
                if ((out.is_boundary() || out.opp().is_boundary()) && out.to() != h.to())
                    across = out.to().idx();
            }
            unlike += star != collapse.faces || across != collapse.across;
            const std::pair<double, int> key{length(collapse.v0, collapse.v1), h.idx()};
            out_of_order += key < last;
            last = key;
            copy.collapse(h);
        }
        CHECK(unlike == 0);
        CHECK(out_of_order == 0);
        auto fine_index = OpenMesh::VProp<int>(copy);
        for (auto v : copy.vertices())
            fine_index[v] = v.idx();
        copy.garbage_collection();
        REQUIRE(copy.n_vertices() == coarse.mesh.n_vertices());
        REQUIRE(copy.n_faces() == coarse.mesh.n_faces());
        std::size_t moved = 0, turned = 0;
        for (auto v : copy.vertices())
            moved += fine_index[v] != coarse.fine_of[v.idx()];
        for (auto f : copy.faces())
        {
            // The coarse face was added as the copy's face reads from its halfedge on, and
            // add_face() gives a face the halfedge into its first corner.
            const auto h = f.halfedge();
            const auto g = OpenMesh::make_smart(
                coarse.mesh.halfedge_handle(coarse.mesh.face_handle(f.idx())), coarse.mesh);
            turned += h.from().idx() != g.to().idx() || h.to().idx() != g.next().to().idx();
        }
        CHECK(moved == 0);
        CHECK(turned == 0);
    }
}

TEST_CASE("multilevel: rounds of independent collapses carry to the same bits on two threads")
{
    // coarsen() records its rounds; prolongate() undoes each round's interior collapses on two
    // threads where a round has enough of them. Without the record it undoes every collapse
    // one after another, and the map must be the same to the bit.
    const Mesh fine = test::cut_cylinder(1.0, 6.0, 128, 160);
    const CoarseMesh coarse = coarsen(fine, static_cast<int>(fine.n_vertices() / 4), {});
    REQUIRE(!coarse.rounds.empty());
    CHECK(coarse.rounds.front() == 0);
    CHECK(std::is_sorted(coarse.rounds.begin(), coarse.rounds.end()));
    CHECK(coarse.rounds.back() < coarse.collapses.size());
    // No two collapses of a round share a vertex of their stars' centres or targets.
    std::size_t largest = 0;
    for (std::size_t r = 0; r < coarse.rounds.size(); ++r)
    {
        const std::size_t end =
            r + 1 < coarse.rounds.size() ? coarse.rounds[r + 1] : coarse.collapses.size();
        std::set<int> ends;
        std::size_t interior = 0;
        for (std::size_t c = coarse.rounds[r]; c < end; ++c)
        {
            const Collapse& collapse = coarse.collapses[c];
            interior += collapse.across < 0;
            CHECK(ends.insert(collapse.v0).second);
            CHECK(ends.insert(collapse.v1).second);
        }
        largest = std::max(largest, interior);
    }
    MESSAGE(coarse.rounds.size() << " rounds, the largest of " << largest << " interior collapses");
    CHECK(largest >= 2048);  // enough for the two threads (prolongate())

    const Eigen::MatrixX2d coarse_uv = coarse_map(coarse.mesh);
    const Eigen::MatrixX2d parallel = prolongate(fine, coarse, coarse_uv, 0.99);
    CoarseMesh unrecorded = coarse;
    unrecorded.rounds.clear();
    const Eigen::MatrixX2d serial = prolongate(fine, unrecorded, coarse_uv, 0.99);
    CHECK(test::count_flips(fine, parallel) == 0);
    CHECK((parallel.array() == serial.array()).all());
}

TEST_CASE("multilevel: a flip-free coarse map carries to a flip-free, one-to-one fine map")
{
    for (const int target : {100, 400})
    {
        CAPTURE(target);
        const Mesh fine = test::cut_cylinder(1.0, 6.0, 32, 40);
        const CoarseMesh coarse = coarsen(fine, target, {});
        const Eigen::MatrixX2d coarse_uv = coarse_map(coarse.mesh);
        REQUIRE(test::count_flips(coarse.mesh, coarse_uv) == 0);
        const Eigen::MatrixX2d uv = prolongate(fine, coarse, coarse_uv, 0.99);
        CHECK(test::count_flips(fine, uv) == 0);
        CHECK(boundary_self_intersection(fine, uv).first < 0);
        for (std::size_t c = 0; c < coarse.fine_of.size(); ++c)
            CHECK((uv.row(coarse.fine_of[c]) - coarse_uv.row(c)).norm() == 0.0);
        // The cylinder unrolls isometrically: the carried map is close to it already.
        CHECK(flat_quality(fine, uv).mean_abs_log_area < 0.1);
    }
}

TEST_CASE("multilevel: relax_area lowers the energy, holds the pins and flips nothing")
{
    const Mesh mesh = test::cut_cylinder(1.0, 6.0, 32, 40);
    const CoarseMesh coarse = coarsen(mesh, 150, {});
    Eigen::MatrixX2d uv = prolongate(mesh, coarse, coarse_map(coarse.mesh), 0.99);
    REQUIRE(test::count_flips(mesh, uv) == 0);
    const double before = flat_quality(mesh, uv).mean_abs_log_area;
    const VertexHandle held = test::boundary_vertices(mesh).front();
    const Eigen::RowVector2d at = uv.row(held.idx());
    const RelaxSummary relaxed = relax_area(mesh, uv, {{held, at.transpose()}}, 0.99);
    CHECK(relaxed.sweeps > 0);
    CHECK(relaxed.energy_after < relaxed.energy_before);
    CHECK(relaxed.energy_after >= 2.0 * face_areas(mesh).sum() * (1.0 - 1e-9));  // the minimum
    CHECK(test::count_flips(mesh, uv) == 0);
    CHECK(boundary_self_intersection(mesh, uv).first < 0);
    CHECK((uv.row(held.idx()) - at).norm() == 0.0);
    CHECK(flat_quality(mesh, uv).mean_abs_log_area < before);
}

namespace {

// A cut cylinder, its level decimated to 300 vertices with a flip-free map, and the map
// carried up from it.
struct CarriedCylinder
{
    Mesh mesh = test::cut_cylinder(1.0, 6.0, 48, 60);
    CoarseMesh coarse = coarsen(mesh, 300, {});
    Eigen::MatrixX2d coarse_uv = coarse_map(coarse.mesh);
    Eigen::MatrixX2d carried = prolongate(mesh, coarse, coarse_uv, 0.99);
};

// Options under which relax_area() makes exactly 6 sweeps (no early stop).
MultilevelOptions six_sweeps()
{
    MultilevelOptions options;
    options.relax_sweeps = 6;
    options.tolerance = 0.0;
    options.area_tolerance = 0.0;  // the whole schedule
    return options;
}

}  // namespace

TEST_CASE("multilevel: relax_area reports its last sweep's decrease")
{
    // Five sweeps and six from the same carried map (sweeps alone, no early stop): the sixth
    // run's last_decrease is what its sixth sweep lowered, the difference of the two ends.
    const Mesh mesh = test::cut_cylinder(1.0, 6.0, 32, 40);
    const CoarseMesh coarse = coarsen(mesh, 150, {});
    const Eigen::MatrixX2d carried = prolongate(mesh, coarse, coarse_map(coarse.mesh), 0.99);
    const VertexHandle held = test::boundary_vertices(mesh).front();
    const Pins pins = {{held, carried.row(held.idx()).transpose()}};
    MultilevelOptions options = six_sweeps();
    options.coarse_corrections = 0;
    Eigen::MatrixX2d six = carried;
    const RelaxSummary after_six = relax_area(mesh, six, pins, 0.99, options);
    options.relax_sweeps = 5;
    Eigen::MatrixX2d five = carried;
    const RelaxSummary after_five = relax_area(mesh, five, pins, 0.99, options);
    REQUIRE(after_six.sweeps == 6);
    REQUIRE(after_five.sweeps == 5);
    CHECK(after_six.last_decrease > 0.0);
    CHECK(after_six.last_decrease ==
          doctest::Approx(after_five.energy_after - after_six.energy_after).epsilon(1e-6));
    CHECK(after_six.last_decrease < after_five.last_decrease);  // the sweeps converge
}

TEST_CASE("multilevel: coarse-grid corrections lower the energy further than the sweeps alone")
{
    // A carried map of a cut cylinder, relaxed with the same sweep budget twice: Gauss-Seidel
    // alone, and alternating with corrections from the level it was carried from.
    const CarriedCylinder cylinder;
    const auto& [mesh, coarse, coarse_uv, carried] = cylinder;
    REQUIRE(test::count_flips(mesh, carried) == 0);
    const VertexHandle held = test::boundary_vertices(mesh).front();
    const Pins pins = {{held, carried.row(held.idx()).transpose()}};
    MultilevelOptions options = six_sweeps();
    Eigen::MatrixX2d alone = carried;
    options.coarse_corrections = 0;
    const RelaxSummary swept = relax_area(mesh, alone, pins, 0.99, options, &coarse, &coarse_uv);
    Eigen::MatrixX2d corrected = carried;
    options.coarse_corrections = 3;
    const RelaxSummary both = relax_area(mesh, corrected, pins, 0.99, options, &coarse, &coarse_uv);
    CHECK(swept.corrections == 0);
    CHECK(both.sweeps == 6);
    CHECK(both.corrections == 3);
    const double minimum = 2.0 * face_areas(mesh).sum();
    MESSAGE("energy / minimum: carried " << swept.energy_before / minimum << ", 6 sweeps "
                                         << swept.energy_after / minimum << ", with corrections "
                                         << both.energy_after / minimum);
    CHECK(both.energy_after - minimum < 0.9 * (swept.energy_after - minimum));
    CHECK(test::count_flips(mesh, corrected) == 0);
    CHECK(boundary_self_intersection(mesh, corrected).first < 0);
    CHECK((corrected.row(held.idx()) - carried.row(held.idx())).norm() == 0.0);
    CHECK(flat_quality(mesh, corrected).mean_abs_log_area <
          flat_quality(mesh, alone).mean_abs_log_area);

    // A coarser level that is not the one the map came from is refused.
    const CoarseMesh other = coarsen(test::cut_cylinder(1.0, 6.0, 16, 10), 50, {});
    Eigen::MatrixX2d uv = carried;
    const Eigen::MatrixX2d other_uv = coarse_map(other.mesh);
    CHECK_THROWS_AS(relax_area(mesh, uv, pins, 0.99, options, &other, &other_uv), InvalidInputError);
    options.coarse_corrections = -1;
    CHECK_THROWS_AS(options.validate(), InvalidInputError);
}

TEST_CASE(
    "multilevel: sweeps without coarse-grid corrections step every vertex and keep "
    "lowering the map's area")
{
    // The carried cylinder relaxed by sweeps alone: 24 sweeps in one call make the same map as
    // 12 and 12 more in a second call, whose first sweep steps every vertex, so each sweep of
    // the one call did too (with corrections, the vertices that lowered the energy little in a
    // sweep are left out of the next until a correction moves them all). The later sweeps still
    // lower the area error.
    const CarriedCylinder cylinder;
    const auto& [mesh, coarse, coarse_uv, carried] = cylinder;
    MultilevelOptions options;
    options.coarse_corrections = 0;
    options.tolerance = 0.0;
    options.area_tolerance = 0.0;
    options.relax_sweeps = 24;
    Eigen::MatrixX2d once = carried;
    relax_area(mesh, once, {}, 0.99, options, &coarse, &coarse_uv);
    options.relax_sweeps = 12;
    Eigen::MatrixX2d twice = carried;
    relax_area(mesh, twice, {}, 0.99, options, &coarse, &coarse_uv);
    const double at_12 = flat_quality(mesh, twice).mean_abs_log_area_normalized;
    relax_area(mesh, twice, {}, 0.99, options, &coarse, &coarse_uv);
    CHECK((once - twice).cwiseAbs().maxCoeff() == 0.0);
    CHECK(test::count_flips(mesh, once) == 0);
    const double at_24 = flat_quality(mesh, once).mean_abs_log_area_normalized;
    MESSAGE("mean |log area| after 12 sweeps " << at_12 << ", after 24 " << at_24);
    CHECK(at_24 < 0.8 * at_12);
}

TEST_CASE("multilevel: relax_area stops at the area tolerance, with the map within it")
{
    // A carried map of a cut cylinder relaxed to the schedule's end (area_tolerance 0), and
    // again with a tolerance between the area after the first correction and at the end: the
    // relaxation stops after a correction, short of the schedule, with the map's mean |log
    // area| (flat_quality()'s measure) at most the tolerance and no face flipped.
    const CarriedCylinder cylinder;
    const auto& [mesh, coarse, coarse_uv, carried] = cylinder;
    REQUIRE(test::count_flips(mesh, carried) == 0);
    MultilevelOptions options = six_sweeps();
    options.relax_sweeps = 12;
    options.coarse_corrections = 6;
    Eigen::MatrixX2d full = carried;
    const RelaxSummary whole = relax_area(mesh, full, {}, 0.99, options, &coarse, &coarse_uv);
    CHECK(whole.sweeps == 12);
    CHECK_FALSE(whole.area_within_tolerance);
    Eigen::MatrixX2d first = carried;
    options.relax_sweeps = 2;  // two sweeps and the first correction
    relax_area(mesh, first, {}, 0.99, options, &coarse, &coarse_uv);
    const double at_first = flat_quality(mesh, first).mean_abs_log_area_normalized;
    const double at_end = flat_quality(mesh, full).mean_abs_log_area_normalized;
    MESSAGE("mean |log area|: carried " << flat_quality(mesh, carried).mean_abs_log_area_normalized
                                        << ", after the first correction " << at_first
                                        << ", after 12 sweeps " << at_end);
    REQUIRE(at_end < 0.9 * at_first);

    options.relax_sweeps = 12;
    options.area_tolerance = 0.5 * (at_first + at_end);
    Eigen::MatrixX2d stopped = carried;
    const RelaxSummary early = relax_area(mesh, stopped, {}, 0.99, options, &coarse, &coarse_uv);
    CHECK(early.area_within_tolerance);
    CHECK(early.sweeps < 12);
    CHECK(early.sweeps % 2 == 0);  // after a correction
    CHECK(early.corrections == early.sweeps / 2);
    CHECK(flat_quality(mesh, stopped).mean_abs_log_area_normalized <= options.area_tolerance);
    CHECK(test::count_flips(mesh, stopped) == 0);
    CHECK(boundary_self_intersection(mesh, stopped).first < 0);

    options.area_tolerance = -1.0;
    CHECK_THROWS_AS(options.validate(), InvalidInputError);
}

TEST_CASE("multilevel: corrections solved iteratively over two levels lower the energy as the "
          "factorized ones do")
{
    // A cut cylinder carried up two levels; on the finest, the same relaxation with the
    // corrections' system factorized, and solved by conjugate gradients with V-cycles over the
    // coarser level and the one below it (direct_correction_vertices 0). The larger cylinder's
    // V-cycles sweep on two threads (the coarser level above 4096 vertices, where the machine
    // has two cores).
    int around = 48, along = 60, coarse_vertices = 150;
    SUBCASE("on one thread") {}
    SUBCASE("on two threads")
    {
        around = 128;
        along = 160;
        coarse_vertices = 1000;
    }
    const Mesh mesh = test::cut_cylinder(1.0, 6.0, around, along);
    const std::vector<CoarseMesh> levels = coarsen_levels(mesh, coarse_vertices, {});
    REQUIRE(levels.size() >= 2);
    const Eigen::MatrixX2d below_uv = coarse_map(levels[1].mesh);
    Eigen::MatrixX2d coarser_uv = prolongate(levels[0].mesh, levels[1], below_uv, 0.99);
    REQUIRE(test::count_flips(levels[0].mesh, coarser_uv) == 0);
    const Eigen::MatrixX2d carried = prolongate(mesh, levels[0], coarser_uv, 0.99);
    REQUIRE(test::count_flips(mesh, carried) == 0);
    const VertexHandle held = test::boundary_vertices(mesh).front();
    const Pins pins = {{held, carried.row(held.idx()).transpose()}};
    MultilevelOptions options = six_sweeps();
    options.coarse_corrections = 0;
    Eigen::MatrixX2d alone = carried;
    const RelaxSummary swept =
        relax_area(mesh, alone, pins, 0.99, options, &levels[0], &coarser_uv);
    options.coarse_corrections = 3;
    Eigen::MatrixX2d factorized = carried;
    const RelaxSummary direct = relax_area(mesh, factorized, pins, 0.99, options, &levels[0],
                                           &coarser_uv, true, &levels[1], &below_uv);
    options.direct_correction_vertices = 0;
    Eigen::MatrixX2d iterated = carried;
    const RelaxSummary iterative = relax_area(mesh, iterated, pins, 0.99, options, &levels[0],
                                              &coarser_uv, true, &levels[1], &below_uv);
    const double minimum = 2.0 * face_areas(mesh).sum();
    MESSAGE(levels[0].mesh.n_vertices() << " coarser vertices; energy / minimum: carried "
            << swept.energy_before / minimum << ", sweeps alone "
                                         << swept.energy_after / minimum << ", factorized "
                                         << direct.energy_after / minimum << ", iterative "
                                         << iterative.energy_after / minimum);
    CHECK(iterative.corrections == 3);
    // The iterative steps are not the factorized ones, but they remove most of what the sweeps
    // leave, as those do.
    CHECK(direct.energy_after - minimum < 0.9 * (swept.energy_after - minimum));
    CHECK(iterative.energy_after - minimum < 0.9 * (swept.energy_after - minimum));
    CHECK(iterative.energy_after - minimum < 1.25 * (direct.energy_after - minimum));
    CHECK(test::count_flips(mesh, iterated) == 0);
    CHECK(boundary_self_intersection(mesh, iterated).first < 0);
    CHECK((iterated.row(held.idx()) - carried.row(held.idx())).norm() == 0.0);

    // A level below that is not the coarser level's is refused; so is a negative threshold.
    Eigen::MatrixX2d uv = carried;
    CHECK_THROWS_AS(relax_area(mesh, uv, pins, 0.99, options, &levels[0], &coarser_uv, true,
                               &levels[0], &coarser_uv),
                    InvalidInputError);
    options.direct_correction_vertices = -1;
    CHECK_THROWS_AS(options.validate(), InvalidInputError);
}

TEST_CASE("multilevel: the coarse operator by blocks equals the Galerkin product P^T H P")
{
    // A carried map of a cut cylinder with one boundary vertex held: the operator of the
    // coarse-grid corrections against the product of the sparse matrices it replaces.
    const Mesh mesh = test::cut_cylinder(1.0, 6.0, 24, 30);
    const CoarseMesh coarse = coarsen(mesh, 200, {});
    const Eigen::MatrixX2d coarse_uv = coarse_map(coarse.mesh);
    Eigen::MatrixX2d uv = prolongate(mesh, coarse, coarse_uv, 0.99);
    relax_area(mesh, uv, {}, 0.99);  // off the carry, so that the faces differ
    REQUIRE(test::count_flips(mesh, uv) == 0);
    const int n = static_cast<int>(mesh.n_vertices());
    std::vector<int> slot(n);
    for (int v = 0; v < n; ++v)
        slot[v] = v;
    slot[test::boundary_vertices(mesh).front().idx()] = -1;  // held
    const std::vector<detail::FaceOperator> faces = detail::face_operators(mesh);
    const Eigen::VectorXd x = detail::interleaved(uv);
    Eigen::SparseMatrix<double> P =
        detail::coarse_interpolation(coarse.mesh, coarse.coarse_of, coarse_uv, uv);
    const Eigen::SparseMatrix<double, Eigen::RowMajor> rows = P;
    const Eigen::SparseMatrix<double> blocks = detail::galerkin_operator(faces, slot, x.data(), 0.99, rows);

    P.prune([&](Eigen::Index r, Eigen::Index, double) { return slot[r / 2] >= 0; });
    detail::PolishHessian hessian(faces, slot, 2 * n);
    hessian.assemble(faces, x.data(), 0.99);
    const Eigen::SparseMatrix<double> full = hessian.matrix().selfadjointView<Eigen::Upper>();
    const Eigen::SparseMatrix<double> product =
        (P.transpose() * full * P).triangularView<Eigen::Upper>();

    check_upper_equals(blocks, product, "coarse operator");
}

TEST_CASE("multilevel: the level below's operator by blocks equals P2^T C P2, on one thread or two")
{
    // The corrections' operator C on a carried map of a cut cylinder, and the interpolation
    // from a coarser level of it: the iterative corrections' operator of the level below.
    const Mesh mesh = test::cut_cylinder(1.0, 6.0, 24, 30);
    const CoarseMesh coarse = coarsen(mesh, 300, {});
    const CoarseMesh below = coarsen(coarse.mesh, 80, {});
    const Eigen::MatrixX2d below_uv = coarse_map(below.mesh);
    Eigen::MatrixX2d coarse_uv = prolongate(coarse.mesh, below, below_uv, 0.99);
    relax_area(coarse.mesh, coarse_uv, {}, 0.99);
    Eigen::MatrixX2d uv = prolongate(mesh, coarse, coarse_uv, 0.99);
    relax_area(mesh, uv, {}, 0.99);
    REQUIRE(test::count_flips(mesh, uv) == 0);
    const int n = static_cast<int>(mesh.n_vertices());
    std::vector<int> slot(n);
    for (int v = 0; v < n; ++v)
        slot[v] = v;
    const std::vector<detail::FaceOperator> faces = detail::face_operators(mesh);
    const Eigen::VectorXd x = detail::interleaved(uv);
    const Eigen::SparseMatrix<double, Eigen::RowMajor> rows =
        detail::coarse_interpolation(coarse.mesh, coarse.coarse_of, coarse_uv, uv);
    const Eigen::SparseMatrix<double> C = detail::galerkin_operator(faces, slot, x.data(), 0.99, rows);
    const Eigen::SparseMatrix<double> P2 =
        detail::coarse_interpolation(below.mesh, below.coarse_of, below_uv, coarse_uv);
    const Eigen::SparseMatrix<double, Eigen::RowMajor> rows2 = P2;

    const Eigen::SparseMatrix<double> one = detail::galerkin_of_operator(C, rows2, 1);
    const Eigen::SparseMatrix<double> two = detail::galerkin_of_operator(C, rows2, 2);
    const Eigen::SparseMatrix<double> full = C.selfadjointView<Eigen::Upper>();
    const Eigen::SparseMatrix<double> product =
        (P2.transpose() * full * P2).triangularView<Eigen::Upper>();

    check_upper_equals(one, product, "level below");
    // Two threads: the same pattern and the same bits.
    REQUIRE(two.nonZeros() == one.nonZeros());
    CHECK(std::equal(one.outerIndexPtr(), one.outerIndexPtr() + one.outerSize() + 1,
                     two.outerIndexPtr()));
    CHECK(std::equal(one.innerIndexPtr(), one.innerIndexPtr() + one.nonZeros(), two.innerIndexPtr()));
    CHECK(std::equal(one.valuePtr(), one.valuePtr() + one.nonZeros(), two.valuePtr()));
}

TEST_CASE("multilevel: the boundary guard keeps boundary parts a clearance apart")
{
    // Tutte's map of a cut cylinder: its boundary a convex polygon, two parts across it far
    // apart. Vertex a is moved toward the edge (b, c) across the polygon.
    const Mesh mesh = test::cut_cylinder(1.0, 6.0, 32, 40);
    const Eigen::MatrixX2d uv = tutte_embedding(mesh);
    const std::vector<int> walk = boundary_walk(mesh);
    const std::size_t half = walk.size() / 2;
    const int a = walk[0], b = walk[half], c = walk[half + 1];
    Eigen::VectorXd xv = detail::interleaved(uv);
    detail::BoundaryGuard guard(mesh);
    guard.rebuild(xv.data());
    const double clearance = guard.clearance();
    REQUIRE(clearance > 0.0);
    CHECK(guard.near_contacts(xv.data()).empty());

    // Points on the far side's edge's inner normal, at a given distance from its midpoint.
    const Eigen::Vector2d pb = uv.row(b).transpose(), pc = uv.row(c).transpose();
    const Eigen::Vector2d mid = 0.5 * (pb + pc);
    Eigen::Vector2d inward(-(pc - pb).y(), (pc - pb).x());
    inward.normalize();
    if (inward.dot(Eigen::Vector2d(uv.colwise().mean().transpose()) - mid) < 0.0)
        inward = -inward;
    const Eigen::Vector2d from = uv.row(a).transpose();
    const auto at = [&](double distance) { return Eigen::Vector2d(mid + distance * inward); };
    CHECK(guard.allows(xv.data(), a, from, at(3.0 * clearance)));
    CHECK_FALSE(guard.allows(xv.data(), a, from, at(0.5 * clearance)));  // nearer than clearance
    CHECK_FALSE(guard.allows(xv.data(), a, from, at(-0.5 * clearance)));  // across: crossing
    CHECK(guard.gap(xv.data(), a, at(0.5 * clearance)) < clearance);

    // Once a is that near, the contact is found at all its ends, and a may widen the gap but
    // not narrow it.
    xv[2 * a] = at(0.5 * clearance).x();
    xv[2 * a + 1] = at(0.5 * clearance).y();
    guard.rebuild(xv.data());
    const std::vector<int> ends = guard.near_contacts(xv.data());
    for (const int v : {a, b, c})
        CHECK(std::count(ends.begin(), ends.end(), v) == 1);
    const Eigen::Vector2d near = at(0.5 * guard.clearance());
    CHECK(guard.allows(xv.data(), a, near, at(0.8 * guard.clearance())));
    CHECK_FALSE(guard.allows(xv.data(), a, near, at(0.2 * guard.clearance())));
}

TEST_CASE("multilevel: relax_area and the options refuse what they cannot use")
{
    const Mesh mesh = test::cut_cylinder(1.0, 6.0, 16, 10);
    Eigen::MatrixX2d uv = tutte_embedding(mesh);
    uv.col(0) *= -1.0;  // every face flipped
    CHECK_THROWS_AS(relax_area(mesh, uv, {}, 0.99), InvalidInputError);
    Eigen::MatrixX2d short_map = Eigen::MatrixX2d::Zero(3, 2);
    CHECK_THROWS_AS(relax_area(mesh, short_map, {}, 0.99), InvalidInputError);
    MultilevelOptions options;
    options.coarse_vertices = 50;
    CHECK_THROWS_AS(options.validate(), InvalidInputError);
    options.coarse_vertices = -1;
    CHECK_THROWS_AS(options.validate(), InvalidInputError);
    options.coarse_vertices = 0;
    options.max_energy_ratio = 1.0;
    CHECK_THROWS_AS(options.validate(), InvalidInputError);
    options.max_energy_ratio = 1.05;
    CHECK_NOTHROW(options.validate());
}

TEST_CASE("multilevel: coarsen_levels shrinks by levels, keeps corners, carries one-to-one")
{
    const Mesh fine = test::cut_cylinder(1.0, 6.0, 48, 60);
    const std::vector<VertexHandle> boundary = test::boundary_vertices(fine);
    const std::vector<VertexHandle> keep = {boundary[0], boundary[boundary.size() / 3],
                                            boundary[2 * boundary.size() / 3]};
    const std::vector<CoarseMesh> levels = coarsen_levels(fine, 100, keep);
    REQUIRE(levels.size() >= 3);
    std::set<int> kept;  // the kept vertices' indices on the current level
    for (auto v : keep)
        kept.insert(v.idx());
    std::size_t above = fine.n_vertices();
    for (const CoarseMesh& level : levels)
    {
        const std::size_t n = level.mesh.n_vertices();
        CHECK(n < above);
        CHECK(n >= above / 5);  // about a quarter per level, never a jump to the bottom
        // A kept boundary vertex (a corner of the layout) never takes a boundary neighbour's
        // star: that star could not be put back onto its edge where the map turns sharply.
        for (const Collapse& collapse : level.collapses)
            if (collapse.across >= 0)
                CHECK(kept.count(collapse.v1) == 0);
        std::set<int> next;
        for (int v : kept)
        {
            REQUIRE(level.coarse_of[v] >= 0);
            next.insert(level.coarse_of[v]);
        }
        kept = next;
        above = n;
    }
    CHECK(levels.back().mesh.n_vertices() <= 110);
    CHECK_THROWS_AS(coarsen_levels(fine, 2, keep), InvalidInputError);

    // Carried up level by level, relaxed on each: flip-free and simple all the way.
    Eigen::MatrixX2d uv = coarse_map(levels.back().mesh);
    for (std::size_t l = levels.size(); l-- > 0;)
    {
        const Mesh& up = l == 0 ? fine : levels[l - 1].mesh;
        const Eigen::MatrixX2d coarser_uv = uv;
        uv = prolongate(up, levels[l], uv, 0.99);
        REQUIRE(test::count_flips(up, uv) == 0);
        relax_area(up, uv, {}, 0.99, {}, &levels[l], &coarser_uv);
        CHECK(test::count_flips(up, uv) == 0);
        CHECK(boundary_self_intersection(up, uv).first < 0);
    }
    CHECK(flat_quality(fine, uv).mean_abs_log_area < 0.02);
}

TEST_CASE("multilevel: coarsening asked for no new chords joins no two boundary vertices anew")
{
    // A chord's face lies between the layout circle and the chord in the coarse map's Tutte
    // start: a sliver wherever the face is wide in 3D. Asked, every level's chords are ones the
    // level above had already; the cut tree phantom's outlets are tube ends that the decimation
    // otherwise triangulates across (the unasked hierarchy's new chords show it).
    FlattenOptions cut_only;
    cut_only.refinement = Refinement::None;
    const Mesh fine = flatten(test::test_tree_phantom(10), cut_only).mesh;
    const auto new_chords = [&](const std::vector<CoarseMesh>& levels) {
        int made = 0;
        const Mesh* above = &fine;
        for (const CoarseMesh& level : levels)
        {
            const Mesh& m = level.mesh;
            for (auto e : m.edges())
            {
                if (m.is_boundary(e) || !m.is_boundary(e.v0()) || !m.is_boundary(e.v1()))
                    continue;
                const auto h = above->find_halfedge(VertexHandle(level.fine_of[e.v0().idx()]),
                                                    VertexHandle(level.fine_of[e.v1().idx()]));
                if (!h.is_valid() || above->is_boundary(above->edge_handle(h)))
                    ++made;
            }
            above = &m;
        }
        return made;
    };
    const std::vector<CoarseMesh> levels = coarsen_levels(fine, 1000, {}, 0, true);
    REQUIRE(levels.size() >= 2);
    CHECK(levels.back().mesh.n_vertices() <= 1100);
    const std::vector<CoarseMesh> unasked = coarsen_levels(fine, 1000, {});
    const int made = new_chords(unasked);
    MESSAGE("new chords: " << new_chords(levels) << " asked, " << made << " unasked");
    CHECK(new_chords(levels) == 0);
    CHECK(made > 0);
}

TEST_CASE("multilevel: levels that keep the boundary insert interior vertices only")
{
    const Mesh fine = test::cut_cylinder(1.0, 6.0, 48, 60);
    const std::size_t n_boundary = test::boundary_vertices(fine).size();
    const std::vector<CoarseMesh> first = coarsen_levels(fine, 100, {}, 1);
    const std::vector<CoarseMesh> every =
        coarsen_levels(fine, 100, {}, std::numeric_limits<std::size_t>::max());
    REQUIRE(first.size() >= 2);
    REQUIRE(!every.empty());
    // The first level keeps every boundary vertex; below it the boundary is decimated.
    for (VertexHandle v : test::boundary_vertices(fine))
        CHECK(first[0].coarse_of[v.idx()] >= 0);
    CHECK(test::boundary_vertices(first.back().mesh).size() < n_boundary);
    // Kept on every level, and the vertex count counts the interior only.
    CHECK(test::boundary_vertices(every.back().mesh).size() == n_boundary);
    CHECK(every.back().mesh.n_vertices() > n_boundary);
    CHECK(every.back().mesh.n_vertices() <= n_boundary + 110);
    for (const CoarseMesh& level : every)
        for (const Collapse& collapse : level.collapses)
            CHECK(collapse.across < 0);  // no boundary vertex removed

    // The carried map's boundary is the coarse map's: every boundary vertex where it was.
    const Eigen::MatrixX2d coarse_uv = coarse_map(every.back().mesh);
    Eigen::MatrixX2d uv = coarse_uv;
    for (std::size_t l = every.size(); l-- > 0;)
        uv = prolongate(l == 0 ? fine : every[l - 1].mesh, every[l], uv, 0.99);
    std::vector<int> coarse_index(fine.n_vertices());
    for (std::size_t v = 0; v < fine.n_vertices(); ++v)
    {
        int c = static_cast<int>(v);
        for (const CoarseMesh& level : every)
            c = level.coarse_of[c];
        coarse_index[v] = c;
    }
    for (VertexHandle v : test::boundary_vertices(fine))
    {
        REQUIRE(coarse_index[v.idx()] >= 0);
        CHECK((uv.row(v.idx()) - coarse_uv.row(coarse_index[v.idx()])).norm() == 0.0);
    }
    CHECK(test::count_flips(fine, uv) == 0);
    CHECK(boundary_self_intersection(fine, uv).first < 0);
}

TEST_CASE("multilevel: a carried map above max_energy_ratio is refused for the full-resolution map")
{
    const Mesh mesh = test::test_tree_phantom(3);
    FlattenOptions options;
    options.multilevel.coarse_vertices = 400;
    const FlattenResult carried = flatten(mesh, options);
    REQUIRE(noted(carried, "coarse-to-fine: the map solved on 400 of"));
    REQUIRE_FALSE(noted(carried, "solved again at full resolution"));

    // Every map is above its isometric minimum, so this bound refuses both hierarchies' maps.
    options.multilevel.max_energy_ratio = 1.0 + 1e-12;
    const FlattenResult refused = flatten(mesh, options);
    FlattenOptions full;
    full.multilevel.coarse_vertices = 0;
    const FlattenResult direct = flatten(mesh, full);
    CHECK(noted(refused, "times its minimum (more than"));
    CHECK(noted(refused, "the map solved again at full resolution"));
    REQUIRE(refused.uv.rows() == direct.uv.rows());
    REQUIRE(carried.uv.rows() == direct.uv.rows());
    CHECK((refused.uv - direct.uv).cwiseAbs().maxCoeff() == 0.0);
    CHECK((carried.uv - direct.uv).cwiseAbs().maxCoeff() > 0.0);
    CHECK(refused.quality.flipped_triangles == 0);
    CHECK(refused.quality.overlapping_triangles == 0);
}

TEST_CASE("multilevel: a carried map above max_energy_ratio is polished before it is refused")
{
    // Without its relaxation a carried map ends far above its minimum; the area polish's
    // Newton steps take it below the bound, and the map is kept without solving it again.
    const Mesh mesh = test::test_tree_phantom(3);
    FlattenOptions options;
    options.multilevel.coarse_vertices = 400;
    options.multilevel.relax_sweeps = 1;
    options.multilevel.coarse_corrections = 0;
    const FlattenResult r = flatten(mesh, options);
    REQUIRE(noted(r, "coarse-to-fine: the map solved on 400 of"));
    CHECK(noted(r, "coarse-to-fine: above the bound, polished ("));
    check_carry_kept(r);
}

TEST_CASE("multilevel: with overlaps kept the map is carried, the inlet's pins held once")
{
    // Under OverlapPolicy::Keep the inlet stays pinned at its layout place, and the levels
    // that keep the boundary hold it too: a pin held twice made untangle() refuse every carry,
    // so each such map was solved again at full resolution.
    const Mesh mesh = test::test_tree_phantom(10, 11);
    FlattenOptions options;
    options.overlaps = OverlapPolicy::Keep;
    const FlattenResult r = flatten(mesh, options);
    CHECK(noted(r, "coarse-to-fine: the map solved on 4000 of"));
    CHECK_FALSE(noted(r, "pinned twice"));
    CHECK_FALSE(noted(r, "solved again at full resolution"));
    CHECK_FALSE(noted(r, "tried again with the whole boundary"));
    CHECK(r.quality.flipped_triangles == 0);
    // Its carry's sweeps converge below 1.001 times the minimum: not finished by Newton steps.
    const auto carried = relaxed_ratios(r, "coarse-to-fine: ");
    REQUIRE(carried.size() == 1);
    CHECK(carried[0].second <= 1.001);
    CHECK_FALSE(noted(r, "coarse-to-fine: finished with"));
}

TEST_CASE("multilevel: a coarse SLIM whose clamped direction stops descending goes on and is carried")
{
    // The 30-outlet tree phantom, seed 33: from the layout circle its coarse SLIM reaches maps
    // whose faces are compressed below the clamp of SLIM's weights; there the clamped proxy's
    // direction no longer descended and SLIM stopped far above its final energy, whose carry
    // was refused and the map solved again on a larger mesh. The proxy matrix applied to the
    // true gradient descends.
    const Mesh mesh = test::test_tree_phantom(30, 33);
    const FlattenResult r = flatten(mesh, FlattenOptions{});
    CHECK(noted(r, "coarse-to-fine: the map solved on 4000 of"));
    CHECK(noted(r, "steps along the true gradient"));
    check_carry_kept(r);
    CHECK(r.quality.mean_abs_log_area_normalized < 0.03);
}

TEST_CASE("multilevel: the carry's finish takes Newton steps whatever the area polish's minimizer")
{
    // The 16-outlet tree phantom of seed 1 at edge 1.2 keeps its look retry's pulled map, whose
    // carry is finished. With the area polish set to L-BFGS the finish still takes its three
    // Newton steps, not the polish's up to 1000 L-BFGS iterations.
    const Mesh mesh = test::test_tree_phantom(16, 1, 1.2);
    FlattenOptions options;
    options.area_polish.newton = false;
    const FlattenResult r = flatten(mesh, options);
    const auto finished = relaxed_ratios(r, "coarse-to-fine: finished with ");
    REQUIRE(finished.size() == 1);
    CHECK(noted(r, "coarse-to-fine: finished with 3 Newton steps"));
    CHECK(finished[0].second < finished[0].first);
    check_carry_kept(r);
}

TEST_CASE("multilevel: a carry whose relaxation stops short of its minimum is finished by Newton steps")
{
    // The 30-outlet tree phantom, seed 1 (edge 0.5): its coarse map moves far from the layout
    // circle, and the finest level's 16 sweeps end above 1.001 times the isometric minimum,
    // where the sweeps are still lowering it; the carry then finishes that level with Newton
    // steps of the whole map, and the map is kept.
    const Mesh mesh = test::test_tree_phantom(30, 1, 0.5);
    const FlattenResult r = flatten(mesh, FlattenOptions{});
    const auto carried = relaxed_ratios(r, "coarse-to-fine: ");
    const auto further = relaxed_ratios(r, "coarse-to-fine: finished with ");
    REQUIRE(carried.size() == 1);
    CHECK(carried[0].second > 1.001);
    REQUIRE(further.size() == 1);
    CHECK(further[0].first == doctest::Approx(carried[0].second).epsilon(1e-4));
    CHECK(further[0].second < carried[0].second);
    check_carry_kept(r);
    CHECK(r.quality.mean_abs_log_area_normalized < 0.03);
}

TEST_CASE(
    "multilevel: a carry whose sweeps stall above 1.01 times its minimum is finished by "
    "Newton steps")
{
    // The 20-outlet tree phantom of seed 1 at edge 0.75, its coarse map restarted from the
    // layout circle on the coarse mesh itself (MultilevelOptions::coarser_start off; from the
    // coarser start its carry ends near its minimum): the finest level's sweeps, held by the
    // boundary's near contacts, stop lowering the energy at about 1.014 times the isometric
    // minimum. The carry is finished all the same, and ends nearer its minimum, one-to-one.
    // Its first three Newton steps remove most of the excess and leave it above 1.001 times
    // the minimum, so the finish goes on, and removes nine tenths of the excess (three steps
    // removed three quarters).
    const Mesh mesh = test::test_tree_phantom(20, 1, 0.75);
    FlattenOptions options;
    options.multilevel.coarser_start = false;
    const FlattenResult r = flatten(mesh, options);
    const auto carried = relaxed_ratios(r, "coarse-to-fine: ");
    const auto further = relaxed_ratios(r, "coarse-to-fine: finished with ");
    REQUIRE(carried.size() == 1);
    CHECK(carried[0].second > 1.01);
    REQUIRE(further.size() == 1);
    CHECK(further[0].second - 1.0 <= 0.1 * (carried[0].second - 1.0));
    CHECK_FALSE(noted(r, "coarse-to-fine: finished with 3 Newton steps"));
    check_carry_kept(r);
    CHECK(r.quality.overlapping_triangles == 0);
    CHECK(r.look.outlets_below_inlet == 0);
    CHECK(r.quality.mean_abs_log_area_normalized < 0.03);
}

TEST_CASE("multilevel: a carry whose relaxation stalls far above its minimum goes to the second "
          "try without the polish")
{
    // Pulmonary Glenn cut along the direction field's streamlines, solved on a coarse mesh of
    // 3 500 vertices: the look retry's pulled map carried to full resolution relaxes to about
    // 42 times its minimum in 16 sweeps (squeezed faces held by the boundary's near contacts).
    // Polished at full resolution, such a carry spends the polish's whole budget and can still
    // end above the bound; the whole boundary kept on every level solves it. The plan is the
    // one the join policy made before a held route's cut back was bounded
    // (test::FirstCutBackJoin). At the default 4 000 vertices this tree's pulled map has no
    // outlet below the inlet, and its carry does not stall.
    const TreeSurface surface = load_tree_surface(std::string(VESSEL_SHARED_DATA) +
                                                  "/svfsi-tests/pulmonary-glenn-wall.ply");
    FlattenOptions options;
    options.cuts.stream_field = StreamField::Direction;
    options.cuts.joiner = std::make_shared<test::FirstCutBackJoin>();
    options.multilevel.coarse_vertices = 3500;
    const FlattenResult r = flatten(surface.mesh, options);
    const auto carried = relaxed_ratios(r, "coarse-to-fine: ");
    REQUIRE(carried.size() == 2);
    // The first carry stalled: far above the minimum, less than half its excess removed.
    CHECK(carried[0].second > 10.0);
    CHECK(carried[0].second - 1.0 > 0.5 * (carried[0].first - 1.0));
    CHECK(noted(r, "the carried map's relaxation stalled at"));
    CHECK(noted(r, "tried again with the whole boundary kept on every level"));
    CHECK_FALSE(noted(r, "above the bound, polished"));
    // The second try's carry converges and the map is one-to-one with its look whole.
    CHECK(carried[1].second <= 1.05);
    CHECK(r.quality.flipped_triangles == 0);
    CHECK(r.quality.overlapping_triangles == 0);
    CHECK(boundary_self_intersection(r.mesh, r.uv).first == -1);
    CHECK(r.look.outlets_below_inlet == 0);
    CHECK(r.quality.mean_abs_log_area_normalized < 0.03);
}

TEST_CASE(
    "multilevel: a restart starts from the map a RestartStart gives, or from its own where "
    "it gives none")
{
    FlattenOptions cut_only;
    cut_only.refinement = Refinement::None;
    const Mesh mesh = flatten(test::test_tree_phantom(3), cut_only).mesh;
    const FlattenOptions options;
    FlattenResult own;
    detail::refine_map(mesh, {}, options, "", std::string("asked"), own);
    REQUIRE(own.injective.iterations > 1);
    CHECK(noted(own, "asked; restarted from the Tutte embedding"));

    // A start that cannot make a map: the restart's own start, the same map to the bit.
    const detail::RestartStart none = [](const FlattenOptions&, std::vector<std::string>& notes) {
        notes.push_back("gave none");
        return Eigen::MatrixX2d();
    };
    FlattenResult fallen;
    detail::refine_map(mesh, {}, options, "", std::string("asked"), fallen, nullptr, nullptr,
                       &none);
    CHECK(noted(fallen, "(the start solved on a coarser mesh was not used)"));
    CHECK(noted(fallen, "coarser start: gave none"));
    REQUIRE(fallen.uv.rows() == own.uv.rows());
    CHECK((fallen.uv - own.uv).cwiseAbs().maxCoeff() == 0.0);

    // A start at the restart's own end: SLIM goes on from it, and stops sooner.
    const Eigen::MatrixX2d end = own.uv;
    const detail::RestartStart near = [&end](const FlattenOptions&, std::vector<std::string>&) {
        return end;
    };
    FlattenResult given;
    detail::refine_map(mesh, {}, options, "", std::string("asked"), given, nullptr, nullptr, &near);
    CHECK(noted(given, "solved on a coarser mesh first"));
    // The area polish after SLIM moves its map a little off SLIM's own minimum.
    CHECK(given.injective.initial_energy <= 1.01 * own.injective.final_energy);
    CHECK(given.injective.iterations < own.injective.iterations);
    CHECK(given.injective.final_energy <= own.injective.final_energy * (1.0 + 1e-3));
    const FlatQuality q = flat_quality(mesh, given.uv);
    CHECK(q.flipped_triangles == 0);
    CHECK(q.overlapping_triangles == 0);
}

TEST_CASE(
    "multilevel: on a tree of ten outlets the coarse map's restart is solved coarser first "
    "and the map keeps its look and area")
{
    // The restart from the layout circle unrolls ten branches: its SLIM iterations are made
    // first on a decimation of the coarse mesh to a quarter of its vertices (NestedStart in
    // solve_map.cpp), so that the coarse mesh's SLIM starts near its end and makes fewer. The
    // map carried from there is one-to-one, keeps the inlet below every outlet, and its area
    // is within issue 27's 1.5x of the map restarted from the circle on the coarse mesh itself.
    const Mesh mesh = tree_phantom({10, 3.0, 0.5, 3});
    const FlattenResult r = flatten(mesh, FlattenOptions());
    REQUIRE(noted(r, "coarse-to-fine: the map solved on 4000 of"));
    CHECK(noted(r,
                "coarse: the map at the layout overlaps itself (its boundary crosses); "
                "restarted from the layout circle, solved on a coarser mesh first"));
    CHECK(noted(r, "coarse: coarser start: solved on "));
    check_carry_kept(r);
    CHECK(boundary_self_intersection(r.mesh, r.uv).first == -1);
    CHECK(r.look.outlets == 10);
    CHECK(r.look.outlets_below_inlet == 0);
    FlattenOptions circle;
    circle.multilevel.coarser_start = false;
    const FlattenResult from_circle = flatten(mesh, circle);
    CHECK_FALSE(noted(from_circle, "coarser start"));
    REQUIRE_FALSE(from_circle.look_retry.kept);  // both are the default map's
    REQUIRE_FALSE(r.look_retry.kept);
    CHECK(r.injective.iterations < from_circle.injective.iterations);
    CHECK(r.quality.mean_abs_log_area_normalized <=
          1.5 * from_circle.quality.mean_abs_log_area_normalized);
    MESSAGE("10-outlet tree: coarse SLIM iterations "
            << r.injective.iterations << " against " << from_circle.injective.iterations
            << ", mean |log area| " << r.quality.mean_abs_log_area_normalized << " against "
            << from_circle.quality.mean_abs_log_area_normalized);
}

namespace {

// BoundaryGuard's answers checked against a search over every boundary edge, for moves of
// every \p stride-th boundary vertex of the map \p x up to the guard's largest step in eight
// directions and toward its nearest non-adjacent edge, and for near_pairs() at two distances.
void check_guard_against_every_edge(const Mesh& mesh, const Eigen::VectorXd& x, int stride)
{
    std::vector<std::array<int, 2>> edges;
    std::vector<int> next(mesh.n_vertices(), -1), prev(mesh.n_vertices(), -1);
    for (auto h : mesh.halfedges())
        if (h.is_boundary())
        {
            edges.push_back({h.from().idx(), h.to().idx()});
            next[h.from().idx()] = h.to().idx();
            prev[h.to().idx()] = h.from().idx();
        }
    const auto at = [&](int v) { return Eigen::Vector2d(x[2 * v], x[2 * v + 1]); };
    detail::BoundaryGuard guard(mesh);
    guard.rebuild(x.data());
    const double clearance = guard.clearance();
    // Every edge that shares no vertex with v's edge (v, w), v at p: visit(gap, gap from `from`).
    const auto for_other_edges = [&](int v, const Eigen::Vector2d& p, const auto& visit) {
        for (const int w : {prev[v], next[v]})
            for (const auto& e : edges)
                if (e[0] != v && e[1] != v && e[0] != w && e[1] != w)
                    visit(detail::segment_distance(p, at(w), at(e[0]), at(e[1])), w, e);
    };
    int refused = 0, probes = 0;
    for (std::size_t k = 0; k < edges.size(); k += static_cast<std::size_t>(stride))
    {
        const int v = edges[k][0];
        const Eigen::Vector2d from = at(v);
        // The nearest other edge's nearer end, for a probe toward it.
        Eigen::Vector2d toward = from + Eigen::Vector2d(guard.max_step(), 0.0);
        double nearest = std::numeric_limits<double>::infinity();
        for_other_edges(v, from, [&](double gap, int, const std::array<int, 2>& e) {
            if (gap < nearest)
            {
                nearest = gap;
                toward = (at(e[0]) - from).norm() < (at(e[1]) - from).norm() ? at(e[0]) : at(e[1]);
            }
        });
        std::vector<Eigen::Vector2d> moves;
        for (int k = 0; k < 8; ++k)
            moves.push_back(from + guard.max_step() * Eigen::Vector2d(std::cos(k * M_PI / 4),
                                                                      std::sin(k * M_PI / 4)));
        const Eigen::Vector2d step = toward - from;
        if (step.norm() > 0.0)
            for (const double share : {0.5, 1.0})
                moves.push_back(from + share * std::min(step.norm(), guard.max_step()) *
                                           step.normalized());
        for (const Eigen::Vector2d& p : moves)
        {
            bool clear = true;
            double gap = clearance;
            for_other_edges(v, p, [&](double to_p, int w, const std::array<int, 2>& e) {
                const double to_from = detail::segment_distance(from, at(w), at(e[0]), at(e[1]));
                clear = clear && (to_p >= clearance || (to_p > 0.0 && to_p >= to_from));
                gap = std::min(gap, to_p);
            });
            ++probes;
            refused += clear ? 0 : 1;
            CHECK(guard.allows(x.data(), v, from, p) == clear);
            CHECK(guard.gap(x.data(), v, p) == gap);
        }
    }
    MESSAGE(probes << " moves, " << refused << " refused");
    CHECK(refused > 0);  // the probes reach the clearance somewhere
    for (const double distance : {clearance, 0.5 * guard.mean_edge()})
    {
        // Every pair whose u ranges come within the distance, swept in the order of their
        // smallest u.
        std::vector<std::size_t> by_u(edges.size());
        std::iota(by_u.begin(), by_u.end(), std::size_t{0});
        const auto u_lo = [&](std::size_t i) {
            return std::min(at(edges[i][0]).x(), at(edges[i][1]).x());
        };
        const auto u_hi = [&](std::size_t i) {
            return std::max(at(edges[i][0]).x(), at(edges[i][1]).x());
        };
        std::sort(by_u.begin(), by_u.end(),
                  [&](std::size_t i, std::size_t j) { return u_lo(i) < u_lo(j); });
        std::vector<int> ends;
        for (std::size_t i = 0; i < by_u.size(); ++i)
            for (std::size_t j = i + 1;
                 j < by_u.size() && u_lo(by_u[j]) <= u_hi(by_u[i]) + distance; ++j)
            {
                const auto &e = edges[by_u[i]], &f = edges[by_u[j]];
                if (e[0] == f[0] || e[0] == f[1] || e[1] == f[0] || e[1] == f[1])
                    continue;
                if (detail::segment_distance(at(e[0]), at(e[1]), at(f[0]), at(f[1])) < distance)
                    ends.insert(ends.end(), {e[0], e[1], f[0], f[1]});
            }
        std::sort(ends.begin(), ends.end());
        ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
        CHECK(guard.near_pairs(x.data(), distance) == ends);
    }
}

}  // namespace

TEST_CASE("multilevel: the boundary guard answers as a search over every boundary edge")
{
    SUBCASE("a tree's map, its branches laid side by side")
    {
        const FlattenResult flat = flatten(test::test_tree_phantom(10));
        REQUIRE(flat.uv.rows() == static_cast<Eigen::Index>(flat.mesh.n_vertices()));
        check_guard_against_every_edge(flat.mesh, detail::interleaved(flat.uv), 3);
    }
    SUBCASE("a square fanned from its centre, one side split into many short edges")
    {
        // Cells two mean edges wide: far more cells than entries, so the guard keeps its
        // entries sorted instead of a run per cell.
        Mesh mesh;
        std::vector<VertexHandle> ring;
        const int pieces = 10000;
        for (int i = 0; i < pieces; ++i)
            ring.push_back(mesh.add_vertex(Mesh::Point(1000.0 * i / pieces, 0.0, 0.0)));
        for (const auto& [u, v] : {std::pair{1000.0, 0.0}, {1000.0, 1000.0}, {0.0, 1000.0}})
            ring.push_back(mesh.add_vertex(Mesh::Point(u, v, 0.0)));
        const VertexHandle centre = mesh.add_vertex(Mesh::Point(500.0, 500.0, 0.0));
        for (std::size_t i = 0; i < ring.size(); ++i)
            mesh.add_face(centre, ring[i], ring[(i + 1) % ring.size()]);
        Eigen::VectorXd x(2 * mesh.n_vertices());
        for (auto v : mesh.vertices())
            x.segment<2>(2 * v.idx()) << mesh.point(v)[0], mesh.point(v)[1];
        check_guard_against_every_edge(mesh, x, 97);
    }
}
