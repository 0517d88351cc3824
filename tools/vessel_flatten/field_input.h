#pragma once

// The input mesh with its arrays and a --fields series, read the same way by vessel-flatten and
// vessel-view.

#include "vessel/fields/field_series.h"
#include "vessel/io/vtk_io.h"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace vessel::cli {

struct FieldInput
{
    PolyData data;              //!< the input file: mesh (file indices) and, for .vtp/.vtk, arrays
    std::vector<Field> fields;  //!< the input's point arrays, then its cell arrays
    TimeSeries series;          //!< --fields (empty without), checked against `data`
};

//! The command-line options --fields, --field and --time-step.
struct FieldArgs
{
    std::string spec;  //!< --fields SPEC (empty: none)
    std::string name;  //!< --field NAME (empty: all arrays)
    //! --time-step, --match-by, --match-tolerance; `name` is set from --field when reading
    FieldSeriesOptions series;
};

//! `--field NAME[:magnitude|x|y|z]`: an array and the value of it that images draw.
struct FieldChoice
{
    std::string name;    //!< the array (empty: none chosen)
    int component = -1;  //!< 0, 1, 2 for x, y, z; -1: a scalar's value or a vector's length
    //! The colorbar title: `NAME`, `|NAME|` (a vector's length) or `NAME_x`.
    std::string title(int components) const;
};

//! \brief Split `--field` at its last ':'.
//! \throw InvalidInputError if the part after ':' is not magnitude, x, y or z.
FieldChoice parse_field_choice(const std::string& spec);

//! Adds --fields (\p purpose says what they are for), --field (unless \p with_field is false: a
//! tool with its own --field binds it to `args.name`), --time-step, --match-by and
//! --match-tolerance to \p app.
//! \return the --fields option.
CLI::Option* add_field_options(CLI::App& app, FieldArgs& args, const std::string& purpose,
                               bool with_field = true);

//! \brief Read \p input (any mesh format; .vtp/.vtk with their arrays) and the series
//! `args.spec` (empty: none) with read_field_series(). With `args.name`, the series keeps only
//! that array, or, with no series, the input must have it.
//! \throw InvalidInputError / IoError as read_polydata(), read_field_series() and find_field().
FieldInput read_field_input(const std::string& input, const FieldArgs& args);

}  // namespace vessel::cli
