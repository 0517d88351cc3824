#include "vessel/cut/split.h"

#include "vessel/cut/boundary.h"
#include "detail/union_find.h"
#include "vessel/core/errors.h"
#include "vessel/direction/geodesic.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <set>

namespace vessel {

void SplitOptions::validate() const
{
    if (!(offset_radii > 0.0 && std::isfinite(offset_radii)))
        throw InvalidInputError("SplitOptions: offset_radii must be positive, got " +
                                std::to_string(offset_radii));
}

namespace {

// A triangle soup with, per vertex, the geodesic distance from the inlet and the input loop the
// vertex lies on (-1: none).
struct Soup
{
    std::vector<Eigen::Vector3d> points;
    std::vector<double> G;
    std::vector<int> loop;
    std::vector<std::array<int, 3>> faces;
};

using detail::UnionFind;

std::string list(const std::set<int>& s)
{
    std::string out;
    for (int x : s)
        out += (out.empty() ? "" : ",") + std::to_string(x);
    return "{" + out + "}";
}

// Walks down the superlevel sets of G: returns the level where the component holding the set
// first meets another loop (`out`), and the level from which all of the set is one component
// (`in`, at most the set's lowest loop vertex).
struct MergeLevels
{
    double out = -std::numeric_limits<double>::infinity();
    double in = std::numeric_limits<double>::infinity();
};

MergeLevels merge_levels(const Soup& soup, const std::set<int>& set)
{
    const std::size_t n = soup.points.size();
    std::vector<std::vector<int>> neighbours(n);
    for (const auto& f : soup.faces)
        for (int k = 0; k < 3; ++k)
        {
            neighbours[f[k]].push_back(f[(k + 1) % 3]);
            neighbours[f[(k + 1) % 3]].push_back(f[k]);
        }
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return soup.G[a] > soup.G[b]; });
    UnionFind uf(n);
    std::vector<std::set<int>> loops(n);  // loops met by each component (at its root)
    std::vector<char> active(n, 0);
    MergeLevels levels;
    for (int v : order)
        if (set.count(soup.loop[v]))
            levels.in = std::min(levels.in, soup.G[v]);
    const auto has_all = [&](const std::set<int>& met) {
        return std::all_of(set.begin(), set.end(), [&](int l) { return met.count(l) > 0; });
    };
    bool joined = false, broken = false;
    for (int v : order)
    {
        active[v] = 1;
        if (soup.loop[v] >= 0)
            loops[v].insert(soup.loop[v]);
        for (int u : neighbours[v])
        {
            const int a = uf.find(u), b = uf.find(v);
            if (!active[u] || a == b)
                continue;
            const int root = uf.unite(a, b), other = root == a ? b : a;
            loops[root].insert(loops[other].begin(), loops[other].end());
            loops[other].clear();
        }
        // Only v's component changed.
        const std::set<int>& met = loops[uf.find(v)];
        const bool all = has_all(met);
        const bool some = std::any_of(set.begin(), set.end(), [&](int l) { return met.count(l); });
        const bool other = std::any_of(met.begin(), met.end(), [&](int l) { return !set.count(l); });
        if (all && !joined)
        {
            joined = true;
            levels.in = std::min(levels.in, soup.G[v]);
        }
        broken = broken || (some && other && !all);
        if (all && other && broken)
            throw InvalidInputError("split_tree: outlets " + list(set) +
                                    " are not one subtree; the smallest subtree holding them "
                                    "has loops " + list(met) + " (0 = inlet); split there instead");
        if (all && other)
        {
            levels.out = soup.G[v];
            return levels;
        }
    }
    throw InvalidInputError("split_tree: outlets " + list(set) +
                            " never join the rest of the tree; the mesh is not connected");
}

// Slices the soup along G = level; returns the faces above the level holding the set (as the
// piece) and leaves the rest in `soup`.
Soup slice_off(Soup& soup, double level, const std::set<int>& set)
{
    std::map<std::pair<int, int>, int> crossing;
    const auto cut = [&](int a, int b) {
        const auto key = std::minmax(a, b);
        auto it = crossing.find(key);
        if (it != crossing.end())
            return it->second;
        const double t = (level - soup.G[a]) / (soup.G[b] - soup.G[a]);
        soup.points.push_back((1.0 - t) * soup.points[a] + t * soup.points[b]);
        soup.G.push_back(level);
        soup.loop.push_back(-1);
        const int id = static_cast<int>(soup.points.size()) - 1;
        crossing.emplace(key, id);
        return id;
    };
    std::vector<std::array<int, 3>> above, below;
    for (const auto& f : soup.faces)
    {
        int n_above = 0;
        for (int v : f)
            n_above += soup.G[v] > level;
        if (n_above == 0 || n_above == 3)
        {
            (n_above == 3 ? above : below).push_back(f);
            continue;
        }
        // Rotate so that corner 0 is the lone vertex on its side.
        int k = 0;
        while ((soup.G[f[k]] > level) == (n_above == 2))
            ++k;
        const int a = f[k], b = f[(k + 1) % 3], c = f[(k + 2) % 3];
        const int ab = cut(a, b), ca = cut(c, a);
        auto& lone = n_above == 1 ? above : below;
        auto& pair = n_above == 1 ? below : above;
        lone.push_back({a, ab, ca});
        pair.push_back({ab, b, c});
        pair.push_back({ab, c, ca});
    }
    // Components of the faces above, through shared edges.
    UnionFind uf(above.size());
    std::map<std::pair<int, int>, int> edge_face;
    for (std::size_t i = 0; i < above.size(); ++i)
        for (int k = 0; k < 3; ++k)
        {
            const auto key = std::minmax(above[i][k], above[i][(k + 1) % 3]);
            auto [it, fresh] = edge_face.emplace(key, static_cast<int>(i));
            if (!fresh)
                uf.unite(it->second, static_cast<int>(i));
        }
    std::set<int> roots;
    for (std::size_t i = 0; i < above.size(); ++i)
        for (int v : above[i])
            if (set.count(soup.loop[v]))
                roots.insert(uf.find(static_cast<int>(i)));
    if (roots.size() != 1)
        throw TopologyError("split_tree: the ring at distance " + std::to_string(level) +
                            " leaves outlets " + list(set) + " in " +
                            std::to_string(roots.size()) + " pieces; try another offset_radii");
    Soup piece;
    std::vector<std::array<int, 3>> rest = below;
    for (std::size_t i = 0; i < above.size(); ++i)
        (uf.find(static_cast<int>(i)) == *roots.begin() ? piece.faces : rest).push_back(above[i]);
    piece.points = soup.points;
    piece.G = soup.G;
    piece.loop = soup.loop;
    soup.faces = rest;
    return piece;
}

// Drops unused vertices.
void compact(Soup& soup)
{
    std::vector<int> id(soup.points.size(), -1);
    Soup out;
    for (auto& f : soup.faces)
        for (int& v : f)
        {
            if (id[v] < 0)
            {
                id[v] = static_cast<int>(out.points.size());
                out.points.push_back(soup.points[v]);
                out.G.push_back(soup.G[v]);
                out.loop.push_back(soup.loop[v]);
            }
            v = id[v];
        }
    out.faces = std::move(soup.faces);
    soup = std::move(out);
}

TreePiece to_piece(const Soup& soup, double level)
{
    TreePiece piece;
    piece.mesh.points = soup.points;
    for (const auto& f : soup.faces)
        piece.mesh.faces.push_back({f[0], f[1], f[2]});
    std::set<int> loops;
    for (int l : soup.loop)
        if (l >= 0)
            loops.insert(l);
    piece.loops.assign(loops.begin(), loops.end());
    piece.level = level;
    return piece;
}

}  // namespace

std::vector<TreePiece> split_tree(const Mesh& mesh, const std::vector<std::vector<int>>& subtrees,
                                  const SplitOptions& options)
{
    options.validate();
    const std::vector<BoundaryLoop> loops = boundary_loops(mesh);
    const int n_loops = static_cast<int>(loops.size());
    Soup soup;
    soup.loop.assign(mesh.n_vertices(), -1);
    for (int l = 0; l < n_loops; ++l)
        for (auto v : loops[l].vertices)
            soup.loop[v.idx()] = l;
    const Eigen::VectorXd G = HeatGeodesics(mesh).distance(loops[0].vertices);
    for (auto v : mesh.vertices())
    {
        soup.points.push_back(to_eigen(mesh.point(v)));
        soup.G.push_back(G[v.idx()]);
    }
    for (auto f : mesh.faces())
    {
        std::array<int, 3> t;
        int k = 0;
        for (auto v : f.vertices())
            t[k++] = v.idx();
        soup.faces.push_back(t);
    }
    const double eps = 1e-3 * mean_edge_length(mesh);

    std::vector<TreePiece> pieces;
    std::set<int> taken;
    for (const auto& outlets : subtrees)
    {
        std::set<int> set(outlets.begin(), outlets.end());
        if (set.empty())
            throw InvalidInputError("split_tree: an empty outlet set; give at least one outlet");
        for (int l : set)
        {
            if (l < 1 || l >= n_loops)
                throw InvalidInputError("split_tree: " + std::to_string(l) +
                                        " is not an outlet; outlets are 1.." +
                                        std::to_string(n_loops - 1));
            if (!taken.insert(l).second)
                throw InvalidInputError("split_tree: outlet " + std::to_string(l) +
                                        " is in two sets; the sets must be disjoint");
        }
        if (static_cast<int>(taken.size()) == n_loops - 1)
            throw InvalidInputError("split_tree: the sets take every outlet; leave at least one "
                                    "with the inlet");
        const MergeLevels m = merge_levels(soup, set);
        double radius = 0.0;
        for (int l : set)
            radius += loops[l].radius() / static_cast<double>(set.size());
        const double level = m.out + std::min(options.offset_radii * radius, 0.5 * (m.in - m.out));
        for (double& g : soup.G)  // no vertex on the ring: no sliver triangles
            if (std::abs(g - level) < eps)
                g = level + eps;
        Soup piece = slice_off(soup, level, set);
        compact(piece);
        pieces.push_back(to_piece(piece, level));
    }
    compact(soup);
    pieces.push_back(to_piece(soup, 0.0));
    return pieces;
}

}  // namespace vessel
