#pragma once

// Text helpers shared by the readers' checks (io.cpp) and the OFF reader (off_reader.cpp).

#include "vessel/core/errors.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace vessel::detail {

//! More elements than any surface mesh has; larger (or negative) counts are corrupt headers.
constexpr long long kMaxElements = 1LL << 31;

//! \p line without leading and trailing white space.
inline std::string trimmed(const std::string& line)
{
    std::size_t begin = 0, end = line.size();
    while (begin < end && std::isspace(static_cast<unsigned char>(line[begin])))
        ++begin;
    while (end > begin && std::isspace(static_cast<unsigned char>(line[end - 1])))
        --end;
    return line.substr(begin, end - begin);
}

//! \p text cut to 40 characters with control bytes shown as '?', to quote it in a message.
inline std::string printable(const std::string& text)
{
    std::string out = trimmed(text).substr(0, 40);
    for (char& c : out)
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f)
            c = '?';
    return out;
}

//! Throws the IoError of a truncated or corrupt file; \p what says what does not fit.
[[noreturn]] inline void truncated(const std::string& path, const std::string& what)
{
    throw IoError("read_raw_mesh: " + path + " is truncated or corrupt: " + what +
                  "; re-export or re-download the file");
}

//! The white-space separated words of \p text.
inline std::vector<std::string> words_of(const std::string& text)
{
    std::istringstream in(text);
    return {std::istream_iterator<std::string>(in), std::istream_iterator<std::string>()};
}

//! The IoError of a number beyond float's range in a format that OpenMesh reads as float (a
//! 1e39 is no corruption of the file, but it cannot be read): \p what names the element
//! ("vertex 3"), \p value the number ("the coordinate '1e39'").
inline IoError beyond_float(const std::string& path, const std::string& what,
                            const std::string& value)
{
    return IoError("read_raw_mesh: " + what + " of " + path + " has " + value +
                   ", beyond the range of float (3.4e38), in which this format is read; fix "
                   "the value or the unit in the source");
}

//! The coordinates in \p columns of the words of vertex \p vertex's line; throws the IoError of
//! a NaN, infinite or unreadable coordinate, and with \p as_float (the reader reads floats) of
//! one beyond float's range, which OpenMesh's OBJ reader dropped with its whole vertex line.
inline std::vector<double> coordinates(const std::string& path, const std::vector<std::string>& all,
                                       std::size_t vertex, const std::vector<int>& columns,
                                       bool as_float = false)
{
    std::vector<double> values;
    for (const int k : columns)
    {
        const std::string word = static_cast<std::size_t>(k) < all.size() ? all[k] : "";
        char* end = nullptr;
        const double value = std::strtod(word.c_str(), &end);
        if (word.empty() || *end != '\0' || !std::isfinite(value))
            throw IoError("read_raw_mesh: vertex " + std::to_string(vertex) + " of " + path +
                          " has a NaN, infinite or unreadable coordinate ('" + printable(word) +
                          "'); fix or remove it in the source");
        if (as_float && std::abs(value) > std::numeric_limits<float>::max())
            throw beyond_float(path, "vertex " + std::to_string(vertex),
                               "the coordinate '" + printable(word) + "'");
        values.push_back(value);
    }
    return values;
}

}  // namespace vessel::detail
