#pragma once
// TEMPORARY profiling aid (branch pspeed): prints wall seconds per sub-step to stderr when
// VESSEL_SUBTIMES is set. Not to be committed.
#include <chrono>
#include <cstdio>
#include <cstdlib>
namespace vessel::detail {
class SubTimer
{
public:
    SubTimer() : on_(std::getenv("VESSEL_SUBTIMES") != nullptr) {}
    void lap(const char* what)
    {
        const auto now = std::chrono::steady_clock::now();
        if (on_)
            std::fprintf(stderr, "  [sub] %-28s %.4f\n", what,
                         std::chrono::duration<double>(now - last_).count());
        last_ = now;
    }
private:
    bool on_;
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};
}  // namespace vessel::detail
