#include "case_process.h"

#include "common/restart.h"

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <system_error>
#include <unistd.h>

extern char** environ;

namespace vessel::cli {

namespace {

[[noreturn]] void throw_errno(const char* what, int error)
{
    throw std::system_error(error, std::generic_category(), what);
}

void close_fd(int& fd)
{
    if (fd >= 0)
        ::close(fd);
    fd = -1;
}

}  // namespace

ChildProcess::ChildProcess(const std::string& exe, const std::vector<std::string>& args)
{
    // Close-on-exec, so that a child started by another worker at the same time holds no end
    // of these pipes (its copy would keep this child's pipe from ever reaching its end).
    int in[2], out[2];
    if (::pipe2(in, O_CLOEXEC) != 0)
        throw_errno("cannot make a pipe to the mesh's process", errno);
    if (::pipe2(out, O_CLOEXEC) != 0)
    {
        const int error = errno;
        ::close(in[0]);
        ::close(in[1]);
        throw_errno("cannot make a pipe from the mesh's process", error);
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, in[0], 0);   // dup2 clears close-on-exec
    posix_spawn_file_actions_adddup2(&actions, out[1], 3);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    sigset_t none, defaults;
    sigemptyset(&none);
    sigemptyset(&defaults);
    for (int s : {SIGPIPE, SIGINT, SIGTERM})  // the batch ignores SIGPIPE; the child must not
        sigaddset(&defaults, s);
    posix_spawnattr_setsigmask(&attr, &none);
    posix_spawnattr_setsigdefault(&attr, &defaults);
    posix_spawnattr_setpgroup(&attr, 0);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF |
                                        POSIX_SPAWN_SETPGROUP);
    std::vector<char*> argv;
    for (const auto& a : args)
        argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    std::vector<std::string> environment = run_environment(environ, true);
    const std::vector<char*> envp = environment_pointers(environment);
    const int error = ::posix_spawn(&pid_, exe.c_str(), &actions, &attr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attr);
    ::close(in[0]);
    ::close(out[1]);
    if (error != 0)
    {
        ::close(in[1]);
        ::close(out[0]);
        pid_ = -1;
        throw_errno(("cannot start " + exe).c_str(), error);
    }
    to_child_ = in[1];
    from_child_ = ::fdopen(out[0], "r");
    if (!from_child_)
    {
        ::close(out[0]);
        kill();
        wait();
        close_fd(to_child_);
        throw_errno("cannot read from the mesh's process", errno);
    }
}

ChildProcess::~ChildProcess()
{
    if (pid_ > 0 && !reaped_)
    {
        kill();
        wait();
    }
    close_fd(to_child_);
    if (from_child_)
        std::fclose(from_child_);
}

bool ChildProcess::read_line(std::string& line)
{
    line.clear();
    for (;;)
    {
        const int c = std::fgetc(from_child_);
        if (c == EOF)
        {
            if (std::ferror(from_child_) && errno == EINTR)  // a signal to the batch
            {
                std::clearerr(from_child_);
                continue;
            }
            return !line.empty();
        }
        if (c == '\n')
            return true;
        line.push_back(static_cast<char>(c));
    }
}

bool ChildProcess::write_line(const std::string& line)
{
    const std::string text = line + "\n";
    std::size_t done = 0;
    while (done < text.size())
    {
        const ssize_t n = ::write(to_child_, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return false;  // EPIPE: the child has ended
        done += static_cast<std::size_t>(n);
    }
    return true;
}

void ChildProcess::kill()
{
    if (pid_ > 0 && !reaped_)
        ::kill(pid_, SIGKILL);
}

ChildProcess::Exit ChildProcess::wait()
{
    Exit exit;
    if (pid_ <= 0 || reaped_)
        return exit;
    int status = 0;
    rusage usage{};
    pid_t got;
    do
        got = ::wait4(pid_, &status, 0, &usage);
    while (got < 0 && errno == EINTR);
    reaped_ = true;
    if (got != pid_)
        return exit;
    if (WIFEXITED(status))
        exit.code = WEXITSTATUS(status);
    else if (WIFSIGNALED(status))
        exit.signal = WTERMSIG(status);
    exit.peak_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: kilobytes
    return exit;
}

Resident resident_mb(pid_t pid)
{
    char path[64];
    std::snprintf(path, sizeof path, "/proc/%d/statm", static_cast<int>(pid));
    std::FILE* f = std::fopen(path, "r");
    if (!f)
        return {};
    long size = 0, resident = 0, shared = 0;
    const int n = std::fscanf(f, "%ld %ld %ld", &size, &resident, &shared);
    std::fclose(f);
    if (n != 3)
        return {};
    static const double page_mb = static_cast<double>(::sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
    return {static_cast<double>(resident) * page_mb,
            static_cast<double>(std::max(resident - shared, 0L)) * page_mb};
}

MemoryWatchdog::MemoryWatchdog(double cap_mb, std::chrono::milliseconds period)
    : cap_mb_(cap_mb), period_(period), thread_([this] { run(); })
{
}

MemoryWatchdog::~MemoryWatchdog()
{
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    stop_.notify_all();
    thread_.join();
}

void MemoryWatchdog::watch(pid_t pid)
{
    std::lock_guard<std::mutex> lock(mutex_);
    watched_[pid] = {};
}

void MemoryWatchdog::admit(pid_t pid, double estimate_mb)
{
    std::lock_guard<std::mutex> lock(mutex_);
    Watched& w = watched_[pid];
    w.estimate_mb = estimate_mb;
    w.admitted = true;
}

MemoryWatchdog::Verdict MemoryWatchdog::forget(pid_t pid)
{
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = watched_.find(pid);
    if (it == watched_.end())
        return {};
    const Verdict verdict = it->second.verdict;
    watched_.erase(it);
    return verdict;
}

void MemoryWatchdog::run()
{
    std::unique_lock<std::mutex> lock(mutex_);
    std::vector<pid_t> pids;
    std::vector<WatchedMemory> looks;
    while (!stop_.wait_for(lock, period_, [this] { return stopping_; }))
    {
        pids.clear();
        looks.clear();
        for (const auto& [pid, w] : watched_)
        {
            if (w.verdict.killed)
                continue;
            pids.push_back(pid);
            looks.push_back({resident_mb(pid), w.estimate_mb, w.admitted});
        }
        const int stop = process_to_stop(looks, cap_mb_);
        if (stop < 0)
            continue;
        ::kill(pids[stop], SIGKILL);
        watched_[pids[stop]].verdict = {true, looks[stop].resident.total_mb,
                                        static_cast<int>(looks.size()) - 1};
    }
}

int process_to_stop(const std::vector<WatchedMemory>& processes, double cap_mb)
{
    // The processes' own pages, and the pages they share (the program and its libraries, the
    // same file pages in every process) once.
    double own = 0.0, shared = 0.0;
    for (const WatchedMemory& p : processes)
    {
        own += p.resident.own_mb;
        shared = std::max(shared, p.resident.total_mb - p.resident.own_mb);
    }
    if (own + shared <= cap_mb)
        return -1;
    const bool any_admitted = std::any_of(processes.begin(), processes.end(),
                                          [](const WatchedMemory& p) { return p.admitted; });
    int worst = -1;
    double worst_excess = 0.0;
    for (int i = 0; i < static_cast<int>(processes.size()); ++i)
    {
        const WatchedMemory& p = processes[i];
        if (p.admitted != any_admitted)
            continue;
        const double excess = p.resident.total_mb - p.estimate_mb;
        if (worst < 0 || excess > worst_excess)
        {
            worst = i;
            worst_excess = excess;
        }
    }
    return worst;
}

}  // namespace vessel::cli
