// vessel-flatten's outputs: written atomically and checked to the end (a planted link is never
// followed, a full disk or file size limit fails the run and keeps the previous output), every
// output path checked before any work, and a late failure leaves no output
// (docs/bad-input.md, "Outputs").
#include <doctest/doctest.h>

#include "support/checks.h"
#include "support/files.h"
#include "support/meshes.h"
#include "vessel/io/io.h"
#include "vessel/phantom/phantom.h"

#include <filesystem>
#include <unistd.h>
#include <fstream>
#include <iterator>
#include <set>
#include <string>

using vessel::test::folder_names;
using vessel::test::read_bytes;
using vessel::test::run;
using vessel::test::temp_dir;
using vessel::test::write_bytes;

namespace fs = std::filesystem;

namespace {

const std::string kFlatten = VESSEL_FLATTEN_EXE;
const std::string kPhantom = VESSEL_PHANTOM_EXE;

// A tube whose flattened OBJ is tens of kilobytes.
std::string write_tube(const std::string& dir)
{
    const std::string path = dir + "/tube.ply";
    vessel::write_mesh(vessel::open_cylinder(1.0, 4.0, 32, 16), path);
    return path;
}

struct Outcome
{
    int status = 0;
    std::string err;
};

// Runs vessel-flatten ARGS (after \p prefix, e.g. a ulimit) in sh, stderr captured in
// \p root (outside the folders whose listings the tests check).
Outcome flatten(const std::string& root, const std::string& args, const std::string& prefix = "")
{
    Outcome o;
    const std::string err = root + "/stderr.txt";
    o.status = run("sh -c '" + prefix + "exec " + kFlatten + " " + args + "' 2> " + err);
    o.err = read_bytes(err);
    return o;
}

}  // namespace

TEST_CASE("outputs: a planted out.obj.tmp link is never followed and its target stays untouched")
{
    const std::string root = temp_dir("outputs_link");
    const std::string dir = root + "/run";
    fs::create_directories(dir);
    const std::string tube = write_tube(root);
    write_bytes(root + "/victim", "victim\n");
    for (const std::string ext : {".obj", ".vtp", ".ply"})
    {
        CAPTURE(ext);
        const std::string out = dir + "/out" + ext;
        fs::create_symlink(root + "/victim", out + ".tmp");
        const Outcome o = flatten(root, tube + " -o " + out + " --report " + dir + "/r.json -q");
        CHECK_MESSAGE(o.status == 0, o.err);
        CHECK(read_bytes(root + "/victim") == "victim\n");
        CHECK(fs::is_symlink(out + ".tmp"));
        CHECK(fs::is_regular_file(fs::symlink_status(out)));
        CHECK(fs::file_size(out) > 1000);
    }
}

TEST_CASE("outputs: past the file size limit the run fails with exit 1 and the previous output "
          "stays intact")
{
    const std::string root = temp_dir("outputs_fsize");
    const std::string dir = root + "/run";
    fs::create_directories(dir);
    const std::string tube = write_tube(root);
    // The limit (ulimit -f counts 512-byte blocks in sh) is far below each output's size, and
    // stderr goes to a file outside the limit's reach only as long as it stays short: -q.
    for (const std::string ext : {".obj", ".vtp", ".ply"})
    {
        CAPTURE(ext);
        const std::string out = dir + "/out" + ext;
        REQUIRE(flatten(root, tube + " -o " + root + "/full" + ext + " -q").status == 0);
        REQUIRE(fs::file_size(root + "/full" + ext) > 16 * 512);
        write_bytes(out, "the previous output\n");
        const Outcome o = flatten(root, tube + " -o " + out + " -q", "ulimit -f 4; ");
        CHECK(o.status == 1);
        CHECK_MESSAGE(o.err.find("vessel-flatten: ") == 0, o.err);
        if (ext != ".vtp")  // VTK words the failure its own way
            CHECK_MESSAGE(o.err.find("File too large") != std::string::npos, o.err);
        CHECK(read_bytes(out) == "the previous output\n");
        // Nothing else left behind: no temporary file, no map part.
        CHECK(folder_names(dir) == std::set<std::string>{"out" + ext});
        fs::remove(out);
    }
}

TEST_CASE("outputs: an output that is the input, or another output, is refused before any work")
{
    const std::string root = temp_dir("outputs_clash");
    const std::string dir = root + "/run";
    fs::create_directories(dir);
    const std::string tube = write_tube(dir);
    fs::create_symlink(tube, dir + "/link.ply");
    const std::string before = read_bytes(tube);
    const Outcome same = flatten(root, tube + " -o " + tube);
    CHECK(same.status == 1);
    CHECK_MESSAGE(same.err.find("-o " + tube + " is the input " + tube) != std::string::npos,
                  same.err);
    // The same file by another name: a link, or a path through '..'.
    CHECK(flatten(root, dir + "/link.ply -o " + tube).status == 1);
    CHECK(flatten(root, tube + " -o " + dir + "/../run/tube.ply").status == 1);
    CHECK(read_bytes(tube) == before);

    const Outcome report = flatten(root, tube + " --report " + dir + "/x.obj -o " + dir + "/x.obj");
    CHECK(report.status == 1);
    CHECK_MESSAGE(report.err.find("--report " + dir + "/x.obj: unknown file type '.obj'") !=
                      std::string::npos,
                  report.err);
    const Outcome twice = flatten(root, tube + " -o " + dir + "/a.obj --report " + dir +
                                            "/r.json --image " + dir + "/x.png --image " + dir +
                                            "/../run/x.png");
    CHECK(twice.status == 1);
    CHECK_MESSAGE(twice.err.find("is also the --image output " + dir + "/x.png") !=
                      std::string::npos,
                  twice.err);
    CHECK(folder_names(dir) == std::set<std::string>{"tube.ply", "link.ply"});
}

TEST_CASE("outputs: a missing folder, an unknown extension or an image without a field is "
          "refused before any work")
{
    const std::string root = temp_dir("outputs_early");
    const std::string dir = root + "/run";
    fs::create_directories(dir);
    const std::string tube = write_tube(dir);
    const std::string out = " -o " + dir + "/out.obj --report " + dir + "/out.json";
    struct Case
    {
        std::string args, message;
    };
    const Case cases[] = {
        {"--html " + dir + "/missing/v.html", "--html " + dir + "/missing/v.html: the folder " +
                                                  dir + "/missing does not exist; create it first"},
        {"--html " + dir + "/v.txt", "unknown file type '.txt'; use .html or .htm"},
        {"--html " + dir, "--html " + dir + " is a folder; give a file name"},
        {"--image " + dir + "/x.jpg", "--image " + dir + "/x.jpg: unknown file type '.jpg'; use "
                                      ".png, .svg or .pdf"},
        {"--image " + dir + "/x.png", "--image/--frames: no point field to draw; give --fields"},
        {"--frames " + tube, "--frames " + tube + " is a file, not a folder"},
        {"--frames " + dir + "/a/b", "the folder " + dir + "/a does not exist"},
    };
    for (const auto& c : cases)
    {
        CAPTURE(c.args);
        const Outcome o = flatten(root, tube + out + " " + c.args);
        CHECK(o.status == 1);
        CHECK_MESSAGE(o.err.find(c.message) != std::string::npos, o.err);
        // Before any work: no progress line, no output.
        CHECK_MESSAGE(o.err.find("[  ] read") == std::string::npos, o.err);
        CHECK(folder_names(dir) == std::set<std::string>{"tube.ply"});
    }
    const Outcome report = flatten(root, tube + " -o " + dir + "/o.obj --report " + dir +
                                             "/missing/r.json");
    CHECK(report.status == 1);
    CHECK_MESSAGE(report.err.find("the folder " + dir + "/missing does not exist") !=
                      std::string::npos,
                  report.err);
    CHECK(folder_names(dir) == std::set<std::string>{"tube.ply"});
}

TEST_CASE("outputs: a failure after the map was made removes every file the run wrote")
{
    const std::string root = temp_dir("outputs_late");
    const std::string dir = root + "/run";
    fs::create_directories(dir);
    REQUIRE(run(kPhantom + " carotid --edge-length 1.0 -o " + dir + "/carotid.ply --pulse " + dir +
                "/pulse -q") == 0);
    const std::set<std::string> inputs = folder_names(dir);
    // --image-time outside the series is found only when the image is drawn, after the .vtp,
    // its map, the EnSight cases and the series folder were written.
    const Outcome o = flatten(root, dir + "/carotid.ply -o " + dir + "/c.vtp --fields " + dir +
                                       "/pulse.pvd --field WSS --refine none --report " + dir +
                                       "/c.json --image " + dir + "/c.png --image-time 99 -q");
    CHECK(o.status == 1);
    CHECK_MESSAGE(o.err.find("--image-time 99 s is outside the series") != std::string::npos,
                  o.err);
    CHECK(folder_names(dir) == inputs);
    // A folder that existed keeps what it held; only the run's entries go.
    fs::create_directories(dir + "/c");
    write_bytes(dir + "/c/mine.txt", "mine\n");
    CHECK(flatten(root, dir + "/carotid.ply -o " + dir + "/c.vtp --fields " + dir +
                           "/pulse.pvd --field WSS --refine none --image " + dir +
                           "/c.png --image-time 99 -q")
              .status == 1);
    CHECK(folder_names(dir + "/c") == std::set<std::string>{"mine.txt"});
    CHECK(read_bytes(dir + "/c/mine.txt") == "mine\n");
}

TEST_CASE("outputs: in a batch every directory entry gets a row, dangling and looping links too")
{
    const std::string root = temp_dir("outputs_batch_links");
    const std::string in = root + "/in";
    fs::create_directories(in + "/sub");
    write_tube(in);
    fs::create_symlink(in + "/nowhere.ply", in + "/dangling.ply");
    fs::create_symlink(in + "/loop.stl", in + "/loop.stl");
    fs::create_symlink(in + "/tube.ply", in + "/sub/linked.ply");
    fs::create_symlink(in, in + "/sub/parent");  // a folder link: not followed, no cycle
    const Outcome o = flatten(root, "--batch " + in + " -o " + root + "/out -q");
    CHECK(o.status == 1);
    const std::string summary = read_bytes(root + "/out/summary.json");
    // Four rows: the tube and its link flattened, the two broken links refused with the reason.
    CHECK_MESSAGE(summary.find("\"inputs\": 4") != std::string::npos, summary);
    CHECK_MESSAGE(summary.find("\"ok\": 2") != std::string::npos, summary);
    CHECK_MESSAGE(summary.find("\"refused\": 2") != std::string::npos, summary);
    CHECK_MESSAGE(summary.find(in + "/dangling.ply is a symbolic link to " + in +
                               "/nowhere.ply, which does not exist; fix or remove the link") !=
                      std::string::npos,
                  summary);
    CHECK_MESSAGE(summary.find(in + "/loop.stl is a symbolic link to " + in +
                               "/loop.stl, which cannot be resolved (Too many levels of "
                               "symbolic links); fix or remove the link") != std::string::npos,
                  summary);
    CHECK(fs::exists(root + "/out/tube.obj"));
    CHECK(fs::exists(root + "/out/linked.obj"));
}

TEST_CASE("outputs: a batch refuses a folder it cannot list, and gives an unlistable subfolder a row")
{
    // Permissions do not bind root: as root the runs drop to user nobody (setpriv), as anyone
    // else the folder's mode is enough.
    const std::string as_user =
        ::geteuid() == 0 ? "setpriv --reuid=65534 --regid=65534 --clear-groups " : "";
    if (!as_user.empty())
        REQUIRE_MESSAGE(run("command -v setpriv > /dev/null") == 0,
                        "setpriv (util-linux) runs the batch as another user than root");
    const std::string root = temp_dir("outputs_batch_unlistable");
    const std::string in = root + "/in";
    fs::create_directories(in + "/sub");
    write_tube(in);
    write_tube(in + "/sub");
    fs::create_directories(root + "/out");
    const auto open_to_all = fs::perms::all;
    fs::permissions(root, open_to_all);
    fs::permissions(root + "/out", open_to_all);
    const auto batch = [&](const std::string& out) {
        Outcome o;
        const std::string err = root + "/stderr.txt";
        o.status = run(as_user + kFlatten + " --batch " + in + " -o " + out + " -q 2> " + err);
        o.err = read_bytes(err);
        return o;
    };

    fs::permissions(in + "/sub", fs::perms::none);
    const Outcome partial = batch(root + "/out");
    CHECK(partial.status == 1);
    const std::string summary = read_bytes(root + "/out/summary.json");
    CHECK_MESSAGE(summary.find("\"inputs\": 2") != std::string::npos, summary);
    CHECK_MESSAGE(summary.find("\"ok\": 1") != std::string::npos, summary);
    CHECK_MESSAGE(summary.find("\"refused\": 1") != std::string::npos, summary);
    CHECK_MESSAGE(summary.find(in + "/sub is a folder that cannot be listed (Permission denied); "
                               "check its permissions") != std::string::npos,
                  summary);
    CHECK(fs::exists(root + "/out/tube.obj"));

    fs::permissions(in, fs::perms::none);
    const Outcome refused = batch(root + "/out2");
    CHECK(refused.status == 1);
    CHECK_MESSAGE(refused.err == "vessel-flatten: --batch: cannot list " + in +
                                     ": Permission denied; check the folder's permissions\n",
                  refused.err);
    CHECK_FALSE(fs::exists(root + "/out2"));
    fs::permissions(in, fs::perms::owner_all);
    fs::permissions(in + "/sub", fs::perms::owner_all);
}
