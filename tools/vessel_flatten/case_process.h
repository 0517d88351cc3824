#pragma once
// One mesh of a batch in a process of its own, and the watchdog that holds the running
// processes to the batch's memory cap.
//
// A process per mesh is what makes the cap enforceable: the resident memory of a process is
// known (/proc/PID/statm), that of one thread of a process is not, and a process can be stopped
// without harm to the others. An address-space limit (setrlimit RLIMIT_AS) is no substitute: a
// process that reaches it may hang instead of failing (OpenBLAS retries a failed buffer
// allocation forever, docs/bad-input.md). It also keeps a mesh that crashes its process from
// taking the batch with it.

#include <sys/types.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace vessel::cli {

//! A child process started from \p exe with \p args (args[0] is its name), in a process group of
//! its own (a terminal's interrupt reaches the batch, which decides), with a pipe to its standard
//! input and one from its file descriptor 3 (its messages to the batch; its standard output and
//! error are the batch's). Not copyable; the destructor kills and reaps a child still running.
class ChildProcess
{
public:
    //! \throws std::system_error if the pipes or the process cannot be made.
    ChildProcess(const std::string& exe, const std::vector<std::string>& args);
    ~ChildProcess();
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

    pid_t pid() const { return pid_; }
    //! The next line the child wrote to its descriptor 3 (without the newline); false at its end.
    bool read_line(std::string& line);
    //! Writes \p line and a newline to the child's standard input; false if it has closed it.
    bool write_line(const std::string& line);
    void kill();

    struct Exit
    {
        int code = -1;       //!< the exit code, or -1 if a signal ended it
        int signal = 0;      //!< the signal that ended it, or 0
        double peak_mb = 0;  //!< its peak resident memory (getrusage's ru_maxrss)
    };
    //! Waits for the child to end (once).
    Exit wait();

private:
    pid_t pid_ = -1;
    int to_child_ = -1;
    std::FILE* from_child_ = nullptr;
    bool reaped_ = false;
};

//! Resident memory of a process (MB, /proc/PID/statm).
struct Resident
{
    double total_mb = 0;  //!< all its resident pages (what getrusage's peak counts)
    double own_mb = 0;    //!< those not shared with other processes (not file-backed)
};
//! The resident memory of process \p pid; zeros if it has ended.
Resident resident_mb(pid_t pid);

//! One watched process at a look of the MemoryWatchdog.
struct WatchedMemory
{
    Resident resident;
    double estimate_mb = 0;  //!< what it was admitted with
    bool admitted = false;   //!< false while it waits for room in the budget, its mesh read
};

//! The process to stop when \p processes together use more than \p cap_mb (each one's own
//! pages, plus the shared pages of the program and its libraries once), or -1 while they fit:
//! the admitted process furthest above its estimate, the mesh that needs more than it said. A
//! process waiting for admission holds only its mesh and will run within the budget, so it is
//! stopped only when no admitted process runs (its mesh alone is above the cap).
int process_to_stop(const std::vector<WatchedMemory>& processes, double cap_mb);

//! Watches the resident memory of the batch's processes every \p period and, whenever they use
//! more than the cap together, kills the one process_to_stop() names: the others go on.
//! Thread-safe.
class MemoryWatchdog
{
public:
    MemoryWatchdog(double cap_mb, std::chrono::milliseconds period);
    ~MemoryWatchdog();
    MemoryWatchdog(const MemoryWatchdog&) = delete;
    MemoryWatchdog& operator=(const MemoryWatchdog&) = delete;

    void watch(pid_t pid);
    //! The estimate (MB) \p pid was admitted with.
    void admit(pid_t pid, double estimate_mb);

    struct Verdict
    {
        bool killed = false;
        double resident_mb = 0;  //!< at the kill
        int beside = 0;          //!< other processes watched at the kill
    };
    //! Stops watching \p pid (call it before reaping \p pid, so that its number cannot be reused
    //! by another process while it is watched) and says whether the watchdog killed it.
    Verdict forget(pid_t pid);

private:
    void run();

    struct Watched
    {
        double estimate_mb = 0;
        bool admitted = false;
        Verdict verdict;
    };
    double cap_mb_;
    std::chrono::milliseconds period_;
    std::mutex mutex_;
    std::condition_variable stop_;
    bool stopping_ = false;
    std::map<pid_t, Watched> watched_;
    std::thread thread_;
};

}  // namespace vessel::cli
