// Binary PLY of the cut mesh with (u, v) and every field as vertex / face properties.
#include "detail/atomic_file.h"
#include "vessel/core/errors.h"
#include "vessel/io/flat_vtk.h"

#include <cctype>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>

namespace vessel {

namespace {

// A PLY property name is one word; CFD array names may hold spaces or other characters.
std::string ply_name(const std::string& name)
{
    std::string out = name;
    for (char& c : out)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_')
            c = '_';
    return out.empty() ? std::string("field") : out;
}

const char* ply_type(FieldType type)
{
    switch (type)
    {
        case FieldType::Float32:
            return "float";
        case FieldType::Float64:
        case FieldType::Int64:  // PLY has no 64-bit integer; a double holds up to 2^53 exactly
            return "double";
        default:
            return "int";
    }
}

void write_value(FILE* out, FieldType type, double value)
{
    if (type == FieldType::Float32)
    {
        const float x = static_cast<float>(value);
        std::fwrite(&x, sizeof x, 1, out);
    }
    else if (type == FieldType::Float64 || type == FieldType::Int64)
        std::fwrite(&value, sizeof value, 1, out);
    else
    {
        const auto x = static_cast<std::int32_t>(value);
        std::fwrite(&x, sizeof x, 1, out);
    }
}

void header_properties(FILE* out, const std::vector<Field>& fields)
{
    for (const auto& f : fields)
        for (int c = 0; c < f.components(); ++c)
            std::fprintf(out, "property %s %s%s\n", ply_type(f.type), ply_name(f.name).c_str(),
                         f.components() == 1 ? "" : ("_" + std::to_string(c)).c_str());
}

void row_values(FILE* out, const std::vector<Field>& fields, Eigen::Index row)
{
    for (const auto& f : fields)
        for (int c = 0; c < f.components(); ++c)
            write_value(out, f.type, f.values(row, c));
}

}  // namespace

void write_flat_ply(const std::string& path, const Mesh& mesh, const Eigen::MatrixX2d& uv,
                    const std::vector<Field>& fields)
{
    PolyData data = flat_polydata(mesh, uv, fields, false);
    // (u, v) goes out as the two properties `u` and `v`, which readers take for texture
    // coordinates; the rest of the point data follows.
    std::vector<Field> point_data(data.point_data.begin() + 1, data.point_data.end());
    detail::write_atomically(path, "write_flat_ply", [&](FILE* out) {
        std::fprintf(out,
                     "ply\nformat binary_little_endian 1.0\ncomment libvessel flattened "
                     "vessel: x y z = 3D cut mesh, u v = flat map\n");
        std::fprintf(out,
                     "element vertex %zu\nproperty double x\nproperty double y\nproperty "
                     "double z\nproperty double u\nproperty double v\n",
                     data.mesh.points.size());
        header_properties(out, point_data);
        std::fprintf(out, "element face %zu\nproperty list uchar int vertex_indices\n",
                     data.mesh.faces.size());
        header_properties(out, data.cell_data);
        std::fprintf(out, "end_header\n");
        for (std::size_t i = 0; i < data.mesh.points.size(); ++i)
        {
            const auto row = static_cast<Eigen::Index>(i);
            const double xyzuv[5] = {data.mesh.points[i].x(), data.mesh.points[i].y(),
                                     data.mesh.points[i].z(), uv(row, 0), uv(row, 1)};
            std::fwrite(xyzuv, sizeof(double), 5, out);
            row_values(out, point_data, row);
        }
        for (std::size_t i = 0; i < data.mesh.faces.size(); ++i)
        {
            const auto& face = data.mesh.faces[i];
            const auto n = static_cast<unsigned char>(face.size());
            std::fwrite(&n, 1, 1, out);
            for (int v : face)
            {
                const auto x = static_cast<std::int32_t>(v);
                std::fwrite(&x, sizeof x, 1, out);
            }
            row_values(out, data.cell_data, static_cast<Eigen::Index>(i));
        }
    });
}

}  // namespace vessel
