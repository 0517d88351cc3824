#pragma once

#include "vessel/fields/fields.h"
#include "vessel/io/vtk_io.h"

#include <string>
#include <vector>

namespace vessel {

//! \file Time series of fields over one geometry: a ParaView `.pvd` collection, numbered `.vtp`
//! / `.vtk` files, or a CSV table; see docs/fields.md for the formats.

struct FieldSeriesOptions
{
    //! CSV in wide form: the field's name (empty: the file's stem). Not used otherwise.
    std::string name;
    //! Seconds between steps where the source has no times (numbered files; CSV columns whose
    //! headers are not numbers): step k is at `k * time_step`.
    double time_step = 1.0;
    //! Largest distance between a step file's point and the mesh's, as a fraction of the
    //! mesh's bounding-box diagonal (float32 files round coordinates at ~1e-7). Checked for
    //! every paired point, however the points are paired (see match_by).
    double position_tolerance = 1e-5;
    //! How the points of a step file (`.vtp`, `.vtk`, `.vtu`) are paired with the mesh's:
    //! - empty (default): by `GlobalNodeID` when the mesh and the step both have that array,
    //!   otherwise in file order;
    //! - `order`: step point i is mesh vertex i (same point and polygon counts);
    //! - `position`: the step's point nearest each mesh vertex, within position_tolerance;
    //! - any other word: the name of an integer point array that the mesh and every step hold
    //!   (each of the mesh's ids must occur in the step; the step may have more points, e.g. a
    //!   solver's volume mesh). The id array itself is then left out of the steps: paired, it
    //!   equals the mesh's.
    //! A mesh vertex left without a partner is an error that counts them; nothing is guessed.
    std::string match_by;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! \brief Read a series given as
//! - `NAME.pvd`: a ParaView collection (DataSet timestep/file entries; part 0 is used),
//! - a pattern of numbered files: printf-style (`wss_%03d.vtp`, counted up from 0 or 1 until a
//!   file is missing) or a glob in the file name (`wss_*.vtp`, ordered by the number in it),
//! - `NAME.csv`: wide (vertex id column, then one column per step whose header is its time) or
//!   long (columns vertex, time, value),
//! - a single `.vtp` / `.vtk` / `.vtu` (one step at time 0),
//! and pair every step's points with \p mesh's (FieldSeriesOptions::match_by: in file order,
//! by an id array such as GlobalNodeID, or by position), checking positions, integer id arrays
//! present in both, and CSV vertex ids (0-based, each exactly once). The step's point arrays come
//! back in the mesh's vertex order. Its cell arrays are placed on the mesh's polygons with the
//! same corners; a step without polygons (a `.vtu` volume) has its cell arrays left out, with a
//! note in TimeSeries::notes.
//! \param mesh the input surface with its arrays (read_polydata(), or a RawMesh with no fields).
//! \throw InvalidInputError saying which step, file, row or id does not match and how (with the
//! number of unpaired vertices or polygons).
//! \throw IoError if a file is missing or unreadable.
TimeSeries read_field_series(const std::string& spec, const PolyData& mesh,
                             const FieldSeriesOptions& options = {});

//! transfer_fields() on every step: the series with rows indexed by the (cut) mesh.
TimeSeries transfer_series(const TimeSeries& series, const Mesh& mesh);

//! \brief Read a CSV series (see read_field_series()) for a mesh of \p points input points.
//! \throw InvalidInputError / IoError as read_field_series().
TimeSeries read_csv_series(const std::string& path, int points,
                           const FieldSeriesOptions& options = {});

//! How write_csv_series() lays out a table.
enum class CsvLayout
{
    Wide,  //!< header `vertex,t0,t1,...`; one row per vertex
    Long,  //!< header `vertex,time,NAME`; one row per (time, vertex)
};

//! \brief Write the scalar point field \p name of \p series as CSV (temporary file + rename).
//! \throw InvalidInputError if the field is missing, not a scalar or not a point field.
//! \throw IoError if the file cannot be written.
void write_csv_series(const std::string& path, const TimeSeries& series, const std::string& name,
                      CsvLayout layout);

//! \brief Write a `.pvd` collection of \p data and each step's fields: for every step k the file
//! `<dir>/<stem>/<stem>_<k, 3 digits>.vtp` holds \p data plus step k's fields (rows = its points
//! / polygons), and the `.pvd` lists them with their `timestep`. Every step file holds the whole
//! geometry, as ParaView's and VTK's `.vtp` readers need; for a series on a fixed mesh that
//! should store it once see write_ensight_series() (vessel/io/ensight.h).
//! \throw InvalidInputError if a field does not fit \p data; IoError if writing fails.
void write_pvd_series(const std::string& pvd_path, const PolyData& data, const TimeSeries& series,
                      const VtkWriteOptions& options = {});

}  // namespace vessel
