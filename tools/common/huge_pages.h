#pragma once
// Transparent huge pages for a tool's own process: glibc's malloc reads its tunables once, at
// start-up, so a program that wants them set starts itself again with them.

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

extern char** environ;

namespace vessel::cli {

//! The value of \p parent's GLIBC_TUNABLES (an environment, null-terminated), or null.
inline const char* glibc_tunables(const char* const* parent)
{
    static const std::string name = "GLIBC_TUNABLES=";
    for (const char* const* e = parent; e && *e; ++e)
        if (std::strncmp(*e, name.c_str(), name.size()) == 0)
            return *e + name.size();
    return nullptr;
}

//! Whether \p parent's GLIBC_TUNABLES names `glibc.malloc.hugetlb` (set either way).
inline bool names_huge_pages(const char* const* parent)
{
    const char* tunables = glibc_tunables(parent);
    return tunables && std::strstr(tunables, "glibc.malloc.hugetlb");
}

//! Whether \p parent's GLIBC_TUNABLES asks glibc's malloc for transparent huge pages
//! (`glibc.malloc.hugetlb=1`, or `=2` for the kernel's preallocated ones).
inline bool asks_huge_pages(const char* const* parent)
{
    static const char setting[] = "glibc.malloc.hugetlb=";
    const char* tunables = glibc_tunables(parent);
    const char* at = tunables ? std::strstr(tunables, setting) : nullptr;
    return at && (at[sizeof setting - 1] == '1' || at[sizeof setting - 1] == '2');
}

//! \p parent (an environment, null-terminated) as strings, in its order.
inline std::vector<std::string> environment_strings(const char* const* parent)
{
    std::vector<std::string> out;
    for (const char* const* e = parent; e && *e; ++e)
        out.emplace_back(*e);
    return out;
}

//! \p strings as execve(2) and posix_spawn(3) take an environment: a pointer to each one's
//! characters, then a null (valid while \p strings lives unchanged).
inline std::vector<char*> environment_pointers(std::vector<std::string>& strings)
{
    std::vector<char*> out;
    out.reserve(strings.size() + 1);
    for (std::string& e : strings)
        out.push_back(e.data());
    out.push_back(nullptr);
    return out;
}

//! \brief \p parent (an environment, null-terminated) with glibc's malloc asked to use
//! transparent huge pages: `glibc.malloc.hugetlb=1` added to `GLIBC_TUNABLES`, or the variable
//! set to it, unless \p parent already names that tunable (a user's `glibc.malloc.hugetlb=0`
//! stays). A large mesh's run is partly bound by page faults, each new sparse factor and mesh
//! array faulted in page by page; unless the host discards freed memory
//! (host_discards_freed_pages()), huge pages make the same computation faster
//! (docs/benchmarks.md, "Machine and conditions"). Other C libraries and glibc before 2.35
//! ignore the tunable.
inline std::vector<std::string> huge_page_environment(const char* const* parent)
{
    std::vector<std::string> out = environment_strings(parent);
    if (names_huge_pages(parent))
        return out;
    const char* tunables = glibc_tunables(parent);
    if (!tunables)
        out.emplace_back("GLIBC_TUNABLES=glibc.malloc.hugetlb=1");
    else
        for (std::string& entry : out)
            if (entry.rfind("GLIBC_TUNABLES=", 0) == 0)
            {
                entry += std::string(*tunables ? ":" : "") + "glibc.malloc.hugetlb=1";
                break;
            }
    return out;
}

//! Inputs from this size (bytes) on are run with huge pages: below it a second start of the
//! program (loading its shared libraries again) costs about what the pages save
//! (docs/benchmarks.md, "Machine and conditions").
constexpr std::uintmax_t kHugePageInputBytes = 128 * 1024;

//! Whether the kernel gives transparent huge pages on request: its THP mode (`enabled`) is
//! not `[never]`.
inline bool kernel_gives_huge_pages()
{
    std::ifstream thp("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string modes;
    return std::getline(thp, modes) && modes.find("[never]") == std::string::npos;
}

//! Whether a virtio device of id \p device (sysfs `device`, e.g. "0x0005") with the feature
//! bits \p features (sysfs `features`: one '0' or '1' per bit, bit 0 first) is a memory balloon
//! that reports free pages to its host (VIRTIO_BALLOON_F_REPORTING, bit 5; virtio 1.2, 5.5.3).
inline bool balloon_reports_free_pages(const std::string& device, const std::string& features)
{
    constexpr std::size_t kReportingBit = 5;
    return device.rfind("0x0005", 0) == 0 && features.size() > kReportingBit &&
           features[kReportingBit] == '1';
}

//! \brief Whether this machine's host discards the memory the guest frees: a virtio balloon that
//! reports free pages (balloon_reports_free_pages()). The guest's kernel then reports each free
//! block of a huge page's size to the host, which drops it, and a fresh huge page is backed
//! again by the host at its first touch, while 4 kB pages are mostly taken from blocks not
//! given back: there fresh huge pages cost more to fault in than they save, where on a guest
//! that traps every 4 kB fault they save more (docs/benchmarks.md, "Machine and conditions").
inline bool host_discards_freed_pages()
{
    namespace fs = std::filesystem;
    std::error_code error;
    for (const auto& entry : fs::directory_iterator("/sys/bus/virtio/devices", error))
    {
        std::ifstream device_file(entry.path() / "device"),
            features_file(entry.path() / "features");
        std::string device, features;
        if (std::getline(device_file, device) && std::getline(features_file, features) &&
            balloon_reports_free_pages(device, features))
            return true;
    }
    return false;
}

}  // namespace vessel::cli
