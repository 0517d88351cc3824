#include "detail/atomic_file.h"

#include "vessel/core/errors.h"

#include <filesystem>
#include <memory>

namespace vessel::detail {

void commit_tmp(const std::string& path, const std::string& who)
{
    const std::string tmp = path + ".tmp";
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec)
        throw IoError(who + ": cannot rename " + tmp + " to " + path + ": " + ec.message());
}

void write_atomically(const std::string& path, const std::string& who,
                      const std::function<void(FILE*)>& write)
{
    const std::string tmp = path + ".tmp";
    {
        std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(tmp.c_str(), "wb"), &std::fclose);
        if (!file)
            throw IoError(who + ": cannot open " + tmp + " for writing");
        write(file.get());
        if (std::ferror(file.get()))
            throw IoError(who + ": write error on " + tmp);
    }
    commit_tmp(path, who);
}

}  // namespace vessel::detail
