#include "output_plan.h"

#include "vessel/core/errors.h"
#include "vessel/io/ensight.h"
#include "vessel/io/flat_vtk.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <exception>
#include <filesystem>
#include <sys/stat.h>
#include <unistd.h>

namespace vessel::cli {

namespace fs = std::filesystem;

namespace {

std::string lower_extension(const std::string& path)
{
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

fs::path folder_of(const std::string& path)
{
    const fs::path parent = fs::path(path).parent_path();
    return parent.empty() ? fs::path(".") : parent;
}

// The path with links and `..` resolved as far as it exists, to compare outputs and inputs.
fs::path identity(const std::string& path)
{
    std::error_code ec;
    fs::path p = fs::weakly_canonical(fs::absolute(path), ec);
    return ec ? fs::absolute(path).lexically_normal() : p;
}

bool same_file(const std::string& a, const std::string& b)
{
    std::error_code ec;
    if (fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec))
        return true;  // also hard links
    return identity(a) == identity(b);
}

// The folder \p folder, where \p option's \p path goes, exists and is writable.
void check_writable(const std::string& option, const std::string& path, const fs::path& folder)
{
    std::error_code ec;
    if (!fs::is_directory(folder, ec))
        throw InvalidInputError(option + " " + path + ": the folder " + folder.string() +
                                " does not exist; create it first");
    if (::access(folder.c_str(), W_OK | X_OK) != 0)
        throw InvalidInputError(option + " " + path + ": the folder " + folder.string() +
                                " is not writable (" + std::strerror(errno) +
                                "); choose another folder");
}

// An output file: a known extension, in a writable folder, not an existing folder.
void check_file(const std::string& option, const std::string& path,
                const std::vector<std::string>& extensions)
{
    std::error_code ec;
    if (fs::is_directory(path, ec))
        throw InvalidInputError(option + " " + path +
                                " is a folder; give a file name to write");
    if (std::find(extensions.begin(), extensions.end(), lower_extension(path)) == extensions.end())
    {
        std::string list;
        for (std::size_t i = 0; i < extensions.size(); ++i)
            list += (i == 0 ? "" : i + 1 == extensions.size() ? " or " : ", ") + extensions[i];
        throw InvalidInputError(option + " " + path + ": unknown file type '" +
                                lower_extension(path) + "'; use " + list);
    }
    check_writable(option, path, folder_of(path));
}

// A folder the run creates (if missing) and writes into.
void check_folder(const std::string& option, const std::string& path)
{
    std::error_code ec;
    const fs::path folder(path);
    if (fs::exists(folder, ec) && !fs::is_directory(folder, ec))
        throw InvalidInputError(option + " " + path + " is a file, not a folder; give a folder");
    check_writable(option, path, fs::is_directory(folder, ec) ? folder : folder_of(path));
}

std::string piece_name(const std::string& path, int piece)
{
    const fs::path p(path);
    return (p.parent_path() / p.stem()).string() + ".piece" + std::to_string(piece) +
           p.extension().string();
}

struct stat status_of(const std::string& path, bool& exists)
{
    struct stat s = {};
    exists = ::lstat(path.c_str(), &s) == 0;
    return s;
}

std::int64_t mtime_ns(const struct stat& s)
{
    return static_cast<std::int64_t>(s.st_mtim.tv_sec) * 1000000000 + s.st_mtim.tv_nsec;
}

}  // namespace

OutputPlan::OutputPlan(const OutputRequest& request) : uncaught_(std::uncaught_exceptions())
{
    // (option, path) of every file, so that a clash names both options.
    std::vector<std::pair<std::string, std::string>> named;
    const auto add = [&](const std::string& option, const std::string& path) {
        named.emplace_back(option, path);
        files_.push_back(path);
    };
    const int pieces = std::max(1, request.pieces);
    for (int i = 0; i < pieces; ++i)
    {
        const auto piece = [&](const std::string& path) {
            return request.pieces > 0 ? piece_name(path, i) : path;
        };
        const std::string out = piece(request.output);
        add("-o", out);
        if (lower_extension(out) == ".vtp")
        {
            add("-o", map_path(out));
            if (request.may_write_series)
            {
                const fs::path series = fs::path(out).replace_extension(".case");
                add("-o", series.string());
                add("-o", map_path(series.string()));
                folders_.push_back(
                    (series.parent_path() / ensight_data_folder(series.string())).string());
            }
        }
        if (!request.report.empty())
            add("--report", piece(request.report));
    }
    if (!request.html.empty())
        add("--html", request.html);
    for (const auto& image : request.images)
        add("--image", image);
    if (!request.frames.empty())
        folders_.push_back(request.frames);

    for (const auto& [option, path] : named)
    {
        if (option == "-o")
            check_file(option, path, {".obj", ".vtp", ".ply", ".case"});
        else if (option == "--report")
            check_file(option, path, {".json"});
        else if (option == "--html")
            check_file(option, path, {".html", ".htm"});
        else
            check_file(option, path, {".png", ".svg", ".pdf"});
    }
    if (!request.frames.empty())
        check_folder("--frames", request.frames);

    for (std::size_t i = 0; i < named.size(); ++i)
    {
        for (const auto& input : request.inputs)
            if (!input.empty() && same_file(named[i].second, input))
                throw InvalidInputError(named[i].first + " " + named[i].second + " is the input " +
                                        input + "; writing it would destroy the input, so "
                                        "choose another output name");
        for (std::size_t j = 0; j < i; ++j)
            if (same_file(named[i].second, named[j].second))
                throw InvalidInputError(named[i].first + " " + named[i].second + " is also the " +
                                        named[j].first + " output " + named[j].second +
                                        "; give each output its own name");
        for (const auto& folder : folders_)
            if (same_file(named[i].second, folder))
                throw InvalidInputError(named[i].first + " " + named[i].second +
                                        " is also a folder this run writes into; give each "
                                        "output its own name");
    }

    const auto remember = [&](const std::string& path) {
        Before b;
        b.path = path;
        const struct stat s = status_of(path, b.existed);
        b.inode = s.st_ino;
        b.mtime_ns = mtime_ns(s);
        before_.push_back(b);
    };
    for (const auto& f : files_)
        remember(f);
    for (const auto& folder : folders_)
    {
        remember(folder);
        std::error_code ec;
        for (const auto& entry : fs::directory_iterator(folder, ec))
            remember(entry.path().string());
    }
}

void OutputPlan::remove_written() const
{
    const auto changed = [&](const std::string& path) {
        bool exists = false;
        const struct stat s = status_of(path, exists);
        if (!exists)
            return false;
        for (const auto& b : before_)
            if (b.path == path)
                return !b.existed || b.inode != s.st_ino || b.mtime_ns != mtime_ns(s);
        return true;  // an entry of a folder that was not there before
    };
    for (const auto& f : files_)
        if (changed(f))
            ::unlink(f.c_str());
    for (const auto& folder : folders_)
    {
        std::error_code ec;
        std::vector<std::string> entries;
        for (const auto& entry : fs::directory_iterator(folder, ec))
            entries.push_back(entry.path().string());
        for (const auto& e : entries)
            if (changed(e))
                ::unlink(e.c_str());
        const bool existed = std::any_of(before_.begin(), before_.end(), [&](const Before& b) {
            return b.path == folder && b.existed;
        });
        if (!existed)
            ::rmdir(folder.c_str());  // only if empty: never what was there before
    }
}

OutputPlan::~OutputPlan()
{
    if (std::uncaught_exceptions() > uncaught_)
        remove_written();
}

}  // namespace vessel::cli
