#pragma once

// A JSON reader and writer for CLI11's --config: a saved set of options, e.g.
//   {"preset": "paper", "relief-cuts": 0, "image": ["map.png"], "viewpoint": [0, 10, 2]}
// Keys are long option names without the dashes; values are strings, numbers, booleans (flags)
// or arrays of them (options that take several values; an inner array is one comma-separated
// value, e.g. "split-at": [[3, 5], [7]]). Options given on the command line win over the file.

#include <CLI/CLI.hpp>

#include <istream>
#include <string>
#include <vector>

namespace vessel::cli {

class JsonConfig : public CLI::Config
{
public:
    //! The options given (and, with \p default_also, those with a default), as one JSON object.
    std::string to_config(const CLI::App* app, bool default_also, bool write_description,
                          std::string prefix) const override;
    //! \throw CLI::ConversionError if \p input is no JSON object of the forms above.
    std::vector<CLI::ConfigItem> from_config(std::istream& input) const override;
};

}  // namespace vessel::cli
