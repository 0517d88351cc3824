#include "solve/paired_pattern.h"
#include "support/meshes.h"

#include <doctest/doctest.h>
#include <Eigen/Sparse>

#include <algorithm>
#include <array>
#include <set>
#include <string>
#include <utility>
#include <vector>

using vessel::detail::PairedPattern;

TEST_CASE("paired pattern: a real mesh's faces couple exactly their vertex pairs, each entry's "
          "value index in its column")
{
    const vessel::Mesh mesh =
        vessel::test::shared_tree_mesh("vmtk-old-website/aneurisk-id1-lateral-aneurysm.ply");
    const int n = static_cast<int>(mesh.n_vertices());
    std::vector<std::array<int, 3>> faces;
    for (auto f : mesh.faces())
    {
        std::array<int, 3> corners{};
        int k = 0;
        for (auto v : f.vertices())
            corners[static_cast<std::size_t>(k++)] = v.idx();
        std::sort(corners.begin(), corners.end());
        faces.push_back(corners);
    }
    const PairedPattern pattern =
        PairedPattern::of_triangles(n, faces.size(), [&](std::size_t f, std::array<int, 3>& s) {
            s = faces[f];
            return 3;
        });
    Eigen::SparseMatrix<double> A;
    pattern.into(A);
    REQUIRE(A.rows() == 2 * n);
    REQUIRE(A.cols() == 2 * n);

    // The vertex pairs I <= J the faces couple; the pattern's upper triangle holds exactly
    // their four (or, for I == J, three) entries.
    std::set<std::pair<int, int>> pairs;
    for (int v = 0; v < n; ++v)
        pairs.insert({v, v});
    for (const auto& s : faces)
        for (int k = 0; k < 3; ++k)
            for (int l = 0; l < k; ++l)
                pairs.insert({s[static_cast<std::size_t>(l)], s[static_cast<std::size_t>(k)]});
    CHECK(A.nonZeros() == static_cast<Eigen::Index>(4 * pairs.size() - n));

    // Every entry (r, c) of those pairs: its value index by index() and by index_at() with the
    // pair's rank, inside column c, at row r; all of them distinct.
    int checked = 0, misplaced = 0;
    std::vector<char> seen(static_cast<std::size_t>(A.nonZeros()), 0);
    for (const auto& [I, J] : pairs)
    {
        const int rank = pattern.rank(I, J);
        for (int r = 2 * I; r < 2 * I + 2; ++r)
            for (int c = std::max(2 * J, r); c < 2 * J + 2; ++c)
            {
                const int at = pattern.index(r, c);
                const bool in_column = at >= A.outerIndexPtr()[c] && at < A.outerIndexPtr()[c + 1];
                if (pattern.index_at(rank, r, c) != at || !in_column ||
                    A.innerIndexPtr()[at] != r || seen[static_cast<std::size_t>(at)]++)
                    ++misplaced;
                ++checked;
            }
    }
    CHECK(misplaced == 0);
    CHECK(checked == A.nonZeros());
}
