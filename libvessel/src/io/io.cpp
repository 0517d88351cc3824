#include "vessel/io/io.h"

#include "vessel/core/errors.h"

#include "detail/atomic_file.h"
#include "detail/off_reader.h"
#include "detail/read_text.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <utility>

namespace vessel {

namespace {

using detail::printable;
using detail::trimmed;
using detail::truncated;
using detail::kMaxElements;

using ScratchMesh = OpenMesh::PolyMesh_ArrayKernelT<>;

// Records every vertex and face the reader emits, in file indices. The faces are recorded only:
// OpenMesh's importer would add them to its mesh, duplicate the vertices of those it cannot add
// (non-manifold, mis-oriented) and drop those with repeated corners, which would hide exactly
// the defects make_tree_surface() reports; and a mesh built only to be discarded is wasted work.
// A face's handle is its index in RawMesh::faces; the setters of face attributes (normals,
// colours, texture coordinates), which would look for it in the importer's mesh, do nothing.
class RecordingImporter : public OpenMesh::IO::ImporterT<ScratchMesh>
{
public:
    RecordingImporter(ScratchMesh& scratch, RawMesh& raw) : ImporterT(scratch), raw_(raw) {}

    VertexHandle add_vertex(const OpenMesh::Vec3f& p) override
    {
        return record(ImporterT::add_vertex(p), {p[0], p[1], p[2]});
    }
    VertexHandle add_vertex(const OpenMesh::Vec3d& p) override
    {
        return record(ImporterT::add_vertex(p), {p[0], p[1], p[2]});
    }
    VertexHandle add_vertex() override
    {
        return record(ImporterT::add_vertex(), Eigen::Vector3d::Zero());
    }
    void set_point(VertexHandle v, const OpenMesh::Vec3f& p) override
    {
        if (v.is_valid() && static_cast<std::size_t>(v.idx()) < raw_.points.size())
            raw_.points[static_cast<std::size_t>(v.idx())] = {p[0], p[1], p[2]};
        ImporterT::set_point(v, p);
    }
    FaceHandle add_face(const VHandles& corners) override
    {
        // A corner beyond the file's vertices keeps the file's index (the PLY reader passes it
        // as the handle), so that the validation names it.
        std::vector<int>& face = raw_.faces.emplace_back();
        face.reserve(corners.size());
        for (auto v : corners)
            face.push_back(v.idx());
        return FaceHandle(static_cast<int>(raw_.faces.size()) - 1);
    }
    std::size_t n_faces() const override { return raw_.faces.size(); }
    void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<OpenMesh::Vec2f>&) override
    {}
    void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<OpenMesh::Vec3f>&) override
    {}
    void set_face_texindex(FaceHandle, int) override {}
    void set_normal(FaceHandle, const OpenMesh::Vec3f&) override {}
    void set_normal(FaceHandle, const OpenMesh::Vec3d&) override {}
    void set_color(FaceHandle, const OpenMesh::Vec3uc&) override {}
    void set_color(FaceHandle, const OpenMesh::Vec4uc&) override {}
    void set_color(FaceHandle, const OpenMesh::Vec3f&) override {}
    void set_color(FaceHandle, const OpenMesh::Vec4f&) override {}
    void set_status(FaceHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    using ImporterT::set_color;
    using ImporterT::set_normal;
    using ImporterT::set_status;

private:
    // The importer's mesh holds the file's vertices alone (no face adds any), so a vertex's
    // handle is its index in the file and in RawMesh::points.
    VertexHandle record(VertexHandle scratch, const Eigen::Vector3d& p)
    {
        raw_.points.push_back(p);
        return scratch;
    }

    RawMesh& raw_;
};

// Truncated files: OpenMesh's PLY reader loops forever on a header cut before `end_header`, its
// OFF and ASCII PLY readers turn missing lines into faces with invalid corners, and its STL reader
// takes a binary STL whose size does not match its triangle count for ASCII and finds no faces.
// So the sizes a header declares are checked against the file before OpenMesh reads it.

// Counts the non-empty lines left in \p in (comments starting with '#' excluded).
std::uintmax_t count_data_lines(std::istream& in)
{
    std::uintmax_t n = 0;
    std::string line;
    while (std::getline(in, line))
    {
        line = trimmed(line);
        if (!line.empty() && line[0] != '#')
            ++n;
    }
    return n;
}

int ply_type_size(const std::string& type)
{
    static const std::map<std::string, int> sizes = {
        {"char", 1},  {"int8", 1},   {"uchar", 1},   {"uint8", 1},   {"short", 2},
        {"int16", 2}, {"ushort", 2}, {"uint16", 2},  {"int", 4},     {"int32", 4},
        {"uint", 4},  {"uint32", 4}, {"float", 4},   {"float32", 4}, {"double", 8},
        {"float64", 8}};
    const auto it = sizes.find(type);
    return it == sizes.end() ? 0 : it->second;
}

// Whether the PLY \p type is floating-point (float, double and their sized names).
bool ply_type_is_float(const std::string& type)
{
    return type == "float" || type == "float32" || type == "double" || type == "float64";
}

// A PLY property: a scalar of `type`, or (item_size > 0) a list with a `type` count.
struct PlyProperty
{
    std::string name;
    std::string type;
    int item_size = 0;
};

[[noreturn]] void bad_ply_list(const std::string& path, const std::string& element,
                               std::uintmax_t index, const PlyProperty& p, const std::string& count,
                               const std::string& room)
{
    truncated(path, element + " " + std::to_string(index) + " has the list " + p.name +
                        " of " + count + " entries, but " + room);
}

// Whether OpenMesh's reader, reading \p word from its stream with operator>> into a T, takes the
// whole word: otherwise it reads on from inside the word, and every later value is shifted.
template <class T>
bool read_in_full(const std::string& word)
{
    std::istringstream in(word);
    T value{};
    in >> value;
    return !in.fail() && in.peek() == std::char_traits<char>::eof();
}

// The rows of an ASCII PLY as OpenMesh reads them: word by word across lines, with operator>>
// into float (vertex coordinates, normals, texture coordinates, float colours), int (other
// colours) or unsigned int (the face's corner count and indices), every other value a word.
// Each row must be one line with exactly the words its properties take, each such number read in
// full, and each corner count a decimal from 0 to the words left on the line: a value read in
// part or a word too many shifts everything after it, and a shifted count ('-4' read as 2^32-4)
// made OpenMesh add billions of corners (a fuzz finding). A blank line is a row without values
// (check_ply_coordinates() reads one vertex a line too).
template <class Elements>
void check_ascii_ply_rows(const std::string& path, std::istream& in, const Elements& elements)
{
    static const std::vector<std::string> real = {"x", "y", "z", "nx", "ny", "nz",
                                                  "u", "v", "s", "t"};
    static const std::vector<std::string> colour = {
        "red", "green", "blue", "alpha", "diffuse_red", "diffuse_green", "diffuse_blue"};
    const auto among = [](const std::vector<std::string>& names, const std::string& name) {
        return std::find(names.begin(), names.end(), name) != names.end();
    };
    std::string line;
    for (const auto& e : elements)
    {
        if (e.properties.empty())
            continue;
        const bool vertex = e.name == "vertex", face = e.name == "face";
        for (std::uintmax_t i = 0; i < e.count; ++i)
        {
            std::getline(in, line);
            const std::vector<std::string> words = detail::words_of(line);
            std::size_t w = 0;
            for (const auto& p : e.properties)
            {
                const std::string word = w < words.size() ? words[w] : "";
                ++w;
                if (p.item_size == 0)
                {
                    const bool is_float = p.type == "float" || p.type == "float32";
                    bool ok = true;
                    if ((vertex && among(real, p.name)) ||
                        ((vertex || face) && among(colour, p.name) && is_float))
                        ok = read_in_full<float>(word);
                    else if ((vertex || face) && among(colour, p.name))
                        ok = read_in_full<int>(word);
                    // A NaN, infinite or unreadable coordinate is check_ply_coordinates()'s to
                    // report; here only those strtod reads and the stream does not (0x10, 1e39).
                    char* end = nullptr;
                    const double x = std::strtod(word.c_str(), &end);
                    const bool coordinate = p.name == "x" || p.name == "y" || p.name == "z";
                    if (coordinate && (word.empty() || *end != '\0' || !std::isfinite(x)))
                        ok = true;
                    // A number beyond float's range (1e39) is no corruption of the row.
                    if (!ok && w <= words.size() && *end == '\0' && !word.empty() &&
                        std::isfinite(x) && std::abs(x) > std::numeric_limits<float>::max())
                        throw detail::beyond_float(path, e.name + " " + std::to_string(i),
                                                   "the value '" + printable(word) + "' for " +
                                                       p.name);
                    if (!ok && w <= words.size())
                        truncated(path, e.name + " " + std::to_string(i) + " has the value '" +
                                            printable(word) + "' for " + p.name +
                                            ", which is no number C++ streams read in full "
                                            "(OpenMesh would read on from inside it)");
                    continue;
                }
                char* end = nullptr;
                const long long n = std::strtoll(word.c_str(), &end, 10);
                if (word.empty() || !std::isdigit(static_cast<unsigned char>(word[0])) ||
                    *end != '\0' || n > static_cast<long long>(words.size() - std::min(w, words.size())))
                    bad_ply_list(path, e.name, i, p, "'" + printable(word) + "'",
                                 "its line has " + std::to_string(words.size() - std::min(w, words.size())) +
                                     " values after the count");
                for (long long k = 0; k < n; ++k, ++w)
                    if (!std::isdigit(static_cast<unsigned char>(words[w][0])) ||
                        !read_in_full<unsigned int>(words[w]))
                        truncated(path, e.name + " " + std::to_string(i) + " has the corner '" +
                                            printable(words[w]) + "' in its list " + p.name +
                                            ", which is no vertex index (a decimal integer)");
            }
            if (w != words.size())
                truncated(path, e.name + " " + std::to_string(i) + " has " +
                                    std::to_string(words.size()) + " values on its line '" +
                                    printable(line) + "', but its properties take " +
                                    std::to_string(w) + "; each row is one line of exactly its "
                                    "values");
        }
    }
}

// Every list count of a binary PLY: from 0 to what the bytes left can hold, walking the data
// element by element (as OpenMesh will) so a count is never trusted beyond the file.
template <class Elements>
void check_binary_ply_lists(const std::string& path, std::istream& in, const Elements& elements,
                            bool big_endian)
{
    const bool lists = std::any_of(elements.begin(), elements.end(), [](const auto& e) {
        return std::any_of(e.properties.begin(), e.properties.end(),
                           [](const PlyProperty& p) { return p.item_size > 0; });
    });
    if (!lists)
        return;
    const std::string data{std::istreambuf_iterator<char>(in), {}};
    // Per property, what the walk reads of it (its type's name is looked up once, not per row).
    struct Column
    {
        std::size_t size = 0;  // bytes of the scalar, or of a list's count
        bool is_signed = false, is_float = false;
    };
    std::size_t at = 0;
    for (const auto& e : elements)
    {
        std::vector<Column> columns;
        std::size_t row_bytes = 0;  // of a row without lists
        bool row_lists = false;
        for (const auto& p : e.properties)
        {
            Column& c = columns.emplace_back();
            c.size = static_cast<std::size_t>(ply_type_size(p.type));
            c.is_signed = p.type == "char" || p.type == "int8" || p.type == "short" ||
                          p.type == "int16" || p.type == "int" || p.type == "int32";
            c.is_float = ply_type_is_float(p.type);
            row_bytes += c.size;
            row_lists = row_lists || p.item_size > 0;
        }
        if (!row_lists && row_bytes > 0 && (data.size() - at) / row_bytes >= e.count)
        {
            at += static_cast<std::size_t>(e.count) * row_bytes;  // rows of scalars: all there
            continue;
        }
        for (std::uintmax_t i = 0; i < e.count; ++i)
            for (std::size_t k = 0; k < columns.size(); ++k)
            {
                const PlyProperty& p = e.properties[k];
                const Column& c = columns[k];
                const std::size_t size = c.size;
                if (data.size() - at < size)
                    truncated(path, "the binary PLY data end inside " + e.name + " " +
                                        std::to_string(i));
                if (p.item_size == 0)
                {
                    at += size;
                    continue;
                }
                std::uint64_t raw = 0;
                for (std::size_t b = 0; b < size; ++b)
                    raw |= static_cast<std::uint64_t>(static_cast<unsigned char>(
                               data[at + (big_endian ? size - 1 - b : b)]))
                           << (8 * b);
                at += size;
                long long n = static_cast<long long>(raw);
                if (c.is_signed && size < 8 && (raw >> (8 * size - 1)) != 0)
                    n -= 1LL << (8 * size);
                if (c.is_float)
                    bad_ply_list(path, e.name, i, p, "a floating-point", "a count is an integer");
                const std::size_t left = data.size() - at;
                if (n < 0 || static_cast<unsigned long long>(n) > left / p.item_size)
                    bad_ply_list(path, e.name, i, p, std::to_string(n),
                                 "only " + std::to_string(left) + " bytes are left");
                at += static_cast<std::size_t>(n) * p.item_size;
            }
    }
}

// The PLY header is checked against the grammar OpenMesh's reader (`_PLYReader_::can_u_read`)
// assumes, and nothing else reaches it. That reader takes the header word by word across lines
// (`>>`), never checks a word it reads as a number, and loops forever once its stream fails (an
// unreadable version or count, a control byte where it splits words differently, the end of the
// file); fuzzing found such hangs one after another. So every line must be one of:
//   line 1   `ply`
//   line 2   `format ascii|binary_little_endian|binary_big_endian 1.0`
//   then     `comment TEXT`, `obj_info WORDS` (none of them a header keyword),
//            `element NAME COUNT` (COUNT decimal, 0 to kMaxElements; with COUNT > 0 at least
//            one property follows),
//            `property TYPE NAME` (NAME not a type) after an element, TYPE a PLY type,
//            `property list COUNT_TYPE TYPE NAME` only as the face element's vertex_indices
//            (or vertex_index), COUNT_TYPE one OpenMesh reads (uchar, uint8, uint16, int),
//            TYPE an integer type
//   last     `end_header` alone
// with words separated by spaces or tabs, lines by '\n' or "\r\n"; comment and obj_info lines
// may hold bytes beyond ASCII (UTF-8 text), no line a control byte. The header must end within
// kMaxPlyHeaderBytes. In binary files, OpenMesh's fixed conversions set the types of vertex
// coordinates, normals, texture coordinates (floating-point) and colours (not double), and the
// data must start where it looks for them: 12 bytes (14 with "\r\n") after the previous line's
// last word, i.e. not after a comment or trailing blanks. Other layouts it misreads silently.

//! Far more than any PLY header needs (a few lines per element); a file whose first 64 KiB hold
//! no `end_header` line is refused rather than read further.
constexpr std::size_t kMaxPlyHeaderBytes = 65536;

struct PlyElement
{
    std::string name;
    std::uintmax_t count = 0;
    std::uintmax_t min_bytes = 0;  // per element
    std::vector<PlyProperty> properties;
};

struct PlyHeader
{
    std::string format;
    std::vector<PlyElement> elements;
    std::uintmax_t data_start = 0;  // byte offset of the first byte after the header
};

[[noreturn]] void bad_ply_line(const std::string& path, std::size_t line, const std::string& what)
{
    truncated(path, "PLY header line " + std::to_string(line) + ": " + what);
}

// \p text split at spaces and tabs (the only blanks a header line may hold).
std::vector<std::string> ply_words(const std::string& text)
{
    std::vector<std::string> words;
    std::size_t i = 0;
    while (i < text.size())
    {
        while (i < text.size() && (text[i] == ' ' || text[i] == '\t'))
            ++i;
        const std::size_t begin = i;
        while (i < text.size() && text[i] != ' ' && text[i] != '\t')
            ++i;
        if (i > begin)
            words.push_back(text.substr(begin, i - begin));
    }
    return words;
}

std::string hex_byte(unsigned char c)
{
    static const char digits[] = "0123456789ABCDEF";
    return std::string("0x") + digits[c >> 4] + digits[c & 15];
}

PlyHeader read_ply_header(const std::string& path, std::uintmax_t file_size)
{
    std::ifstream in(path, std::ios::binary);
    std::string head(static_cast<std::size_t>(std::min<std::uintmax_t>(file_size, kMaxPlyHeaderBytes)),
                     '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    const std::string first = head.substr(0, head.find('\n'));
    if (first != "ply" && first != "ply\r")
        throw IoError("read_raw_mesh: " + path + " is not a PLY file (its first line is '" +
                      printable(first) + "', not 'ply')");
    PlyHeader header;
    // OpenMesh reads the rows of an element without properties as rows of no bytes, and reserves
    // and adds up to 2^31 vertices or faces without reaching the end of the file.
    std::size_t element_line = 0;
    const auto check_last_element = [&] {
        if (!header.elements.empty() && header.elements.back().count > 0 &&
            header.elements.back().properties.empty())
            bad_ply_line(path, element_line,
                         "the element '" + printable(header.elements.back().name) + "' has " +
                             std::to_string(header.elements.back().count) +
                             " rows but no property line follows it; give it its properties "
                             "or a count of 0");
    };
    // OpenMesh reads a list as one value unless it is the face's corners, and in binary files
    // reads some named properties with a fixed conversion that takes no bytes of another type;
    // either way it reads on from the wrong byte (checked: a second face list dropped a face).
    const auto check_openmesh_type = [&](std::size_t number, const PlyElement& e, bool list,
                                         const std::string& type, const std::string& name) {
        const bool integer = !ply_type_is_float(type);
        const std::string what = "the property '" + printable(name) + "' of the element '" +
                                 printable(e.name) + "'";
        if (list)
        {
            const bool corners = e.name == "face" && (name == "vertex_indices" || name == "vertex_index");
            const bool second = std::any_of(e.properties.begin(), e.properties.end(),
                                            [](const PlyProperty& p) { return p.item_size > 0; });
            if (!corners || second)
                bad_ply_line(path, number,
                             what + " is a list; OpenMesh reads only one list, the face's "
                                    "vertex_indices (or vertex_index), and misreads the rest of "
                                    "the file after any other; remove it");
            if (!integer)
                bad_ply_line(path, number, "the face's corner indices must be of an integer type, "
                                           "got '" + type + "'");
            return;
        }
        if (header.format == "ascii")
            return;
        static const std::vector<std::string> real = {"x", "y", "z", "nx", "ny", "nz",
                                                      "u", "v", "s", "t"};
        static const std::vector<std::string> vertex_colour = {
            "red", "green", "blue", "alpha", "diffuse_red", "diffuse_green", "diffuse_blue"};
        const auto among = [&](const std::vector<std::string>& names) {
            return std::find(names.begin(), names.end(), name) != names.end();
        };
        if (e.name == "vertex" && among(real) && integer)
            bad_ply_line(path, number, "OpenMesh reads " + what + " of a binary PLY only as "
                                       "float, float32, double or float64, got '" + type +
                                       "'; write it as float");
        const bool colour = (e.name == "vertex" && among(vertex_colour)) ||
                            (e.name == "face" && among({"red", "green", "blue", "alpha"}));
        if (colour && (type == "double" || type == "float64"))
            bad_ply_line(path, number, "OpenMesh reads " + what + " of a binary PLY only as an "
                                       "integer type, float or float32, got '" + type +
                                       "'; write it as uchar or float");
    };
    std::size_t start = first.size() + 1;  // of the current line
    std::size_t after_last_word = start;   // where OpenMesh's stream stands before end_header
    for (std::size_t number = 2;; ++number)
    {
        const std::size_t newline = head.find('\n', start);
        if (newline == std::string::npos)
        {
            if (file_size > kMaxPlyHeaderBytes)
                truncated(path, "the PLY header has no 'end_header' line in its first " +
                                    std::to_string(kMaxPlyHeaderBytes) +
                                    " bytes (a PLY header is a few hundred bytes)");
            truncated(path, "the PLY header has no 'end_header' line");
        }
        std::string line = head.substr(start, newline - start);
        if (!line.empty() && line.back() == '\r')
            line.pop_back();
        const std::vector<std::string> words = ply_words(line);
        const std::string keyword = words.empty() ? "" : words[0];
        const std::string quoted = "'" + printable(line) + "'";
        const bool text = keyword == "comment" || keyword == "obj_info";
        for (const char c : line)
        {
            const auto u = static_cast<unsigned char>(c);
            if ((u < 0x20 && c != '\t') || u == 0x7f)
                bad_ply_line(path, number, "the control byte " + hex_byte(u) + " in " + quoted +
                                               "; header lines are text (words separated by "
                                               "spaces or tabs)");
            if (u >= 0x80 && !text)
                bad_ply_line(path, number, "the byte " + hex_byte(u) + " in " + quoted +
                                               "; only comment and obj_info lines may hold "
                                               "text beyond ASCII");
        }
        if (number == 2)
        {
            if (keyword != "format" || words.size() != 3)
                bad_ply_line(path, number, "expected 'format ascii 1.0' (or binary_little_endian, "
                                           "binary_big_endian), got " + quoted);
            if (words[1] != "ascii" && words[1] != "binary_little_endian" &&
                words[1] != "binary_big_endian")
                bad_ply_line(path, number, "format must be ascii, binary_little_endian or "
                                           "binary_big_endian, got '" + printable(words[1]) + "'");
            if (words[2] != "1.0")
                bad_ply_line(path, number, "format version must be 1.0, got '" +
                                               printable(words[2]) + "'");
            header.format = words[1];
        }
        else if (keyword == "end_header")
        {
            check_last_element();
            if (words.size() != 1)
                bad_ply_line(path, number, "end_header must be alone on its line, got " + quoted);
            header.data_start = newline + 1;
            if (header.format != "ascii")
            {
                // OpenMesh seeks from the stream position before the word end_header.
                const bool crlf = head.compare(after_last_word, 2, "\r\n") == 0;
                const std::size_t openmesh = after_last_word + (crlf ? 14 : 12);
                if (openmesh != header.data_start)
                    bad_ply_line(path, number,
                                 "OpenMesh would read the binary data from byte " +
                                     std::to_string(openmesh) + ", but they start at byte " +
                                     std::to_string(header.data_start) +
                                     "; put end_header right after the previous line's last "
                                     "word and one line break (no comment or trailing blanks "
                                     "before it)");
            }
            return header;
        }
        else if (keyword == "comment")
        {
        }
        else if (keyword == "obj_info")
        {
            // OpenMesh reads the words after obj_info as header keywords.
            for (std::size_t w = 1; w < words.size(); ++w)
                if (words[w] == "element" || words[w] == "property" || words[w] == "end_header")
                    bad_ply_line(path, number, "the obj_info line " + quoted + " holds the word '" +
                                                   words[w] +
                                                   "', which PLY readers can take for a header "
                                                   "keyword; make it a comment line");
        }
        else if (keyword == "element")
        {
            if (words.size() != 3)
                bad_ply_line(path, number, "an element line is 'element NAME COUNT', got " + quoted);
            const std::string& count = words[2];
            std::uintmax_t n = 0;
            bool ok = count.size() <= 12;
            for (const char c : count)
            {
                ok = ok && c >= '0' && c <= '9';
                n = ok ? n * 10 + static_cast<std::uintmax_t>(c - '0') : n;
            }
            if (!ok || n > static_cast<std::uintmax_t>(kMaxElements))
                bad_ply_line(path, number, "element count must be a decimal integer from 0 to " +
                                               std::to_string(kMaxElements) + ", got '" +
                                               printable(count) + "'");
            check_last_element();
            header.elements.push_back({words[1], n, 0, {}});
            element_line = number;
        }
        else if (keyword == "property")
        {
            const bool list = words.size() > 1 && words[1] == "list";
            if (words.size() != (list ? 5u : 3u))
                bad_ply_line(path, number,
                             "a property line is 'property TYPE NAME' or 'property list "
                             "COUNT_TYPE TYPE NAME', got " + quoted);
            if (header.elements.empty())
                bad_ply_line(path, number, "the property " + quoted +
                                               " comes before any element line");
            const std::string& type = words[list ? 3 : 1];
            if (ply_type_size(type) == 0)
                bad_ply_line(path, number, "unknown property type '" + printable(type) +
                                               "' in " + quoted +
                                               "; PLY types are char, uchar, short, ushort, int, "
                                               "uint, float, double (or int8 ... float64)");
            PlyElement& e = header.elements.back();
            const std::string& name = words[list ? 4 : 2];
            const std::string& count_type = words[2];
            if (list && count_type != "uchar" && count_type != "uint8" && count_type != "uint16" &&
                count_type != "int")
                bad_ply_line(path, number, "list count type must be uchar, uint8, uint16 or int "
                                           "(the ones OpenMesh reads), got '" +
                                               printable(count_type) + "'");
            // OpenMesh takes either word of `property A B` for the type (some writers swap
            // them), so `property uchar double` would be a double to it.
            if (!list && ply_type_size(name) > 0)
                bad_ply_line(path, number, "the property name '" + name + "' in " + quoted +
                                               " is a type name, which PLY readers can take for "
                                               "the type; rename the property");
            check_openmesh_type(number, e, list, type, name);
            if (list)
            {
                // A face lists at least three corners; other lists may be empty.
                const int corners = (name == "vertex_indices" || name == "vertex_index") ? 3 : 0;
                e.min_bytes += ply_type_size(count_type) + corners * ply_type_size(type);
                e.properties.push_back({name, count_type, ply_type_size(type)});
            }
            else
            {
                e.min_bytes += ply_type_size(type);
                e.properties.push_back({name, type, 0});
            }
        }
        else if (keyword.empty())
            bad_ply_line(path, number, "an empty line; remove it");
        else
            bad_ply_line(path, number,
                         "unknown line " + quoted +
                             "; a PLY header line is comment, obj_info, element, property or "
                             "end_header (format only as line 2)");
        if (keyword != "comment")
        {
            const std::size_t last = line.find_last_not_of(" \t");
            after_last_word = start + last + 1;
        }
        else
            after_last_word = newline + 1;
        start = newline + 1;
    }
}

void check_ply(const std::string& path, std::uintmax_t file_size)
{
    const PlyHeader header = read_ply_header(path, file_size);
    const std::string& format = header.format;
    const std::vector<PlyElement>& elements = header.elements;
    std::ifstream in(path, std::ios::binary);
    in.seekg(static_cast<std::streamoff>(header.data_start));
    std::string counts;
    for (const auto& e : elements)
        counts += (counts.empty() ? "elements " : ", ") + e.name + " " + std::to_string(e.count);
    if (format == "ascii")
    {
        std::uintmax_t lines = 0;
        for (const auto& e : elements)
            lines += e.count;
        const auto data_start = in.tellg();
        const std::uintmax_t found = count_data_lines(in);
        if (found < lines)
            truncated(path, "the PLY header declares " + counts + " (" + std::to_string(lines) +
                                " lines) but only " + std::to_string(found) + " lines follow it");
        in.clear();
        in.seekg(data_start);
        check_ascii_ply_rows(path, in, elements);
        return;
    }
    const std::uintmax_t header_bytes = header.data_start;
    std::uintmax_t min_bytes = 0;
    for (const auto& e : elements)
        min_bytes += e.count * e.min_bytes;
    const std::uintmax_t data = file_size - std::min(file_size, header_bytes);
    if (data < min_bytes)
        truncated(path, "the binary PLY header declares " + counts + " (at least " +
                            std::to_string(min_bytes) + " bytes of data) but only " +
                            std::to_string(data) + " bytes follow it");
    check_binary_ply_lists(path, in, elements, format == "binary_big_endian");
}

// ASCII STL: every `vertex` has three finite numbers (OpenMesh reads `nan` and `abc` as 0) and
// every facet three vertices (OpenMesh drops other facets without a word).
void check_ascii_stl(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    std::string line;
    std::size_t vertex = 0, facet = 0;
    int corners = -1;  // in the open facet; -1 outside one
    while (std::getline(in, line))
    {
        const std::vector<std::string> words = detail::words_of(line);
        if (words.empty())
            continue;
        if (words[0] == "facet")
            corners = 0;
        else if (words[0] == "vertex")
        {
            detail::coordinates(path, {words.begin() + 1, words.end()}, vertex++, {0, 1, 2}, true);
            ++corners;
        }
        else if (words[0] == "endfacet")
        {
            if (corners != 3)
                throw IoError("read_raw_mesh: facet " + std::to_string(facet) + " of " + path +
                              " has " + std::to_string(std::max(corners, 0)) +
                              " vertices; an STL facet needs exactly 3 (the file is corrupt)");
            ++facet;
            corners = -1;
        }
    }
}

void check_stl(const std::string& path, std::uintmax_t file_size)
{
    std::ifstream in(path, std::ios::binary);
    std::string head(84, '\0');
    in.read(head.data(), 84);
    head.resize(static_cast<std::size_t>(in.gcount()));
    // ASCII STL starts with "solid" and is text; a binary header may also start with "solid",
    // but its triangle count (bytes 80-83) is binary.
    const bool text = std::all_of(head.begin(), head.end(), [](char c) {
        const auto u = static_cast<unsigned char>(c);
        return u == '\t' || u == '\n' || u == '\r' || (u >= 0x20 && u < 0x7f);
    });
    if (text && trimmed(head).rfind("solid", 0) == 0)
        return check_ascii_stl(path);
    if (head.size() < 84)
        truncated(path, "a binary STL needs an 84-byte header but the file has " +
                            std::to_string(file_size) + " bytes");
    const auto* b = reinterpret_cast<const unsigned char*>(head.data() + 80);
    const std::uintmax_t triangles = static_cast<std::uintmax_t>(b[0]) | (b[1] << 8) |
                                     (b[2] << 16) | (static_cast<std::uintmax_t>(b[3]) << 24);
    const std::uintmax_t expected = 84 + 50 * triangles;
    if (expected != file_size)
        truncated(path, "the binary STL header declares " + std::to_string(triangles) +
                            " triangles (" + std::to_string(expected) + " bytes) but the file has " +
                            std::to_string(file_size) + " bytes");
}

// ASCII PLY: the x, y, z columns of the vertex element (after the lines of earlier elements).
void check_ply_coordinates(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    std::string line, format;
    std::vector<std::pair<std::string, std::uintmax_t>> elements;
    std::vector<int> columns;  // of x, y, z in the vertex element
    int column = 0;
    while (std::getline(in, line))
    {
        std::istringstream words(trimmed(line));
        std::string keyword, type, name;
        words >> keyword;
        if (keyword == "end_header")
            break;
        if (keyword == "format")
            words >> format;
        else if (keyword == "element")
        {
            std::uintmax_t count = 0;
            words >> name >> count;
            elements.emplace_back(name, count);
            column = 0;
        }
        else if (keyword == "property" && !elements.empty())
        {
            words >> type >> name;
            if (elements.back().first == "vertex" && type != "list" &&
                (name == "x" || name == "y" || name == "z"))
                columns.push_back(column);
            ++column;
        }
    }
    if (format != "ascii" || columns.empty())
        return;
    for (const auto& [name, count] : elements)
    {
        for (std::uintmax_t i = 0; i < count; ++i)
        {
            if (!std::getline(in, line))
                return;  // check_ply reports the missing lines
            if (name == "vertex")
                detail::coordinates(path, detail::words_of(line), i, columns);
        }
        if (name == "vertex")
            return;
    }
}

// An OBJ reference \p word to one of \p count earlier elements: 1-based, or negative counting
// back from the last; the 0-based index, or -1 if \p word is not one.
long obj_reference(const std::string& word, long count)
{
    char* end = nullptr;
    const long i = std::strtol(word.c_str(), &end, 10);
    const long index = i < 0 ? count + i : i - 1;
    if (word.empty() || *end != '\0' || i == 0 || index < 0 || index >= count)
        return -1;
    return index;
}

[[noreturn]] void bad_obj_face(const std::string& path, std::size_t face, const std::string& what)
{
    throw IoError("read_raw_mesh: face " + std::to_string(face) + " of " + path + " " + what +
                  "; the file is corrupt");
}

// OBJ: `v` lines, and `f` lines whose corners (`v`, `v/vt`, `v/vt/vn`, `v//vn`) do not refer to
// earlier `v`, `vt` and `vn` lines (OpenMesh's reader asserts on vertex indices it cannot
// resolve) or name a vertex twice (OpenMesh's reader drops such a face without a word, which
// leaves a hole that would be reported as something else).
void check_obj(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    std::string line;
    long vertices = 0, texcoords = 0, normals = 0;
    std::size_t face = 0, line_number = 0;
    while (std::getline(in, line))
    {
        ++line_number;
        // OpenMesh's reader drops a line it cannot parse (the first vertex after a byte order
        // mark, a face with a NUL byte), which shifts every index after it.
        if (line_number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0)
            throw IoError("read_raw_mesh: " + path +
                          " starts with a UTF-8 byte order mark (bytes EF BB BF), which OBJ "
                          "readers take for part of the first line; remove it (e.g. sed -i "
                          "'1s/^\\xEF\\xBB\\xBF//' FILE)");
        std::istringstream words(line);
        std::string keyword;
        words >> keyword;
        if (keyword == "vt")
            ++texcoords;
        else if (keyword == "vn")
            ++normals;
        else if (keyword == "v")
            detail::coordinates(path, detail::words_of(line.substr(line.find('v') + 1)),
                                static_cast<std::size_t>(vertices++), {0, 1, 2}, true);
        else if (keyword == "f")
        {
            std::vector<long> corners;
            for (std::string word; words >> word;)
            {
                std::vector<std::string> parts{""};
                for (const char c : word)
                {
                    if (c == '/')
                        parts.emplace_back();
                    else
                        parts.back().push_back(c);
                }
                const long index = obj_reference(parts[0], vertices);
                if (index < 0)
                    bad_obj_face(path, face, "refers to vertex '" + detail::printable(word) +
                                                 "', which is not one of the " +
                                                 std::to_string(vertices) + " vertices before it");
                if (parts.size() > 3 || (parts.size() == 2 && parts[1].empty()) ||
                    (parts.size() == 3 && parts[2].empty()))
                    bad_obj_face(path, face, "has the corner '" + detail::printable(word) +
                                                 "', which is not v, v/vt, v/vt/vn or v//vn");
                if (parts.size() >= 2 && !parts[1].empty() && obj_reference(parts[1], texcoords) < 0)
                    bad_obj_face(path, face, "refers to texture coordinate '" +
                                                 detail::printable(parts[1]) + "' (corner '" +
                                                 detail::printable(word) + "'), which is not one of the " +
                                                 std::to_string(texcoords) + " 'vt' lines before it");
                if (parts.size() == 3 && obj_reference(parts[2], normals) < 0)
                    bad_obj_face(path, face, "refers to normal '" + detail::printable(parts[2]) +
                                                 "' (corner '" + detail::printable(word) +
                                                 "'), which is not one of the " +
                                                 std::to_string(normals) + " 'vn' lines before it");
                corners.push_back(index);
            }
            if (corners.size() < 3)
                bad_obj_face(path, face, "has " + std::to_string(corners.size()) +
                                             " corners; a face needs at least 3");
            for (std::size_t a = 0; a < corners.size(); ++a)
                for (std::size_t b = a + 1; b < corners.size(); ++b)
                    if (corners[a] == corners[b])
                        throw IoError("read_raw_mesh: face " + std::to_string(face) + " of " +
                                      path + " uses vertex " + std::to_string(corners[a]) +
                                      " twice (degenerate face); remove degenerate faces first");
            ++face;
        }
        if (line.find('\0') != std::string::npos)
            throw IoError("read_raw_mesh: line " + std::to_string(line_number) + " of " + path +
                          " contains a NUL byte; the file is corrupt (re-export it)");
    }
}

// OpenMesh's readers and writers are process-wide singletons that keep per-file state (the PLY
// reader's elements, the OFF reader's options) and omerr() is one global stream: one file at a
// time, whichever thread asks.
std::mutex& openmesh_io_mutex()
{
    static std::mutex mutex;
    return mutex;
}

// OBJ, PLY and STL after the checks above, through OpenMesh's readers.
RawMesh read_with_openmesh(const std::string& path, const std::string& ext)
{
    const std::uintmax_t size = std::filesystem::file_size(path);
    if (ext == ".ply")
    {
        check_ply(path, size);
        check_ply_coordinates(path);
    }
    else if (ext == ".obj")
        check_obj(path);
    else
        check_stl(path, size);
    RawMesh raw;
    ScratchMesh scratch;
    RecordingImporter importer(scratch, raw);
    OpenMesh::IO::Options options;
    const std::lock_guard<std::mutex> lock(openmesh_io_mutex());
    // OpenMesh prints warnings for the defects we report ourselves; keep stderr for our messages.
    const bool was_enabled = omerr().is_enabled();
    omerr().disable();
    const bool ok = OpenMesh::IO::IOManager().read(path, importer, options);
    if (was_enabled)
        omerr().enable();
    if (!ok)
        throw IoError("read_raw_mesh: OpenMesh could not read " + path +
                      " (truncated or malformed file?)");
    return raw;
}

struct ReaderRegistry
{
    std::mutex mutex;
    std::map<std::string, MeshReader> readers;
};

// Constructed on first use, so that registrations from other libraries' static initializers
// (vtk_io.h) find it whatever the order of initialization.
ReaderRegistry& reader_registry()
{
    static ReaderRegistry registry;
    return registry;
}

MeshReader registered_reader(const std::string& ext)
{
    ReaderRegistry& registry = reader_registry();
    std::lock_guard<std::mutex> lock(registry.mutex);
    const auto it = registry.readers.find(ext);
    return it == registry.readers.end() ? MeshReader{} : it->second;
}

}  // namespace

void register_mesh_reader(const std::string& extension, MeshReader reader)
{
    if (extension.size() < 2 || extension[0] != '.')
        throw InvalidInputError("register_mesh_reader: extension '" + extension +
                                "' must start with a dot, e.g. \".vtp\"");
    if (extension == ".obj" || extension == ".off" || extension == ".ply" || extension == ".stl")
        throw InvalidInputError("register_mesh_reader: " + extension +
                                " is read by the library itself and cannot be replaced");
    ReaderRegistry& registry = reader_registry();
    std::lock_guard<std::mutex> lock(registry.mutex);
    registry.readers[extension] = std::move(reader);
}

RawMesh read_raw_mesh(const std::string& path)
{
    // Checked through error codes and an open(): an unreadable file (EACCES) was reported by each
    // format's check as a malformed file ("not a PLY file"), and a folder that cannot be searched
    // as a raw std::filesystem error.
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::status(path, ec);
    if (status.type() == std::filesystem::file_type::not_found)
        throw IoError("read_raw_mesh: file not found: " + path);
    if (ec)
        throw IoError("read_raw_mesh: cannot reach " + path + ": " + ec.message() +
                      "; check the permissions of its folders");
    if (std::filesystem::is_directory(status))
        throw IoError("read_raw_mesh: " + path + " is a folder, not a mesh file");
    if (std::FILE* file = std::fopen(path.c_str(), "rb"))
        std::fclose(file);
    else
        throw IoError("read_raw_mesh: cannot open " + path + ": " + std::strerror(errno) +
                      "; check that the file is readable (its permissions)");
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec)
        throw IoError("read_raw_mesh: cannot read the size of " + path + ": " + ec.message());
    if (size == 0)
        throw IoError("read_raw_mesh: file is empty: " + path);
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".stl")
    {
        if (const MeshReader reader = registered_reader(ext))
            return reader(path);
        if (ext == ".vtp" || ext == ".vtk")
            throw IoError("read_raw_mesh: " + path + " is a VTK file, and this program was built "
                          "without the library's VTK module; link vessel::vtk (or vessel::vessel) "
                          "and include <vessel/io/vtk_io.h>, or convert the file to .ply");
        throw IoError("read_raw_mesh: unknown file format '" + ext + "' (" + path +
                      "); use .obj, .off, .ply, .stl, .vtp or .vtk");
    }
    const RawMesh raw = ext == ".off" ? detail::read_off(path) : read_with_openmesh(path, ext);
    if (raw.faces.empty())
        throw IoError("read_raw_mesh: no faces in " + path + "; expected a triangulated surface");
    return raw;
}

RawMesh to_raw_mesh(const Mesh& mesh)
{
    RawMesh raw;
    raw.points.reserve(mesh.n_vertices());
    for (auto v : mesh.vertices())
        raw.points.push_back(to_eigen(mesh.point(v)));
    raw.faces.reserve(mesh.n_faces());
    for (auto f : mesh.faces())
    {
        auto& face = raw.faces.emplace_back();
        for (auto v : f.vertices())
            face.push_back(v.idx());
    }
    return raw;
}

void write_mesh(const Mesh& mesh, const std::string& path)
{
    OpenMesh::IO::Options options;
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".ply" || ext == ".stl")
        options += OpenMesh::IO::Options::Binary;
    std::ostringstream out;
    {
        const std::lock_guard<std::mutex> lock(openmesh_io_mutex());
        if (!OpenMesh::IO::write_mesh(mesh, out, ext, options))
            throw IoError("write_mesh: OpenMesh could not write " + path +
                          "; use .obj, .off, .ply or .stl");
    }
    const std::string bytes = out.str();
    detail::write_atomically(path, "write_mesh", [&](FILE* file) {
        std::fwrite(bytes.data(), 1, bytes.size(), file);
    });
}

}  // namespace vessel
