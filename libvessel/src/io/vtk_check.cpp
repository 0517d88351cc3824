#include "detail/vtk_check.h"

#include "vessel/core/errors.h"

#include <vtkBase64Utilities.h>
#include <vtkDataCompressor.h>
#include <vtkLZ4DataCompressor.h>
#include <vtkLZMADataCompressor.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkZLibDataCompressor.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace vessel::detail {

namespace {

// \p text with control and non-ASCII bytes as '?', so that words quoted from a corrupt file
// print as one readable line.
std::string printable(std::string text)
{
    for (char& c : text)
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f)
            c = '?';
    return text;
}

[[noreturn]] void corrupt(const std::string& path, const std::string& what)
{
    throw IoError("read_polydata: " + path + " is truncated or corrupt: " + printable(what) +
                  "; re-export or re-download the file");
}

// A file that is well formed but uses a part of the format this check does not walk (so VTK's
// reader would meet it unchecked).
[[noreturn]] void unsupported(const std::string& path, const std::string& what)
{
    throw IoError("read_polydata: " + path + " uses " + printable(what) +
                  ", which this reader does not accept in legacy .vtk files; save the surface "
                  "as .vtp instead (ParaView: File > Save Data, VTK PolyData Files)");
}

std::string read_all(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw IoError("read_polydata: cannot open " + path);
    return {std::istreambuf_iterator<char>(in), {}};
}

std::string upper(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    return s;
}

// A legacy VTK data type: bytes per value in BINARY files, and what an ASCII value must be for
// vtkDataReader's stream extraction (operator>>) to read it without failing.
struct LegacyType
{
    int size = 0;            // 0: not a numeric type
    bool real = false;       // float or double
    long double low = 0;     // integers: the range operator>> accepts
    long double high = 0;
};

LegacyType legacy_type(const std::string& name)
{
    constexpr long double i32 = 2147483647.0L, i64 = 9223372036854775807.0L;
    static const std::map<std::string, LegacyType> types = {
        // vtkDataReader reads 1-byte types as int and narrows them.
        {"bit", {1, false, 0, 1}},
        {"char", {1, false, -i32 - 1, i32}},
        {"signed_char", {1, false, -i32 - 1, i32}},
        {"unsigned_char", {1, false, -i32 - 1, i32}},
        {"short", {2, false, -32768, 32767}},
        {"unsigned_short", {2, false, 0, 65535}},
        {"int", {4, false, -i32 - 1, i32}},
        {"unsigned_int", {4, false, 0, 4294967295.0L}},
        {"vtkidtype", {4, false, -i64 - 1, i64}},
        {"vtktypeint32", {4, false, -i32 - 1, i32}},
        {"vtktypeuint32", {4, false, 0, 4294967295.0L}},
        {"long", {8, false, -i64 - 1, i64}},
        {"unsigned_long", {8, false, 0, i64}},
        {"vtktypeint64", {8, false, -i64 - 1, i64}},
        {"vtktypeuint64", {8, false, 0, i64}},
        {"float", {4, true}},
        {"double", {8, true}}};
    std::string lower = name;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const auto it = types.find(lower);
    return it == types.end() || lower == "bit" ? LegacyType{} : it->second;
}

// Whether \p w is a number the way std::num_get reads one in full: [+-]digits for integers,
// [+-]digits[.digits][(e|E)[+-]digits] (a digit somewhere in the mantissa) for reals. strtod
// alone would also take "nan", "inf" and hexadecimal, which the stream refuses.
bool number_syntax(const std::string& w, bool real)
{
    std::size_t i = 0;
    if (i < w.size() && (w[i] == '+' || w[i] == '-'))
        ++i;
    std::size_t digits = 0;
    while (i < w.size() && std::isdigit(static_cast<unsigned char>(w[i])))
        ++i, ++digits;
    if (!real)
        return digits > 0 && i == w.size();
    if (i < w.size() && w[i] == '.')
        for (++i; i < w.size() && std::isdigit(static_cast<unsigned char>(w[i]));)
            ++i, ++digits;
    if (digits == 0)
        return false;
    if (i < w.size() && (w[i] == 'e' || w[i] == 'E'))
    {
        ++i;
        if (i < w.size() && (w[i] == '+' || w[i] == '-'))
            ++i;
        std::size_t exponent = 0;
        while (i < w.size() && std::isdigit(static_cast<unsigned char>(w[i])))
            ++i, ++exponent;
        if (exponent == 0)
            return false;
    }
    return i == w.size();
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
        // vtkDataReader reads words into 256-character buffers; a longer one is split.
        if (w.size() > 255)
            corrupt(*path_, "a word of " + std::to_string(w.size()) +
                                " characters (at byte " + std::to_string(start) +
                                "); VTK reads at most 255");
        return !w.empty();
    }
    std::string peek()
    {
        const std::size_t at = pos_;
        std::string w;
        word(w);
        pos_ = at;
        return w;
    }
    std::string line()
    {
        const std::size_t end = s().find('\n', pos_);
        std::string l = s().substr(pos_, end == std::string::npos ? std::string::npos : end - pos_);
        pos_ = end == std::string::npos ? s().size() : end + 1;
        return l;
    }
    // A word that names something (an array, a lookup table); \p what says where.
    std::string name(const std::string& what)
    {
        std::string w;
        if (!word(w))
            corrupt(*path_, "the file ends where " + what + " needs a name");
        return w;
    }
    // A count after \p keyword: a non-negative integer, at most the file's size (every counted
    // item takes at least a byte) unless \p unbounded.
    long long count(const std::string& keyword, bool unbounded = false)
    {
        std::string w;
        char* end = nullptr;
        errno = 0;
        const long long n = word(w) ? std::strtoll(w.c_str(), &end, 10) : -1;
        if (w.empty() || !number_syntax(w, false) || errno == ERANGE || n < 0)
            corrupt(*path_, keyword + " has the count '" + w + "', not a non-negative integer");
        if (!unbounded && n > static_cast<long long>(s().size()))
            corrupt(*path_, keyword + " declares " + w + " items but the file has only " +
                                std::to_string(s().size()) + " bytes");
        return n;
    }
    // \p n times \p k, refused when more values than the file has bytes.
    long long times(const std::string& what, long long n, long long k)
    {
        if (k > 0 && n > static_cast<long long>(s().size()) / k)
            corrupt(*path_, what + " declares " + std::to_string(n) + " x " + std::to_string(k) +
                                " values but the file has only " + std::to_string(s().size()) +
                                " bytes");
        return n * k;
    }
    // \p n values of the type named \p type_name: binary, that many bytes after the keyword's
    // line; ASCII, that many words, each a number operator>> reads in full. Integers are
    // checked against \p limit (an exclusive upper bound, or -1 for none) and kept in \p out.
    void values(const std::string& what, long long n, const std::string& type_name,
                long long limit = -1, std::vector<long long>* out = nullptr)
    {
        const LegacyType type = legacy_type(type_name);
        if (type.size == 0)
            unsupported(*path_, what + " of type '" + type_name + "'");
        times(what, n, 1);
        if (binary_)
        {
            // The data starts after the keyword's line.
            const std::size_t end = s().find('\n', pos_);
            pos_ = end == std::string::npos ? s().size() : end + 1;
            const std::size_t left = s().size() - pos_;
            if (n > static_cast<long long>(left / static_cast<std::size_t>(type.size)))
                corrupt(*path_, what + " declares " + std::to_string(n) + " values of " +
                                   std::to_string(type.size) + " bytes but only " +
                                   std::to_string(left) + " bytes follow");
            for (long long i = 0; i < n && (limit >= 0 || out) && !type.real; ++i)
            {
                long long v = 0;
                for (int b = 0; b < type.size; ++b)
                    v = static_cast<long long>(static_cast<unsigned long long>(v) << 8) |
                        static_cast<unsigned char>(s()[pos_ + i * type.size + b]);
                if (type.size == 4)
                    v = static_cast<std::int32_t>(static_cast<std::uint32_t>(v));
                take(what, i, v, limit, out);
            }
            pos_ += static_cast<std::size_t>(n) * type.size;
            return;
        }
        std::string w;
        for (long long i = 0; i < n; ++i)
        {
            if (!word(w))
                corrupt(*path_, what + " declares " + std::to_string(n) +
                                   " values but the file ends after " + std::to_string(i));
            if (!number_syntax(w, type.real))
                corrupt(*path_, "value " + std::to_string(i) + " of " + what + " is '" + w +
                                   "', not " + (type.real ? "a number" : "an integer"));
            errno = 0;
            if (type.real)
            {
                const double v = type.size == 4 ? std::strtof(w.c_str(), nullptr)
                                                : std::strtod(w.c_str(), nullptr);
                if (std::isinf(v))
                    corrupt(*path_, "value " + std::to_string(i) + " of " + what + " is " + w +
                                       ", beyond the range of " + type_name);
                continue;
            }
            const long double v = std::strtold(w.c_str(), nullptr);
            if (v < type.low || v > type.high)
                corrupt(*path_, "value " + std::to_string(i) + " of " + what + " is " + w +
                                   ", beyond the range of " + type_name);
            if (limit >= 0 || out)
                take(what, i, std::strtoll(w.c_str(), nullptr, 10), limit, out);
        }
    }
    // vtkDataReader::ReadArray looks for a METADATA block after each array: past spaces and
    // newlines (nothing else), a line starting with METADATA, then lines up to an empty one:
    // COMPONENT_NAMES (one line per component) or INFORMATION N (N pairs of NAME and DATA lines).
    void metadata(const std::string& what, long long components)
    {
        if (upper(peek()) != "METADATA")
            return;
        const std::size_t start = s().find_first_not_of(" \n", pos_);
        if (start == std::string::npos || upper(s().substr(start, 8)) != "METADATA")
            corrupt(*path_, "the METADATA after " + what +
                                " is preceded by characters other than spaces and newlines");
        pos_ = start;
        line();
        while (true)
        {
            const std::string l = line();
            if (l.empty())
                return;
            const std::string key = upper(l);
            if (key.rfind("COMPONENT_NAMES", 0) == 0)
            {
                for (long long c = 0; c < components; ++c)
                    if (const std::string n = line(); n.empty() || n.size() > 255)
                        corrupt(*path_, "the COMPONENT_NAMES of " + what + " lack the name of "
                                        "component " + std::to_string(c));
            }
            else if (key.rfind("INFORMATION", 0) == 0)
            {
                char* end = nullptr;
                const long long keys = std::strtoll(l.c_str() + 11, &end, 10);
                if (keys < 0 || keys > static_cast<long long>(s().size()) ||
                    std::string(end).find_first_not_of(" \t\r") != std::string::npos)
                    corrupt(*path_, "the METADATA line '" + l.substr(0, 60) + "' after " + what +
                                        " is not INFORMATION and a key count");
                for (long long k = 0; k < keys; ++k)
                    information(what);
            }
            else
                corrupt(*path_, "the METADATA after " + what + " has the line '" +
                                    l.substr(0, 60) +
                                    "', not COMPONENT_NAMES, INFORMATION or an empty line");
        }
    }

    bool binary_ = false;

private:
    // One INFORMATION key: "NAME key LOCATION class", then "DATA" and numbers.
    void information(const std::string& what)
    {
        const std::string name = line(), data = line();
        const std::string at = "INFORMATION key of " + what;
        if (name.rfind("NAME ", 0) != 0 || name.find(" LOCATION ") == std::string::npos ||
            name.size() > 255)
            corrupt(*path_, "the " + at + " has the line '" + name.substr(0, 60) +
                                "', not NAME <key> LOCATION <class>");
        if (data.rfind("DATA", 0) != 0 || data.size() > 255)
            corrupt(*path_, "the " + at + " has the line '" + data.substr(0, 60) +
                                "', not DATA and its values");
        std::size_t i = 4;
        while (i < data.size())
        {
            while (i < data.size() && std::isspace(static_cast<unsigned char>(data[i])))
                ++i;
            const std::size_t start = i;
            while (i < data.size() && !std::isspace(static_cast<unsigned char>(data[i])))
                ++i;
            if (i > start && !number_syntax(data.substr(start, i - start), true))
                unsupported(*path_, "the " + at + " '" + data.substr(0, 60) +
                                        "' (only numeric INFORMATION values are read)");
        }
    }
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
    // A 5.x file names its OFFSETS array next; a legacy one starts its values.
    if (upper(in.peek()) == "OFFSETS")
    {
        std::string w, type;
        in.word(w);
        in.word(type);
        std::vector<long long> offsets;
        in.values(keyword + " OFFSETS", n, type, size + 1, &offsets);
        in.metadata(keyword + " OFFSETS", 1);
        for (std::size_t i = 1; i < offsets.size(); ++i)
            if (offsets[i] < offsets[i - 1])
                corrupt(path, keyword + " OFFSETS decrease at cell " + std::to_string(i - 1));
        if (!offsets.empty() && (offsets.front() != 0 || offsets.back() != size))
            corrupt(path, keyword + " OFFSETS run from " + std::to_string(offsets.front()) +
                              " to " + std::to_string(offsets.back()) + ", not 0 to " +
                              std::to_string(size));
        if (!in.word(w) || upper(w) != "CONNECTIVITY")
            corrupt(path, keyword + " has OFFSETS but no CONNECTIVITY after them");
        in.word(type);
        in.values(keyword + " CONNECTIVITY", size, type, points);
        in.metadata(keyword + " CONNECTIVITY", 1);
        return n > 0 ? n - 1 : 0;
    }
    // Legacy: corner counts and corners, `size` values in all, as 32-bit integers.
    std::vector<long long> all;
    in.values(keyword, size, "int", -1, &all);
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

// FIELD name count, then per array: name components tuples type, values (NULL_ARRAY: none).
void check_field(Legacy& in, const std::string& path)
{
    in.name("FIELD");
    const long long arrays = in.count("FIELD");
    for (long long a = 0; a < arrays; ++a)
    {
        const std::string name = in.name("array " + std::to_string(a) + " of FIELD");
        if (name == "NULL_ARRAY")
            continue;
        const std::string what = "FIELD array '" + name + "'";
        const long long components = in.count(what), tuples = in.count(what);
        if (components < 1)
            corrupt(path, what + " has " + std::to_string(components) + " components");
        std::string type;
        in.word(type);
        in.values(what, in.times(what, tuples, components), type);
        in.metadata(what, components);
    }
}

// The attributes after POINT_DATA or CELL_DATA, to the end of the file.
void check_attributes(Legacy& in, const std::string& path, std::string section, long long points,
                      long long cells)
{
    const auto expect = [&](const std::string& keyword) {
        const long long n = in.count(keyword);
        const long long want = keyword == "POINT_DATA" ? points : cells;
        if (n != want)
            corrupt(path, keyword + " declares " + std::to_string(n) + " values per array but " +
                              "the file has " + std::to_string(want) +
                              (keyword == "POINT_DATA" ? " points" : " cells"));
        return n;
    };
    long long n = expect(section);
    std::string w;
    while (in.word(w))
    {
        const std::string key = upper(w);
        const std::string what = section + " " + key;
        if (key == "POINT_DATA" || key == "CELL_DATA")
        {
            section = key;
            n = expect(key);
        }
        else if (key == "FIELD")
            check_field(in, path);
        else if (key == "SCALARS")
        {
            const std::string name = in.name(what), type = in.name(what);
            long long components = 1;
            if (upper(in.peek()) != "LOOKUP_TABLE")
            {
                components = in.count(what);
                if (components < 1)
                    corrupt(path, what + " '" + name + "' has 0 components");
            }
            std::string table;
            if (!in.word(table) || upper(table) != "LOOKUP_TABLE")
                corrupt(path, what + " '" + name + "' has no LOOKUP_TABLE line");
            in.name(what + " LOOKUP_TABLE");
            in.values(what + " '" + name + "'", in.times(what, n, components), type);
            in.metadata(what + " '" + name + "'", components);
        }
        else if (key == "LOOKUP_TABLE" || key == "COLOR_SCALARS")
        {
            const std::string name = in.name(what);
            const long long k = in.count(what);
            const long long values = key == "LOOKUP_TABLE" ? in.times(what, k, 4)
                                                           : in.times(what, n, k);
            in.values(what + " '" + name + "'", values, in.binary_ ? "unsigned_char" : "float");
        }
        else if (key == "VECTORS" || key == "NORMALS" || key == "TENSORS" || key == "TENSORS6" ||
                 key == "GLOBAL_IDS" || key == "PEDIGREE_IDS" || key == "TEXTURE_COORDINATES")
        {
            const std::string name = in.name(what);
            long long components = key == "TENSORS" ? 9 : key == "TENSORS6" ? 6
                                   : key == "VECTORS" || key == "NORMALS" ? 3 : 1;
            if (key == "TEXTURE_COORDINATES")
            {
                components = in.count(what);
                if (components < 1 || components > 3)
                    corrupt(path, what + " '" + name + "' has " + std::to_string(components) +
                                      " dimensions, not 1 to 3");
            }
            const std::string type = in.name(what);
            in.values(what + " '" + name + "'", in.times(what, n, components), type);
            in.metadata(what + " '" + name + "'", components);
        }
        else
            unsupported(path, "the keyword '" + w + "' after " + section);
    }
}

}  // namespace

bool check_legacy_vtk(const std::string& path)
{
    const std::string bytes = read_all(path);
    Legacy in(path, bytes);
    if (in.line().rfind("# vtk DataFile Version", 0) != 0)
        corrupt(path, "the first line is not '# vtk DataFile Version x.x'");
    // vtkDataReader reads the title into a 256-character buffer.
    if (in.line().size() > 255)
        corrupt(path, "the title (second line) is longer than 255 characters");
    std::string w;
    in.word(w);
    if (upper(w) != "ASCII" && upper(w) != "BINARY")
        corrupt(path, "the third line is '" + w + "', not ASCII or BINARY");
    in.binary_ = upper(w) == "BINARY";
    // VTK compares keywords by their first letters ("DATASETx" passes as DATASET); here they
    // must be whole.
    if (!in.word(w) || upper(w) != "DATASET")
        corrupt(path, "the fourth line starts with '" + w.substr(0, 60) + "', not DATASET");
    if (!in.word(w) || upper(w) != "POLYDATA")
        return false;
    long long points = -1, cells = 0;
    while (in.word(w))
    {
        const std::string key = upper(w);
        if (key == "POINTS")
        {
            points = in.count(w);
            const std::string type = in.name(w);
            in.values("POINTS", in.times("POINTS", points, 3), type);
            in.metadata("POINTS", 3);
        }
        else if (key == "VERTICES" || key == "LINES" || key == "POLYGONS" ||
                 key == "TRIANGLE_STRIPS")
        {
            if (points < 0)
                corrupt(path, w + " comes before POINTS");
            cells += check_cells(in, path, key, points);
        }
        else if (key == "FIELD")
            check_field(in, path);
        else if (key == "POINT_DATA" || key == "CELL_DATA")
        {
            check_attributes(in, path, key, std::max(points, 0LL), cells);
            return true;
        }
        else
            unsupported(path, "the keyword '" + w + "' in its POLYDATA section");
    }
    return true;
}

namespace {

// One XML start or end tag: its name and attributes (name="value" or name='value').
struct Tag
{
    bool end = false;
    bool empty = false;  // <name ... />
    std::string name;
    std::map<std::string, std::string> attributes;
    std::size_t close = 0;  // the position just after its '>'

    std::string get(const std::string& key) const
    {
        const auto it = attributes.find(key);
        return it == attributes.end() ? std::string() : it->second;
    }
};

// The next tag at or after \p from in \p xml (declarations, comments and CDATA skipped); false
// at the end. A tag that does not close is refused (expat refuses it too).
bool next_tag(const std::string& path, const std::string& xml, std::size_t& from, Tag& tag)
{
    while (true)
    {
        const std::size_t open = xml.find('<', from);
        if (open == std::string::npos)
            return false;
        if (xml.compare(open, 4, "<!--") == 0 || xml.compare(open, 2, "<?") == 0 ||
            xml.compare(open, 2, "<!") == 0)
        {
            const char* end = xml.compare(open, 4, "<!--") == 0 ? "-->"
                              : xml.compare(open, 2, "<?") == 0 ? "?>" : ">";
            const std::size_t stop = xml.find(end, open + 2);
            if (stop == std::string::npos)
                return false;
            from = stop + 1;
            continue;
        }
        tag = Tag{};
        std::size_t i = open + 1;
        if (i < xml.size() && xml[i] == '/')
            tag.end = true, ++i;
        const auto name_char = [&](std::size_t k) {
            const unsigned char c = static_cast<unsigned char>(xml[k]);
            return std::isalnum(c) || c == '_' || c == ':' || c == '-' || c == '.';
        };
        const std::size_t name_start = i;
        while (i < xml.size() && name_char(i))
            ++i;
        tag.name = xml.substr(name_start, i - name_start);
        while (true)
        {
            while (i < xml.size() && std::isspace(static_cast<unsigned char>(xml[i])))
                ++i;
            if (i >= xml.size())
                corrupt(path, "the XML tag <" + tag.name + " does not close");
            if (xml[i] == '>' || xml[i] == '/')
            {
                const std::size_t gt = xml.find('>', i);
                if (gt == std::string::npos)
                    corrupt(path, "the XML tag <" + tag.name + " does not close");
                tag.empty = xml[i] == '/';
                from = tag.close = gt + 1;
                return true;
            }
            const std::size_t key_start = i;
            while (i < xml.size() && name_char(i))
                ++i;
            const std::string key = xml.substr(key_start, i - key_start);
            while (i < xml.size() && std::isspace(static_cast<unsigned char>(xml[i])))
                ++i;
            if (key.empty() || i + 1 >= xml.size() || xml[i] != '=')
                corrupt(path, "the XML tag <" + tag.name + "> has a malformed attribute near byte " +
                                  std::to_string(i));
            ++i;
            while (i < xml.size() && std::isspace(static_cast<unsigned char>(xml[i])))
                ++i;
            const char quote = i < xml.size() ? xml[i] : '\0';
            const std::size_t value_end = quote == '"' || quote == '\''
                                              ? xml.find(quote, i + 1)
                                              : std::string::npos;
            if (value_end == std::string::npos)
                corrupt(path, "the attribute " + key + " of the XML tag <" + tag.name +
                                  "> has no quoted value");
            tag.attributes[key] = xml.substr(i + 1, value_end - i - 1);
            i = value_end + 1;
        }
    }
}

// Base64 text decoded four characters at a time, so that units padded on their own (VTK encodes
// a compression header and the data after it separately) decode to their bytes end to end.
// Refused if a character is not base64 or a group is cut short. \p groups, if given, receives
// the decoded position at the start of each 4-character group.
std::string decode_base64(const std::string& path, const std::string& what, const std::string& text,
                          std::vector<std::size_t>* groups = nullptr)
{
    static const std::string alphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    if (text.size() % 4 != 0)
        corrupt(path, what + " has " + std::to_string(text.size()) +
                          " base64 characters, not a multiple of 4");
    std::string out;
    out.reserve(text.size() / 4 * 3);
    for (std::size_t i = 0; i < text.size(); i += 4)
    {
        for (std::size_t k = 0; k < 4; ++k)
        {
            const char c = text[i + k];
            const bool pad = c == '=' && k >= 2 && (k == 3 || text[i + 3] == '=');
            if (!pad && alphabet.find(c) == std::string::npos)
                corrupt(path, what + " has the character '" + std::string(1, c) +
                                  "' in its base64 data (at " + std::to_string(i + k) + ")");
        }
        if (groups)
            groups->push_back(out.size());
        unsigned char o[3];
        const int n = vtkBase64Utilities::DecodeTriplet(
            static_cast<unsigned char>(text[i]), static_cast<unsigned char>(text[i + 1]),
            static_cast<unsigned char>(text[i + 2]), static_cast<unsigned char>(text[i + 3]),
            &o[0], &o[1], &o[2]);
        out.append(reinterpret_cast<const char*>(o), static_cast<std::size_t>(n));
    }
    return out;
}

std::string trim(const std::string& s)
{
    const std::size_t a = s.find_first_not_of(" \t\r\n");
    const std::size_t b = s.find_last_not_of(" \t\r\n");
    return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

// What a binary array must hold, from its section and the piece's counts.
struct Need
{
    std::uint64_t bytes = 0;     // exactly (or at least, when !exact) this many bytes
    std::uint64_t or_bytes = 0;  // exact arrays: this many is also right (offsets with a leading 0)
    bool exact = true;
};

// One binary array's size header and data (VTK XML "binary" layout): \p src from \p at holds
// \p left bytes: the header (uncompressed: the byte count; compressed: blocks, block size, last
// block size, each block's compressed size) and then the data. Returns the size of the data
// (uncompressed); with \p values, also the data itself (decompressed by \p compressor).
std::uint64_t check_binary_array(const std::string& path, const std::string& array,
                                 const std::string& src, std::size_t at, std::uint64_t left,
                                 int header, bool little, vtkDataCompressor* compressor,
                                 const Need& need, std::string* values = nullptr)
{
    const bool compressed = compressor != nullptr;
    const auto read_uint = [&](std::size_t where) {
        std::uint64_t v = 0;
        for (int b = 0; b < header; ++b)
        {
            const auto byte = static_cast<unsigned char>(src[where + (little ? header - 1 - b : b)]);
            v = (v << 8) | byte;
        }
        return v;
    };
    if (!compressed)
    {
        if (left < static_cast<std::uint64_t>(header))
            corrupt(path, "the array '" + array + "' has no size header");
        const std::uint64_t size = read_uint(at);
        if (size > left - header)
            corrupt(path, "the array '" + array + "' declares " + std::to_string(size) +
                              " bytes but only " + std::to_string(left - header) + " follow");
        if (size < need.bytes)
            corrupt(path, "the array '" + array + "' holds " + std::to_string(size) +
                              " bytes but needs " + std::to_string(need.bytes));
        if (values)
            *values = src.substr(at + header, size);
        return size;
    }
    if (left < 3ull * header)
        corrupt(path, "the array '" + array + "' has no compression header");
    const std::uint64_t blocks = read_uint(at), block_size = read_uint(at + header),
                        last_size = read_uint(at + 2 * header);
    if (blocks > (left - 3ull * header) / header)
        corrupt(path, "the compression header of array '" + array + "' declares " +
                          std::to_string(blocks) + " blocks, more than the " +
                          std::to_string(left) + " bytes left can describe");
    std::uint64_t compressed_total = 0;
    for (std::uint64_t b = 0; b < blocks && compressed_total <= left; ++b)
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
    if (need.exact ? size != need.bytes && size != need.or_bytes : size < need.bytes)
        corrupt(path, "the compression header of array '" + array + "' declares " +
                          std::to_string(size) + " bytes (" + std::to_string(blocks) +
                          " blocks) but the array needs " + (need.exact ? "" : "at least ") +
                          std::to_string(need.bytes));
    // zlib, LZ4 and LZMA expand at most about 1000-fold; more is a bomb, not data.
    if (size > 2048 * (compressed_total + 64))
        corrupt(path, "array '" + array + "' would expand " + std::to_string(compressed_total) +
                          " compressed bytes to " + std::to_string(size));
    if (values)
    {
        values->assign(size, '\0');
        std::size_t from = at + (3 + blocks) * header, to = 0;
        for (std::uint64_t b = 0; b < blocks; ++b)
        {
            const std::uint64_t in = read_uint(at + (3 + b) * header);
            const std::uint64_t out = b + 1 == blocks ? last : block_size;
            if (compressor->Uncompress(reinterpret_cast<const unsigned char*>(src.data() + from),
                                       in, reinterpret_cast<unsigned char*>(&(*values)[to]),
                                       out) != out)
                corrupt(path, "block " + std::to_string(b) + " of array '" + array +
                                  "' does not decompress to its " + std::to_string(out) + " bytes");
            from += in;
            to += out;
        }
    }
    return size;
}

// The cell arrays of one section (Verts, Lines, Strips, Polys): vtkXMLPolyDataReader reads
// the offsets (each cell's end in the connectivity), allocates as many connectivity values as
// the last offset says and builds cells from consecutive offsets, so the offsets must rise
// from 0 to at most the connectivity's length.
struct CellArrays
{
    std::uint64_t cells = 0;
    std::uint64_t connectivity = 0;  // values
    std::vector<long long> offsets;  // values, or empty if the section has none
    bool has_offsets = false;
};

void check_cell_arrays(const std::string& path, const std::string& section, const CellArrays& c)
{
    if (c.cells == 0)
        return;
    if (!c.has_offsets || c.offsets.size() < c.cells)
        corrupt(path, "<" + section + "> declares " + std::to_string(c.cells) + " cells but has " +
                          std::to_string(c.offsets.size()) + " offsets");
    long long previous = 0;
    for (std::size_t i = 0; i < c.cells; ++i)
    {
        if (c.offsets[i] < previous)
            corrupt(path, "offset " + std::to_string(i) + " of <" + section + "> is " +
                              std::to_string(c.offsets[i]) + ", below the one before it (" +
                              std::to_string(previous) + ")");
        previous = c.offsets[i];
    }
    if (static_cast<std::uint64_t>(previous) > c.connectivity)
        corrupt(path, "the last offset of <" + section + "> is " + std::to_string(previous) +
                          " but its connectivity holds " + std::to_string(c.connectivity) +
                          " values");
}

// Integers of \p size bytes from \p bytes (signed unless \p is_unsigned).
std::vector<long long> integers(const std::string& bytes, int size, bool is_unsigned, bool little)
{
    std::vector<long long> out;
    for (std::size_t i = 0; i + size <= bytes.size(); i += size)
    {
        std::uint64_t v = 0;
        for (int b = 0; b < size; ++b)
            v = (v << 8) | static_cast<unsigned char>(bytes[i + (little ? size - 1 - b : b)]);
        if (!is_unsigned && size < 8 && (v >> (8 * size - 1)) != 0)
            v |= ~std::uint64_t{0} << (8 * size);  // sign-extend
        out.push_back(is_unsigned && v > static_cast<std::uint64_t>(
                                              std::numeric_limits<long long>::max())
                          ? std::numeric_limits<long long>::max()
                          : static_cast<long long>(v));
    }
    return out;
}

}  // namespace

void check_vtp(const std::string& path)
{
    const std::string bytes = read_all(path);
    const std::size_t appended = bytes.find("<AppendedData");
    const std::string xml = bytes.substr(0, appended);
    // The appended data: raw bytes after its '_', or base64 text decoded once (offsets count
    // characters there, each array's header starting a 4-character group).
    std::size_t data = std::string::npos;
    bool raw = true;
    std::string decoded;
    std::vector<std::size_t> groups;
    if (appended != std::string::npos)
    {
        std::size_t from = appended;
        Tag tag;
        if (!next_tag(path, bytes, from, tag))
            corrupt(path, "the <AppendedData> tag does not close");
        raw = tag.get("encoding") == "raw";
        // vtkXMLDataParser::FindAppendedDataPosition() takes the data to start one byte after
        // the first non-space byte past the tag's first '>', which is meant to be '_'; the
        // arrays' offsets count from there, so anything else before the '_' moves every
        // array VTK reads away from the one checked here.
        std::size_t underscore = bytes.find('>', appended);
        if (underscore != std::string::npos)
            underscore = bytes.find_first_not_of(" \t\n\v\f\r", underscore + 1);
        if (underscore == std::string::npos || bytes[underscore] != '_')
            corrupt(path, "the data of <AppendedData> does not start with '_' after its tag");
        data = underscore + 1;
        if (!raw)
        {
            std::size_t end = data;
            while (end < bytes.size() && (std::isalnum(static_cast<unsigned char>(bytes[end])) ||
                                          bytes[end] == '+' || bytes[end] == '/' ||
                                          bytes[end] == '='))
                ++end;
            decoded = decode_base64(path, "the base64 <AppendedData>",
                                    bytes.substr(data, end - data), &groups);
        }
    }

    Tag tag;
    std::size_t from = 0;
    bool little = true;
    int header = 4;
    vtkSmartPointer<vtkDataCompressor> compressor;
    CellArrays cell_arrays;
    static const std::map<std::string, int> type_sizes = {
        {"Int8", 1},   {"UInt8", 1},   {"Int16", 2},   {"UInt16", 2},  {"Int32", 4},
        {"UInt32", 4}, {"Int64", 8},   {"UInt64", 8},  {"Float32", 4}, {"Float64", 8}};
    // The tags in order: the section (Points, PointData, CellData, Verts, ...) and the piece's
    // counts give each binary array the number of values it needs.
    std::uint64_t n_points = 0, n_cells = 0;
    std::map<std::string, std::uint64_t> section_cells;  // Verts, Lines, Strips, Polys
    std::string section;
    // VTK allocates each array from the piece's counts before reading it; compressed data
    // expands at most ~1000-fold, so a count beyond 2048 x the file's size is a bomb.
    const std::uint64_t most = 2048 * static_cast<std::uint64_t>(bytes.size() + 64);
    const auto piece_count = [&](const Tag& piece, const std::string& key) {
        const std::string text = piece.get(key);
        errno = 0;
        char* end = nullptr;
        const unsigned long long n = std::strtoull(text.c_str(), &end, 10);
        if (!text.empty() && (errno == ERANGE || text[0] == '-' || n > most))
            corrupt(path, "the <Piece> declares " + key + "=\"" + text.substr(0, 30) +
                              "\", more than a file of " + std::to_string(bytes.size()) +
                              " bytes can hold");
        return static_cast<std::uint64_t>(n);
    };
    while (next_tag(path, xml, from, tag))
    {
        if (tag.end)
        {
            if (tag.name == section)
            {
                if (section_cells.count(section))
                    check_cell_arrays(path, section, cell_arrays);
                section.clear();
            }
            continue;
        }
        if (tag.name == "VTKFile")
        {
            const std::string name = tag.get("compressor");
            if (name == "vtkZLibDataCompressor")
                compressor = vtkSmartPointer<vtkZLibDataCompressor>::New();
            else if (name == "vtkLZ4DataCompressor")
                compressor = vtkSmartPointer<vtkLZ4DataCompressor>::New();
            else if (name == "vtkLZMADataCompressor")
                compressor = vtkSmartPointer<vtkLZMADataCompressor>::New();
            else if (!name.empty())
                corrupt(path, "the compressor '" + name + "' is not one VTK has (zlib, LZ4, LZMA)");
            header = tag.get("header_type") == "UInt64" ? 8 : 4;
            little = tag.get("byte_order") != "BigEndian";
            continue;
        }
        if (tag.name == "Piece")
        {
            n_points = piece_count(tag, "NumberOfPoints");
            n_cells = 0;
            for (const char* c : {"Verts", "Lines", "Strips", "Polys"})
                n_cells += section_cells[c] = piece_count(tag, std::string("NumberOf") + c);
            continue;
        }
        if (tag.name != "DataArray")
        {
            section = tag.name;
            cell_arrays = CellArrays{};
            if (section_cells.count(section))
                cell_arrays.cells = section_cells[section];
            continue;
        }
        const std::string format = tag.get("format");
        const std::string array = tag.get("Name");
        // Bytes the array needs: exactly (points, point and cell data, cell offsets: one per
        // cell, or one more with a leading 0), or at least (connectivity: a corner per cell).
        const auto type = type_sizes.find(tag.get("type"));
        const std::uint64_t value_size = type == type_sizes.end() ? 1 : type->second;
        const std::string components = tag.get("NumberOfComponents");
        const std::uint64_t width =
            components.empty() ? 1 : std::strtoull(components.c_str(), nullptr, 10);
        // Saturating: a product beyond `most` is refused below whatever its exact value.
        const auto product = [&](std::uint64_t a, std::uint64_t b, std::uint64_t c) {
            if (a == 0 || b == 0 || c == 0)
                return std::uint64_t{0};
            return a > most / b || a * b > most / c ? most + 1 : a * b * c;
        };
        // vtkXMLUnstructuredDataReader refuses other widths, leaking the array it made.
        if (section == "Points" && width != 3)
            corrupt(path, "the <Points> array '" + array + "' has NumberOfComponents=\"" +
                              components + "\", not 3");
        Need need;
        if (section == "Points" || section == "PointData")
            need.bytes = product(n_points, width, value_size);
        else if (section == "CellData")
            need.bytes = product(n_cells, width, value_size);
        else if (section_cells.count(section) && array == "offsets")
            need.bytes = section_cells[section] * value_size;
        else
        {
            need.exact = false;
            need.bytes = section_cells.count(section) ? section_cells[section] * value_size : 0;
        }
        need.or_bytes = need.exact && array == "offsets" ? need.bytes + value_size : need.bytes;
        if (need.bytes > most)
            corrupt(path, "the array '" + array + "' needs " + components + " components for " +
                              "each of the piece's items, more than a file of " +
                              std::to_string(bytes.size()) + " bytes can hold");
        const bool cell_array = section_cells.count(section) &&
                                (array == "offsets" || array == "connectivity");
        const std::string type_name = tag.get("type");
        if (cell_array && array == "offsets" &&
            (type == type_sizes.end() || type_name.rfind("Float", 0) == 0))
            corrupt(path, "the offsets of <" + section + "> have the type '" + type_name +
                              "', not an integer type");
        // The values of the cell arrays: offsets in full, connectivity counted.
        const auto take = [&](std::uint64_t size, const std::string& payload) {
            if (!cell_array)
                return;
            if (array == "connectivity")
                cell_arrays.connectivity = size / value_size;
            else
            {
                cell_arrays.has_offsets = true;
                cell_arrays.offsets = integers(payload, static_cast<int>(value_size),
                                               type_name.rfind("UInt", 0) == 0, little);
            }
        };
        std::string payload;
        std::string* want = cell_array && array == "offsets" ? &payload : nullptr;
        if (format != "appended" && format != "binary")
        {
            // ascii: read by a stream that stops at the first bad value; the cell arrays are
            // counted (and the offsets read) here.
            if (!cell_array)
                continue;
            const std::size_t end = tag.empty ? tag.close : std::min(xml.find('<', tag.close), xml.size());
            std::size_t i = tag.close, n = 0;
            std::vector<long long> offsets;
            while (i < end)
            {
                while (i < end && std::isspace(static_cast<unsigned char>(xml[i])))
                    ++i;
                const std::size_t start = i;
                while (i < end && !std::isspace(static_cast<unsigned char>(xml[i])))
                    ++i;
                if (i == start)
                    break;
                ++n;
                if (want)
                    offsets.push_back(std::strtoll(xml.substr(start, i - start).c_str(), nullptr, 10));
            }
            if (array == "connectivity")
                cell_arrays.connectivity = n;
            else
                cell_arrays.has_offsets = true, cell_arrays.offsets = std::move(offsets);
            continue;
        }
        if (format == "binary")
        {
            // Inline base64 up to the closing tag; VTK's base64 stream reads it without
            // skipping whitespace inside.
            const std::size_t end = tag.empty ? tag.close : std::min(xml.find('<', tag.close), xml.size());
            const std::string text = trim(xml.substr(tag.close, end - tag.close));
            const std::string what = "the binary array '" + array + "'";
            const std::string block = decode_base64(path, what, text);
            take(check_binary_array(path, array, block, 0, block.size(), header, little,
                                    compressor, need, want),
                 payload);
            continue;
        }
        if (data == std::string::npos)
            corrupt(path, "the array '" + array + "' is appended but the file has no "
                                                  "<AppendedData>");
        const std::string offset_text = tag.get("offset");
        const std::uint64_t offset = std::strtoull(offset_text.c_str(), nullptr, 10);
        const std::uint64_t length = raw ? bytes.size() - data : groups.size() * 4;
        if (offset_text.empty() || offset >= length || (!raw && offset % 4 != 0))
            corrupt(path, "the appended array '" + array + "' starts at offset '" + offset_text +
                              "', beyond the " + std::to_string(length) +
                              " bytes of appended data" + (raw ? "" : " (or inside a base64 group)"));
        if (raw)
            take(check_binary_array(path, array, bytes, data + offset, length - offset, header,
                                    little, compressor, need, want),
                 payload);
        else
        {
            const std::size_t at = groups[offset / 4];
            take(check_binary_array(path, array, decoded, at, decoded.size() - at, header, little,
                                    compressor, need, want),
                 payload);
        }
    }
}

}  // namespace vessel::detail
