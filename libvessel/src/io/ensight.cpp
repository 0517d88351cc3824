#include "vessel/io/ensight.h"

#include "detail/atomic_file.h"

#include "vessel/core/errors.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>

namespace vessel {

namespace {

namespace fs = std::filesystem;

constexpr const char* kWho = "write_ensight_series";

// C Binary records: 80-byte strings (zero-padded), 32-bit integers and floats in the machine's
// byte order (VTK's reader finds the order from the part numbers).
void put_string(FILE* out, const std::string& text)
{
    char record[80] = {};
    std::copy_n(text.data(), std::min<std::size_t>(text.size(), 79), record);
    std::fwrite(record, 1, sizeof record, out);
}

void put_int(FILE* out, std::int32_t value) { std::fwrite(&value, sizeof value, 1, out); }

// Component \p c of every row of \p values as floats.
void put_column(FILE* out, const Eigen::MatrixXd& values, int c)
{
    std::vector<float> column(static_cast<std::size_t>(values.rows()), 0.0f);
    if (c < values.cols())
        for (Eigen::Index r = 0; r < values.rows(); ++r)
            column[static_cast<std::size_t>(r)] = static_cast<float>(values(r, c));
    std::fwrite(column.data(), sizeof(float), column.size(), out);
}

// \p text with every character other than a letter, a digit, `_` or one of \p also replaced by
// `_`; "_" if empty.
std::string sanitized(std::string text, const char* also)
{
    for (char& c : text)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && !std::strchr(also, c))
            c = '_';
    return text.empty() ? "_" : text;
}

std::string variable_name(const std::string& name)
{
    const std::string out = sanitized(name, "");
    return std::isdigit(static_cast<unsigned char>(out[0])) ? "_" + out : out;
}

// One EnSight variable: a field, or one component of a field of 4 or more components.
struct Variable
{
    std::string name;      // EnSight name (the description in the case file)
    std::size_t field{};   // index in its list (static: point then cell data; step: the step's)
    int component = -1;    // -1: the whole field
    bool vector = false;
    FieldLocation location = FieldLocation::Point;
};

// The variables of \p fields, named uniquely against \p taken (which they are added to).
std::vector<Variable> variables(const std::vector<Field>& fields, std::set<std::string>& taken)
{
    const auto unique = [&](const std::string& base) {
        std::string name = base;
        for (int k = 2; taken.count(name); ++k)
            name = base + "_" + std::to_string(k);
        taken.insert(name);
        return name;
    };
    std::vector<Variable> out;
    for (std::size_t i = 0; i < fields.size(); ++i)
    {
        const Field& f = fields[i];
        const std::string base = variable_name(f.name);
        const int n = f.components();
        if (n <= 3)
            out.push_back({unique(base), i, -1, n > 1, f.location});
        else
            for (int c = 0; c < n; ++c)
                out.push_back({unique(base + "_" + std::to_string(c)), i, c, false, f.location});
    }
    return out;
}

void write_variable(const std::string& path, const Variable& v, const Field& field)
{
    detail::write_atomically(path, kWho, [&](FILE* out) {
        put_string(out, v.name);
        put_string(out, "part");
        put_int(out, 1);
        put_string(out, v.location == FieldLocation::Point ? "coordinates" : "tria3");
        if (v.component >= 0)
            put_column(out, field.values, v.component);
        else
            for (int c = 0; c < (v.vector ? 3 : 1); ++c)
                put_column(out, field.values, c);
    });
}

std::string case_line(const Variable& v, const std::string& file, bool per_step)
{
    return std::string(v.vector ? "vector" : "scalar") + " per " +
           (v.location == FieldLocation::Point ? "node" : "element") + ": " +
           (per_step ? "1 " : "") + v.name + " " + file + "\n";
}

}  // namespace

std::string ensight_data_folder(const std::string& case_path)
{
    return sanitized(fs::path(case_path).stem().string(), "-.");
}

void write_ensight_series(const std::string& case_path, const PolyData& data,
                          const TimeSeries& series, const EnSightOptions& options)
{
    if (series.size() == 0)
        throw InvalidInputError(std::string(kWho) + ": the series has no steps");
    if (series.steps.size() != series.times.size())
        throw InvalidInputError(std::string(kWho) + ": the series has " +
                                std::to_string(series.times.size()) + " times but " +
                                std::to_string(series.steps.size()) + " steps");
    if (options.folder.find_first_of(" \t\n") != std::string::npos)
        throw InvalidInputError(std::string(kWho) + ": the data folder '" + options.folder +
                                "' has white space, which the case file cannot hold; name it "
                                "without");
    const auto rows = [&](const Field& f) {
        return static_cast<Eigen::Index>(f.location == FieldLocation::Point
                                              ? data.mesh.points.size()
                                              : data.mesh.faces.size());
    };
    const auto check_fits = [&](const Field& f, const std::string& where) {
        if (f.rows() != rows(f))
            throw InvalidInputError(std::string(kWho) + ": field '" + f.name + "' " + where +
                                    " has " + std::to_string(f.rows()) + " rows but the mesh has " +
                                    std::to_string(rows(f)) +
                                    (f.location == FieldLocation::Point ? " points" : " triangles"));
    };
    for (std::size_t i = 0; i < data.mesh.faces.size(); ++i)
        if (data.mesh.faces[i].size() != 3)
            throw InvalidInputError(std::string(kWho) + ": polygon " + std::to_string(i) + " has " +
                                    std::to_string(data.mesh.faces[i].size()) +
                                    " vertices; EnSight's tria3 parts hold triangles only");

    // Everything checked before the first file is written.
    const auto check_step = [&](int k, const std::vector<Field>& fields,
                                const std::vector<Field>& first) {
        bool same = fields.size() == first.size();
        for (std::size_t i = 0; same && i < fields.size(); ++i)
            same = fields[i].name == first[i].name &&
                   fields[i].components() == first[i].components() &&
                   fields[i].location == first[i].location;
        if (!same)
            throw InvalidInputError(std::string(kWho) + ": step " + std::to_string(k) +
                                    " has other fields than step 0 (names, order, components or "
                                    "location)");
        for (const Field& f : fields)
            check_fits(f, "of step " + std::to_string(k));
    };
    for (const Field& f : data.point_data)
        check_fits(f, "of the mesh");
    for (const Field& f : data.cell_data)
        check_fits(f, "of the mesh");
    for (int k = 0; k < series.size(); ++k)
        check_step(k, series.steps[k], series.steps[0]);

    const fs::path case_file(case_path);
    const std::string folder =
        options.folder.empty() ? ensight_data_folder(case_path) : options.folder;
    const fs::path dir = case_file.parent_path() / folder;
    std::error_code error;
    fs::create_directories(dir, error);
    if (error)
        throw IoError(std::string(kWho) + ": cannot make the folder " + dir.string() + ": " +
                      error.message());
    const std::string stem = ensight_data_folder(case_path);
    const auto relative = [&](const std::string& name) { return folder + "/" + stem + name; };
    const auto file = [&](const std::string& name) { return (dir / (stem + name)).string(); };

    // Geometry, once.
    detail::write_atomically(file(".geo"), kWho, [&](FILE* out) {
        put_string(out, "C Binary");
        put_string(out, "libvessel: " + stem);
        put_string(out, "triangles of one part");
        put_string(out, "node id off");
        put_string(out, "element id off");
        put_string(out, "part");
        put_int(out, 1);
        put_string(out, options.part_name);
        put_string(out, "coordinates");
        const auto n = static_cast<std::int32_t>(data.mesh.points.size());
        put_int(out, n);
        std::vector<float> column(data.mesh.points.size());
        for (int c = 0; c < 3; ++c)
        {
            for (std::size_t i = 0; i < column.size(); ++i)
                column[i] = static_cast<float>(data.mesh.points[i][c]);
            std::fwrite(column.data(), sizeof(float), column.size(), out);
        }
        put_string(out, "tria3");
        put_int(out, static_cast<std::int32_t>(data.mesh.faces.size()));
        std::vector<std::int32_t> corners;
        corners.reserve(3 * data.mesh.faces.size());
        for (const auto& face : data.mesh.faces)
            for (int v : face)
                corners.push_back(v + 1);  // EnSight numbers nodes from 1
        std::fwrite(corners.data(), sizeof(std::int32_t), corners.size(), out);
    });

    std::string lines;
    std::set<std::string> taken;
    // The PolyData's arrays: static variables.
    std::vector<Field> fixed = data.point_data;
    fixed.insert(fixed.end(), data.cell_data.begin(), data.cell_data.end());
    for (const Variable& v : variables(fixed, taken))
    {
        const std::string suffix = "." + v.name;
        write_variable(file(suffix), v, fixed[v.field]);
        lines += case_line(v, relative(suffix), false);
    }

    // The steps: one file per variable and step, numbered with a wildcard of >= 4 digits.
    const auto step_fields = [&](int k) {
        return options.step_fields ? options.step_fields(series.steps[k]) : series.steps[k];
    };
    const std::vector<Field> first = step_fields(0);
    const std::vector<Variable> changing = variables(first, taken);
    const int width = std::max(4, static_cast<int>(std::to_string(series.size() - 1).size()));
    for (int k = 0; k < series.size(); ++k)
    {
        const std::vector<Field> later = k == 0 ? std::vector<Field>{} : step_fields(k);
        const std::vector<Field>& fields = k == 0 ? first : later;
        check_step(k, fields, first);
        std::string number = std::to_string(k);
        number.insert(0, static_cast<std::size_t>(width) - number.size(), '0');
        for (const Variable& v : changing)
            write_variable(file("." + v.name + "." + number), v, fields[v.field]);
    }
    for (const Variable& v : changing)
        lines += case_line(v, relative("." + v.name + "." + std::string(width, '*')), true);

    std::string text = "# libvessel: " + stem +
                       "\nFORMAT\ntype: ensight gold\n\nGEOMETRY\nmodel: " + relative(".geo") +
                       "\n\nVARIABLE\n" + lines + "\nTIME\ntime set: 1\nnumber of steps: " +
                       std::to_string(series.size()) +
                       "\nfilename start number: 0\nfilename increment: 1\ntime values:\n";
    for (int k = 0; k < series.size(); ++k)
    {
        char value[32];
        std::snprintf(value, sizeof value, "%.9g%s", series.times[k],
                      (k % 6 == 5 || k + 1 == series.size()) ? "\n" : " ");
        text += value;
    }
    detail::write_atomically(case_path, kWho,
                             [&](FILE* out) { std::fwrite(text.data(), 1, text.size(), out); });
}

}  // namespace vessel
