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
#include <unordered_map>

#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStaticPointLocator.h>

namespace vessel {

namespace fs = std::filesystem;

namespace {

std::string lower(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

constexpr const char* kGlobalNodeId = "GlobalNodeID";

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

std::string point_text(const Eigen::Vector3d& p)
{
    char buf[128];
    std::snprintf(buf, sizeof buf, "(%g, %g, %g)", p.x(), p.y(), p.z());
    return buf;
}

const Field* find_point_array(const PolyData& data, const std::string& name)
{
    for (const auto& f : data.point_data)
        if (f.name == name)
            return &f;
    return nullptr;
}

// In file order: counts, positions and the id arrays both sides have must agree row by row.
void check_same_order(const PolyData& step, const PolyData& mesh, const std::string& what,
                      double tolerance)
{
    const std::size_t np = mesh.mesh.points.size(), nf = mesh.mesh.faces.size();
    if (step.mesh.points.size() != np || step.mesh.faces.size() != nf)
        throw InvalidInputError(what + " has " + std::to_string(step.mesh.points.size()) +
                                " points and " + std::to_string(step.mesh.faces.size()) +
                                " polygons but the mesh has " + std::to_string(np) + " and " +
                                std::to_string(nf) +
                                "; the series was computed on another mesh (or its points come "
                                "in another order: --match-by GlobalNodeID or position)");
    for (std::size_t i = 0; i < np; ++i)
    {
        const double d = (step.mesh.points[i] - mesh.mesh.points[i]).norm();
        if (!(d <= tolerance))
        {
            char buf[96];
            std::snprintf(buf, sizeof buf, " (%g apart, tolerance %g)", d, tolerance);
            throw InvalidInputError(what + ": point " + std::to_string(i) + " is at " +
                                    point_text(step.mesh.points[i]) + " but mesh vertex " +
                                    std::to_string(i) + " is at " +
                                    point_text(mesh.mesh.points[i]) + buf +
                                    "; the series belongs to another mesh or vertex order "
                                    "(--match-by GlobalNodeID or position pairs the points)");
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

// "N of the mesh's M vertices ... (vertex a, vertex b, ...)": the count and the first few.
std::string unpaired_text(const std::vector<std::string>& examples, std::size_t count,
                          std::size_t total, const std::string& what_of)
{
    std::string s = std::to_string(count) + " of the mesh's " + std::to_string(total) + " " +
                    what_of + " (";
    for (std::size_t i = 0; i < examples.size(); ++i)
        s += (i == 0 ? "" : "; ") + examples[i];
    return s + (count > examples.size() ? "; ..." : "") + ")";
}

// Step point paired with each mesh vertex through the integer point array \p name.
std::vector<int> pair_by_id(const PolyData& step, const PolyData& mesh, const std::string& name,
                            const std::string& what)
{
    const Field* mine = find_point_array(mesh, name);
    const Field* theirs = find_point_array(step, name);
    if (!mine || !theirs)
        throw InvalidInputError(what + ": --match-by " + name + " needs the point array '" +
                                name + "' in the mesh and in every step, but " +
                                (mine ? "the step" : "the mesh") +
                                " has none; use --match-by position to pair by coordinates");
    if (mine->components() != 1 || theirs->components() != 1)
        throw InvalidInputError(what + ": the id array '" + name +
                                "' must have one component per point");
    std::unordered_map<long long, int> index;
    index.reserve(static_cast<std::size_t>(theirs->rows()));
    for (Eigen::Index i = 0; i < theirs->rows(); ++i)
    {
        const auto id = static_cast<long long>(theirs->values(i, 0));
        if (!index.emplace(id, static_cast<int>(i)).second)
            throw InvalidInputError(what + ": id " + std::to_string(id) + " of '" + name +
                                    "' is at points " + std::to_string(index[id]) + " and " +
                                    std::to_string(i) +
                                    "; the ids must be unique to pair the points");
    }
    std::vector<int> pair(static_cast<std::size_t>(mine->rows()), -1);
    std::vector<std::string> examples;
    std::size_t missing = 0;
    for (Eigen::Index v = 0; v < mine->rows(); ++v)
    {
        const auto id = static_cast<long long>(mine->values(v, 0));
        const auto it = index.find(id);
        if (it != index.end())
            pair[static_cast<std::size_t>(v)] = it->second;
        else if (++missing <= 5)
            examples.push_back("vertex " + std::to_string(v) + ": " + std::to_string(id));
    }
    if (missing > 0)
        throw InvalidInputError(what + ": " +
                                unpaired_text(examples, missing, pair.size(),
                                              "vertices have a " + name + " the step does not hold") +
                                "; the series was computed on another mesh or numbering");
    return pair;
}

// Step point nearest each mesh vertex, within \p tolerance.
std::vector<int> pair_by_position(const PolyData& step, const PolyData& mesh,
                                  const std::string& what, double tolerance)
{
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(static_cast<vtkIdType>(step.mesh.points.size()));
    for (std::size_t i = 0; i < step.mesh.points.size(); ++i)
        points->SetPoint(static_cast<vtkIdType>(i), step.mesh.points[i].data());
    vtkNew<vtkPolyData> cloud;
    cloud->SetPoints(points);
    vtkNew<vtkStaticPointLocator> locator;
    locator->SetDataSet(cloud);
    locator->BuildLocator();
    std::vector<int> pair(mesh.mesh.points.size(), -1);
    std::vector<std::string> examples;
    std::size_t missing = 0;
    for (std::size_t v = 0; v < pair.size(); ++v)
    {
        const Eigen::Vector3d& p = mesh.mesh.points[v];
        const vtkIdType near = locator->FindClosestPoint(p.data());
        const double d = near < 0 ? INFINITY : (step.mesh.points[near] - p).norm();
        if (d <= tolerance)
            pair[v] = static_cast<int>(near);
        else if (++missing <= 5)
        {
            char buf[64];
            std::snprintf(buf, sizeof buf, " is %g from the nearest", d);
            examples.push_back("vertex " + std::to_string(v) + " at " + point_text(p) + buf);
        }
    }
    if (missing > 0)
    {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%g", tolerance);
        throw InvalidInputError(what + ": " +
                                unpaired_text(examples, missing, pair.size(),
                                              std::string("vertices have no step point within ") +
                                                  buf) +
                                "; the series was computed on another mesh (or in other units); "
                                "a larger --match-tolerance accepts coarser coordinates");
    }
    return pair;
}

// The paired points must be where the mesh's vertices are (ids from another mesh otherwise).
void check_paired_positions(const PolyData& step, const PolyData& mesh,
                            const std::vector<int>& pair, const std::string& what,
                            double tolerance)
{
    for (std::size_t v = 0; v < pair.size(); ++v)
    {
        const double d = (step.mesh.points[pair[v]] - mesh.mesh.points[v]).norm();
        if (!(d <= tolerance))
        {
            char buf[96];
            std::snprintf(buf, sizeof buf, " (%g apart, tolerance %g)", d, tolerance);
            throw InvalidInputError(what + ": mesh vertex " + std::to_string(v) + " at " +
                                    point_text(mesh.mesh.points[v]) + " is paired with point " +
                                    std::to_string(pair[v]) + " at " +
                                    point_text(step.mesh.points[pair[v]]) + buf +
                                    "; the ids belong to another mesh (or another unit: "
                                    "--match-tolerance)");
        }
    }
}

// Step polygon with the same corners as each mesh polygon (-1: none), through the point pairs.
std::vector<int> pair_faces(const PolyData& step, const PolyData& mesh,
                            const std::vector<int>& pair)
{
    std::vector<int> mesh_of(step.mesh.points.size(), -1);
    for (std::size_t v = 0; v < pair.size(); ++v)
        mesh_of[pair[v]] = static_cast<int>(v);
    std::map<std::vector<int>, int> by_corners;
    for (std::size_t f = 0; f < step.mesh.faces.size(); ++f)
    {
        std::vector<int> key;
        for (int c : step.mesh.faces[f])
            key.push_back(c >= 0 && c < static_cast<int>(mesh_of.size()) ? mesh_of[c] : -1);
        if (std::find(key.begin(), key.end(), -1) != key.end())
            continue;  // not on the wall
        std::sort(key.begin(), key.end());
        by_corners.emplace(std::move(key), static_cast<int>(f));
    }
    std::vector<int> faces(mesh.mesh.faces.size(), -1);
    for (std::size_t f = 0; f < faces.size(); ++f)
    {
        std::vector<int> key = mesh.mesh.faces[f];
        std::sort(key.begin(), key.end());
        if (const auto it = by_corners.find(key); it != by_corners.end())
            faces[f] = it->second;
    }
    return faces;
}

// \p field with row i taken from row rows[i].
Field rows_of(const Field& field, const std::vector<int>& rows)
{
    Field out = field;
    out.values.resize(static_cast<Eigen::Index>(rows.size()), field.components());
    for (std::size_t i = 0; i < rows.size(); ++i)
        out.values.row(static_cast<Eigen::Index>(i)) = field.values.row(rows[i]);
    return out;
}

// The step's arrays in the mesh's order: point rows through \p pair, cell rows through the
// polygons with the same corners.
std::vector<Field> paired_fields(const PolyData& step, const PolyData& mesh,
                                 const std::vector<int>& pair, const std::string& what)
{
    std::vector<Field> fields;
    for (const auto& f : step.point_data)
        fields.push_back(rows_of(f, pair));
    if (step.cell_data.empty())
        return fields;
    const std::vector<int> faces = pair_faces(step, mesh, pair);
    std::vector<std::string> examples;
    const auto missing =
        static_cast<std::size_t>(std::count(faces.begin(), faces.end(), -1));
    for (std::size_t f = 0; f < faces.size() && examples.size() < 5; ++f)
        if (faces[f] < 0)
            examples.push_back("polygon " + std::to_string(f));
    if (missing > 0)
        throw InvalidInputError(what + ": " +
                                unpaired_text(examples, missing, faces.size(),
                                              "polygons have no polygon with the same corners "
                                              "in the step") +
                                ", so its cell arrays cannot be placed; remove them from the "
                                "files or compute the series on this mesh");
    for (const auto& f : step.cell_data)
        fields.push_back(rows_of(f, faces));
    return fields;
}

// One step file's arrays in the mesh's order, its points paired as FieldSeriesOptions::match_by
// says.
std::vector<Field> step_fields(const PolyData& step, const PolyData& mesh,
                               const std::string& what, const FieldSeriesOptions& options)
{
    const double tolerance = options.position_tolerance * bbox_diagonal(mesh.mesh);
    std::string how = options.match_by;
    if (how.empty())
        how = find_point_array(mesh, kGlobalNodeId) && find_point_array(step, kGlobalNodeId)
                  ? kGlobalNodeId
                  : "order";
    if (how == "order")
    {
        check_same_order(step, mesh, what, tolerance);
        std::vector<Field> fields = step.point_data;
        fields.insert(fields.end(), step.cell_data.begin(), step.cell_data.end());
        return fields;
    }
    if (how == "position")
        return paired_fields(step, mesh, pair_by_position(step, mesh, what, tolerance), what);
    const std::vector<int> pair = pair_by_id(step, mesh, how, what);
    check_paired_positions(step, mesh, pair, what, tolerance);
    std::vector<Field> fields = paired_fields(step, mesh, pair, what);
    // Paired, the id array is the mesh's own: not repeated beside it in the outputs.
    fields.erase(std::remove_if(fields.begin(), fields.end(),
                                [&](const Field& f) {
                                    return f.location == FieldLocation::Point && f.name == how;
                                }),
                 fields.end());
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
        std::vector<std::string> dropped;
        PolyData step;
        if (lower(fs::path(file).extension().string()) == ".vtu")
        {
            UnstructuredGrid grid = read_unstructured_grid(file);
            step = std::move(grid.data);
            dropped = std::move(grid.volume_cell_arrays);
        }
        else
            step = read_polydata(file);
        auto fields = step_fields(step, mesh, what, options);
        if (k == 0 && !dropped.empty())
        {
            std::string names;
            for (const auto& name : dropped)
                names += (names.empty() ? "" : ", ") + name;
            series.notes.push_back(spec + ": the cell arrays " + names + " of " + file +
                                   " belong to volume cells, not to the wall's polygons; "
                                   "they are not carried");
        }
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
    if (ext == ".vtp" || ext == ".vtk" || ext == ".vtu")
        return read_vtk_steps({{0.0, spec}}, mesh, spec, options);
    throw InvalidInputError("read_field_series: '" + spec +
                            "' is not a .pvd, .csv, .vtp, .vtk or .vtu file nor a pattern with %d "
                            "or *");
}

TimeSeries transfer_series(const TimeSeries& series, const Mesh& mesh)
{
    TimeSeries out = series;
    for (auto& step : out.steps)
        step = transfer_fields(step, mesh);
    return out;
}

void write_pvd_series(const std::string& pvd_path, const PolyData& data, const TimeSeries& series,
                      const VtkWriteOptions& options)
{
    const fs::path pvd(pvd_path);
    const std::string stem = pvd.stem().string();
    const fs::path dir = pvd.parent_path() / stem;
    fs::create_directories(dir);
    std::vector<detail::PvdEntry> entries;
    for (int k = 0; k < series.size(); ++k)
    {
        char step[32];
        std::snprintf(step, sizeof step, "_%03d", k);
        PolyData with_step = data;
        for (const auto& f : series.steps[k])
            (f.location == FieldLocation::Point ? with_step.point_data : with_step.cell_data)
                .push_back(f);
        const std::string name = stem + step + ".vtp";
        write_polydata((dir / name).string(), with_step, options);
        entries.push_back({series.times[k], 0, stem + "/" + name});
    }
    detail::write_pvd(pvd_path, entries);
}

}  // namespace vessel
