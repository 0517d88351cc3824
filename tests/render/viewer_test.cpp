// write_viewer_html and the viewer's fields: the page embeds what it claims, bad fields are refused.
#include <doctest/doctest.h>

#include "support/checks.h"
#include "vessel/core/errors.h"
#include "vessel/io/io.h"
#include "vessel/phantom/phantom.h"
#include "vessel/core/properties.h"
#include "vessel/render/viewer.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

using namespace vessel;

namespace {

const FlattenResult& carotid()
{
    static const FlattenResult result = flatten(carotid_phantom());
    return result;
}

// The text of the <script> element with the given id.
std::string script_text(const std::string& html, const std::string& id)
{
    const std::string open = "id=\"" + id + "\">";
    const auto begin = html.find(open);
    REQUIRE_MESSAGE(begin != std::string::npos, "no element " << id);
    const auto start = begin + open.size();
    return html.substr(start, html.find("</script>", start) - start);
}

std::vector<unsigned char> decode_base64(const std::string& text)
{
    const std::string table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::vector<unsigned char> out;
    std::uint32_t bits = 0;
    int n = 0;
    for (char c : text)
    {
        if (c == '=')
            break;
        const auto k = table.find(c);
        if (k == std::string::npos)
            throw std::runtime_error(std::string("not base64: '") + c + "'");
        bits = (bits << 6) | static_cast<std::uint32_t>(k);
        if ((n += 6) >= 8)
            out.push_back(static_cast<unsigned char>((bits >> (n -= 8)) & 255));
    }
    return out;
}

template <class T>
std::vector<T> buffer(const std::string& html, const std::string& name)
{
    const auto bytes = decode_base64(script_text(html, "vessel-buffer-" + name));
    REQUIRE(bytes.size() % sizeof(T) == 0);
    std::vector<T> values(bytes.size() / sizeof(T));
    std::memcpy(values.data(), bytes.data(), bytes.size());
    return values;
}

std::string read_file(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

}  // namespace

TEST_CASE("viewer: the pulse travels from the inlet over one period in [-1, 1]")
{
    const FlattenResult& r = carotid();
    const ViewerField pulse = pulse_field(r);
    REQUIRE(pulse.times.size() == 90);
    REQUIRE(pulse.steps.size() == 90);
    CHECK(pulse.times.front() == 0.0);
    CHECK(pulse.times.back() < 1.8);
    const auto nv = static_cast<Eigen::Index>(r.mesh.n_vertices());
    Eigen::VectorXd mean = Eigen::VectorXd::Zero(nv);
    for (const auto& step : pulse.steps)
    {
        REQUIRE(step.size() == nv);
        CHECK(step.minCoeff() >= -1.0f);
        CHECK(step.maxCoeff() <= 1.0f);
        mean += step.cast<double>() / 90.0;
    }
    // Equally spaced samples of a full sine period average to zero at every vertex.
    CHECK(mean.cwiseAbs().maxCoeff() < 1e-5);
    // Travelling: the vertex nearest the inlet peaks first; one farther away peaks later.
    const Eigen::VectorXf d = geodesic_field(r).steps[0];
    Eigen::Index near = 0, far = 0;
    d.minCoeff(&near);
    Eigen::VectorXf quarter = (d.array() - d.maxCoeff() / 6).abs();  // 1/4 wave from the inlet
    quarter.minCoeff(&far);
    auto peak = [&](Eigen::Index v) {
        int best = 0;
        for (int i = 0; i < 90; ++i)
            if (pulse.steps[i][v] > pulse.steps[best][v])
                best = i;
        return best;
    };
    CHECK(peak(far) - peak(near) == doctest::Approx(22.5).epsilon(0.1));
}

TEST_CASE("viewer: the page embeds the cut mesh, the seam and every field step")
{
    const FlattenResult& r = carotid();
    const std::vector<ViewerField> fields = {geodesic_field(r, "mm"), pulse_field(r)};
    const std::string path = test::temp_dir("viewer") + "/carotid.html";
    ViewerOptions options;
    options.title = "carotid </script> test";
    options.viewpoint = Eigen::Vector3d(0, -100, 0);
    if (!viewer_available())
    {
        CHECK_THROWS_AS(write_viewer_html(path, r, fields, options), IoError);
        return;
    }
    write_viewer_html(path, r, fields, options);
    const std::string html = read_file(path);
    CHECK(html.rfind("<!DOCTYPE html>", 0) == 0);
    // The title cannot close the script element early.
    CHECK(html.find("carotid </script>") == std::string::npos);

    const nlohmann::json meta = nlohmann::json::parse(script_text(html, "vessel-meta"));
    CHECK(meta["title"] == options.title);
    REQUIRE(meta["fields"].size() == 2);
    const std::size_t nv = r.mesh.n_vertices(), nf = r.mesh.n_faces();
    const auto positions = buffer<float>(html, "positions");
    const auto normals = buffer<float>(html, "normals");
    const auto indices = buffer<std::uint32_t>(html, "indices");
    CHECK(positions.size() == 3 * nv);
    CHECK(normals.size() == 3 * nv);
    CHECK(buffer<float>(html, "uv").size() == 2 * nv);
    REQUIRE(indices.size() == 3 * nf);
    CHECK(*std::max_element(indices.begin(), indices.end()) < nv);
    // Positions are stored relative to meta.centre.
    const auto p0 = r.mesh.point(VertexHandle(0));
    for (int d = 0; d < 3; ++d)
        CHECK(positions[d] + meta["centre"][d].get<double>() ==
              doctest::Approx(p0[d]).epsilon(1e-5));
    double worst_norm = 0;
    for (std::size_t v = 0; v < nv; ++v)
        worst_norm = std::max<double>(
            worst_norm,
            std::abs(std::hypot(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]) - 1));
    CHECK(worst_norm < 1e-4);
    std::size_t seam_halfedges = 0;
    for (const auto& p : r.plan.paths)
        seam_halfedges += p.halfedges.size();
    CHECK(buffer<float>(html, "seam").size() == 6 * seam_halfedges);

    for (std::size_t k = 0; k < fields.size(); ++k)
    {
        const auto& field = fields[k];
        const auto& m = meta["fields"][k];
        CHECK(m["name"] == field.name);
        CHECK(m["times"].size() == field.times.size());
        const auto q = buffer<std::uint16_t>(html, "field" + std::to_string(k));
        REQUIRE(q.size() == field.steps.size() * nv);
        const double lo = m["lo"], hi = m["hi"];
        double worst = 0;
        for (std::size_t s = 0; s < field.steps.size(); ++s)
            for (std::size_t v = 0; v < nv; ++v)
                worst = std::max(
                    worst, std::abs(lo + q[s * nv + v] * (hi - lo) / 65535.0 - field.steps[s][v]));
        CHECK(worst <= (hi - lo) / 65535.0);
    }
}

TEST_CASE("viewer: malformed fields and options are refused")
{
    const FlattenResult& r = carotid();
    const std::string path = test::temp_dir("viewer-bad") + "/bad.html";
    const ViewerField good = geodesic_field(r);
    CHECK_THROWS_AS(write_viewer_html(path, r, {}), InvalidInputError);
    auto refused = [&](ViewerField field) {
        CHECK_THROWS_AS(write_viewer_html(path, r, {good, field}), InvalidInputError);
    };
    ViewerField bad = good;
    bad.steps[0].conservativeResize(bad.steps[0].size() - 1);
    refused(bad);
    bad = good;
    bad.steps[0][3] = std::nanf("");
    refused(bad);
    bad = good;
    bad.name.clear();
    refused(bad);
    bad = good;
    bad.times.push_back(1.0);
    refused(bad);
    bad = good;
    bad.times = {0.0, 0.0};
    bad.steps = {good.steps[0], good.steps[0]};
    refused(bad);
    ViewerOptions options;
    options.viewpoint = Eigen::Vector3d(0, NAN, 0);
    CHECK_THROWS_AS(write_viewer_html(path, r, {good}, options), InvalidInputError);
    CHECK_FALSE(std::ifstream(path).good());  // nothing written

    PulseOptions pulse;
    pulse.steps = 1;
    CHECK_THROWS_AS(pulse_field(r, pulse), InvalidInputError);
    pulse = {};
    pulse.period_s = 0;
    CHECK_THROWS_AS(pulse_field(r, pulse), InvalidInputError);
    FlattenResult bare;
    bare.mesh = carotid_phantom();
    CHECK_THROWS_AS(geodesic_field(bare), InvalidInputError);
}

TEST_CASE("viewer: vessel-view and vessel-flatten --html write pages with the re-cut command")
{
    const std::string dir = test::temp_dir("viewer-cli");
    const std::string mesh = std::string(VESSEL_SHARED_DATA) + "/vampy/artery-coarse.ply";
    if (!viewer_available())
    {
        // A build without node/npm: the tool says so and fails.
        CHECK(test::run(std::string(VESSEL_VIEW_EXE) + " " + mesh + " -o " + dir + "/v.html") != 0);
        return;
    }
    REQUIRE(test::run(std::string(VESSEL_VIEW_EXE) + " " + mesh + " -o " + dir +
                      "/view.html --demo-field --viewpoint 10 -40 5 -q") == 0);
    const std::string view = read_file(dir + "/view.html");
    const nlohmann::json meta = nlohmann::json::parse(script_text(view, "vessel-meta"));
    CHECK(meta["fields"].size() == 2);
    CHECK(meta["fields"][1]["times"].size() == 90);
    CHECK(meta["camera"].is_array());  // starts at the viewpoint
    const std::string flatten = meta["flatten_command"];
    CHECK(flatten.rfind("vessel-flatten " + mesh + " -o artery-coarse-flat.obj", 0) == 0);
    CHECK(meta["view_command"].get<std::string>().find("--viewpoint") == std::string::npos);

    REQUIRE(test::run(std::string(VESSEL_FLATTEN_EXE) + " " + mesh + " -o " + dir +
                      "/flat.obj --html " + dir + "/flat.html -q") == 0);
    const nlohmann::json flat_meta =
        nlohmann::json::parse(script_text(read_file(dir + "/flat.html"), "vessel-meta"));
    CHECK(flat_meta["fields"].size() == 1);
    CHECK(flat_meta["flatten_command"].get<std::string>().find("--html") != std::string::npos);
    // The one-word form: the page's command drops it alone and starts from the mesh's
    // face-on viewpoint.
    REQUIRE(test::run(std::string(VESSEL_FLATTEN_EXE) + " " + mesh + " -o " + dir +
                      "/face.obj --viewpoint face-on --html " + dir + "/face.html -q") == 0);
    const nlohmann::json face_meta =
        nlohmann::json::parse(script_text(read_file(dir + "/face.html"), "vessel-meta"));
    const std::string face_command = face_meta["flatten_command"];
    CHECK(face_command.find("--viewpoint") == std::string::npos);
    CHECK(face_command.find("--html") != std::string::npos);
    CHECK(face_command.find(" -q") != std::string::npos);
    CHECK(face_meta["camera"].is_array());
    CHECK(test::run(std::string(VESSEL_VIEW_EXE) + " " + mesh + " -o " + dir + "/x.obj -q") != 0);
}

TEST_CASE("viewer: vessel-view --remove-caps opens SimVascular's capped demo model")
{
    const std::string dir = test::temp_dir("viewer-caps");
    const std::string mesh =
        std::string(VESSEL_SHARED_DATA) + "/simvascular-tests/demo-model-capped.vtp";
    const std::string view = std::string(VESSEL_VIEW_EXE) + " " + mesh + " -o " + dir;
    CHECK(test::run(view + "/closed.html -q 2> " + dir + "/err") != 0);
    CHECK(read_file(dir + "/err").find("(flat caps: vessel-flatten --remove-caps)") !=
          std::string::npos);
    if (!viewer_available())
        return;
    REQUIRE(test::run(view + "/open.html --remove-caps -q") == 0);
    const nlohmann::json meta =
        nlohmann::json::parse(script_text(read_file(dir + "/open.html"), "vessel-meta"));
    const std::string flatten = meta["flatten_command"];
    CHECK(flatten.find(" --remove-caps") != std::string::npos);
}

TEST_CASE("viewer: vessel-view shows the input's arrays and a --fields series, as vessel-flatten")
{
    const std::string dir = test::temp_dir("viewer-fields");
    const std::string view = std::string(VESSEL_VIEW_EXE) + " ";
    REQUIRE(test::run(std::string(VESSEL_PHANTOM_EXE) + " carotid --edge-length 1.0 -o " + dir +
                      "/carotid.ply --pulse " + dir + "/pulse --pulse-steps 12 -q") == 0);
    if (!viewer_available())
    {
        CHECK(test::run(view + dir + "/carotid.ply -o " + dir + "/v.html --fields " + dir +
                        "/pulse.pvd -q") != 0);
        return;
    }
    REQUIRE(test::run(view + dir + "/carotid.ply -o " + dir + "/v.html --fields " + dir +
                      "/pulse.csv --field WSS -q") == 0);
    const std::string html = read_file(dir + "/v.html");
    const nlohmann::json meta = nlohmann::json::parse(script_text(html, "vessel-meta"));
    REQUIRE(meta["fields"].size() == 2);  // geodesic distance + the series
    CHECK(meta["fields"][1]["name"] == "WSS");
    REQUIRE(meta["fields"][1]["times"].size() == 12);
    CHECK(meta["fields"][1]["times"][3].get<double>() == doctest::Approx(0.45));
    const std::string flatten = meta["flatten_command"];
    CHECK(flatten.find("-o carotid-flat.vtp --fields " + dir + "/pulse.csv --field WSS") !=
          std::string::npos);

    // Every cut vertex shows, at every step, the CSV value of the input vertex at its position
    // (seam copies included), to the page's 16-bit quantization.
    std::vector<std::vector<double>> table;  // [vertex][step]
    {
        std::ifstream csv(dir + "/pulse.csv");
        std::string line;
        std::getline(csv, line);
        while (std::getline(csv, line))
        {
            std::vector<double> row;
            std::stringstream cells(line);
            std::string cell;
            std::getline(cells, cell, ',');  // vertex id = row number
            while (std::getline(cells, cell, ','))
                row.push_back(std::stod(cell));
            table.push_back(row);
        }
    }
    const RawMesh input = read_raw_mesh(dir + "/carotid.ply");
    REQUIRE(table.size() == input.points.size());
    const auto positions = buffer<float>(html, "positions");
    const auto q = buffer<std::uint16_t>(html, "field1");
    const std::size_t nv = positions.size() / 3;
    REQUIRE(q.size() == 12 * nv);
    REQUIRE(nv > input.points.size());  // seam copies
    const double lo = meta["fields"][1]["lo"], hi = meta["fields"][1]["hi"];
    double worst = 0;
    for (std::size_t v = 0; v < nv; ++v)
    {
        Eigen::Vector3d p;
        for (int d = 0; d < 3; ++d)
            p[d] = positions[3 * v + d] + meta["centre"][d].get<double>();
        std::size_t nearest = 0;
        for (std::size_t i = 1; i < input.points.size(); ++i)
            if ((input.points[i] - p).squaredNorm() < (input.points[nearest] - p).squaredNorm())
                nearest = i;
        for (std::size_t s = 0; s < 12; ++s)
            worst = std::max(worst, std::abs(lo + q[s * nv + v] * (hi - lo) / 65535.0 -
                                             table[nearest][s]));
    }
    MESSAGE("largest difference from the CSV: ", worst, " (range ", hi - lo, ")");
    CHECK(worst <= (hi - lo) / 65535.0 + 1e-6 * hi);

    // The same series through vessel-flatten --html gives the same fields.
    REQUIRE(test::run(std::string(VESSEL_FLATTEN_EXE) + " " + dir + "/carotid.ply -o " + dir +
                      "/f.vtp --fields " + dir + "/pulse.pvd --html " + dir + "/f.html -q") == 0);
    const std::string flat_html = read_file(dir + "/f.html");
    const nlohmann::json flat_meta = nlohmann::json::parse(script_text(flat_html, "vessel-meta"));
    REQUIRE(flat_meta["fields"].size() == 2);
    CHECK(flat_meta["fields"][1]["name"] == "WSS");
    CHECK(buffer<std::uint16_t>(flat_html, "field1") == q);

    // A real .vtp input: its point array (Normals, a vector) is shown as its length.
    const std::string artery = std::string(VESSEL_SHARED_DATA) + "/vampy/artery.vtp";
    REQUIRE(test::run(view + artery + " -o " + dir + "/artery.html -q") == 0);
    const nlohmann::json artery_meta =
        nlohmann::json::parse(script_text(read_file(dir + "/artery.html"), "vessel-meta"));
    REQUIRE(artery_meta["fields"].size() == 2);
    CHECK(artery_meta["fields"][1]["name"] == "|Normals|");

    // A series of another mesh is refused with vessel-flatten's message; no page is written.
    CHECK(test::run(view + artery + " -o " + dir + "/bad.html --fields " + dir +
                    "/pulse.pvd -q 2> " + dir + "/err.txt") == 1);
    CHECK(read_file(dir + "/err.txt").find("the series was computed on another mesh") !=
          std::string::npos);
    CHECK_FALSE(std::ifstream(dir + "/bad.html").good());
}
