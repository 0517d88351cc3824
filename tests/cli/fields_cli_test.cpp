// vessel-phantom --pulse and vessel-flatten --fields end to end, checked with python3-vtk9.
#include <doctest/doctest.h>

#include "support/files.h"
#include "support/checks.h"
#include "support/png.h"
#include "vessel/fields/field_series.h"
#include "vessel/render/map_image.h"
#include "vessel/core/properties.h"
#include "vessel/fields/pulse_series.h"
#include "vessel/check/validation.h"
#include "vessel/core/operators.h"
#include "vessel/cut/boundary.h"
#include "vessel/direction/geodesic.h"
#include "vessel/render/viewer.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

using vessel::test::read_bytes;
using vessel::test::run;
using vessel::test::temp_dir;

namespace fs = std::filesystem;

namespace {

const std::string kFlatten = VESSEL_FLATTEN_EXE;
const std::string kPhantom = VESSEL_PHANTOM_EXE;

// Independent check with VTK's Python reader (ParaView's): OUT.case (the 3D cut mesh) and
// OUT-map.case (the map) are separate datasets of one part each, with the CSV's times; at every
// step WSS equals the input CSV's value (as a 32-bit float) at the cut vertex's InputVertex; the
// map has z = 0, uv = its (x, y) and the distortion cell arrays; the geometry is written once.
const char* kCheckSeries = R"(import sys, os, numpy as np, vtk
from vtk.util.numpy_support import vtk_to_numpy as np_of
case, csv = sys.argv[1], sys.argv[2]
table = np.loadtxt(csv, delimiter=",", skiprows=1)
times = np.loadtxt(csv, delimiter=",", max_rows=1, dtype=str)[1:].astype(float)
folder = case[:-5]
assert sorted(f for f in os.listdir(folder) if f.endswith(".geo")) == \
    [os.path.basename(folder) + s + ".geo" for s in ("-map", "")]
for suffix in ("", "-map"):
    def reader():
        r = vtk.vtkGenericEnSightReader(); r.SetCaseFileName(case[:-5] + suffix + ".case")
        r.ReadAllVariablesOn(); r.UpdateInformation(); return r
    steps = reader().GetOutputInformation(0).Get(vtk.vtkStreamingDemandDrivenPipeline.TIME_STEPS())
    assert len(steps) == len(times), (suffix, len(steps), len(times))
    assert np.allclose(steps, times, rtol=1e-7, atol=0), (steps, times)
    for k, t in enumerate(steps):
        r = reader(); r.UpdateTimeStep(t)
        o = r.GetOutput(); assert o.GetNumberOfBlocks() == 1
        o = o.GetBlock(0); pd = o.GetPointData()
        wss = np_of(pd.GetArray("WSS")); src = np_of(pd.GetArray("InputVertex")).astype(int)
        rows = table[:, 0].astype(int)
        expected = np.empty(len(rows)); expected[rows] = table[:, k + 1]
        assert np.array_equal(wss, expected[src].astype(np.float32)), k
        has_distortion = o.GetCellData().GetArray("LogAreaRatio") is not None
        assert has_distortion == (suffix == "-map")
        if suffix == "-map":
            xyz = np_of(o.GetPoints().GetData())
            assert np.all(xyz[:, 2] == 0)
            assert np.array_equal(np_of(pd.GetArray("uv"))[:, :2], xyz[:, :2])
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
        CHECK(read_bytes(dir + "/csv.html").find("\"name\":\"WSS\"") != std::string::npos);
    for (const std::string out : {"pvd", "csv"})
    {
        INFO(out);
        CHECK(fs::exists(dir + "/" + out + ".vtp"));
        CHECK(fs::exists(dir + "/" + out + "-map.vtp"));
        std::ofstream(dir + "/check.py") << kCheckSeries;
        CHECK(run("/usr/bin/python3 " + dir + "/check.py " + dir + "/" + out + ".case " + dir +
                  "/pulse.csv > " + dir + "/check.txt") == 0);
        CHECK(read_bytes(dir + "/check.txt") == "90 steps checked\n");
    }
    // Same values out: the step files of both runs are identical byte for byte.
    CHECK(read_bytes(dir + "/pvd/pvd.WSS.0044") == read_bytes(dir + "/csv/csv.WSS.0044"));
    CHECK(read_bytes(dir + "/pvd/pvd-map.WSS.0044") == read_bytes(dir + "/csv/csv-map.WSS.0044"));
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
        const std::string err = read_bytes(dir + "/stderr.txt");
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
    CHECK(read_bytes(dir + "/c.png").rfind("\x89PNG", 0) == 0);
    // 25 frames per second over the series' 1.78 s: t = 0, 0.04, ..., 1.76.
    const int expected = static_cast<int>(std::floor(1.78 * 25 + 1e-9)) + 1;
    int frames = 0;
    for (const auto& e : fs::directory_iterator(dir + "/frames"))
        frames += e.path().extension() == ".png";
    CHECK(frames == expected);
    // A field that is not in the series is named.
    CHECK(run(kFlatten + " " + dir + "/carotid.ply -o " + dir + "/d.vtp --fields " + dir +
              "/pulse.pvd --field P --image " + dir + "/d.png -q 2> " + dir + "/err.txt") == 1);
    CHECK(read_bytes(dir + "/err.txt").find("no field named 'P'") != std::string::npos);
}

namespace {

// Pixels of \p png within 2/255 of viridis(t).
int pixels_of(const std::string& png, double t)
{
    const vessel::test::Png image(png);
    const Eigen::Vector3d color = vessel::colormap_rgb(vessel::Colormap::Viridis, t);
    int n = 0;
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x)
            n += vessel::test::color_error(image.pixel(x, y), color) <= 2.0 / 255;
    return n;
}

}  // namespace

namespace {

// DIR/steps.csv: one row per vertex of DIR/pulse.csv's mesh, the values 10, 20, 30 at t = 0,
// 0.5, 1 s (a series uniform in space). Returns the rows written.
int write_uniform_steps(const std::string& dir)
{
    std::ifstream pulse(dir + "/pulse.csv");
    std::string line;
    std::getline(pulse, line);
    std::ofstream csv(dir + "/steps.csv");
    csv << "vertex,0,0.5,1\n";
    int vertices = 0;
    while (std::getline(pulse, line))
        csv << vertices++ << ",10,20,30\n";
    return vertices;
}

}  // namespace

TEST_CASE("cli: --image-step and --image-time choose the moment of a series that --image draws")
{
    const std::string dir = temp_dir("cli_fields_image_time");
    REQUIRE(run(kPhantom + " carotid --edge-length 1.0 -o " + dir + "/carotid.ply --pulse " + dir +
                "/pulse -q") == 0);
    // A series that is uniform in space: 10, 20, 30 at t = 0, 0.5, 1 s. At t = 0.25 s the
    // interpolated value is 15 everywhere, i.e. a quarter of the series' range [10, 30].
    REQUIRE(write_uniform_steps(dir) > 1000);
    const std::string flatten = kFlatten + " " + dir + "/carotid.ply --fields " + dir +
                                "/steps.csv --field P --refine none -q";
    REQUIRE(run(flatten + " -o " + dir + "/a.vtp --image " + dir + "/t025.png --image-time 0.25") ==
            0);
    REQUIRE(run(flatten + " -o " + dir + "/b.vtp --image " + dir + "/s1.png --image-step 1") == 0);
    REQUIRE(run(flatten + " -o " + dir + "/c.vtp --image " + dir + "/s0.png") == 0);
    // --image takes one file per use: an input after it is the input, not a second image.
    REQUIRE(run(kFlatten + " --fields " + dir + "/steps.csv --field P --refine none -q --image " +
                dir + "/e.png " + dir + "/carotid.ply -o " + dir + "/e.vtp --image " + dir +
                "/e.svg") == 0);
    CHECK(std::filesystem::file_size(dir + "/e.png") > 0);
    CHECK(std::filesystem::file_size(dir + "/e.svg") > 0);
    // The map fills tens of thousands of pixels in its one colour; the other images' colours
    // appear only in a thin band of the colorbar.
    const int at_quarter = pixels_of(dir + "/t025.png", 0.25);
    const int at_half = pixels_of(dir + "/s1.png", 0.5);
    const int at_start = pixels_of(dir + "/s0.png", 0.0);
    MESSAGE("pixels: t=0.25 s ", at_quarter, ", step 1 ", at_half, ", step 0 ", at_start);
    CHECK(at_quarter > 20000);
    CHECK(at_half > 20000);
    CHECK(at_start > 20000);
    CHECK(pixels_of(dir + "/t025.png", 0.5) < at_half / 20);
    CHECK(pixels_of(dir + "/s1.png", 0.25) < at_quarter / 20);
    CHECK(pixels_of(dir + "/s0.png", 0.25) < at_quarter / 20);

    // Moments that are not in the series are refused with the series' extent.
    const std::string err = " 2> " + dir + "/err.txt";
    CHECK(run(flatten + " -o " + dir + "/d.vtp --image " + dir + "/d.png --image-time 1.5" + err) ==
          1);
    CHECK(read_bytes(dir + "/err.txt").find("--image-time 1.5 s is outside the series (0 s to 1 s)") !=
          std::string::npos);
    CHECK(run(flatten + " -o " + dir + "/d.vtp --image " + dir + "/d.png --image-step 3" + err) ==
          1);
    CHECK(read_bytes(dir + "/err.txt").find("the series has steps 0 to 2") != std::string::npos);
    CHECK(run(kFlatten + " " + dir + "/carotid.ply -o " + dir + "/d.vtp --fields " + dir +
              "/pulse/pulse_000.vtp --image " + dir + "/d.png --image-step 0 -q" + err) == 1);
    CHECK(read_bytes(dir + "/err.txt").find("not one (give --fields with a series)") !=
          std::string::npos);
    CHECK_FALSE(fs::exists(dir + "/d.png"));
}

TEST_CASE("cli: vessel-pulse writes the synthetic pulse over a real .vtp's points, in file order")
{
    const std::string dir = temp_dir("cli_pulse_real");
    const std::string artery = std::string(VESSEL_SHARED_DATA) + "/vampy/artery.vtp";
    REQUIRE(run(std::string(VESSEL_PULSE_EXE) + " " + artery + " " + dir + "/pulse -q") == 0);
    const vessel::PolyData input = vessel::read_polydata(artery);
    // Read back through the checks of --fields (counts, positions), as .pvd and as CSV.
    const vessel::TimeSeries pvd = vessel::read_field_series(dir + "/pulse.pvd", input);
    const vessel::TimeSeries csv = vessel::read_field_series(dir + "/pulse-long.csv", input);
    REQUIRE(pvd.size() == 90);
    REQUIRE(csv.size() == 90);
    CHECK(pvd.times[89] == doctest::Approx(1.78));
    // Row i is the pulse at the surface vertex made from input point i (the surface numbers its
    // vertices in order of first use by the triangulated faces, not in file order).
    const vessel::TreeSurface surface = vessel::make_tree_surface(input.mesh);
    const vessel::TimeSeries expected = vessel::travelling_pulse(surface.mesh);
    OpenMesh::VPropHandleT<int> index;
    REQUIRE(surface.mesh.get_property_handle(index, vessel::prop::input_index));
    const auto input_index = [&](OpenMesh::VertexHandle v) { return surface.mesh.property(index, v); };
    double worst = 0;
    int moved = 0;
    for (int k = 0; k < 90; ++k)
    {
        const auto& got = vessel::find_field(pvd.steps[k], "WSS").values;
        const auto& got_csv = vessel::find_field(csv.steps[k], "WSS").values;
        const auto& want = expected.steps[k][0].values;
        REQUIRE(got.rows() == static_cast<Eigen::Index>(input.mesh.points.size()));
        for (auto v : surface.mesh.vertices())
        {
            worst = std::max({worst, std::abs(got(input_index(v), 0) - want(v.idx(), 0)),
                              std::abs(got_csv(input_index(v), 0) - want(v.idx(), 0))});
            moved += k == 0 && input_index(v) != v.idx();
        }
    }
    MESSAGE(moved, " of ", surface.mesh.n_vertices(), " vertices are numbered differently");
    CHECK(worst <= 1e-12);
    // It flattens with the series and draws a moment of it.
    CHECK(run(kFlatten + " " + artery + " -o " + dir + "/a.vtp --fields " + dir +
              "/pulse.pvd --image " + dir + "/a.png --image-time 0.31 -q") == 0);
    CHECK(read_bytes(dir + "/a.png").rfind("\x89PNG", 0) == 0);
}

TEST_CASE("cli: --image-range, --colormap, --image-size and --fps shape the figures")
{
    const std::string dir = temp_dir("cli_fields_figure");
    REQUIRE(run(kPhantom + " carotid --edge-length 1.0 -o " + dir + "/carotid.ply --pulse " + dir +
                "/pulse -q") == 0);
    REQUIRE(write_uniform_steps(dir) > 1000);  // 10, 20, 30 at t = 0, 0.5, 1 s
    const std::string flatten = kFlatten + " " + dir + "/carotid.ply --fields " + dir +
                                "/steps.csv --field P --refine none -q --image-step 1";
    // Step 1 is 20: a quarter of the way up the range 0..80, at the bottom of 20..40.
    REQUIRE(run(flatten + " -o " + dir + "/a.vtp --image " + dir + "/quarter.png --image-range 0 80 "
                "--image-size 640 480") == 0);
    REQUIRE(run(flatten + " -o " + dir + "/b.vtp --image " + dir + "/bottom.png --image-range 20 40") ==
            0);
    REQUIRE(run(flatten + " -o " + dir + "/c.vtp --image " + dir + "/grey.png --image-range 0 40 "
                "--colormap diverging") == 0);
    const vessel::test::Png quarter(dir + "/quarter.png");
    CHECK(quarter.width() == 640);
    CHECK(quarter.height() == 480);
    const auto count = [](const vessel::test::Png& image, vessel::Colormap map, double t) {
        const Eigen::Vector3d color = vessel::colormap_rgb(map, t);
        int n = 0;
        for (int y = 0; y < image.height(); ++y)
            for (int x = 0; x < image.width(); ++x)
                n += vessel::test::color_error(image.pixel(x, y), color) <= 2.0 / 255;
        return n;
    };
    const vessel::test::Png bottom(dir + "/bottom.png"), grey(dir + "/grey.png");
    MESSAGE("map pixels: quarter ", count(quarter, vessel::Colormap::Viridis, 0.25), ", bottom ",
            count(bottom, vessel::Colormap::Viridis, 0.0), ", diverging middle ",
            count(grey, vessel::Colormap::Diverging, 0.5));
    CHECK(count(quarter, vessel::Colormap::Viridis, 0.25) > 5000);
    CHECK(count(quarter, vessel::Colormap::Viridis, 0.5) < 500);
    CHECK(count(bottom, vessel::Colormap::Viridis, 0.0) > 20000);
    CHECK(count(grey, vessel::Colormap::Diverging, 0.5) > 20000);
    CHECK(count(grey, vessel::Colormap::Viridis, 0.5) < 500);

    // --fps 5 over the series' 1 s: t = 0, 0.2, ..., 1.
    REQUIRE(run(kFlatten + " " + dir + "/carotid.ply --fields " + dir + "/steps.csv --field P "
                "--refine none -q -o " + dir + "/d.vtp --frames " + dir + "/frames --fps 5") == 0);
    int frames = 0;
    for (const auto& e : fs::directory_iterator(dir + "/frames"))
        frames += e.path().extension() == ".png";
    CHECK(frames == 6);

    // Bad figure options fail before any work, with nothing written.
    const auto fails_with = [&](const std::string& args, const std::string& message) {
        INFO(args);
        CHECK(run(flatten + " -o " + dir + "/e.vtp --image " + dir + "/e.png " + args + " 2> " +
                  dir + "/err.txt") == 1);
        const std::string err = read_bytes(dir + "/err.txt");
        CHECK_MESSAGE(err.find(message) != std::string::npos, err);
        CHECK_FALSE(fs::exists(dir + "/e.vtp"));
        CHECK_FALSE(fs::exists(dir + "/e.png"));
    };
    fails_with("--image-range 5 1", "--image-range: LO must be below HI");
    fails_with("--image-size 20 480", "--image-size: W and H must be in [64, 16384]");
    fails_with("--fps 0", "--fps must be in (0, 240]");
    fails_with("--colormap jet", "--colormap");
}

TEST_CASE("cli: vessel-pulse --vector and --image-arrows draw the direction of a vector series")
{
    const std::string dir = temp_dir("cli_pulse_arrows");
    const std::string artery = std::string(VESSEL_SHARED_DATA) + "/vampy/artery.vtp";
    REQUIRE(run(std::string(VESSEL_PULSE_EXE) + " " + artery + " " + dir + "/pulse --vector -q") ==
            0);
    CHECK_FALSE(fs::exists(dir + "/pulse.csv"));  // a CSV holds scalars
    const vessel::PolyData input = vessel::read_polydata(artery);
    const vessel::TimeSeries pvd = vessel::read_field_series(dir + "/pulse.pvd", input);
    REQUIRE(pvd.size() == 90);
    // Each vector is the scalar pulse's value along the distance's unit gradient: its length is
    // the scalar pulse's, its direction along the wall, away from the inlet.
    const vessel::TreeSurface surface = vessel::make_tree_surface(input.mesh);
    vessel::PulseSeriesOptions vector_options;
    vector_options.vector = true;
    const vessel::TimeSeries scalar = vessel::travelling_pulse(surface.mesh);
    const vessel::TimeSeries vector = vessel::travelling_pulse(surface.mesh, vector_options);
    const Eigen::VectorXd s = vessel::heat_geodesic_distance(
        surface.mesh, vessel::boundary_loops(surface.mesh)[0].vertices);
    const Eigen::MatrixX3d gradient = vessel::vertex_gradient(surface.mesh, s);
    double worst_length = 0, worst_direction = 1;
    for (int k : {0, 17, 60})
    {
        const auto& v = vector.steps[k][0].values;
        REQUIRE(v.cols() == 3);
        for (auto h : surface.mesh.vertices())
        {
            const int i = h.idx();
            worst_length = std::max(worst_length,
                                    std::abs(v.row(i).norm() - scalar.steps[k][0].values(i, 0)));
            worst_direction = std::min(worst_direction,
                                       v.row(i).normalized().dot(gradient.row(i).normalized()));
        }
    }
    MESSAGE("length error ", worst_length, ", least cosine to the gradient ", worst_direction);
    CHECK(worst_length < 1e-12);
    CHECK(worst_direction > 1 - 1e-12);

    // Drawn as arrows over |WSS| by vessel-flatten and vessel-render.
    const std::string flatten = kFlatten + " " + artery + " -o " + dir + "/a.vtp --fields " + dir +
                                "/pulse.pvd --field WSS -q";
    REQUIRE(run(flatten + " --image " + dir + "/plain.png --image-time 0.31") == 0);
    REQUIRE(run(flatten + " --image " + dir + "/arrows.png --image-time 0.31 --image-arrows WSS") ==
            0);
    REQUIRE(run(flatten + " --frames " + dir + "/frames --image-arrows WSS") == 0);
    CHECK(fs::exists(dir + "/frames/frame_0000.png"));
    const auto dark = [](const std::string& png_path) {
        const vessel::test::Png png(png_path);
        int n = 0;
        for (int y = 0; y < png.height(); ++y)
            for (int x = 0; x < png.width(); ++x)
                n += png.pixel(x, y).maxCoeff() < 0.1;
        return n;
    };
    const int plain = dark(dir + "/plain.png"), arrows = dark(dir + "/arrows.png");
    MESSAGE("near-black pixels: ", plain, " without arrows, ", arrows, " with");
    CHECK(arrows > plain + 1000);
    REQUIRE(run(std::string(VESSEL_RENDER_EXE) + " " + artery + " " + dir + "/r.png --fields " +
                dir + "/pulse.pvd --field WSS --arrows WSS > /dev/null 2>&1") == 0);

    // A scalar array cannot give arrows; the refusal comes before any work or output.
    const std::string err = " 2> " + dir + "/err.txt";
    REQUIRE(run(std::string(VESSEL_PULSE_EXE) + " " + artery + " " + dir + "/scalar -q") == 0);
    CHECK(run(kFlatten + " " + artery + " -o " + dir + "/b.vtp --fields " + dir +
              "/scalar.pvd --field WSS --image " + dir + "/b.png --image-arrows WSS -q" + err) == 1);
    CHECK(read_bytes(dir + "/err.txt").find("--image-arrows WSS: arrows need a 3-component point "
                                            "array") != std::string::npos);
    CHECK_FALSE(fs::exists(dir + "/b.png"));
    CHECK_FALSE(fs::exists(dir + "/b.vtp"));
}
