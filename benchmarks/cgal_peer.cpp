// The CGAL peer pipeline (see cgal_peer.h): what a user without libvessel would assemble from
// CGAL 5.5 and Boost Graph for the same stages, timed under the same Table 1 names.
//   Z   boundary cycles, jet fitting (Monge_via_jet_fitting, degree 2, ball of `scale` mean
//       edge lengths, grown by rings to `min_neighbors`) for the smallest-|k| direction, heat
//       method (Heat_method_3) distance from the inlet, sign of the direction toward the inlet
//   GC  a directed boost::adjacency_list with the same cost 1 - <unit edge, z> per halfedge
//   VC  boost::dijkstra_shortest_paths per outlet, largest first, from a zero-cost node joined to
//       the outlet loop to the inlet (first cut) or a vertex already on a cut (later cuts, the
//       method's rule; PeerJoin::TreeOrInlet also lets them end on the inlet), never through
//       another loop
//   AC  Seam_mesh with the path edges as seams, and its longest border
//   L   (no counterpart: CGAL's parameterizers place the border themselves)
//   F   ARAP_parameterizer_3 (which starts from its own LSCM); LSCM_parameterizer_3 alone is
//       timed too (F_lscm, not in Total) for its quality.
#include "cgal_peer.h"
#include "common/quality_json.h"

#include "vessel/quality/metrics.h"

#include <CGAL/Heat_method_3/Surface_mesh_geodesic_distances_3.h>
#include <CGAL/Monge_via_jet_fitting.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/ARAP_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>
#include <CGAL/boost/graph/Seam_mesh.h>

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/dijkstra_shortest_paths.hpp>
#include <boost/property_map/function_property_map.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace vessel_bench {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point_3 = Kernel::Point_3;
using Point_2 = Kernel::Point_2;
using Vector_3 = Kernel::Vector_3;
using SM = CGAL::Surface_mesh<Point_3>;
using SM_vertex = SM::Vertex_index;
using SM_halfedge = SM::Halfedge_index;
using SM_edge = SM::Edge_index;
using Seam_edge_pmap = SM::Property_map<SM_edge, bool>;
using Seam_vertex_pmap = SM::Property_map<SM_vertex, bool>;
using Seam = CGAL::Seam_mesh<SM, Seam_edge_pmap, Seam_vertex_pmap>;
using UV_pmap = SM::Property_map<SM_halfedge, Point_2>;
using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::directedS, boost::no_property,
                                    boost::property<boost::edge_weight_t, double>>;
namespace PMP = CGAL::Polygon_mesh_processing;
namespace SMP = CGAL::Surface_mesh_parameterization;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

SM to_cgal(const vessel::Mesh& mesh)
{
    SM sm;
    sm.reserve(mesh.n_vertices(), mesh.n_edges(), mesh.n_faces());
    for (auto v : mesh.vertices())
    {
        const auto& p = mesh.point(v);
        sm.add_vertex(Point_3(p[0], p[1], p[2]));
    }
    for (auto f : mesh.faces())
    {
        std::vector<SM_vertex> corners;
        for (auto v : f.vertices())
            corners.emplace_back(static_cast<SM::size_type>(v.idx()));
        if (sm.add_face(corners) == SM::null_face())
            throw std::runtime_error("CGAL Surface_mesh rejected face " + std::to_string(f.idx()));
    }
    return sm;
}

struct Loop
{
    std::vector<SM_vertex> vertices;
    double length = 0.0;
};

// Z: boundary loops (longest = inlet), directions and distances.
struct Frames
{
    std::vector<Loop> loops;
    std::vector<Vector_3> z;  // unit, toward the inlet
};

std::vector<Loop> boundary_loops(SM& sm)
{
    std::vector<SM_halfedge> cycles;
    PMP::extract_boundary_cycles(sm, std::back_inserter(cycles));
    std::vector<Loop> loops;
    for (SM_halfedge c : cycles)
    {
        Loop loop;
        for (SM_halfedge h : CGAL::halfedges_around_face(c, sm))
        {
            loop.vertices.push_back(sm.source(h));
            loop.length += std::sqrt(CGAL::squared_distance(sm.point(sm.source(h)),
                                                            sm.point(sm.target(h))));
        }
        loops.push_back(std::move(loop));
    }
    std::sort(loops.begin(), loops.end(),
              [](const Loop& a, const Loop& b) { return a.length > b.length; });
    if (loops.size() < 2)
        throw std::runtime_error("fewer than two boundary loops");
    return loops;
}

// Direction of smaller |curvature| from a degree-2 jet fitted over the ball around each vertex.
std::vector<Vector_3> jet_directions(const SM& sm, const PeerSettings& settings)
{
    double sum = 0.0;
    for (SM_edge e : sm.edges())
        sum += std::sqrt(CGAL::squared_distance(sm.point(sm.vertex(e, 0)), sm.point(sm.vertex(e, 1))));
    const double radius = settings.scale * sum / std::max<double>(1.0, sm.number_of_edges());
    const double r2 = radius * radius;
    const std::size_t wanted = static_cast<std::size_t>(settings.min_neighbors) + 1;

    std::vector<Vector_3> direction(sm.number_of_vertices());
    std::vector<std::size_t> stamp(sm.number_of_vertices(), std::numeric_limits<std::size_t>::max());
    std::vector<SM_vertex> ring, next;
    std::vector<Point_3> points;
    CGAL::Monge_via_jet_fitting<Kernel> fit;
    for (SM_vertex v : sm.vertices())
    {
        const Point_3& p = sm.point(v);
        points.assign(1, p);  // the fit is made at the first point
        stamp[v] = v;
        ring.assign(1, v);
        while (!ring.empty())
        {
            next.clear();
            for (SM_vertex u : ring)
                for (SM_vertex w : CGAL::vertices_around_target(sm.halfedge(u), sm))
                {
                    if (stamp[w] == v)
                        continue;
                    stamp[w] = v;
                    if (CGAL::squared_distance(sm.point(w), p) <= r2 || points.size() < wanted)
                    {
                        points.push_back(sm.point(w));
                        next.push_back(w);
                    }
                }
            ring.swap(next);
        }
        if (points.size() < 6)
            throw std::runtime_error("vertex " + std::to_string(v.idx()) + " has fewer than 6 "
                                     "points around it for a degree-2 jet");
        const auto monge = fit(points.begin(), points.end(), 2, 2);
        const bool first_smaller =
            std::abs(monge.principal_curvatures(0)) < std::abs(monge.principal_curvatures(1));
        direction[v] = first_smaller ? monge.maximal_principal_direction()
                                     : monge.minimal_principal_direction();
    }
    return direction;
}

Frames stage_z(SM& sm, const PeerSettings& settings)
{
    Frames frames;
    frames.loops = boundary_loops(sm);
    const std::vector<Vector_3> c = jet_directions(sm, settings);
    auto G = sm.add_property_map<SM_vertex, double>("v:peer_geodesic", 0.0).first;
    CGAL::Heat_method_3::Surface_mesh_geodesic_distances_3<SM> heat(sm);
    heat.add_sources(frames.loops[0].vertices);
    heat.estimate_geodesic_distances(G);
    // Toward the inlet: against the (1-ring difference) gradient of the distance.
    frames.z.resize(sm.number_of_vertices());
    for (SM_vertex v : sm.vertices())
    {
        Vector_3 g(0, 0, 0);
        for (SM_vertex w : CGAL::vertices_around_target(sm.halfedge(v), sm))
            g = g + (G[w] - G[v]) * (sm.point(w) - sm.point(v));
        const Vector_3 unit = c[v] / std::sqrt(c[v].squared_length());
        frames.z[v] = unit * g < 0 ? unit : -unit;
    }
    return frames;
}

// GC: arcs of every interior halfedge with 1 - <unit edge, z_from> (or \p cost(from, to) when
// given), plus one extra node per loop joined to its vertices at zero cost.
Graph stage_gc(const SM& sm, const Frames& frames, const PeerCost& cost = nullptr)
{
    const std::size_t n = sm.number_of_vertices();
    std::vector<std::pair<std::size_t, std::size_t>> arcs;
    std::vector<double> weights;
    arcs.reserve(sm.number_of_halfedges());
    weights.reserve(sm.number_of_halfedges());
    for (SM_halfedge h : sm.halfedges())
    {
        if (sm.is_border(sm.edge(h)))
            continue;
        const SM_vertex s = sm.source(h), t = sm.target(h);
        const Vector_3 d = sm.point(t) - sm.point(s);
        arcs.emplace_back(s, t);
        weights.push_back(cost ? cost(s, t)
                               : std::max(0.0, 1.0 - (d * frames.z[s]) / std::sqrt(d.squared_length())));
    }
    for (std::size_t k = 0; k < frames.loops.size(); ++k)
        for (SM_vertex v : frames.loops[k].vertices)
        {
            arcs.emplace_back(n + k, v);
            weights.push_back(0.0);
        }
    return Graph(arcs.begin(), arcs.end(), weights.begin(), n + frames.loops.size());
}

struct Reached
{
    std::size_t vertex;
};

struct StopAtTarget : boost::default_dijkstra_visitor
{
    const std::vector<char>* is_target = nullptr;
    std::size_t* examined = nullptr;
    template <class Vertex, class G>
    void examine_vertex(Vertex u, const G&) const
    {
        ++*examined;
        if (u < is_target->size() && (*is_target)[u])
            throw Reached{u};
    }
};

// VC: one path per outlet, largest first. Targets: the inlet for the first; for the later ones
// the interior vertices already on a cut (PeerJoin::Tree, the method's rule, as the library) or
// those and the inlet (PeerJoin::TreeOrInlet). Never through a loop that is not a target.
PeerPaths stage_vc(const SM& sm, const Frames& frames, const Graph& graph, PeerJoin join)
{
    const std::size_t n = sm.number_of_vertices();
    std::vector<int> loop_of(n, -1);
    for (std::size_t k = 0; k < frames.loops.size(); ++k)
        for (SM_vertex v : frames.loops[k].vertices)
            loop_of[v] = static_cast<int>(k);
    std::vector<char> is_target(n, 0);
    for (SM_vertex v : frames.loops[0].vertices)
        is_target[v] = 1;
    const std::size_t nodes = boost::num_vertices(graph);
    std::vector<double> distance(nodes);
    std::vector<std::size_t> predecessor(nodes);
    const auto weight = boost::get(boost::edge_weight, graph);
    PeerPaths out;
    for (std::size_t k = 1; k < frames.loops.size(); ++k)
    {
        if (k == 2 && join == PeerJoin::Tree)
            for (SM_vertex v : frames.loops[0].vertices)
                is_target[v] = 0;  // later cuts end on a cut; the inlet is now blocked
        // Never enter another loop, except at a target.
        const auto allowed = boost::make_function_property_map<Graph::edge_descriptor, double>(
            [&](const Graph::edge_descriptor& e) {
                const std::size_t t = boost::target(e, graph);
                if (t < n && loop_of[t] >= 0 && loop_of[t] != static_cast<int>(k) && !is_target[t])
                    return std::numeric_limits<double>::max();
                return boost::get(weight, e);
            });
        StopAtTarget stop;
        stop.is_target = &is_target;
        stop.examined = &out.settled;
        std::size_t end = nodes;
        try
        {
            boost::dijkstra_shortest_paths(graph, n + k,
                                           boost::predecessor_map(predecessor.data())
                                               .distance_map(distance.data())
                                               .weight_map(allowed)
                                               .visitor(stop));
        }
        catch (const Reached& r)
        {
            end = r.vertex;
        }
        if (end == nodes)
            throw std::runtime_error("outlet " + std::to_string(k) + " cannot reach the cut tree");
        std::vector<std::size_t> path{end};
        for (std::size_t u = end; predecessor[u] != n + k; u = predecessor[u])
        {
            const std::size_t p = predecessor[u];
            path.push_back(p);
            if (loop_of[p] < 0)
                is_target[p] = 1;  // later outlets may end on this cut
        }
        std::reverse(path.begin(), path.end());
        out.paths.push_back(std::move(path));
    }
    return out;
}

// Builds the cut mesh of \p seam as a vessel::Mesh (one vertex per seam-mesh vertex) with its uv,
// and measures it with vessel::flat_quality. A map mirrored as a whole is mirrored back first.
nlohmann::json measure(const SM& sm, const Seam& seam, const UV_pmap& uv_map)
{
    vessel::Mesh flat;
    std::vector<int> index(sm.number_of_halfedges(), -1);
    std::vector<Point_2> uvs;
    for (auto vd : CGAL::vertices(seam))
    {
        const SM_halfedge h = vd;
        const Point_3& p = sm.point(sm.target(h));
        index[h.idx()] = flat.add_vertex(vessel::Mesh::Point(p.x(), p.y(), p.z())).idx();
        uvs.push_back(uv_map[h]);
    }
    for (auto fd : CGAL::faces(seam))
    {
        std::vector<vessel::VertexHandle> corners;
        for (auto hd : CGAL::halfedges_around_face(CGAL::halfedge(fd, seam), seam))
        {
            const SM_halfedge h = CGAL::target(hd, seam);
            if (index[h.idx()] < 0)
                throw std::runtime_error("a seam-mesh corner is not among its vertices");
            corners.emplace_back(index[h.idx()]);
        }
        if (!flat.add_face(corners).is_valid())
            throw std::runtime_error("the seam mesh is not a manifold disk");
    }
    Eigen::MatrixX2d uv(uvs.size(), 2);
    for (std::size_t i = 0; i < uvs.size(); ++i)
        uv.row(static_cast<Eigen::Index>(i)) << uvs[i].x(), uvs[i].y();
    vessel::FlatQuality q = vessel::flat_quality(flat, uv);
    bool mirrored = false;
    if (2 * q.flipped_triangles > static_cast<int>(flat.n_faces()))
    {
        uv.col(0) *= -1.0;
        q = vessel::flat_quality(flat, uv);
        mirrored = true;
    }
    nlohmann::json out = vessel::cli::quality_json(q);
    out.update({{"mirrored", mirrored}, {"vertices", flat.n_vertices()}});
    return out;
}

}  // namespace

nlohmann::json run_cgal_peer(const vessel::Mesh& mesh, const PeerSettings& settings)
{
    const SM input = to_cgal(mesh);
    nlohmann::json out{{"errors", nlohmann::json::object()}};
    const char* const names[] = {"Z", "GC", "VC", "AC", "F", "F_lscm", "Total"};
    std::vector<std::vector<double>> samples(7);
    bool time_boxed = false;
    for (int run = 0; run < settings.runs; ++run)
    {
        SM sm = input;
        // Each stage's time is kept when it completes, so a later stage's failure still leaves
        // the earlier stages' figures; Total only for complete runs.
        const char* stage = "Z";
        auto start = Clock::now();
        auto done = [&](int k) { samples[k].push_back(seconds_since(start)); };
        try
        {
            const Frames frames = stage_z(sm, settings);
            done(0);

            stage = "GC";
            start = Clock::now();
            const Graph graph = stage_gc(sm, frames);
            done(1);

            stage = "VC";
            start = Clock::now();
            const PeerPaths cuts = stage_vc(sm, frames, graph, settings.join);
            done(2);

            stage = "AC";
            start = Clock::now();
            auto seam_edges = sm.add_property_map<SM_edge, bool>("e:on_seam", false).first;
            auto seam_vertices = sm.add_property_map<SM_vertex, bool>("v:on_seam", false).first;
            Seam seam(sm, seam_edges, seam_vertices);
            int rejected = 0;
            for (const auto& path : cuts.paths)
                for (std::size_t i = 0; i + 1 < path.size(); ++i)
                    rejected += seam.add_seam(SM_vertex(static_cast<SM::size_type>(path[i])),
                                              SM_vertex(static_cast<SM::size_type>(path[i + 1])))
                                    ? 0
                                    : 1;
            const auto bhd = PMP::longest_border(seam).first;
            done(3);
            if (run == 0)
            {
                out["seam_edges"] = cuts.seam_edges();
                out["cut_paths"] = frames.loops.size() - 1;
                out["cut_vertex_paths"] = cuts.paths;
            }
            if (rejected > 0)
                throw std::runtime_error(std::to_string(rejected) + " seam edges were rejected");
            const unsigned borders = PMP::number_of_borders(seam);
            if (borders != 1)
                throw std::runtime_error("the cut left " + std::to_string(borders) +
                                         " borders, not one (not a disk)");

            stage = "F_lscm";
            UV_pmap uv_lscm = sm.add_property_map<SM_halfedge, Point_2>("h:uv_lscm").first;
            start = Clock::now();
            SMP::Error_code status =
                SMP::parameterize(seam, SMP::LSCM_parameterizer_3<Seam>(), bhd, uv_lscm);
            done(5);
            if (status != SMP::OK)
                throw std::runtime_error(std::string("LSCM_parameterizer_3: ") +
                                         SMP::get_error_message(status));
            if (run == 0)
                out["quality"]["lscm"] = measure(sm, seam, uv_lscm);

            stage = "F";
            UV_pmap uv_arap = sm.add_property_map<SM_halfedge, Point_2>("h:uv_arap").first;
            start = Clock::now();
            status = SMP::parameterize(seam, SMP::ARAP_parameterizer_3<Seam>(), bhd, uv_arap);
            const double f = seconds_since(start);
            if (status != SMP::OK)
                throw std::runtime_error(std::string("ARAP_parameterizer_3: ") +
                                         SMP::get_error_message(status) + " (after " +
                                         std::to_string(f) + " s)");
            samples[4].push_back(f);
            if (run == 0)
                out["quality"]["arap"] = measure(sm, seam, uv_arap);
        }
        catch (const std::exception& e)
        {
            out["errors"][stage] = e.what();
            break;
        }
        samples[6].push_back(samples[0].back() + samples[1].back() + samples[2].back() +
                             samples[3].back() + samples[4].back());
        if (samples[6].back() + samples[5].back() > settings.time_box_s && run + 1 < settings.runs)
        {
            time_boxed = true;
            break;
        }
    }
    for (int k = 0; k < 7; ++k)
        out["samples"][names[k]] = samples[k];
    out["runs"] = samples[0].size();
    out["time_boxed"] = time_boxed;
    return out;
}

struct PeerCutStages::Impl
{
    SM sm;
    Frames frames;
    Graph graph;
};

PeerCutStages::PeerCutStages(const vessel::Mesh& mesh, const PeerSettings& settings)
    : impl_(std::make_unique<Impl>())
{
    impl_->sm = to_cgal(mesh);
    impl_->frames = stage_z(impl_->sm, settings);
}

PeerCutStages::~PeerCutStages() = default;

void PeerCutStages::build_graph(const PeerCost& cost)
{
    impl_->graph = stage_gc(impl_->sm, impl_->frames, cost);
}

PeerPaths PeerCutStages::cut_paths(PeerJoin join)
{
    return stage_vc(impl_->sm, impl_->frames, impl_->graph, join);
}

std::size_t PeerPaths::seam_edges() const
{
    std::size_t edges = 0;
    for (const auto& path : paths)
        edges += path.size() - 1;
    return edges;
}

}  // namespace vessel_bench
