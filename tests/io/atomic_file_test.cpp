// The atomic writer (detail/atomic_file.h) every libvessel output goes through.
#include <doctest/doctest.h>

#include "detail/atomic_file.h"
#include "support/checks.h"
#include "support/files.h"
#include "vessel/core/errors.h"
#include "vessel/io/io.h"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <stdexcept>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

using namespace vessel;
using vessel::test::folder_names;
using vessel::test::read_bytes;
using vessel::test::temp_dir;
using vessel::test::write_bytes;

namespace fs = std::filesystem;

TEST_CASE("atomic file: a planted PATH.tmp link is never followed")
{
    const std::string dir = temp_dir("atomic_link");
    std::ofstream(dir + "/victim") << "victim\n";
    fs::create_symlink(dir + "/victim", dir + "/out.txt.tmp");
    write_text_file(dir + "/out.txt", "new\n");
    CHECK(read_bytes(dir + "/victim") == "victim\n");
    CHECK(fs::is_regular_file(fs::symlink_status(dir + "/out.txt")));
    CHECK(read_bytes(dir + "/out.txt") == "new\n");
    CHECK(folder_names(dir) == std::set<std::string>{"victim", "out.txt", "out.txt.tmp"});
}

TEST_CASE("atomic file: two writers of one target get their own temporary files in its folder")
{
    const std::string dir = temp_dir("atomic_unique");
    detail::TempFile a(dir + "/out.txt", "test"), b(dir + "/out.txt", "test");
    CHECK(a.path() != b.path());
    for (const auto* t : {&a, &b})
    {
        CHECK(fs::path(t->path()).parent_path() == fs::path(dir));
        CHECK(fs::path(t->path()).filename().string().rfind("out.txt.", 0) == 0);
        CHECK(fs::path(t->path()).extension() == ".tmp");
    }
    std::fputs("a\n", a.stream());
    a.commit();
    std::fputs("b\n", b.stream());
    b.commit();
    CHECK(read_bytes(dir + "/out.txt") == "b\n");
    CHECK(folder_names(dir) == std::set<std::string>{"out.txt"});
}

TEST_CASE("atomic file: a failed write keeps the target and leaves no temporary file")
{
    const std::string dir = temp_dir("atomic_fail");
    std::ofstream(dir + "/out.txt") << "before\n";
    CHECK_THROWS_AS(detail::write_atomically(dir + "/out.txt", "test",
                                             [](FILE* f) {
                                                 std::fputs("partial", f);
                                                 throw std::runtime_error("writer failed");
                                             }),
                    std::runtime_error);
    CHECK(read_bytes(dir + "/out.txt") == "before\n");
    CHECK(folder_names(dir) == std::set<std::string>{"out.txt"});
    // A writer by name that replaced the file it was given is caught.
    CHECK_THROWS_AS(detail::write_atomically_by_name(dir + "/out.txt", "test",
                                                     [](const std::string& tmp) {
                                                         fs::remove(tmp);
                                                         std::ofstream(tmp) << "other\n";
                                                     }),
                    IoError);
    CHECK(read_bytes(dir + "/out.txt") == "before\n");
    CHECK(folder_names(dir) == std::set<std::string>{"out.txt"});
    // A missing folder is named.
    try
    {
        write_text_file(dir + "/missing/out.txt", "x");
        FAIL("no error");
    }
    catch (const IoError& e)
    {
        CHECK(std::string(e.what()).find("cannot create a file in " + dir + "/missing") !=
              std::string::npos);
    }
}

TEST_CASE("atomic file: a write past the file size limit fails with an error, not a signal")
{
    const std::string dir = temp_dir("atomic_fsize");
    std::ofstream(dir + "/out.txt") << "before\n";
    // In a child process, so the limit does not reach the test runner: exit 0 if the write
    // failed with an IoError saying why, 2 if it succeeded, 3 on another error.
    const pid_t child = fork();
    REQUIRE(child >= 0);
    if (child == 0)
    {
        const rlimit limit{4096, 4096};
        setrlimit(RLIMIT_FSIZE, &limit);
        int code = 2;
        try
        {
            write_text_file(dir + "/out.txt", std::string(100000, 'x'));
        }
        catch (const IoError& e)
        {
            code = std::string(e.what()).find("File too large") != std::string::npos ? 0 : 3;

        }
        catch (...)
        {
            code = 3;
        }
        _exit(code);
    }
    int status = 0;
    REQUIRE(waitpid(child, &status, 0) == child);
    CHECK_MESSAGE(WIFEXITED(status), "killed by signal " << WTERMSIG(status));
    CHECK(WEXITSTATUS(status) == 0);
    CHECK(read_bytes(dir + "/out.txt") == "before\n");
    CHECK(folder_names(dir) == std::set<std::string>{"out.txt"});
}
