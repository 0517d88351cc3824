#pragma once

#include "vessel/fields/fields.h"
#include "vessel/io/vtk_io.h"

#include <functional>
#include <string>
#include <vector>

namespace vessel {

//! \file A time series of fields on one fixed triangle mesh as an EnSight Gold case, the format
//! of CFD post-processing that keeps the geometry in one file and each variable of each step in
//! its own (EnSight Gold user manual, "EnSight Gold Case File Format" and "EnSight Gold
//! Geometry File Format", C Binary form). ParaView opens `OUT.case` and so do VTK's
//! `vtkGenericEnSightReader` (C++ and Python), with the series' times as its time values.
//!
//! Files: the case file `DIR/NAME.case` (text) and, in the folder ensight_data_folder() names,
//! `NAME.geo` (points and triangles, once), `NAME.VAR` for each field that does not change
//! (the PolyData's own arrays) and `NAME.VAR.0000` ... for each field of each step. C Binary
//! stores 32-bit floats: values are rounded to single precision (about 7 significant digits),
//! integer arrays stay exact up to 2^24.
//! Arrays of 1 component are scalars, of 3 vectors, of 2 vectors with a zero third component
//! (e.g. `uv`); any other count is written as one scalar per component, `NAME_0`, `NAME_1`, ...
//! Array names become EnSight variable names with every character other than a letter, digit or
//! `_` replaced by `_` (and `_` put before a leading digit), made unique with `_2`, `_3`, ...

//! How write_ensight_series() lays out its files.
struct EnSightOptions
{
    //! Folder of the data files, relative to the case file's folder, without white space;
    //! empty: the default ensight_data_folder() of the case file. Two cases may share a folder (their data files
    //! are named after their own case files), as the 3D mesh and its map do.
    std::string folder;
    //! What a step's fields become on this geometry (empty: written as they are), e.g.
    //! map_fields() for a map.
    std::function<std::vector<Field>(const std::vector<Field>&)> step_fields;
    //! Description of the single part in the geometry file (at most 79 characters).
    std::string part_name = "wall";
};

//! \brief The default data folder of \p case_path, relative to its folder: the case file's stem
//! with every character other than a letter, digit, `_`, `-` or `.` replaced by `_` (VTK's
//! reader splits the case file's lines at white space).
std::string ensight_data_folder(const std::string& case_path);

//! \brief Write \p data's geometry and arrays once and every step of \p series as an EnSight
//! Gold case (see the file comment). Each file goes through a temporary file + rename; the case
//! file is written last.
//! \param data triangles only; its point and cell arrays are the case's static variables.
//! \param series at least one step; its times (seconds, increasing) become the case's time
//! values; each step's fields (after EnSightOptions::step_fields) must have the same names, in
//! the same order, and rows that fit \p data.
//! \throw InvalidInputError if a polygon is not a triangle, the series is empty, a field does not
//! fit or EnSightOptions::folder has white space; IoError if a folder or file cannot be written.
void write_ensight_series(const std::string& case_path, const PolyData& data,
                          const TimeSeries& series, const EnSightOptions& options = {});

}  // namespace vessel
