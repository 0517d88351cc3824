#include "detail/vtk_check.h"

#include "vessel/core/errors.h"

#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <string>
#include <vector>

namespace vessel::detail {

namespace {

[[noreturn]] void corrupt(const std::string& path, const std::string& what)
{
    throw IoError("read_polydata: " + path + " is truncated or corrupt: " + what +
                  "; re-export or re-download the file");
}

std::string read_all(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw IoError("read_polydata: cannot open " + path);
    return {std::istreambuf_iterator<char>(in), {}};
}

// Bytes per value of a legacy VTK data type; 0 if unknown.
int legacy_type_size(const std::string& type)
{
    static const std::map<std::string, int> sizes = {
        {"unsigned_char", 1}, {"char", 1},          {"short", 2},        {"unsigned_short", 2},
        {"int", 4},           {"unsigned_int", 4},  {"float", 4},        {"long", 8},
        {"unsigned_long", 8}, {"double", 8},        {"vtkIdType", 4},    {"vtktypeint64", 8},
        {"vtktypeuint64", 8}, {"vtktypeint32", 4},  {"vtktypeuint32", 4}};
    const auto it = sizes.find(type);
    return it == sizes.end() ? 0 : it->second;
}

// A legacy file read the way vtkDataReader reads it: keywords and ASCII values are words;
// binary values follow the keyword's line as big-endian bytes.
class Legacy
{
public:
    Legacy(const std::string& path, const std::string& bytes) : path_(&path), bytes_(&bytes) {}

    bool word(std::string& w)
    {
        while (pos_ < s().size() && std::isspace(static_cast<unsigned char>(s()[pos_])))
            ++pos_;
        const std::size_t start = pos_;
        while (pos_ < s().size() && !std::isspace(static_cast<unsigned char>(s()[pos_])))
            ++pos_;
        w = s().substr(start, pos_ - start);
        return !w.empty();
    }
    std::string line()
    {
        const std::size_t end = s().find('\n', pos_);
        std::string l = s().substr(pos_, end == std::string::npos ? std::string::npos : end - pos_);
        pos_ = end == std::string::npos ? s().size() : end + 1;
        return l;
    }
    // A count after \p keyword: a non-negative integer.
    long long count(const std::string& keyword)
    {
        std::string w;
        char* end = nullptr;
        const long long n = word(w) ? std::strtoll(w.c_str(), &end, 10) : -1;
        if (w.empty() || *end != '\0' || n < 0)
            corrupt(*path_, keyword + " has the count '" + w + "', not a non-negative integer");
        return n;
    }
    // \p n values of \p size bytes (binary) or \p n words (ASCII); each checked against \p limit
    // (an exclusive upper bound, or -1 for none) when \p integers.
    void values(const std::string& what, long long n, int size, bool integers, long long limit,
                std::vector<long long>* out = nullptr)
    {
        if (binary_)
        {
            // The data starts after the keyword's line.
            const std::size_t end = s().find('\n', pos_);
            pos_ = end == std::string::npos ? s().size() : end + 1;
            const std::size_t left = s().size() - pos_;
            if (n > static_cast<long long>(left / static_cast<std::size_t>(size)))
                corrupt(*path_, what + " declares " + std::to_string(n) + " values of " +
                                   std::to_string(size) + " bytes but only " +
                                   std::to_string(left) + " bytes follow");
            for (long long i = 0; i < n && (integers || out); ++i)
            {
                long long v = 0;
                for (int b = 0; b < size; ++b)
                    v = (v << 8) | static_cast<unsigned char>(s()[pos_ + i * size + b]);
                if (size == 4)
                    v = static_cast<std::int32_t>(static_cast<std::uint32_t>(v));
                take(what, i, v, limit, out);
            }
            pos_ += static_cast<std::size_t>(n) * size;
            return;
        }
        std::string w;
        for (long long i = 0; i < n; ++i)
        {
            if (!word(w))
                corrupt(*path_, what + " declares " + std::to_string(n) +
                                   " values but the file ends after " + std::to_string(i));
            if (!integers && !out)
                continue;
            char* end = nullptr;
            const long long v = std::strtoll(w.c_str(), &end, 10);
            if (*end != '\0')
                corrupt(*path_, "value " + std::to_string(i) + " of " + what + " is '" + w +
                                   "', not an integer");
            take(what, i, v, limit, out);
        }
    }

    bool binary_ = false;

private:
    void take(const std::string& what, long long i, long long v, long long limit,
              std::vector<long long>* out)
    {
        if (limit >= 0 && (v < 0 || v >= limit))
            corrupt(*path_, "value " + std::to_string(i) + " of " + what + " is " +
                               std::to_string(v) + ", outside 0 to " + std::to_string(limit - 1));
        if (out)
            out->push_back(v);
    }

    const std::string& s() const { return *bytes_; }

    const std::string* path_;
    const std::string* bytes_;
    std::size_t pos_ = 0;
};

// One cell section, legacy (`n size` then per cell: corner count, corners) or 5.x (OFFSETS and
// CONNECTIVITY arrays); returns the number of cells.
long long check_cells(Legacy& in, const std::string& path, const std::string& keyword,
                      long long points)
{
    const long long n = in.count(keyword), size = in.count(keyword);
    std::string w;
    // Peek: a 5.x file names its OFFSETS array next; a legacy one starts its values.
    Legacy peek = in;
    if (peek.word(w) && w == "OFFSETS")
    {
        in = peek;
        std::string type;
        in.word(type);
        const int bytes = legacy_type_size(type);
        if (bytes == 0)
            corrupt(path, keyword + " OFFSETS has the unknown type '" + type + "'");
        std::vector<long long> offsets;
        in.values(keyword + " OFFSETS", n, bytes, true, size + 1, &offsets);
        for (std::size_t i = 1; i < offsets.size(); ++i)
            if (offsets[i] < offsets[i - 1])
                corrupt(path, keyword + " OFFSETS decrease at cell " + std::to_string(i - 1));
        if (!offsets.empty() && (offsets.front() != 0 || offsets.back() != size))
            corrupt(path, keyword + " OFFSETS run from " + std::to_string(offsets.front()) +
                              " to " + std::to_string(offsets.back()) + ", not 0 to " +
                              std::to_string(size));
        if (!in.word(w) || w != "CONNECTIVITY")
            corrupt(path, keyword + " has OFFSETS but no CONNECTIVITY after them");
        in.word(type);
        const int cbytes = legacy_type_size(type);
        if (cbytes == 0)
            corrupt(path, keyword + " CONNECTIVITY has the unknown type '" + type + "'");
        in.values(keyword + " CONNECTIVITY", size, cbytes, true, points);
        return n > 0 ? n - 1 : 0;
    }
    // Legacy: corner counts and corners, `size` values in all, as 32-bit integers.
    std::vector<long long> all;
    in.values(keyword, size, 4, false, -1, &all);
    std::size_t i = 0;
    for (long long c = 0; c < n; ++c)
    {
        if (i >= all.size())
            corrupt(path, keyword + " declares " + std::to_string(n) + " cells in " +
                              std::to_string(size) + " values but they end after cell " +
                              std::to_string(c));
        const long long corners = all[i++];
        if (corners < 0 || corners > static_cast<long long>(all.size() - i))
            corrupt(path, "cell " + std::to_string(c) + " of " + keyword + " has " +
                              std::to_string(corners) + " corners but only " +
                              std::to_string(all.size() - i) + " values are left");
        for (long long k = 0; k < corners; ++k, ++i)
            if (all[i] < 0 || all[i] >= points)
                corrupt(path, "cell " + std::to_string(c) + " of " + keyword +
                                  " refers to point " + std::to_string(all[i]) + " of " +
                                  std::to_string(points));
    }
    if (i != all.size())
        corrupt(path, keyword + " declares " + std::to_string(size) + " values but its " +
                          std::to_string(n) + " cells use " + std::to_string(i));
    return n;
}

}  // namespace

void check_legacy_vtk(const std::string& path)
{
    const std::string bytes = read_all(path);
    Legacy in(path, bytes);
    const std::string version = in.line();
    if (version.find("vtk DataFile") == std::string::npos)
        corrupt(path, "the first line is not '# vtk DataFile Version x.x'");
    in.line();  // title
    std::string w;
    in.word(w);
    if (w != "ASCII" && w != "BINARY")
        corrupt(path, "the third line is '" + w + "', not ASCII or BINARY");
    in.binary_ = w == "BINARY";
    if (!in.word(w) || w != "DATASET" || !in.word(w) || w != "POLYDATA")
        return;  // read_polydata() refuses other data sets
    long long points = -1, cells = 0;
    while (in.word(w))
    {
        if (w == "POINTS")
        {
            points = in.count(w);
            std::string type;
            in.word(type);
            const int size = legacy_type_size(type);
            if (size == 0)
                corrupt(path, "POINTS has the unknown type '" + type + "'");
            if (points > (1LL << 40))
                corrupt(path, "POINTS declares " + std::to_string(points) + " points");
            in.values("POINTS", 3 * points, size, false, -1);
        }
        else if (w == "VERTICES" || w == "LINES" || w == "POLYGONS" || w == "TRIANGLE_STRIPS")
        {
            if (points < 0)
                corrupt(path, w + " comes before POINTS");
            cells += check_cells(in, path, w, points);
        }
        else if (w == "POINT_DATA" || w == "CELL_DATA")
        {
            const long long n = in.count(w);
            const long long expected = w == "POINT_DATA" ? points : cells;
            if (n != expected)
                corrupt(path, w + " declares " + std::to_string(n) + " values per array but the " +
                                  "file has " + std::to_string(expected) +
                                  (w == "POINT_DATA" ? " points" : " cells"));
            return;  // the arrays' own sizes follow from these counts, each bounded by VTK
        }
        else
            return;  // FIELD, METADATA: left to VTK
    }
}

void check_vtp(const std::string& path)
{
    const std::string bytes = read_all(path);
    const std::size_t appended = bytes.find("<AppendedData");
    if (appended == std::string::npos)
        return;
    const std::size_t appended_end = bytes.find('>', appended);
    if (appended_end == std::string::npos ||
        bytes.substr(appended, appended_end - appended).find("encoding=\"raw\"") ==
            std::string::npos)
        return;  // base64: VTK decodes it into a buffer of the encoded size, bounded by the file
    const std::size_t underscore = bytes.find('_', appended_end);
    if (underscore == std::string::npos)
        corrupt(path, "<AppendedData> has no '_' before its data");
    const std::size_t data = underscore + 1;
    const std::string xml = bytes.substr(0, appended);
    const auto attribute = [](const std::string& tag, const std::string& name) {
        std::smatch m;
        const std::regex re("\\b" + name + "=\"([^\"]*)\"");
        return std::regex_search(tag, m, re) ? m[1].str() : std::string();
    };
    const std::size_t file_tag_end = xml.find('>', xml.find("<VTKFile"));
    const std::string file_tag = xml.substr(0, file_tag_end);
    const bool compressed = !attribute(file_tag, "compressor").empty();
    const int header = attribute(file_tag, "header_type") == "UInt64" ? 8 : 4;
    const bool little = attribute(file_tag, "byte_order") != "BigEndian";
    const auto read_uint = [&](std::size_t at) {
        std::uint64_t v = 0;
        for (int b = 0; b < header; ++b)
        {
            const auto byte = static_cast<unsigned char>(bytes[at + (little ? header - 1 - b : b)]);
            v = (v << 8) | byte;
        }
        return v;
    };
    static const std::map<std::string, int> type_sizes = {
        {"Int8", 1},   {"UInt8", 1},   {"Int16", 2},   {"UInt16", 2},  {"Int32", 4},
        {"UInt32", 4}, {"Int64", 8},   {"UInt64", 8},  {"Float32", 4}, {"Float64", 8}};

    // The tags in order: the section (Points, PointData, CellData, Verts, ...) and the piece's
    // counts give each appended array the number of values it needs.
    const std::regex tag_re("<(/?)([A-Za-z]+)([^>]*)>");
    std::uint64_t n_points = 0, n_cells = 0;
    std::map<std::string, std::uint64_t> section_cells;  // Verts, Lines, Strips, Polys
    std::string section;
    for (std::sregex_iterator it(xml.begin(), xml.end(), tag_re), end; it != end; ++it)
    {
        const std::string name = (*it)[2].str(), attributes = (*it)[3].str();
        if ((*it)[1].length() > 0)
        {
            if (name == section)
                section.clear();
            continue;
        }
        if (name == "Piece")
        {
            n_points = std::strtoull(attribute(attributes, "NumberOfPoints").c_str(), nullptr, 10);
            n_cells = 0;
            for (const char* c : {"Verts", "Lines", "Strips", "Polys"})
                n_cells += section_cells[c] = std::strtoull(
                    attribute(attributes, std::string("NumberOf") + c).c_str(), nullptr, 10);
        }
        else if (name != "DataArray")
            section = name;
        if (name != "DataArray" || attribute(attributes, "format") != "appended")
            continue;
        const std::string array = attribute(attributes, "Name");
        const std::string offset_text = attribute(attributes, "offset");
        const std::uint64_t offset = std::strtoull(offset_text.c_str(), nullptr, 10);
        if (offset_text.empty() || offset >= bytes.size() - data)
            corrupt(path, "the appended array '" + array + "' starts at offset '" + offset_text +
                              "', beyond the " + std::to_string(bytes.size() - data) +
                              " bytes of appended data");
        const std::size_t at = data + offset;
        const std::uint64_t left = bytes.size() - at;
        // Values the array needs, where the section says (connectivity: at least one per cell).
        const auto type = type_sizes.find(attribute(attributes, "type"));
        const int value_size = type == type_sizes.end() ? 1 : type->second;
        const std::string components = attribute(attributes, "NumberOfComponents");
        const std::uint64_t width = components.empty() ? 1 : std::strtoull(components.c_str(), nullptr, 10);
        // Bytes the array needs: exactly (points, cell data, cell offsets: one per cell, or
        // one more with a leading 0), or at least (connectivity: a corner per cell).
        std::uint64_t needed = 0, or_needed = 0;
        bool exact = true;
        if (section == "Points" || section == "PointData")
            needed = n_points * width * value_size;
        else if (section == "CellData")
            needed = n_cells * width * value_size;
        else if (section_cells.count(section) && array == "offsets")
            needed = section_cells[section] * value_size;
        else
        {
            exact = false;
            needed = section_cells.count(section) ? section_cells[section] * value_size : 0;
        }
        or_needed = exact && array == "offsets" ? needed + value_size : needed;
        if (!compressed)
        {
            if (left < static_cast<std::uint64_t>(header))
                corrupt(path, "the appended array '" + array + "' has no size header");
            const std::uint64_t size = read_uint(at);
            if (size > left - header)
                corrupt(path, "the appended array '" + array + "' declares " +
                                  std::to_string(size) + " bytes but only " +
                                  std::to_string(left - header) + " follow");
            if (size < needed)
                corrupt(path, "the appended array '" + array + "' holds " + std::to_string(size) +
                                  " bytes but needs " + std::to_string(needed));
            continue;
        }
        if (left < 3ull * header)
            corrupt(path, "the appended array '" + array + "' has no compression header");
        const std::uint64_t blocks = read_uint(at), block_size = read_uint(at + header),
                            last_size = read_uint(at + 2 * header);
        if (blocks > (left - 3ull * header) / header)
            corrupt(path, "the compression header of array '" + array + "' declares " +
                              std::to_string(blocks) + " blocks, more than the " +
                              std::to_string(left) + " bytes left can describe");
        std::uint64_t compressed_total = 0;
        for (std::uint64_t b = 0; b < blocks; ++b)
            compressed_total += read_uint(at + (3 + b) * header);
        if (compressed_total > left - (3 + blocks) * header)
            corrupt(path, "the compressed blocks of array '" + array + "' declare " +
                              std::to_string(compressed_total) + " bytes but only " +
                              std::to_string(left - (3 + blocks) * header) + " follow");
        const std::uint64_t last = last_size == 0 ? block_size : last_size;
        const std::uint64_t size = blocks == 0 ? 0 : (blocks - 1) * block_size + last;
        if (last > block_size || (blocks > 0 && block_size == 0))
            corrupt(path, "the compression header of array '" + array + "' has blocks of " +
                              std::to_string(block_size) + " bytes and a last block of " +
                              std::to_string(last_size));
        if (exact ? size != needed && size != or_needed : size < needed)
            corrupt(path, "the compression header of array '" + array + "' declares " +
                              std::to_string(size) + " bytes (" + std::to_string(blocks) +
                              " blocks) but the array needs " + (exact ? "" : "at least ") +
                              std::to_string(needed));
        // zlib, LZ4 and LZMA expand at most about 1000-fold; more is a bomb, not data.
        if (size > 2048 * (compressed_total + 64))
            corrupt(path, "array '" + array + "' would expand " + std::to_string(compressed_total) +
                              " compressed bytes to " + std::to_string(size));
    }
}

}  // namespace vessel::detail
