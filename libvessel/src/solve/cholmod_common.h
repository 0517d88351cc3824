#pragma once

#include <cholmod.h>

#include <vector>

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

//! The symbolic analysis of \p A: in the elimination order \p order when given (each unknown
//! once; CHOLMOD_GIVEN is the only method of \p c for this call, its methods are restored
//! after), else by \p c's ordering methods. Null if CHOLMOD fails (see c.status).
inline cholmod_factor* analyze_in_order(cholmod_sparse& A, std::vector<int>* order,
                                        cholmod_common& c)
{
    if (!order)
        return cholmod_analyze(&A, &c);
    const int nmethods = c.nmethods, first = c.method[0].ordering;
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_GIVEN;
    cholmod_factor* L = cholmod_analyze_p(&A, order->data(), nullptr, 0, &c);
    c.nmethods = nmethods;
    c.method[0].ordering = first;
    return L;
}

//! A CHOLMOD view (no copy) of the symmetric pattern whose upper triangle is given column by
//! column: column j's rows (each <= j, any order) are rows[column_start[j] ..
//! column_start[j + 1]). For orderings (cholmod_amd, cholmod_metis) of a vertex graph.
inline cholmod_sparse upper_pattern(std::vector<int>& column_start, std::vector<int>& rows)
{
    cholmod_sparse pattern{};
    pattern.nrow = pattern.ncol = column_start.size() - 1;
    pattern.nzmax = rows.size();
    pattern.p = column_start.data();
    pattern.i = rows.data();
    pattern.stype = 1;  // upper triangle
    pattern.itype = CHOLMOD_INT;
    pattern.xtype = CHOLMOD_PATTERN;
    pattern.dtype = CHOLMOD_DOUBLE;
    pattern.sorted = 0;
    pattern.packed = 1;
    return pattern;
}

}  // namespace vessel::detail
