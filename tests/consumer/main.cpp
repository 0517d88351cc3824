// Flattens an open cylinder (one inlet, one outlet) with the installed vessel::core alone and
// prints what a caller would check: exit 0 only if the map has one uv per cut-mesh vertex and no
// flipped triangle.
#include <vessel/check/validation.h>
#include <vessel/pipeline.h>

#include <cmath>
#include <iostream>

int main()
{
    constexpr int ring = 32;
    constexpr int rows = 40;
    vessel::RawMesh raw;
    for (int j = 0; j <= rows; ++j)
        for (int i = 0; i < ring; ++i)
        {
            const double a = 2.0 * M_PI * i / ring;
            raw.points.emplace_back(std::cos(a), std::sin(a), 0.25 * j);
        }
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < ring; ++i)
        {
            const int a = j * ring + i;
            const int b = j * ring + (i + 1) % ring;
            raw.faces.push_back({a, b, b + ring});
            raw.faces.push_back({a, b + ring, a + ring});
        }
    try
    {
        const vessel::FlattenResult flat =
            vessel::flatten(vessel::make_tree_surface(raw).mesh);
        const auto n = static_cast<long>(flat.mesh.n_vertices());
        std::cout << "vertices " << n << " uv " << flat.uv.rows() << " flipped "
                  << flat.quality.flipped_triangles << "\n";
        return flat.uv.rows() == n && flat.quality.flipped_triangles == 0 ? 0 : 1;
    }
    catch (const std::exception& e)
    {
        std::cerr << "consumer: " << e.what() << "\n";
        return 1;
    }
}
