#pragma once
// MemoryBudget: admission of the batch's meshes to its workers by estimated peak memory.

#include <condition_variable>
#include <cstddef>
#include <mutex>

namespace vessel::cli {

//! \brief The peak memory (MB) flattening a mesh of \p faces triangles with the default options
//! is expected to need: 32 MB + 3 KB per triangle, a line at or above the peak resident sets
//! of the real trees and carotid phantoms from 7.5k to 301k triangles (docs/scale.md,
//! "Memory"); the trees, whose look retry runs a full-resolution reference map beside the
//! coarse-to-fine one, lie nearest to it.
inline double estimated_peak_mb(std::size_t faces)
{
    return 32.0 + 3.0 * static_cast<double>(faces) / 1024.0;
}

//! Admits meshes to the batch's workers by their estimated peak memory (MB): each takes its
//! estimate from a budget shared by the running meshes and gives it back when done. A mesh
//! waits while the others use too much for it to fit beside them; alone, it always runs if
//! its estimate is within the cap. Thread-safe.
class MemoryBudget
{
public:
    explicit MemoryBudget(double cap_mb) : cap_(cap_mb) {}
    double cap() const { return cap_; }

    //! Waits for room for \p need MB beside the running meshes; false (at once) if \p need is
    //! above the cap itself.
    bool acquire(double need)
    {
        if (need > cap_)
            return false;
        std::unique_lock<std::mutex> lock(mutex_);
        room_.wait(lock, [&] { return running_ == 0 || used_ + need <= cap_; });
        used_ += need;
        ++running_;
        return true;
    }

    //! Gives back what acquire() took for \p need.
    void release(double need)
    {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            used_ -= need;
            --running_;
        }
        room_.notify_all();
    }

private:
    double cap_;
    double used_ = 0.0;
    int running_ = 0;
    std::mutex mutex_;
    std::condition_variable room_;
};

}  // namespace vessel::cli
