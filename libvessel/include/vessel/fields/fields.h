#pragma once

#include "vessel/core/mesh.h"

#include <string>
#include <vector>

namespace vessel {

//! \file Data arrays on a surface (CFD results: wall shear stress, displacement, ids, ...) and
//! how they follow the mesh through the cut.

//! Where a field lives: one row per input point, or one row per input polygon (cell).
enum class FieldLocation
{
    Point,
    Cell,
};

//! The type the values had in the file and are written back as; values are held as double
//! (exact for integers up to 2^53).
enum class FieldType
{
    Float32,
    Float64,
    Int32,
    Int64,
};

//! One named data array.
struct Field
{
    std::string name;
    FieldLocation location = FieldLocation::Point;
    FieldType type = FieldType::Float64;
    //! rows = points (or polygons) in file order, cols = components (1 scalar, 3 vector, ...).
    Eigen::MatrixXd values;

    int components() const { return static_cast<int>(values.cols()); }
    Eigen::Index rows() const { return values.rows(); }
};

//! The same fields at several times over one geometry (a heart cycle, say).
struct TimeSeries
{
    std::vector<double> times;              //!< seconds, strictly increasing
    std::vector<std::vector<Field>> steps;  //!< `steps[k]` = fields at `times[k]`, same names
    std::vector<std::string> sources;       //!< where step k came from (file, CSV column)
    std::vector<std::string> notes;         //!< what reading left out (e.g. volume cell arrays)

    int size() const { return static_cast<int>(times.size()); }
};

//! \brief The field called \p name.
//! \throw InvalidInputError listing the available names if there is none.
const Field& find_field(const std::vector<Field>& fields, const std::string& name);

//! \brief Check that every field fits a mesh with \p points input points and \p cells input
//! polygons, and that names are unique per location.
//! \param source where the fields come from, for the message (e.g. the file name).
//! \throw InvalidInputError naming the field, its row count and the expected one.
void check_fields(const std::vector<Field>& fields, int points, int cells,
                  const std::string& source);

//! \brief Carry fields of the input file onto a (cut) mesh: vertex v gets the point row
//! `prop::input_index[v]` (so every seam copy gets its original's values), face f the cell row
//! `prop::input_face[f]` (polygons split into triangles give each triangle their row).
//! \param fields rows in input-file order (see Field::values).
//! \param mesh a mesh from load_tree_surface() / make_tree_surface(), cut or not.
//! \return the fields with rows indexed by `v.idx()` (points) or `f.idx()` (cells) of \p mesh.
//! \throw InvalidInputError if a needed property is missing or an index exceeds a field's rows.
std::vector<Field> transfer_fields(const std::vector<Field>& fields, const Mesh& mesh);

}  // namespace vessel
