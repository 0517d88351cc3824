#include "detail/off_reader.h"

#include "detail/read_text.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <regex>

namespace vessel::detail {

namespace {

// The header keyword `[ST][C][N][4][n]OFF`: texture coordinates, colours, normals, homogeneous
// coordinate, dimension given in the file.
struct OffVariant
{
    bool texture = false, color = false, normal = false, homogeneous = false, any_dimension = false;
    int dimension = 3;
};

std::optional<OffVariant> parse_keyword(const std::string& word)
{
    static const std::regex keyword("(ST)?(C)?(N)?(4)?(n)?OFF");
    std::smatch m;
    if (!std::regex_match(word, m, keyword))
        return std::nullopt;
    OffVariant v;
    v.texture = m[1].matched;
    v.color = m[2].matched;
    v.normal = m[3].matched;
    v.homogeneous = m[4].matched;
    v.any_dimension = m[5].matched;
    return v;
}

void check_dimension(const std::string& path, long long dimension)
{
    if (dimension != 3)
        throw IoError("read_raw_mesh: " + path + " is an nOFF file of dimension " +
                      std::to_string(dimension) +
                      "; only 3-dimensional surfaces (x, y, z) can be flattened");
}

void check_counts(const std::string& path, long long vertices, long long faces)
{
    if (vertices < 0 || faces < 0 || vertices > kMaxElements || faces > kMaxElements)
        truncated(path, "the OFF header declares " + std::to_string(vertices) + " vertices and " +
                            std::to_string(faces) + " faces");
}

bool parse_integer(const std::string& word, long long& value)
{
    char* end = nullptr;
    value = std::strtoll(word.c_str(), &end, 10);
    return !word.empty() && *end == '\0';
}

[[noreturn]] void malformed_face(const std::string& path, std::size_t face, const std::string& line,
                                 long long vertices)
{
    throw IoError("read_raw_mesh: face " + std::to_string(face) + " of " + path +
                  " is malformed ('" + printable(line) +
                  "'): an OFF face is a corner count (3 or more) and that many vertex indices "
                  "below " +
                  std::to_string(vertices) + "; the file is corrupt");
}

[[noreturn]] void point_at_infinity(const std::string& path, std::size_t vertex)
{
    throw IoError("read_raw_mesh: vertex " + std::to_string(vertex) + " of " + path +
                  " has the homogeneous coordinate w = 0 (a point at infinity); fix or remove it "
                  "in the source");
}

// ---- ASCII ----------------------------------------------------------------------------------

// The lines of \p text without `#` comments, trimmed, empty ones left out.
std::vector<std::string> data_lines(const std::string& text)
{
    std::vector<std::string> lines;
    std::size_t start = 0;
    while (start < text.size())
    {
        std::size_t end = text.find('\n', start);
        if (end == std::string::npos)
            end = text.size();
        std::string line = text.substr(start, end - start);
        const std::size_t hash = line.find('#');
        if (hash != std::string::npos)
            line.erase(hash);
        line = trimmed(line);
        if (!line.empty())
            lines.push_back(std::move(line));
        start = end + 1;
    }
    return lines;
}

RawMesh read_ascii(const std::string& path, const std::vector<std::string>& lines,
                   const OffVariant& variant)
{
    std::size_t next = 1;  // lines[0] is the header
    // The header's numbers (dimension for nOFF, then V F [E]) may follow the keyword on its
    // line or come on the next lines.
    std::vector<std::string> header(words_of(lines[0]));
    header.erase(header.begin());
    auto more = [&] {
        if (header.empty() && next < lines.size())
            header = words_of(lines[next++]);
        return !header.empty();
    };
    if (variant.any_dimension)
    {
        long long dimension = 0;
        if (!more() || !parse_integer(header.front(), dimension))
            truncated(path, "the nOFF header has no dimension");
        check_dimension(path, dimension);
        header.erase(header.begin());
    }
    long long counts[3] = {0, 0, 0};
    if (!more() || header.size() < 2 || header.size() > 3)
        truncated(path, "the OFF header has no vertex and face counts (a line 'V F' or 'V F E')");
    for (std::size_t k = 0; k < header.size(); ++k)
        if (!parse_integer(header[k], counts[k]))
            truncated(path, "the OFF counts line '" + printable(lines[next - 1]) +
                                "' is not 'V F' or 'V F E' (integers)");
    const long long n_vertices = counts[0], n_faces = counts[1];
    check_counts(path, n_vertices, n_faces);
    const auto needed = static_cast<std::size_t>(n_vertices + n_faces);
    if (lines.size() - next < needed)
        truncated(path, "the OFF header declares " + std::to_string(n_vertices) +
                            " vertices and " + std::to_string(n_faces) + " faces (" +
                            std::to_string(needed) + " lines) but only " +
                            std::to_string(lines.size() - next) + " lines follow it");

    RawMesh raw;
    raw.points.reserve(static_cast<std::size_t>(n_vertices));
    std::vector<int> columns{0, 1, 2};
    if (variant.homogeneous)
        columns.push_back(3);
    for (std::size_t i = 0; i < static_cast<std::size_t>(n_vertices); ++i)
    {
        const std::vector<double> c = coordinates(path, words_of(lines[next++]), i, columns);
        const double w = variant.homogeneous ? c[3] : 1.0;
        if (w == 0)
            point_at_infinity(path, i);
        raw.points.emplace_back(c[0] / w, c[1] / w, c[2] / w);
    }
    raw.faces.reserve(static_cast<std::size_t>(n_faces));
    for (std::size_t f = 0; f < static_cast<std::size_t>(n_faces); ++f)
    {
        const std::string& line = lines[next++];
        const std::vector<std::string> words = words_of(line);
        long long corners = 0;
        if (!parse_integer(words[0], corners) || corners < 3 ||
            static_cast<std::size_t>(corners) >= words.size())
            malformed_face(path, f, line, n_vertices);
        std::vector<int>& face = raw.faces.emplace_back();
        for (std::size_t k = 1; k <= static_cast<std::size_t>(corners); ++k)
        {
            long long index = -1;
            if (!parse_integer(words[k], index) || index < 0 || index >= n_vertices)
                malformed_face(path, f, line, n_vertices);
            face.push_back(static_cast<int>(index));
        }
        // What follows the indices is the face's colour, ignored.
    }
    return raw;
}

// ---- Binary ---------------------------------------------------------------------------------

// One way of reading the binary data: the byte order, and whether each face ends with a colour
// count and that many floats (Geomview) or not (OpenMesh's writer).
struct BinaryLayout
{
    bool big_endian;
    bool face_color_count;
    const char* name;
};

class ByteReader
{
public:
    ByteReader(const std::string& data, std::size_t offset, bool big_endian)
        : data_(data), offset_(offset), big_endian_(big_endian)
    {
    }
    bool read(std::uint32_t& value)
    {
        if (data_.size() - offset_ < 4)
            return false;
        unsigned char b[4];
        std::memcpy(b, data_.data() + offset_, 4);
        offset_ += 4;
        value = big_endian_ ? (std::uint32_t{b[0]} << 24 | std::uint32_t{b[1]} << 16 |
                               std::uint32_t{b[2]} << 8 | b[3])
                            : (std::uint32_t{b[3]} << 24 | std::uint32_t{b[2]} << 16 |
                               std::uint32_t{b[1]} << 8 | b[0]);
        return true;
    }
    bool read(std::int32_t& value)
    {
        std::uint32_t u = 0;
        if (!read(u))
            return false;
        std::memcpy(&value, &u, 4);
        return true;
    }
    bool read(float& value)
    {
        std::uint32_t u = 0;
        if (!read(u))
            return false;
        std::memcpy(&value, &u, 4);
        return true;
    }
    std::size_t left() const { return data_.size() - offset_; }

private:
    const std::string& data_;
    std::size_t offset_;
    bool big_endian_;
};

// The mesh if \p layout accounts for every byte after the header line, else why not.
std::optional<RawMesh> read_binary_as(const std::string& data, std::size_t offset,
                                      const OffVariant& variant, const BinaryLayout& layout,
                                      std::string& why)
{
    ByteReader in(data, offset, layout.big_endian);
    std::int32_t dimension = 3, n_vertices = 0, n_faces = 0, n_edges = 0;
    if ((variant.any_dimension && !in.read(dimension)) || !in.read(n_vertices) ||
        !in.read(n_faces) || !in.read(n_edges))
    {
        why = "the file ends inside the counts";
        return std::nullopt;
    }
    if (variant.any_dimension && dimension != 3)
    {
        why = "the dimension reads as " + std::to_string(dimension);
        return std::nullopt;
    }
    const std::size_t floats = 3 + (variant.homogeneous ? 1 : 0) + (variant.normal ? 3 : 0) +
                               (variant.color ? 4 : 0) + (variant.texture ? 2 : 0);
    // Each face takes at least a count and three indices.
    if (n_vertices < 0 || n_faces < 0 ||
        static_cast<std::uint64_t>(n_vertices) * floats * 4 + static_cast<std::uint64_t>(n_faces) * 16 >
            in.left())
    {
        why = "the header declares " + std::to_string(n_vertices) + " vertices and " +
              std::to_string(n_faces) + " faces, more than the file can hold";
        return std::nullopt;
    }
    RawMesh raw;
    raw.points.reserve(static_cast<std::size_t>(n_vertices));
    for (std::int32_t i = 0; i < n_vertices; ++i)
    {
        float c[13] = {};
        for (std::size_t k = 0; k < floats; ++k)
            in.read(c[k]);  // sizes checked above
        const float w = variant.homogeneous ? c[3] : 1.0f;
        if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2]) ||
            !std::isfinite(w) || w == 0)
        {
            why = "vertex " + std::to_string(i) + " reads as a NaN, infinite or w = 0 coordinate";
            return std::nullopt;
        }
        raw.points.emplace_back(c[0] / w, c[1] / w, c[2] / w);
    }
    raw.faces.reserve(static_cast<std::size_t>(n_faces));
    for (std::int32_t f = 0; f < n_faces; ++f)
    {
        std::int32_t corners = 0;
        if (!in.read(corners) || corners < 3 || static_cast<std::size_t>(corners) > in.left() / 4)
        {
            why = "face " + std::to_string(f) + " has no valid corner count";
            return std::nullopt;
        }
        std::vector<int>& face = raw.faces.emplace_back();
        for (std::int32_t k = 0; k < corners; ++k)
        {
            std::int32_t index = -1;
            if (!in.read(index) || index < 0 || index >= n_vertices)
            {
                why = "face " + std::to_string(f) + " has a vertex index out of range";
                return std::nullopt;
            }
            face.push_back(index);
        }
        std::int32_t colors = 0;
        if (layout.face_color_count && (!in.read(colors) || colors < 0 || colors > 4 ||
                                        static_cast<std::size_t>(colors) * 4 > in.left()))
        {
            why = "face " + std::to_string(f) + " has no valid colour count";
            return std::nullopt;
        }
        for (float ignored = 0; colors > 0; --colors)
            in.read(ignored);
    }
    if (in.left() != 0)
    {
        why = std::to_string(in.left()) + " bytes are left after the last face";
        return std::nullopt;
    }
    return raw;
}

RawMesh read_binary(const std::string& path, const std::string& data, std::size_t offset,
                    const OffVariant& variant)
{
    static const BinaryLayout layouts[] = {{true, true, "big-endian with face colour counts"},
                                           {false, true, "little-endian with face colour counts"},
                                           {false, false, "little-endian (OpenMesh)"},
                                           {true, false, "big-endian without face colour counts"}};
    std::string reasons;
    for (const BinaryLayout& layout : layouts)
    {
        std::string why;
        if (auto raw = read_binary_as(data, offset, variant, layout, why))
            return std::move(*raw);
        reasons += std::string(reasons.empty() ? "" : "; ") + layout.name + ": " + why;
    }
    truncated(path, "the binary OFF data fit none of the layouts it can have (" + reasons + ")");
}

}  // namespace

RawMesh read_off(const std::string& path)
{
    std::ifstream file(path, std::ios::binary);
    const std::string data{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
    if (!file && !file.eof())
        throw IoError("read_raw_mesh: cannot read " + path);
    // A binary header is the file's first line, its data start right after it.
    const std::size_t first_end = std::min(data.find('\n'), data.size());
    const std::vector<std::string> first = words_of(data.substr(0, first_end));
    if (first.size() >= 2 && first[1] == "BINARY")
    {
        const auto variant = parse_keyword(first[0]);
        if (!variant)
            truncated(path, "the first line '" + printable(data.substr(0, first_end)) +
                                "' is not an OFF header");
        return read_binary(path, data, std::min(first_end + 1, data.size()), *variant);
    }
    const std::vector<std::string> lines = data_lines(data);
    const std::string keyword = lines.empty() ? "" : words_of(lines[0])[0];
    const auto variant = parse_keyword(keyword);
    if (!variant)
        truncated(path, "the first line '" + printable(lines.empty() ? "" : lines[0]) +
                            "' is not an OFF header ([ST][C][N][4][n]OFF [BINARY])");
    return read_ascii(path, lines, *variant);
}

}  // namespace vessel::detail
