#include "vessel/render/viewer.h"

#include "detail/atomic_file.h"
#include "detail/viewer_bundle.h"
#include "vessel/core/errors.h"
#include "vessel/core/properties.h"
#include "detail/uv_rows.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace vessel {

namespace {

std::string base64(const void* data, std::size_t size)
{
    static const char* const table =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const auto* bytes = static_cast<const unsigned char*>(data);
    std::string out;
    out.reserve((size + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 2 < size; i += 3)
    {
        const std::uint32_t n = (bytes[i] << 16) | (bytes[i + 1] << 8) | bytes[i + 2];
        for (int shift : {18, 12, 6, 0})
            out += table[(n >> shift) & 63];
    }
    if (i < size)
    {
        const std::uint32_t n = (bytes[i] << 16) | (i + 1 < size ? bytes[i + 1] << 8 : 0);
        out += table[(n >> 18) & 63];
        out += table[(n >> 12) & 63];
        out += i + 1 < size ? table[(n >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

// A JSON string literal that is also safe inside a <script> element.
std::string json_string(const std::string& s)
{
    std::string out = "\"";
    for (unsigned char c : s)
    {
        if (c == '"' || c == '\\')
            out += {'\\', static_cast<char>(c)};
        else if (c < 0x20 || c == '<' || c == '>' || c == '&')
        {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out += buf;
        }
        else
            out += static_cast<char>(c);
    }
    return out + "\"";
}

std::string json_number(double x)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", x);
    return buf;
}

void check_field(const ViewerField& field, std::size_t index, std::size_t n_vertices)
{
    const std::string who =
        "write_viewer_html: field " + std::to_string(index) + " ('" + field.name + "')";
    if (field.name.empty())
        throw InvalidInputError(who + " has no name; set ViewerField::name");
    if (field.steps.empty() || field.steps.size() != field.times.size())
        throw InvalidInputError(who + " has " + std::to_string(field.steps.size()) + " steps and " +
                                std::to_string(field.times.size()) +
                                " times; give one time per step (at least one)");
    for (std::size_t i = 0; i < field.times.size(); ++i)
    {
        if (!std::isfinite(field.times[i]) || (i > 0 && field.times[i] <= field.times[i - 1]))
            throw InvalidInputError(who + ": times must be finite and strictly increasing (step " +
                                    std::to_string(i) + ")");
        if (static_cast<std::size_t>(field.steps[i].size()) != n_vertices)
            throw InvalidInputError(who + ": step " + std::to_string(i) + " has " +
                                    std::to_string(field.steps[i].size()) + " values for " +
                                    std::to_string(n_vertices) + " cut-mesh vertices");
        if (!field.steps[i].allFinite())
            throw InvalidInputError(who + ": step " + std::to_string(i) +
                                    " has NaN or infinite values");
    }
}

// The field's range and its values as 16-bit fractions of that range, step after step.
std::vector<std::uint16_t> quantize(const ViewerField& field, double& lo, double& hi)
{
    lo = field.steps[0].minCoeff();
    hi = field.steps[0].maxCoeff();
    for (const auto& step : field.steps)
    {
        lo = std::min<double>(lo, step.minCoeff());
        hi = std::max<double>(hi, step.maxCoeff());
    }
    const double scale = hi > lo ? 65535.0 / (hi - lo) : 0.0;
    std::vector<std::uint16_t> q;
    q.reserve(field.steps.size() * field.steps[0].size());
    for (const auto& step : field.steps)
        for (Eigen::Index i = 0; i < step.size(); ++i)
            q.push_back(static_cast<std::uint16_t>(std::lround((step[i] - lo) * scale)));
    return q;
}

// Unit vertex normals averaged over the input vertex each cut vertex came from, so that the
// shading is smooth across the seam.
std::vector<float> smooth_normals(const Mesh& mesh)
{
    OpenMesh::VPropHandleT<int> origin;
    const bool has_origin = mesh.get_property_handle(origin, prop::origin);
    auto key = [&](VertexHandle v) { return has_origin ? mesh.property(origin, v) : v.idx(); };
    int n_keys = 0;
    for (auto v : mesh.vertices())
        n_keys = std::max(n_keys, key(v) + 1);
    std::vector<Eigen::Vector3d> sum(n_keys, Eigen::Vector3d::Zero());
    for (auto f : mesh.faces())
    {
        auto h = f.halfedge();
        const Eigen::Vector3d a = to_eigen(mesh.point(h.from())), b = to_eigen(mesh.point(h.to())),
                              c = to_eigen(mesh.point(h.next().to()));
        const Eigen::Vector3d n = (b - a).cross(c - a);
        for (auto v : f.vertices())
            sum[key(v)] += n;
    }
    std::vector<float> normals;
    normals.reserve(3 * mesh.n_vertices());
    for (auto v : mesh.vertices())
    {
        const Eigen::Vector3d n = sum[key(v)].normalized();
        for (int d = 0; d < 3; ++d)
            normals.push_back(std::isfinite(n[d]) ? static_cast<float>(n[d]) : 0.0f);
    }
    return normals;
}

template <class T>
void write_buffer(std::ostream& out, const std::string& name, const std::vector<T>& values)
{
    out << "<script type=\"application/octet-stream\" id=\"vessel-buffer-" << name << "\">"
        << base64(values.data(), values.size() * sizeof(T)) << "</script>\n";
}

}  // namespace

void ViewerOptions::validate() const
{
    if (viewpoint && !viewpoint->allFinite())
        throw InvalidInputError("ViewerOptions::viewpoint must be finite");
}

bool viewer_available()
{
    return !detail::viewer_bundle().empty();
}

void write_viewer_html(const std::string& path, const FlattenResult& result,
                       const std::vector<ViewerField>& fields, const ViewerOptions& options)
{
    options.validate();
    const Mesh& mesh = result.mesh;
    const std::size_t nv = mesh.n_vertices();
    if (fields.empty())
        throw InvalidInputError(
            "write_viewer_html: no fields; pass at least one, e.g. "
            "geodesic_field(result)");
    detail::require_uv_rows(mesh, result.uv, "write_viewer_html");
    for (std::size_t i = 0; i < fields.size(); ++i)
        check_field(fields[i], i, nv);
    const std::string bundle = detail::viewer_bundle();
    if (bundle.empty())
        throw IoError(
            "write_viewer_html: libvessel was built without the viewer (node and npm "
            "were not found); install nodejs and npm and rebuild");

    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
    for (auto v : mesh.vertices())
    {
        lo = lo.cwiseMin(to_eigen(mesh.point(v)));
        hi = hi.cwiseMax(to_eigen(mesh.point(v)));
    }
    const Eigen::Vector3d centre = nv ? Eigen::Vector3d((lo + hi) / 2) : Eigen::Vector3d::Zero();
    // Float32 positions relative to the centre keep full precision for meshes far from the origin.
    std::vector<float> positions, uv, seam;
    for (auto v : mesh.vertices())
    {
        const Eigen::Vector3d p = to_eigen(mesh.point(v)) - centre;
        positions.insert(positions.end(), {float(p.x()), float(p.y()), float(p.z())});
        uv.insert(uv.end(), {float(result.uv(v.idx(), 0)), float(result.uv(v.idx(), 1))});
    }
    std::vector<std::uint32_t> indices;
    for (auto f : mesh.faces())
        for (auto v : f.vertices())
            indices.push_back(static_cast<std::uint32_t>(v.idx()));
    for (const auto* paths : {&result.plan.paths, &result.plan.relief})
        for (const auto& path_ : *paths)
            for (auto h : path_.halfedges)
                for (auto v : {mesh.from_vertex_handle(h), mesh.to_vertex_handle(h)})
                {
                    const Eigen::Vector3d p = to_eigen(mesh.point(v)) - centre;
                    seam.insert(seam.end(), {float(p.x()), float(p.y()), float(p.z())});
                }

    std::ostringstream meta;
    meta << "{\"title\":" << json_string(options.title)
         << ",\"flatten_command\":" << json_string(options.flatten_command)
         << ",\"view_command\":" << json_string(options.view_command) << ",\"centre\":["
         << json_number(centre.x()) << "," << json_number(centre.y()) << ","
         << json_number(centre.z()) << "],\"camera\":";
    if (options.viewpoint && (*options.viewpoint - centre).norm() > 0)
    {
        const Eigen::Vector3d d = (*options.viewpoint - centre).normalized();
        meta << "[" << json_number(d.x()) << "," << json_number(d.y()) << "," << json_number(d.z())
             << "]";
    }
    else
        meta << "null";
    meta << ",\"fields\":[";

    detail::TempFile temp(path, "write_viewer_html");
    const std::string& tmp = temp.path();
    {
        std::ofstream out(tmp, std::ios::binary);
        if (!out)
            throw IoError("write_viewer_html: cannot open " + tmp + " for writing");
        out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
               "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
               "<title>libvessel viewer</title>\n</head>\n<body>\n";
        write_buffer(out, "positions", positions);
        write_buffer(out, "normals", smooth_normals(mesh));
        write_buffer(out, "uv", uv);
        write_buffer(out, "indices", indices);
        write_buffer(out, "seam", seam);
        for (std::size_t i = 0; i < fields.size(); ++i)
        {
            double field_lo = 0, field_hi = 0;
            write_buffer(out, "field" + std::to_string(i), quantize(fields[i], field_lo, field_hi));
            meta << (i ? "," : "") << "{\"name\":" << json_string(fields[i].name)
                 << ",\"unit\":" << json_string(fields[i].unit)
                 << ",\"lo\":" << json_number(field_lo) << ",\"hi\":" << json_number(field_hi)
                 << ",\"colormap\":"
                 << (fields[i].diverging ? "\"blue-white-red (diverging)\"" : "\"viridis\"")
                 << ",\"times\":[";
            for (std::size_t k = 0; k < fields[i].times.size(); ++k)
                meta << (k ? "," : "") << json_number(fields[i].times[k]);
            meta << "]}";
        }
        meta << "]}";
        out << "<script type=\"application/json\" id=\"vessel-meta\">" << meta.str()
            << "</script>\n<script>" << bundle << "</script>\n</body>\n</html>\n";
        out.close();
        if (!out)
            throw IoError("write_viewer_html: cannot write " + tmp + " (for " + path +
                          "); check the free space and the file size limit");
    }
    temp.commit();
}

}  // namespace vessel
