#include "detail/atomic_file.h"

#include "vessel/core/errors.h"
#include "vessel/io/io.h"

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace vessel::detail {

namespace {

// The process's umask without changing it (umask() can only be read by setting it, which
// would race with other threads creating files): Linux reports it in /proc/self/status.
mode_t current_umask()
{
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("Umask:", 0) == 0)
            return static_cast<mode_t>(std::strtoul(line.c_str() + 6, nullptr, 8));
    return 022;
}

std::string folder_of(const std::string& target)
{
    const std::filesystem::path parent = std::filesystem::path(target).parent_path();
    return parent.empty() ? std::string(".") : parent.string();
}

}  // namespace

void ignore_file_size_signal()
{
    static std::once_flag once;
    std::call_once(once, [] {
        struct sigaction old = {};
        if (sigaction(SIGXFSZ, nullptr, &old) == 0 && old.sa_handler == SIG_DFL &&
            !(old.sa_flags & SA_SIGINFO))
            std::signal(SIGXFSZ, SIG_IGN);
    });
}

TempFile::TempFile(const std::string& target, const std::string& who)
    : target_(target), who_(who)
{
    ignore_file_size_signal();
    std::vector<char> name(target.begin(), target.end());
    const std::string suffix = ".XXXXXX.tmp";
    name.insert(name.end(), suffix.begin(), suffix.end());
    name.push_back('\0');
    // mkstemps: O_CREAT | O_EXCL (and mode 0600), so the name is new: never a link, never a
    // file another run is writing.
    fd_ = mkstemps(name.data(), 4);
    if (fd_ < 0)
    {
        const int error = errno;
        throw IoError(who_ + ": cannot create a file in " + folder_of(target) + " (for " +
                      target + "): " + std::strerror(error) +
                      "; check that the folder exists and is writable");
    }
    tmp_ = name.data();
    if (fchmod(fd_, 0666 & ~current_umask()) != 0)
        fail("cannot set the permissions of", errno);
}

TempFile::~TempFile()
{
    if (file_)
        std::fclose(file_);
    else if (fd_ >= 0)
        ::close(fd_);
    if (!committed_ && !tmp_.empty())
        ::unlink(tmp_.c_str());
}

FILE* TempFile::stream()
{
    if (!file_)
    {
        file_ = fdopen(fd_, "wb");
        if (!file_)
            fail("cannot open", errno);
    }
    return file_;
}

void TempFile::fail(const std::string& what, int error)
{
    throw IoError(who_ + ": " + what + " " + tmp_ + " (for " + target_ + "): " +
                  std::strerror(error) + "; nothing was written to " + target_);
}

void TempFile::commit(int write_error)
{
    if (file_)
    {
        // fflush() writes (again) what is buffered, so errno names the cause even when an
        // earlier fwrite() failed and only set the error flag.
        errno = 0;
        const bool flush_failed = std::fflush(file_) != 0;
        const int error = errno ? errno : write_error ? write_error : EIO;
        if (flush_failed || std::ferror(file_))
            fail("cannot write", error);
    }
    if (::fsync(fd_) != 0)
        fail("cannot write (fsync)", errno);
    // The name must still be the file created here (a writer by name could have replaced it).
    struct stat mine = {}, named = {};
    if (::fstat(fd_, &mine) != 0 || ::lstat(tmp_.c_str(), &named) != 0)
        fail("cannot find", errno);
    if (mine.st_dev != named.st_dev || mine.st_ino != named.st_ino)
        fail("found another file in place of", EEXIST);
    const int closed = file_ ? std::fclose(file_) : ::close(fd_);
    file_ = nullptr;
    fd_ = -1;
    if (closed != 0)
        fail("cannot write (close)", errno);
    if (std::rename(tmp_.c_str(), target_.c_str()) != 0)
    {
        const int error = errno;
        throw IoError(who_ + ": cannot rename " + tmp_ + " to " + target_ + ": " +
                      std::strerror(error));
    }
    committed_ = true;
    // Make the rename itself durable; a folder that cannot be synced (some file systems refuse
    // fsync on a directory) leaves the data written all the same.
    const int dir = ::open(folder_of(target_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0)
    {
        ::fsync(dir);
        ::close(dir);
    }
}

void write_atomically(const std::string& path, const std::string& who,
                      const std::function<void(FILE*)>& write)
{
    TempFile tmp(path, who);
    FILE* file = tmp.stream();
    errno = 0;
    write(file);
    tmp.commit(std::ferror(file) ? errno : 0);  // a large fwrite() bypasses the buffer
}

void write_atomically_by_name(const std::string& path, const std::string& who,
                              const std::function<void(const std::string& tmp)>& write)
{
    TempFile tmp(path, who);
    write(tmp.path());
    tmp.commit();
}

}  // namespace vessel::detail

namespace vessel {

void write_text_file(const std::string& path, const std::string& text)
{
    detail::write_atomically(path, "write_text_file", [&](FILE* file) {
        std::fwrite(text.data(), 1, text.size(), file);
    });
}

}  // namespace vessel
