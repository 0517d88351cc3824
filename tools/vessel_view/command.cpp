#include "command.h"

#include "vessel/core/errors.h"
#include "vessel/cut/endpoints.h"

#include <exception>
#include <memory>

namespace vessel::cli {

void apply_viewpoint(const std::vector<std::string>& words, FlattenOptions& options)
{
    if (words.empty())
        return;
    if (words.size() == 1 && words[0] == "face-on")
    {
        options.cost.face_on = true;  // flatten() takes the viewpoint from each mesh
        return;
    }
    if (words.size() != 3)
        throw InvalidInputError("--viewpoint takes a point X Y Z or the word face-on, got " +
                                join_quoted(words));
    Eigen::Vector3d point;
    for (int i = 0; i < 3; ++i)
    {
        std::size_t used = 0;
        try
        {
            point[i] = std::stod(words[i], &used);
        }
        catch (const std::exception&)
        {
            used = 0;
        }
        if (used != words[i].size())
            throw InvalidInputError("--viewpoint: '" + words[i] +
                                    "' is not a number; give X Y Z or face-on");
    }
    options.cuts.endpoints = std::make_shared<FarSideEndpoints>(point);
    options.cost.viewpoint = point;
}

std::string shell_quote(const std::string& word)
{
    const bool plain = !word.empty() && word.find_first_not_of(
                                            "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                            "0123456789-_./=:,+@%") == std::string::npos;
    if (plain)
        return word;
    std::string out = "'";
    for (char c : word)
        out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

std::string join_quoted(const std::vector<std::string>& words)
{
    std::string out;
    for (const auto& w : words)
        out += (out.empty() ? "" : " ") + shell_quote(w);
    return out;
}

std::string command_without_viewpoint(const std::string& program, int argc, char** argv)
{
    std::vector<std::string> words = {program};
    for (int i = 1; i < argc; ++i)
    {
        const std::string arg = argv[i];
        if (arg == "--viewpoint")
            i += i + 1 < argc && std::string(argv[i + 1]) == "face-on" ? 1 : 3;
        else if (arg.rfind("--viewpoint=", 0) != 0)
            words.push_back(arg);
    }
    return join_quoted(words);
}

}  // namespace vessel::cli
