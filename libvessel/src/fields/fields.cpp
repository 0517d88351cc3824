#include "vessel/fields/fields.h"

#include "vessel/core/errors.h"
#include "vessel/core/properties.h"

#include <set>

namespace vessel {

namespace {

const char* location_name(FieldLocation location)
{
    return location == FieldLocation::Point ? "point" : "cell";
}

// Rows of the carried field: out.row(i) = in.row(index[i]).
Field gather(const Field& field, const std::vector<int>& index, const char* element)
{
    Field out = field;
    out.values.resize(static_cast<Eigen::Index>(index.size()), field.components());
    for (std::size_t i = 0; i < index.size(); ++i)
    {
        if (index[i] < 0 || index[i] >= field.rows())
            throw InvalidInputError(
                "transfer_fields: " + std::string(element) + " " + std::to_string(i) +
                " comes from input row " + std::to_string(index[i]) + " but " +
                location_name(field.location) + " field '" + field.name + "' has " +
                std::to_string(field.rows()) + " rows; the fields belong to another mesh");
        out.values.row(static_cast<Eigen::Index>(i)) = field.values.row(index[i]);
    }
    return out;
}

}  // namespace

const Field& find_field(const std::vector<Field>& fields, const std::string& name)
{
    std::string names;
    for (const auto& f : fields)
    {
        if (f.name == name)
            return f;
        names += (names.empty() ? "" : ", ") + f.name;
    }
    throw InvalidInputError("no field named '" + name +
                            "'; available: " + (names.empty() ? std::string("none") : names));
}

void check_fields(const std::vector<Field>& fields, int points, int cells,
                  const std::string& source)
{
    std::set<std::pair<FieldLocation, std::string>> seen;
    for (const auto& f : fields)
    {
        const int expected = f.location == FieldLocation::Point ? points : cells;
        if (f.rows() != expected)
            throw InvalidInputError(std::string(location_name(f.location)) + " field '" + f.name +
                                    "' of " + source + " has " + std::to_string(f.rows()) +
                                    " values but the mesh has " + std::to_string(expected) + " " +
                                    (f.location == FieldLocation::Point ? "points" : "polygons") +
                                    "; the field belongs to another mesh");
        if (f.components() < 1)
            throw InvalidInputError("field '" + f.name + "' of " + source + " has no components");
        if (!seen.insert({f.location, f.name}).second)
            throw InvalidInputError(source + " has two " + location_name(f.location) +
                                    " fields named '" + f.name + "'; rename one");
    }
}

std::vector<Field> transfer_fields(const std::vector<Field>& fields, const Mesh& mesh)
{
    OpenMesh::VPropHandleT<int> input_index;
    OpenMesh::FPropHandleT<int> input_face;
    const bool has_index = mesh.get_property_handle(input_index, prop::input_index);
    const bool has_face = mesh.get_property_handle(input_face, prop::input_face);
    std::vector<int> point_rows, cell_rows;
    std::vector<Field> out;
    out.reserve(fields.size());
    for (const auto& f : fields)
    {
        const bool point = f.location == FieldLocation::Point;
        if (point ? !has_index : !has_face)
            throw InvalidInputError(std::string("transfer_fields: the mesh has no '") +
                                    (point ? prop::input_index : prop::input_face) +
                                    "' property; load it with load_tree_surface()");
        std::vector<int>& rows = point ? point_rows : cell_rows;
        if (rows.empty())
        {
            if (point)
                for (auto v : mesh.vertices())
                    rows.push_back(mesh.property(input_index, v));
            else
                for (auto fh : mesh.faces())
                    rows.push_back(mesh.property(input_face, fh));
        }
        out.push_back(gather(f, rows, point ? "vertex" : "face"));
    }
    return out;
}

}  // namespace vessel
