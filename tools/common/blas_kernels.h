#pragma once
// The BLAS kernels a tool's process runs with. OpenBLAS picks its kernels for the CPU when it
// is loaded (on a virtual machine that hides the CPU model, its SSE3 Prescott kernels), and
// CHOLMOD's supernodal factorizations round differently under each set; a many-outlet tree's
// map can follow that rounding into another basin (docs/overlaps.md, "Rounding"). So where the
// CPU has AVX2 and FMA the tools ask for the Haswell kernels, which OpenBLAS's Zen target uses
// too and the test suite runs with: an input then gives the same map on every such machine.
// A user's own OPENBLAS_CORETYPE is left as it is.

#include <dlfcn.h>

#include <cstring>
#include <string>
#include <vector>

namespace vessel::cli {

//! The kernel set the tools ask OpenBLAS for where the CPU has AVX2 and FMA.
inline constexpr const char* kBlasKernels = "Haswell";

//! Whether \p kernels (an `openblas_get_corename()`) round as kBlasKernels do: Haswell's own,
//! or the Zen target, which is built from them.
inline bool rounds_as_asked(const std::string& kernels)
{
    return kernels == kBlasKernels || kernels == "Zen";
}

//! The kernel set OpenBLAS runs in this process (`openblas_get_corename()`, looked up when
//! called), or "" where the BLAS loaded is not OpenBLAS.
inline std::string running_blas_kernels()
{
    using CoreName = char* (*)();
    const auto core_name =
        reinterpret_cast<CoreName>(::dlsym(RTLD_DEFAULT, "openblas_get_corename"));
    const char* name = core_name ? core_name() : nullptr;
    return name ? std::string(name) : std::string();
}

//! Whether this CPU has AVX2 and FMA, which kBlasKernels need.
inline bool cpu_has_avx2_fma()
{
#if defined(__x86_64__) || defined(__i386__)
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
    return false;
#endif
}

//! Whether \p parent (an environment, null-terminated) sets OPENBLAS_CORETYPE.
inline bool names_blas_kernels(const char* const* parent)
{
    static const char name[] = "OPENBLAS_CORETYPE=";
    for (const char* const* e = parent; e && *e; ++e)
        if (std::strncmp(*e, name, sizeof name - 1) == 0)
            return true;
    return false;
}

//! \brief Whether a process started from \p parent should be given
//! `OPENBLAS_CORETYPE=` kBlasKernels: \p parent does not name the kernels, the CPU has AVX2 and
//! FMA (\p avx2_fma) and OpenBLAS runs kernels that round otherwise (\p running, as
//! running_blas_kernels(); "" = not OpenBLAS, nothing to ask).
inline bool wants_blas_kernels(const char* const* parent, const std::string& running, bool avx2_fma)
{
    return !names_blas_kernels(parent) && avx2_fma && !running.empty() && !rounds_as_asked(running);
}

//! \p env with `OPENBLAS_CORETYPE=` kBlasKernels added where wants_blas_kernels() says so for
//! this process and CPU (\p parent: the environment \p env was made from).
inline void add_blas_kernels(const char* const* parent, std::vector<std::string>& env)
{
    if (wants_blas_kernels(parent, running_blas_kernels(), cpu_has_avx2_fma()))
        env.push_back(std::string("OPENBLAS_CORETYPE=") + kBlasKernels);
}

}  // namespace vessel::cli
