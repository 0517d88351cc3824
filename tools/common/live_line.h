#pragma once
// One status line on a terminal, redrawn in place while a long step runs, so that no step is
// silent: what runs and for how long, redrawn a few times a second whether or not the step
// reports its own progress (stage Z and the reading of a large mesh report none).

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>

#include <unistd.h>

namespace vessel::cli {

class LiveLine
{
public:
    //! \p live: draw on stderr (a terminal, not --quiet); otherwise every call but print() does
    //! nothing, and print() writes its line as is.
    explicit LiveLine(bool live) : live_(live)
    {
        if (live_)
            ticker_ = std::thread([this] { tick(); });
    }

    ~LiveLine()
    {
        if (!live_)
            return;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
            erase();
        }
        wake_.notify_one();
        ticker_.join();
    }

    //! The status line of a tool's run: drawn when not \p quiet and stderr is a terminal (off a
    //! terminal, e.g. in a log, the output stays line by line).
    static LiveLine on_terminal(bool quiet) { return LiveLine(!quiet && isatty(fileno(stderr))); }

    LiveLine(const LiveLine&) = delete;
    LiveLine& operator=(const LiveLine&) = delete;

    //! Whether it draws (else show(), detail() and hide() do nothing).
    bool live() const { return live_; }

    using Clock = std::chrono::steady_clock;

    //! From now on the line reads \p label, then the seconds since \p since (by default this
    //! call).
    void show(const std::string& label, Clock::time_point since = Clock::now())
    {
        if (!live_)
            return;
        std::lock_guard<std::mutex> lock(mutex_);
        label_ = label;
        detail_.clear();
        since_ = since;
        shown_ = true;
        draw();
    }

    //! \p detail after the label (e.g. a solver's phase and iteration), the clock running on.
    void detail(const std::string& detail)
    {
        if (!live_)
            return;
        std::lock_guard<std::mutex> lock(mutex_);
        detail_ = detail;
        if (shown_)
            draw();
    }

    //! Erases the line until the next show().
    void hide()
    {
        if (!live_)
            return;
        std::lock_guard<std::mutex> lock(mutex_);
        erase();
        shown_ = false;
    }

    //! A line that stays (\p line, with no newline), printed where the status line was; the
    //! status line is hidden until the next show() (a finished step's line replaces it).
    void print(const std::string& line)
    {
        std::lock_guard<std::mutex> lock(mutex_);
        erase();
        std::fprintf(stderr, "%s\n", line.c_str());
        std::fflush(stderr);
        shown_ = false;
    }

private:
    // Often enough that the seconds shown (one decimal) visibly run.
    static constexpr std::chrono::milliseconds kInterval{200};

    void tick()
    {
        std::unique_lock<std::mutex> lock(mutex_);
        while (!wake_.wait_for(lock, kInterval, [this] { return stop_; }))
            if (shown_)
                draw();
    }
    // Callers hold mutex_.
    void draw() const
    {
        const double seconds = std::chrono::duration<double>(Clock::now() - since_).count();
        std::fprintf(stderr, "\r\033[K%s%s%s %.1f s", label_.c_str(), detail_.empty() ? "" : ": ",
                     detail_.c_str(), seconds);
        std::fflush(stderr);
    }
    void erase() const
    {
        if (live_)
            std::fputs("\r\033[K", stderr);
    }

    const bool live_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stop_ = false;
    bool shown_ = false;
    std::string label_, detail_;
    Clock::time_point since_;
    std::thread ticker_;
};

}  // namespace vessel::cli
