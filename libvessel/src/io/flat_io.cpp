#include "vessel/io/flat_io.h"

#include "detail/atomic_file.h"

#include "vessel/core/errors.h"
#include "vessel/core/properties.h"
#include "detail/uv_rows.h"

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <type_traits>

namespace vessel {

namespace {

constexpr std::size_t kBlock = 1 << 20;  // bytes written at a time

}  // namespace

void write_flat_obj(const std::string& path, const std::vector<Eigen::Vector3d>& input_points,
                    const Mesh& mesh, const Eigen::MatrixX2d& uv)
{
    OpenMesh::VPropHandleT<int> input_index;
    if (!mesh.get_property_handle(input_index, prop::input_index))
        throw InvalidInputError(std::string("write_flat_obj: the mesh has no '") +
                                prop::input_index + "' property; load it with load_tree_surface");
    detail::require_uv_rows(mesh, uv, "write_flat_obj");
    detail::write_atomically(path, "write_flat_obj", [&](FILE* out) {
        // Formatted with std::to_chars into a buffer written in blocks: its `general` format
        // with a precision is printf's %.9g (C++17 [utility.to.chars]), at a fraction of
        // fprintf's cost per number (write_atomically() checks the stream after the writer).
        std::string buffer;
        buffer.reserve(kBlock + 256);
        const auto flush = [&](bool all) {
            if (buffer.size() >= kBlock || (all && !buffer.empty()))
            {
                std::fwrite(buffer.data(), 1, buffer.size(), out);
                buffer.clear();
            }
        };
        const auto number = [&](auto value) {
            char text[32];
            std::to_chars_result done{};
            if constexpr (std::is_floating_point_v<decltype(value)>)
                done = std::to_chars(text, text + sizeof text, value, std::chars_format::general,
                                     9);
            else
                done = std::to_chars(text, text + sizeof text, value);
            buffer.append(text, done.ptr);
        };
        buffer += "# libvessel flattened vessel: v = input positions, vt = (u, v)\n";
        for (const auto& p : input_points)
        {
            buffer += "v ";
            number(p.x());
            buffer += ' ';
            number(p.y());
            buffer += ' ';
            number(p.z());
            buffer += '\n';
            flush(false);
        }
        for (Eigen::Index i = 0; i < uv.rows(); ++i)
        {
            buffer += "vt ";
            number(uv(i, 0));
            buffer += ' ';
            number(uv(i, 1));
            buffer += '\n';
            flush(false);
        }
        for (auto f : mesh.faces())
        {
            buffer += 'f';
            for (auto v : f.vertices())
            {
                buffer += ' ';
                number(mesh.property(input_index, v) + 1);
                buffer += '/';
                number(v.idx() + 1);
            }
            buffer += '\n';
            flush(false);
        }
        flush(true);
    });
}

}  // namespace vessel
