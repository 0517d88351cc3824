#pragma once

// The files of a synthetic pulse series, written the same way by vessel-phantom --pulse and
// vessel-pulse.

#include "vessel/fields/fields.h"
#include "vessel/io/io.h"

#include <string>

namespace vessel::cli {

//! \brief Write \p series (point field \p name, rows = points of \p geometry) as PREFIX.pvd (+
//! PREFIX/PREFIX_NNN.vtp over \p geometry) and, with \p csv (a scalar field), PREFIX.csv (wide)
//! and PREFIX-long.csv.
//! \throw InvalidInputError / IoError as write_pvd_series() and write_csv_series().
void write_pulse_files(const std::string& prefix, const RawMesh& geometry,
                       const TimeSeries& series, const std::string& name, bool csv = true);

}  // namespace vessel::cli
