#pragma once

// Every file one vessel-flatten run may write, checked before any work starts, and removed
// again if the run fails after writing some of them: a run either writes all its outputs or
// leaves the folder as it found it (docs/bad-input.md, "Outputs").

#include <cstdint>
#include <string>
#include <vector>

namespace vessel::cli {

//! What the command line asks vessel-flatten to write and read (empty strings: not asked).
struct OutputRequest
{
    std::string output;               //!< -o: .obj, .vtp or .ply
    std::string report;               //!< --report: .json
    std::string html;                 //!< --html: .html or .htm
    std::vector<std::string> images;  //!< --image: .png, .svg or .pdf
    std::string frames;               //!< --frames: a folder (created if missing)
    bool may_write_series = false;    //!< --fields with a .vtp output: OUT.case, OUT-map.case, OUT/
    int pieces = 0;                   //!< with --split-at: the number of pieces (0: no split)
    std::vector<std::string> inputs;  //!< files the run reads (the mesh, --fields files)
};

//! \brief The files (and folders) a run may write; on destruction during stack unwinding (the
//! run failed), removes every planned file and folder entry the run created or replaced.
class OutputPlan
{
public:
    //! \brief Plans and checks \p request: every output's folder exists and is writable, its
    //! extension is one the run writes, it is not an existing folder, not one of the inputs and
    //! not another output (after following links and `..`).
    //! \throw InvalidInputError naming the option, the path and what to change.
    explicit OutputPlan(const OutputRequest& request);
    ~OutputPlan();
    OutputPlan(const OutputPlan&) = delete;
    OutputPlan& operator=(const OutputPlan&) = delete;

    //! Every file the run may write, in the order of the request.
    const std::vector<std::string>& files() const { return files_; }

    //! Removes what the run wrote (called by the destructor when the run fails).
    void remove_written() const;

private:
    struct Before  // a planned path as it was before the run
    {
        std::string path;
        bool existed = false;
        std::uintmax_t inode = 0;
        std::int64_t mtime_ns = 0;
    };
    std::vector<std::string> files_;
    std::vector<std::string> folders_;  // folders whose new entries belong to the run
    std::vector<Before> before_;        // files_ and the entries of folders_, before the run
    int uncaught_ = 0;
};

}  // namespace vessel::cli
