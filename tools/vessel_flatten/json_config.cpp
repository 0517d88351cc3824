#include "json_config.h"

#include <nlohmann/json.hpp>

namespace vessel::cli {

namespace {

using nlohmann::json;

// One command-line word for a scalar JSON value; an array becomes one comma-separated word.
std::string word(const json& value, const std::string& key)
{
    if (value.is_string())
        return value.get<std::string>();
    if (value.is_boolean())
        return value.get<bool>() ? "true" : "false";
    if (value.is_number())
        return value.dump();  // integers as written, doubles with round-trip precision
    if (value.is_array())
    {
        std::string joined;
        for (const json& item : value)
            joined += (joined.empty() ? "" : ",") + word(item, key);
        return joined;
    }
    throw CLI::ConversionError("--config: the value of \"" + key +
                               "\" must be a string, number, boolean or array, got " +
                               value.dump());
}

}  // namespace

std::vector<CLI::ConfigItem> JsonConfig::from_config(std::istream& input) const
{
    json j;
    try
    {
        input >> j;
    }
    catch (const json::exception& e)
    {
        throw CLI::ConversionError(std::string("--config: not valid JSON: ") + e.what());
    }
    if (!j.is_object())
        throw CLI::ConversionError(
            "--config: the file must hold one JSON object "
            "{\"option-name\": value, ...}, got " +
            std::string(j.type_name()));
    std::vector<CLI::ConfigItem> items;
    for (auto it = j.begin(); it != j.end(); ++it)
    {
        CLI::ConfigItem item;
        item.name = it.key();
        if (it->is_array())
            for (const json& value : *it)
                item.inputs.push_back(word(value, it.key()));
        else
            item.inputs.push_back(word(*it, it.key()));
        items.push_back(std::move(item));
    }
    return items;
}

std::string JsonConfig::to_config(const CLI::App* app, bool default_also,
                                  bool /*write_description*/, std::string /*prefix*/) const
{
    json j = json::object();
    for (const CLI::Option* option : app->get_options())
    {
        const std::string name = option->get_single_name();
        if (!option->get_configurable() || name.empty())
            continue;
        std::vector<std::string> values = option->results();
        if (values.empty() && default_also && !option->get_default_str().empty())
            values = {option->get_default_str()};
        if (values.empty())
            continue;
        j[name] = values.size() == 1 ? json(values.front()) : json(values);
    }
    return j.dump(2) + "\n";
}

}  // namespace vessel::cli
