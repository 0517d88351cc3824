#include "vessel/io/flat_vtk.h"

#include "vessel/core/errors.h"
#include "vessel/core/properties.h"
#include "vessel/fields/map_vectors.h"
#include "vessel/io/ensight.h"
#include "detail/uv_rows.h"

#include <filesystem>

namespace vessel {

PolyData flat_polydata(const Mesh& mesh, const Eigen::MatrixX2d& uv,
                       const std::vector<Field>& fields, bool map)
{
    OpenMesh::VPropHandleT<int> input_index;
    OpenMesh::FPropHandleT<int> input_face;
    if (!mesh.get_property_handle(input_index, prop::input_index) ||
        !mesh.get_property_handle(input_face, prop::input_face))
        throw InvalidInputError(std::string("flat_polydata: the mesh needs the '") +
                                prop::input_index + "' and '" + prop::input_face +
                                "' properties; load it with load_tree_surface()");
    const auto nv = static_cast<Eigen::Index>(mesh.n_vertices());
    const auto nf = static_cast<Eigen::Index>(mesh.n_faces());
    detail::require_uv_rows(mesh, uv, "flat_polydata");
    PolyData out;
    out.mesh.points.reserve(mesh.n_vertices());
    for (auto v : mesh.vertices())
        out.mesh.points.push_back(map ? Eigen::Vector3d(uv(v.idx(), 0), uv(v.idx(), 1), 0.0)
                                      : to_eigen(mesh.point(v)));
    Field tcoords{uv_array, FieldLocation::Point, FieldType::Float64, uv};
    Field vertex{input_vertex_array, FieldLocation::Point, FieldType::Int32,
                 Eigen::MatrixXd(nv, 1)};
    for (auto v : mesh.vertices())
        vertex.values(v.idx(), 0) = mesh.property(input_index, v);
    Field cell{input_cell_array, FieldLocation::Cell, FieldType::Int32, Eigen::MatrixXd(nf, 1)};
    out.mesh.faces.reserve(mesh.n_faces());
    for (auto f : mesh.faces())
    {
        cell.values(f.idx(), 0) = mesh.property(input_face, f);
        auto& face = out.mesh.faces.emplace_back();
        for (auto v : f.vertices())
            face.push_back(v.idx());
    }
    out.point_data = {tcoords, vertex};
    out.cell_data = {cell};
    out.tcoords = uv_array;
    for (const auto& f : map ? map_fields(fields, mesh, uv) : fields)
        (f.location == FieldLocation::Point ? out.point_data : out.cell_data).push_back(f);
    if (map)
        for (auto& f : distortion_fields(mesh, uv))
            out.cell_data.push_back(std::move(f));
    return out;
}

std::string map_path(const std::string& path)
{
    const std::filesystem::path p(path);
    return (p.parent_path() / (p.stem().string() + "-map" + p.extension().string())).string();
}

void write_flat_vtp(const std::string& path, const Mesh& mesh, const Eigen::MatrixX2d& uv,
                    const std::vector<Field>& fields)
{
    write_polydata(path, flat_polydata(mesh, uv, fields, false));
    write_polydata(map_path(path), flat_polydata(mesh, uv, fields, true));
}

void write_flat_series(const std::string& case_path, const Mesh& mesh, const Eigen::MatrixX2d& uv,
                       const std::vector<Field>& fields, const TimeSeries& series)
{
    EnSightOptions wall;
    wall.folder = ensight_data_folder(case_path);
    write_ensight_series(case_path, flat_polydata(mesh, uv, fields, false), series, wall);
    EnSightOptions map = wall;
    map.part_name = "map";
    map.step_fields = [&](const std::vector<Field>& step) { return map_fields(step, mesh, uv); };
    write_ensight_series(map_path(case_path), flat_polydata(mesh, uv, fields, true), series, map);
}

}  // namespace vessel
