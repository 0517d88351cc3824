#include "vessel/fields/field_series.h"

#include "detail/pvd.h"
#include "vessel/core/errors.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

namespace vessel {

namespace fs = std::filesystem;

namespace {

std::string lower(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

// Integer point arrays whose name says they are ids (GlobalNodeID, vtkOriginalPointIds, ...).
bool is_id_array(const Field& f)
{
    if (f.type != FieldType::Int32 && f.type != FieldType::Int64)
        return false;
    const std::string n = lower(f.name);
    return n.size() >= 2 && (n.compare(n.size() - 2, 2, "id") == 0 ||
                             (n.size() >= 3 && n.compare(n.size() - 3, 3, "ids") == 0));
}

double bbox_diagonal(const RawMesh& mesh)
{
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
    for (const auto& p : mesh.points)
    {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    return mesh.points.empty() ? 0.0 : (hi - lo).norm();
}

// One step file of a series against the mesh: counts, positions, shared id arrays.
void check_step(const PolyData& step, const PolyData& mesh, const std::string& what,
                const FieldSeriesOptions& options)
{
    const std::size_t np = mesh.mesh.points.size(), nf = mesh.mesh.faces.size();
    if (step.mesh.points.size() != np || step.mesh.faces.size() != nf)
        throw InvalidInputError(what + " has " + std::to_string(step.mesh.points.size()) +
                                " points and " + std::to_string(step.mesh.faces.size()) +
                                " polygons but the mesh has " + std::to_string(np) + " and " +
                                std::to_string(nf) + "; the series was computed on another mesh");
    const double tolerance = options.position_tolerance * bbox_diagonal(mesh.mesh);
    for (std::size_t i = 0; i < np; ++i)
    {
        const double d = (step.mesh.points[i] - mesh.mesh.points[i]).norm();
        if (!(d <= tolerance))
        {
            const auto& p = step.mesh.points[i];
            const auto& q = mesh.mesh.points[i];
            char buf[256];
            std::snprintf(buf, sizeof buf,
                          ": point %zu is at (%g, %g, %g) but mesh vertex %zu is at (%g, %g, %g)"
                          " (%g apart, tolerance %g)",
                          i, p.x(), p.y(), p.z(), i, q.x(), q.y(), q.z(), d, tolerance);
            throw InvalidInputError(what + buf +
                                    "; the series belongs to another mesh or vertex order");
        }
    }
    for (const auto& f : step.point_data)
    {
        if (!is_id_array(f))
            continue;
        for (const auto& g : mesh.point_data)
            if (g.name == f.name && g.components() == f.components())
                for (Eigen::Index i = 0; i < f.rows(); ++i)
                    if (f.values.row(i) != g.values.row(i))
                        throw InvalidInputError(
                            what + ": id array '" + f.name + "' has " +
                            std::to_string(static_cast<long long>(f.values(i, 0))) + " at point " +
                            std::to_string(i) + " where the mesh has " +
                            std::to_string(static_cast<long long>(g.values(i, 0))) +
                            "; the series uses another vertex numbering");
    }
}

std::vector<Field> step_fields(const PolyData& step)
{
    std::vector<Field> fields = step.point_data;
    fields.insert(fields.end(), step.cell_data.begin(), step.cell_data.end());
    return fields;
}

std::string field_names(const std::vector<Field>& fields)
{
    std::string s;
    for (const auto& f : fields)
        s += (s.empty() ? "" : ", ") + f.name;
    return s.empty() ? "none" : s;
}

// Reads every file as one step and checks it; times must increase.
TimeSeries read_vtk_steps(const std::vector<std::pair<double, std::string>>& files,
                          const PolyData& mesh, const std::string& spec,
                          const FieldSeriesOptions& options)
{
    TimeSeries series;
    for (std::size_t k = 0; k < files.size(); ++k)
    {
        const auto& [time, file] = files[k];
        const std::string what = "step " + std::to_string(k) + " of " + spec + " (" + file + ")";
        if (k > 0 && !(time > series.times.back()))
            throw InvalidInputError(
                what + " has time " + std::to_string(time) + ", not after the previous step's " +
                std::to_string(series.times.back()) + "; order the steps by time");
        const PolyData step = read_polydata(file);
        check_step(step, mesh, what, options);
        auto fields = step_fields(step);
        if (k > 0)
        {
            std::vector<Field>& first = series.steps.front();
            bool same = fields.size() == first.size();
            for (std::size_t i = 0; same && i < fields.size(); ++i)
                same = fields[i].name == first[i].name && fields[i].location == first[i].location &&
                       fields[i].components() == first[i].components();
            if (!same)
                throw InvalidInputError(what + " has the arrays " + field_names(fields) +
                                        " but step 0 has " + field_names(first) +
                                        "; every step must carry the same arrays");
        }
        series.times.push_back(time);
        series.steps.push_back(std::move(fields));
        series.sources.push_back(file);
    }
    if (series.steps.empty() || series.steps.front().empty())
        throw InvalidInputError(spec + " has no data arrays; nothing to map");
    return series;
}

std::vector<std::pair<double, std::string>> pvd_files(const std::string& path)
{
    const fs::path dir = fs::path(path).parent_path();
    std::vector<std::pair<double, std::string>> files;
    for (const auto& e : detail::read_pvd(path))
        if (e.part == 0)
        {
            const fs::path file(e.file);
            files.emplace_back(e.time, (file.is_absolute() ? file : dir / file).string());
        }
    return files;
}

bool glob_match(const char* pattern, const char* name)
{
    if (*pattern == '\0')
        return *name == '\0';
    if (*pattern == '*')
        return glob_match(pattern + 1, name) || (*name != '\0' && glob_match(pattern, name + 1));
    return *name != '\0' && (*pattern == '?' || *pattern == *name) &&
           glob_match(pattern + 1, name + 1);
}

// The last run of digits in a file name, for ordering glob matches numerically.
long long last_number(const std::string& name)
{
    const auto end = name.find_last_of("0123456789");
    if (end == std::string::npos)
        return -1;
    auto begin = end;
    while (begin > 0 && std::isdigit(static_cast<unsigned char>(name[begin - 1])))
        --begin;
    return std::stoll(name.substr(begin, end - begin + 1));
}

std::vector<std::pair<double, std::string>> pattern_files(const std::string& pattern,
                                                          const FieldSeriesOptions& options)
{
    std::vector<std::string> names;
    if (pattern.find('%') != std::string::npos)
    {
        // Exactly one %d conversion (with optional zero padding and width): the pattern is used
        // as a printf format.
        const auto percent = pattern.find('%');
        auto d = percent + 1;
        while (d < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[d])))
            ++d;
        if (d >= pattern.size() || pattern[d] != 'd' ||
            pattern.find('%', percent + 1) != std::string::npos)
            throw InvalidInputError("read_field_series: pattern '" + pattern +
                                    "' must hold exactly one %d (e.g. wss_%03d.vtp)");
        const auto format = [&](int k) {
            char buf[4096];
            std::snprintf(buf, sizeof buf, pattern.c_str(), k);
            return std::string(buf);
        };
        int k = fs::exists(format(0)) ? 0 : 1;
        for (; fs::exists(format(k)); ++k)
            names.push_back(format(k));
    }
    else
    {
        const fs::path p(pattern);
        const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
        const std::string name_pattern = p.filename().string();
        if (fs::is_directory(dir))
            for (const auto& entry : fs::directory_iterator(dir))
                if (entry.is_regular_file() &&
                    glob_match(name_pattern.c_str(), entry.path().filename().string().c_str()))
                    names.push_back((p.parent_path() / entry.path().filename()).string());
        std::sort(names.begin(), names.end(), [](const std::string& a, const std::string& b) {
            const auto na = last_number(fs::path(a).filename().string());
            const auto nb = last_number(fs::path(b).filename().string());
            return na != nb ? na < nb : a < b;
        });
    }
    if (names.empty())
        throw IoError("read_field_series: no file matches '" + pattern +
                      "' (use wss_%03d.vtp counting from 0 or 1, or wss_*.vtp)");
    std::vector<std::pair<double, std::string>> files;
    for (std::size_t k = 0; k < names.size(); ++k)
        files.emplace_back(static_cast<double>(k) * options.time_step, names[k]);
    return files;
}

}  // namespace

void FieldSeriesOptions::validate() const
{
    if (!(time_step > 0.0) || !std::isfinite(time_step))
        throw InvalidInputError("FieldSeriesOptions: time_step must be positive, got " +
                                std::to_string(time_step));
    if (!(position_tolerance >= 0.0))
        throw InvalidInputError("FieldSeriesOptions: position_tolerance must be >= 0, got " +
                                std::to_string(position_tolerance));
}

TimeSeries read_field_series(const std::string& spec, const PolyData& mesh,
                             const FieldSeriesOptions& options)
{
    options.validate();
    const std::string ext = lower(fs::path(spec).extension().string());
    if (spec.find_first_of("%*?") != std::string::npos)
        return read_vtk_steps(pattern_files(spec, options), mesh, spec, options);
    if (ext == ".pvd")
        return read_vtk_steps(pvd_files(spec), mesh, spec, options);
    if (ext == ".csv")
        return read_csv_series(spec, static_cast<int>(mesh.mesh.points.size()), options);
    if (ext == ".vtp" || ext == ".vtk")
        return read_vtk_steps({{0.0, spec}}, mesh, spec, options);
    throw InvalidInputError("read_field_series: '" + spec +
                            "' is not a .pvd, .csv, .vtp or .vtk file nor a pattern with %d or *");
}

TimeSeries transfer_series(const TimeSeries& series, const Mesh& mesh)
{
    TimeSeries out = series;
    for (auto& step : out.steps)
        step = transfer_fields(step, mesh);
    return out;
}

void write_pvd_series(const std::string& pvd_path, const std::vector<PvdPart>& parts,
                      const TimeSeries& series, const VtkWriteOptions& options)
{
    const fs::path pvd(pvd_path);
    const std::string stem = pvd.stem().string();
    const fs::path dir = pvd.parent_path() / stem;
    fs::create_directories(dir);
    std::vector<detail::PvdEntry> entries;
    for (int k = 0; k < series.size(); ++k)
    {
        char number[32];
        std::snprintf(number, sizeof number, "_%03d", k);
        for (std::size_t p = 0; p < parts.size(); ++p)
        {
            PolyData data = parts[p].data;
            for (const auto& f : series.steps[k])
                (f.location == FieldLocation::Point ? data.point_data : data.cell_data)
                    .push_back(f);
            const std::string name = stem + number + parts[p].suffix + ".vtp";
            write_polydata((dir / name).string(), data, options);
            entries.push_back({series.times[k], static_cast<int>(p), stem + "/" + name});
        }
    }
    detail::write_pvd(pvd_path, entries);
}

}  // namespace vessel
