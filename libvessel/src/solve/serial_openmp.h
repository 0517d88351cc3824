#pragma once

#include <dlfcn.h>

namespace vessel::detail {

//! While alive, lets the OpenMP runtime run fewer threads than asked for on this thread's
//! parallel regions (the per-thread dyn-var ICV, restored on destruction). Debian's CHOLMOD
//! opens a 4-thread OpenMP region per large supernode to scatter updates while the flops run in
//! serial BLAS; on two busy cores those threads mostly wait on each other (the SLIM
//! factorization of a 72k-unknown system took 1.5x longer wall time than serially). OpenMP is
//! looked up at run time: libvessel does not link it, CHOLMOD does. Wrap CHOLMOD factorizations
//! in it.
//! If the BLAS is OpenBLAS's pthread flavour (e.g. Debian's libopenblas0-pthread as the
//! libblas.so.3 alternative), its thread count is set to 1 as well and left there: it is
//! process-wide, so restoring it would race between concurrent factorizations (`--batch
//! --jobs 2` already runs one pipeline per core), and its default of one thread per core made
//! the carotid-44k run 3-4x slower in wall time on the loaded 2-core machine (docs/benchmarks.md).
class SerialOpenMp
{
public:
    SerialOpenMp()
    {
        if (const auto set_blas_threads =
                reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads")))
            set_blas_threads(1);
        set_ = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "omp_set_dynamic"));
        const auto get = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "omp_get_dynamic"));
        if (!set_ || !get)
        {
            set_ = nullptr;
            return;
        }
        previous_ = get();
        set_(1);
    }
    ~SerialOpenMp()
    {
        if (set_)
            set_(previous_);
    }
    SerialOpenMp(const SerialOpenMp&) = delete;
    SerialOpenMp& operator=(const SerialOpenMp&) = delete;

private:
    void (*set_)(int) = nullptr;
    int previous_ = 0;
};

}  // namespace vessel::detail
