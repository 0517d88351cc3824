// CSV series: wide (vertex id, one column per step) and long (vertex, time, value) tables.
#include "detail/atomic_file.h"
#include "vessel/core/errors.h"
#include "vessel/fields/field_series.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>

namespace vessel {

namespace {

std::string trim(const std::string& s)
{
    std::size_t a = 0, b = s.size();
    while (a < b && (std::isspace(static_cast<unsigned char>(s[a])) || s[a] == '"'))
        ++a;
    while (b > a && (std::isspace(static_cast<unsigned char>(s[b - 1])) || s[b - 1] == '"'))
        --b;
    return s.substr(a, b - a);
}

std::vector<std::string> split(const std::string& line, char delimiter)
{
    std::vector<std::string> cells;
    std::size_t start = 0;
    for (;;)
    {
        const auto end = line.find(delimiter, start);
        cells.push_back(trim(line.substr(start, end - start)));
        if (end == std::string::npos)
            return cells;
        start = end + 1;
    }
}

bool parse_number(const std::string& text, double& value)
{
    if (text.empty())
        return false;
    char* end = nullptr;
    value = std::strtod(text.c_str(), &end);
    return *end == '\0' && std::isfinite(value);  // nan and inf are no field values
}

class CsvTable
{
public:
    explicit CsvTable(const std::string& path) : path_(path)
    {
        in_.open(path);
        if (!in_)
            throw IoError("read_csv_series: cannot open " + path);
        std::string line;
        if (!next_line(line))
            throw InvalidInputError("read_csv_series: " + path + " is empty");
        delimiter_ = line.find(',') != std::string::npos   ? ','
                     : line.find(';') != std::string::npos ? ';'
                                                           : '\t';
        header_ = split(line, delimiter_);
    }
    const std::vector<std::string>& header() const { return header_; }
    int line_number() const { return line_number_; }

    //! Next data row as numbers; false at the end. Throws naming the line and column.
    bool next_row(std::vector<double>& values)
    {
        std::string line;
        if (!next_line(line))
            return false;
        const auto cells = split(line, delimiter_);
        if (cells.size() != header_.size())
            throw InvalidInputError(where() + " has " + std::to_string(cells.size()) +
                                    " columns but the header has " +
                                    std::to_string(header_.size()));
        values.resize(cells.size());
        for (std::size_t c = 0; c < cells.size(); ++c)
            if (!parse_number(cells[c], values[c]))
                throw InvalidInputError(where() + ", column " + std::to_string(c + 1) + " ('" +
                                        header_[c] + "'): '" + cells[c] + "' is not a number");
        return true;
    }
    const std::string& path() const { return path_; }
    std::string where() const { return path_ + " line " + std::to_string(line_number_); }

private:
    bool next_line(std::string& line)
    {
        while (std::getline(in_, line))
        {
            ++line_number_;
            if (!line.empty() && line.back() == '\r')
                line.pop_back();
            if (!trim(line).empty() && line[0] != '#')
                return true;
        }
        return false;
    }

    std::string path_;
    std::ifstream in_;
    char delimiter_ = ',';
    std::vector<std::string> header_;
    int line_number_ = 0;
};

// Checks a vertex id read from a table and returns it as a row index.
int vertex_row(double id, int points, const CsvTable& table)
{
    if (id != std::floor(id) || id < 0 || id >= points)
    {
        char text[64];
        std::snprintf(text, sizeof text, "%.17g", id);
        throw InvalidInputError(table.where() + ": vertex id " + text +
                                " is not an index of the mesh's " + std::to_string(points) +
                                " points (ids are 0-based input vertex indices)");
    }
    return static_cast<int>(id);
}

// Throws if some row of \p seen is unset, listing the first missing ids.
void check_complete(const std::vector<int>& seen_line, const std::string& what)
{
    std::string missing;
    std::size_t count = 0;
    for (std::size_t i = 0; i < seen_line.size(); ++i)
        if (seen_line[i] == 0 && count++ < 5)
            missing += (missing.empty() ? "" : ", ") + std::to_string(i);
    if (count > 0)
        throw InvalidInputError(what + " has no value for " + std::to_string(count) +
                                " of the mesh's " + std::to_string(seen_line.size()) +
                                " vertices (ids " + missing + (count > 5 ? ", ..." : "") +
                                "); give one row per vertex");
}

void record(std::vector<int>& seen_line, int row, const CsvTable& table, const std::string& what)
{
    if (seen_line[row] != 0)
        throw InvalidInputError(table.where() + ": vertex " + std::to_string(row) +
                                " appears twice" + what + " (first on line " +
                                std::to_string(seen_line[row]) + ")");
    seen_line[row] = table.line_number();
}

Field scalar_field(const std::string& name, int points)
{
    Field f;
    f.name = name;
    f.values = Eigen::MatrixXd::Zero(points, 1);
    return f;
}

TimeSeries read_wide(CsvTable& table, int points, const std::string& name,
                     const FieldSeriesOptions& options)
{
    const auto& header = table.header();
    TimeSeries series;
    bool numeric = true;
    for (std::size_t c = 1; c < header.size(); ++c)
    {
        double t = 0;
        numeric = numeric && parse_number(header[c], t);
        series.times.push_back(t);
        series.sources.push_back("column '" + header[c] + "'");
    }
    if (!numeric)
        for (std::size_t k = 0; k < series.times.size(); ++k)
            series.times[k] = static_cast<double>(k) * options.time_step;
    for (std::size_t k = 1; k < series.times.size(); ++k)
        if (!(series.times[k] > series.times[k - 1]))
            throw InvalidInputError("read_csv_series: column " + std::to_string(k + 2) + " ('" +
                                    header[k + 1] +
                                    "') is not after the previous column's time; "
                                    "order the columns by time");
    series.steps.assign(series.times.size(), {scalar_field(name, points)});
    std::vector<int> seen(points, 0);
    std::vector<double> row;
    while (table.next_row(row))
    {
        const int v = vertex_row(row[0], points, table);
        record(seen, v, table, "");
        for (std::size_t k = 0; k < series.steps.size(); ++k)
            series.steps[k][0].values(v, 0) = row[k + 1];
    }
    check_complete(seen, table.path());
    return series;
}

TimeSeries read_long(CsvTable& table, int points)
{
    const std::string name = table.header()[2];
    std::map<double, std::pair<Field, std::vector<int>>> by_time;
    std::vector<double> row;
    while (table.next_row(row))
    {
        const int v = vertex_row(row[0], points, table);
        auto it = by_time.find(row[1]);
        if (it == by_time.end())
            it = by_time
                     .emplace(row[1], std::make_pair(scalar_field(name, points),
                                                     std::vector<int>(points, 0)))
                     .first;
        record(it->second.second, v, table, " at time " + std::to_string(row[1]));
        it->second.first.values(v, 0) = row[2];
    }
    TimeSeries series;
    for (auto& [time, step] : by_time)
    {
        char t[64];
        std::snprintf(t, sizeof t, "%g", time);
        check_complete(step.second, table.path() + " at time " + t);
        series.times.push_back(time);
        series.steps.push_back({std::move(step.first)});
        series.sources.push_back(std::string("rows at time ") + t);
    }
    return series;
}

std::string lower(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

}  // namespace

TimeSeries read_csv_series(const std::string& path, int points, const FieldSeriesOptions& options)
{
    options.validate();
    CsvTable table(path);
    const auto& header = table.header();
    if (header.size() < 2)
        throw InvalidInputError("read_csv_series: " + path +
                                " needs a vertex id column and at least one value column");
    const std::string second = lower(header[1]);
    TimeSeries series;
    if (header.size() == 3 && (second == "time" || second == "t"))
        series = read_long(table, points);
    else
        series = read_wide(
            table, points,
            options.name.empty() ? std::filesystem::path(path).stem().string() : options.name,
            options);
    if (series.steps.empty())
        throw InvalidInputError("read_csv_series: " + path + " has no data rows");
    for (auto& s : series.sources)
        s = path + " " + s;
    return series;
}

void write_csv_series(const std::string& path, const TimeSeries& series, const std::string& name,
                      CsvLayout layout)
{
    std::vector<const Field*> steps;
    for (const auto& step : series.steps)
    {
        const Field& f = find_field(step, name);
        if (f.location != FieldLocation::Point || f.components() != 1)
            throw InvalidInputError("write_csv_series: field '" + name +
                                    "' must be a scalar point field");
        steps.push_back(&f);
    }
    detail::write_atomically(path, "write_csv_series", [&](FILE* out) {
        const Eigen::Index n = steps.empty() ? 0 : steps[0]->rows();
        if (layout == CsvLayout::Wide)
        {
            std::fprintf(out, "vertex");
            for (double t : series.times)
                std::fprintf(out, ",%.15g", t);
            std::fputc('\n', out);
            for (Eigen::Index v = 0; v < n; ++v)
            {
                std::fprintf(out, "%ld", static_cast<long>(v));
                for (const Field* f : steps)
                    std::fprintf(out, ",%.17g", f->values(v, 0));
                std::fputc('\n', out);
            }
        }
        else
        {
            std::fprintf(out, "vertex,time,%s\n", name.c_str());
            for (std::size_t k = 0; k < steps.size(); ++k)
                for (Eigen::Index v = 0; v < n; ++v)
                    std::fprintf(out, "%ld,%.15g,%.17g\n", static_cast<long>(v), series.times[k],
                                 steps[k]->values(v, 0));
        }
    });
}

}  // namespace vessel
