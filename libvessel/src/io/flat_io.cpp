#include "vessel/io/flat_io.h"

#include "detail/atomic_file.h"

#include "vessel/core/errors.h"
#include "vessel/core/properties.h"
#include "detail/uv_rows.h"

#include <cstdio>
#include <filesystem>
#include <memory>

namespace vessel {

void write_flat_obj(const std::string& path, const std::vector<Eigen::Vector3d>& input_points,
                    const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    OpenMesh::VPropHandleT<int> input_index;
    if (!mesh.get_property_handle(input_index, prop::input_index))
        throw InvalidInputError(std::string("write_flat_obj: the mesh has no '") +
                                prop::input_index + "' property; load it with load_tree_surface");
    detail::require_uv_rows(mesh, uv, "write_flat_obj");
    detail::write_atomically(path, "write_flat_obj", [&](FILE* out) {
        std::fprintf(out, "# libvessel flattened vessel: v = input positions, vt = (u, v)\n");
        for (const auto& p : input_points)
            std::fprintf(out, "v %.9g %.9g %.9g\n", p.x(), p.y(), p.z());
        for (Eigen::Index i = 0; i < uv.rows(); ++i)
            std::fprintf(out, "vt %.9g %.9g\n", uv(i, 0), uv(i, 1));
        for (auto f : mesh.faces())
        {
            std::fputc('f', out);
            for (auto v : f.vertices())
                std::fprintf(out, " %d/%d", mesh.property(input_index, v) + 1, v.idx() + 1);
            std::fputc('\n', out);
        }
    });
}

}  // namespace vessel
