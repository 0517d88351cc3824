#pragma once
// Transparent huge pages for a tool's own process: glibc's malloc reads its tunables once, at
// start-up, so a program that wants them set starts itself again with them.

#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

extern char** environ;

namespace vessel::cli {

//! \brief \p parent (an environment, null-terminated) with glibc's malloc asked to use
//! transparent huge pages: `glibc.malloc.hugetlb=1` added to `GLIBC_TUNABLES`, or the variable
//! set to it, unless \p parent already sets that tunable (a user's `glibc.malloc.hugetlb=0`
//! stays). A large mesh's run is partly bound by page faults, each new sparse factor and mesh
//! array faulted in by 4 kB pages; huge pages make the same computation faster
//! (docs/benchmarks.md, "Machine and conditions"). Other C libraries and glibc before 2.35
//! ignore the tunable.
inline std::vector<std::string> huge_page_environment(const char* const* parent)
{
    static const std::string tunables = "GLIBC_TUNABLES=", huge = "glibc.malloc.hugetlb";
    std::vector<std::string> out;
    bool set = false;
    for (const char* const* e = parent; e && *e; ++e)
    {
        std::string entry = *e;
        if (entry.rfind(tunables, 0) == 0)
        {
            if (entry.find(huge) == std::string::npos)
                entry += (entry.size() > tunables.size() ? ":" : "") + huge + "=1";
            set = true;
        }
        out.push_back(std::move(entry));
    }
    if (!set)
        out.push_back(tunables + huge + "=1");
    return out;
}

//! Whether \p parent's GLIBC_TUNABLES names `glibc.malloc.hugetlb` (set either way).
inline bool names_huge_pages(const char* const* parent)
{
    for (const char* const* e = parent; e && *e; ++e)
    {
        const std::string entry = *e;
        if (entry.rfind("GLIBC_TUNABLES=", 0) == 0 &&
            entry.find("glibc.malloc.hugetlb") != std::string::npos)
            return true;
    }
    return false;
}

//! Whether \p parent's GLIBC_TUNABLES asks glibc's malloc for transparent huge pages
//! (`glibc.malloc.hugetlb=1`, or `=2` for the kernel's preallocated ones).
inline bool asks_huge_pages(const char* const* parent)
{
    for (const char* const* e = parent; e && *e; ++e)
    {
        const std::string entry = *e;
        if (entry.rfind("GLIBC_TUNABLES=", 0) != 0)
            continue;
        const std::size_t at = entry.find("glibc.malloc.hugetlb=");
        if (at == std::string::npos)
            return false;
        const char value = entry[at + std::string("glibc.malloc.hugetlb=").size()];
        return value == '1' || value == '2';
    }
    return false;
}

//! Inputs from this size (bytes) on are run with huge pages: below it a second start of the
//! program (loading its shared libraries again) costs about what the pages save
//! (docs/benchmarks.md, "Machine and conditions").
constexpr std::uintmax_t kHugePageInputBytes = 128 * 1024;

//! \brief Starts this program again in place (execve(2) of /proc/self/exe: the same process,
//! arguments and open descriptors) with huge_page_environment(), where the environment does not
//! name the tunable yet, glibc is the C library and the kernel gives transparent huge pages on
//! request (`enabled` not `[never]`). Returns where it does not, or where the exec fails: the
//! run then goes on as it is. Call it before any output (the new start prints it again).
inline void restart_with_huge_pages(char** argv)
{
#if defined(__linux__) && defined(__GLIBC__)
    if (names_huge_pages(environ))
        return;
    std::ifstream thp("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string modes;
    if (!std::getline(thp, modes) || modes.find("[never]") != std::string::npos)
        return;
    std::vector<std::string> env = huge_page_environment(environ);
    std::vector<char*> envp;
    for (std::string& e : env)
        envp.push_back(e.data());
    envp.push_back(nullptr);
    ::execve("/proc/self/exe", argv, envp.data());
#else
    (void)argv;
#endif
}

//! restart_with_huge_pages() where \p input is a file of at least kHugePageInputBytes.
inline void restart_with_huge_pages(char** argv, const std::string& input)
{
    struct stat st;
    if (!input.empty() && ::stat(input.c_str(), &st) == 0 &&
        static_cast<std::uintmax_t>(st.st_size) >= kHugePageInputBytes)
        restart_with_huge_pages(argv);
}

}  // namespace vessel::cli
