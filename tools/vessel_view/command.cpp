#include "command.h"

namespace vessel::cli {

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
            i += 3;
        else if (arg.rfind("--viewpoint=", 0) != 0)
            words.push_back(arg);
    }
    return join_quoted(words);
}

}  // namespace vessel::cli
