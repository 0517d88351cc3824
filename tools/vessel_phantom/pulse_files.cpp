#include "pulse_files.h"

#include "vessel/fields/field_series.h"

namespace vessel::cli {

void write_pulse_files(const std::string& prefix, const RawMesh& geometry,
                       const TimeSeries& series, const std::string& name, bool csv)
{
    write_pvd_series(prefix + ".pvd", PolyData{geometry, {}, {}, {}}, series);
    if (!csv)
        return;
    write_csv_series(prefix + ".csv", series, name, CsvLayout::Wide);
    write_csv_series(prefix + "-long.csv", series, name, CsvLayout::Long);
}

}  // namespace vessel::cli
