// vessel-phantom --pulse and vessel-flatten --fields end to end, checked with python3-vtk9.
#include <doctest/doctest.h>

#include "support/checks.h"
#include "vessel/viewer.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

using vessel::test::run;
using vessel::test::temp_dir;

namespace fs = std::filesystem;

namespace {

const std::string kFlatten = VESSEL_FLATTEN_EXE;
const std::string kPhantom = VESSEL_PHANTOM_EXE;

std::string read_text(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

// Independent check with VTK's Python reader: every step file of OUT.pvd (both parts) holds
// WSS equal to the input CSV's value at the cut vertex's InputVertex; the map part has z = 0.
const char* kCheckSeries = R"(import sys, numpy as np, vtk, xml.etree.ElementTree as ET
from vtk.util.numpy_support import vtk_to_numpy as np_of
pvd, csv = sys.argv[1], sys.argv[2]
table = np.loadtxt(csv, delimiter=",", skiprows=1)
times = np.loadtxt(csv, delimiter=",", max_rows=1, dtype=str)[1:].astype(float)
entries = ET.parse(pvd).getroot().find("Collection").findall("DataSet")
assert len(entries) == 2 * len(times), (len(entries), len(times))
base = pvd.rsplit("/", 1)[0]
for i, e in enumerate(entries):
    k = i // 2
    assert abs(float(e.get("timestep")) - times[k]) < 1e-12
    assert int(e.get("part")) == i % 2
    r = vtk.vtkXMLPolyDataReader(); r.SetFileName(base + "/" + e.get("file")); r.Update()
    o = r.GetOutput(); pd = o.GetPointData()
    wss = np_of(pd.GetArray("WSS")); src = np_of(pd.GetArray("InputVertex"))
    rows = table[:, 0].astype(int)
    expected = np.empty(len(rows)); expected[rows] = table[:, k + 1]
    assert np.array_equal(wss, expected[src]), k
    if i % 2 == 1:
        z = np_of(o.GetPoints().GetData())[:, 2]
        assert np.all(z == 0)
        uv = np_of(pd.GetTCoords()); xy = np_of(o.GetPoints().GetData())[:, :2]
        assert np.array_equal(uv, xy)
print(len(times), "steps checked")
)";

}  // namespace

TEST_CASE("cli: the phantom's 90-step pulse flattens from .pvd and from CSV to the same series")
{
    const std::string dir = temp_dir("cli_fields");
    REQUIRE(run(kPhantom + " carotid --edge-length 1.0 -o " + dir + "/carotid.ply --pulse " + dir +
                "/pulse -q") == 0);
    REQUIRE(fs::exists(dir + "/pulse.pvd"));
    REQUIRE(fs::exists(dir + "/pulse/pulse_089.vtp"));
    REQUIRE(fs::exists(dir + "/pulse.csv"));
    REQUIRE(fs::exists(dir + "/pulse-long.csv"));
    const std::string common = " --refine none -q 2> " + dir + "/stderr.txt";
    REQUIRE(run(kFlatten + " " + dir + "/carotid.ply -o " + dir + "/pvd.vtp --fields " + dir +
                "/pulse.pvd" + common) == 0);
    REQUIRE(run(kFlatten + " " + dir + "/carotid.ply -o " + dir + "/csv.vtp --fields " + dir +
                "/pulse-long.csv --field WSS" +
                (vessel::viewer_available() ? " --html " + dir + "/csv.html" : std::string()) +
                common) == 0);
    if (vessel::viewer_available())  // the HTML viewer offers the series beside the geodesic
        CHECK(read_text(dir + "/csv.html").find("\"name\":\"WSS\"") != std::string::npos);
    for (const std::string out : {"pvd", "csv"})
    {
        INFO(out);
        CHECK(fs::exists(dir + "/" + out + ".vtp"));
        CHECK(fs::exists(dir + "/" + out + "-map.vtp"));
        std::ofstream(dir + "/check.py") << kCheckSeries;
        CHECK(run("/usr/bin/python3 " + dir + "/check.py " + dir + "/" + out + ".pvd " + dir +
                  "/pulse.csv > " + dir + "/check.txt") == 0);
        CHECK(read_text(dir + "/check.txt") == "90 steps checked\n");
    }
    // Same values out: the step files of both runs are identical byte for byte.
    CHECK(read_text(dir + "/pvd/pvd_044.vtp") == read_text(dir + "/csv/csv_044.vtp"));
}

TEST_CASE("cli: --fields that do not fit, or a series with a non-VTP output, are refused")
{
    const std::string dir = temp_dir("cli_fields_bad");
    REQUIRE(run(kPhantom + " carotid --edge-length 1.0 -o " + dir + "/carotid.ply --pulse " + dir +
                "/pulse -q") == 0);
    REQUIRE(run(kPhantom + " helix -o " + dir + "/helix.ply -q") == 0);
    const auto fails_with = [&](const std::string& args, const std::string& message) {
        INFO(args);
        CHECK(run(kFlatten + " " + args + " -q 2> " + dir + "/stderr.txt") == 1);
        const std::string err = read_text(dir + "/stderr.txt");
        CHECK_MESSAGE(err.find(message) != std::string::npos, err);
    };
    fails_with(dir + "/helix.ply -o " + dir + "/h.vtp --fields " + dir + "/pulse.pvd",
               "step 0 of " + dir + "/pulse.pvd (" + dir + "/pulse/pulse_000.vtp) has ");
    fails_with(dir + "/carotid.ply -o " + dir + "/c.ply --fields " + dir + "/pulse.csv",
               "--fields gives 90 time steps; write them with an OUT.vtp output");
    fails_with(dir + "/carotid.ply -o " + dir + "/c.vtp --fields " + dir + "/pulse.pvd --field P",
               "no field named 'P'; available: WSS");
    CHECK_FALSE(fs::exists(dir + "/c.vtp"));
    CHECK_FALSE(fs::exists(dir + "/h.vtp"));
}

TEST_CASE("cli: --image and --frames draw the chosen field of the series on the map")
{
    const std::string dir = temp_dir("cli_fields_images");
    REQUIRE(run(kPhantom + " carotid --edge-length 1.0 -o " + dir + "/carotid.ply --pulse " + dir +
                "/pulse -q") == 0);
    REQUIRE(run(kFlatten + " " + dir + "/carotid.ply -o " + dir + "/c.vtp --fields " + dir +
                "/pulse.pvd --field WSS --image " + dir + "/c.png --frames " + dir +
                "/frames --refine none -q") == 0);
    CHECK(read_text(dir + "/c.png").rfind("\x89PNG", 0) == 0);
    // 25 frames per second over the series' 1.78 s: t = 0, 0.04, ..., 1.76.
    const int expected = static_cast<int>(std::floor(1.78 * 25 + 1e-9)) + 1;
    int frames = 0;
    for (const auto& e : fs::directory_iterator(dir + "/frames"))
        frames += e.path().extension() == ".png";
    CHECK(frames == expected);
    // A field that is not in the series is named.
    CHECK(run(kFlatten + " " + dir + "/carotid.ply -o " + dir + "/d.vtp --fields " + dir +
              "/pulse.pvd --field P --image " + dir + "/d.png -q 2> " + dir + "/err.txt") == 1);
    CHECK(read_text(dir + "/err.txt").find("no field named 'P'") != std::string::npos);
}
