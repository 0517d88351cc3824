#pragma once

#include <cholmod.h>

namespace vessel::detail {

//! A cholmod_common started on construction and finished on destruction. CHOLMOD keeps its
//! workspace and status there, so each thread (and each concurrent query of a shared factor)
//! uses its own.
struct CholmodCommon
{
    cholmod_common c;
    CholmodCommon() { cholmod_start(&c); }
    ~CholmodCommon() { cholmod_finish(&c); }
    CholmodCommon(const CholmodCommon&) = delete;
    CholmodCommon& operator=(const CholmodCommon&) = delete;
};

}  // namespace vessel::detail
