#pragma once
// A tool's process started again in place with what a run wants of its environment: glibc's
// malloc and OpenBLAS read theirs once, when the process starts (huge_pages.h,
// blas_kernels.h).

#include "common/blas_kernels.h"
#include "common/huge_pages.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <string>
#include <vector>

namespace vessel::cli {

//! \brief \p parent (an environment, null-terminated) with what a run wants added: the BLAS
//! kernels (add_blas_kernels()) and, if \p huge_pages, the kernel gives them and the host does
//! not discard freed memory (host_discards_freed_pages()), transparent huge pages
//! (huge_page_environment()); \p parent's own setting of them stays.
inline std::vector<std::string> run_environment(const char* const* parent, bool huge_pages)
{
    std::vector<std::string> env =
        huge_pages && kernel_gives_huge_pages() && !host_discards_freed_pages()
            ? huge_page_environment(parent)
            : environment_strings(parent);
    add_blas_kernels(parent, env);
    return env;
}

//! \brief Starts this program again in place (execve(2) of /proc/self/exe: the same process,
//! arguments and open descriptors) with run_environment(), where that adds to the environment
//! and glibc is the C library. Returns where it adds nothing, or where the exec fails: the run
//! then goes on as it is. Call it before any output (the new start prints it again).
inline void restart_for_run(char** argv, bool huge_pages)
{
#if defined(__linux__) && defined(__GLIBC__)
    std::vector<std::string> env = run_environment(environ, huge_pages);
    if (env == environment_strings(environ))
        return;
    ::execve("/proc/self/exe", argv, environment_pointers(env).data());
#else
    (void)argv;
    (void)huge_pages;
#endif
}

//! restart_for_run() with huge pages where \p input is a file of at least kHugePageInputBytes.
inline void restart_for_run(char** argv, const std::string& input)
{
    struct stat st;
    restart_for_run(argv, !input.empty() && ::stat(input.c_str(), &st) == 0 &&
                              static_cast<std::uintmax_t>(st.st_size) >= kHugePageInputBytes);
}

}  // namespace vessel::cli
