// The compiled part of the Python package `vessel` (python/vessel/__init__.py wraps it): reading
// a surface file, flattening points and faces with FlattenOptions set from keyword arguments, and
// the library's exceptions translated into the package's Python exception classes.
#include "../../tools/vessel_flatten/prepare.h"
#include "../../tools/vessel_flatten/report.h"
#include "vessel/core/errors.h"
#include "vessel/core/properties.h"
#include "vessel/io/io.h"
#include "vessel/io/vtk_io.h"
#include "vessel/layout/layout.h"
#include "vessel/phantom/phantom.h"
#include "vessel/pipeline.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace py = pybind11;

namespace {

// The Python classes the library's exceptions become (set by vessel/__init__.py, which defines
// them with the built-in exception each one is like: InvalidInputError is a ValueError).
struct ExceptionClasses
{
    py::object invalid_input, topology, solver, io;
};

ExceptionClasses& exception_classes()
{
    // Never destroyed: Python objects must not be released after the interpreter has ended.
    static auto* classes = new ExceptionClasses;
    return *classes;
}

void set_exceptions(py::object invalid_input, py::object topology, py::object solver,
                    py::object io)
{
    exception_classes() = {std::move(invalid_input), std::move(topology), std::move(solver),
                           std::move(io)};
}

void translate(std::exception_ptr p)
{
    const ExceptionClasses& c = exception_classes();
    const auto raise = [](const py::object& cls, PyObject* fallback, const char* what) {
        PyErr_SetString(cls ? cls.ptr() : fallback, what);
    };
    try
    {
        if (p)
            std::rethrow_exception(p);
    }
    catch (const vessel::InvalidInputError& e)
    {
        raise(c.invalid_input, PyExc_ValueError, e.what());
    }
    catch (const vessel::TopologyError& e)
    {
        raise(c.topology, PyExc_RuntimeError, e.what());
    }
    catch (const vessel::SolverError& e)
    {
        raise(c.solver, PyExc_RuntimeError, e.what());
    }
    catch (const vessel::IoError& e)
    {
        raise(c.io, PyExc_OSError, e.what());
    }
}

using Array2d = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Array2i = py::array_t<long long, py::array::c_style | py::array::forcecast>;

std::string shape_text(const py::array& a)
{
    std::string s = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i)
        s += (i ? ", " : "") + std::to_string(a.shape(i));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

vessel::RawMesh raw_mesh(const Array2d& points, const Array2i& faces)
{
    if (points.ndim() != 2 || points.shape(1) != 3)
        throw vessel::InvalidInputError("points must be an (n, 3) array of coordinates, got shape " +
                                        shape_text(points));
    if (faces.ndim() != 2 || faces.shape(1) != 3)
        throw vessel::InvalidInputError("faces must be an (m, 3) array of triangle corner indices "
                                        "into points, got shape " + shape_text(faces));
    vessel::RawMesh raw;
    const auto p = points.unchecked<2>();
    raw.points.reserve(static_cast<std::size_t>(p.shape(0)));
    for (py::ssize_t i = 0; i < p.shape(0); ++i)
        raw.points.emplace_back(p(i, 0), p(i, 1), p(i, 2));
    const auto f = faces.unchecked<2>();
    const long long n = p.shape(0);
    raw.faces.reserve(static_cast<std::size_t>(f.shape(0)));
    for (py::ssize_t i = 0; i < f.shape(0); ++i)
    {
        std::vector<int> corners(3);
        for (int k = 0; k < 3; ++k)
        {
            if (f(i, k) < 0 || f(i, k) >= n)
                throw vessel::InvalidInputError(
                    "faces[" + std::to_string(i) + "] has corner " + std::to_string(f(i, k)) +
                    ", outside the " + std::to_string(n) + " points (indices are 0-based)");
            corners[static_cast<std::size_t>(k)] = static_cast<int>(f(i, k));
        }
        raw.faces.push_back(std::move(corners));
    }
    return raw;
}

// ---------------------------------------------------------------------------------------------
// Keyword options: the names of vessel-flatten's flags with '_' for '-', so that a command line
// and a Python call read alike (README.md, "vessel-flatten").

struct CallOptions
{
    vessel::FlattenOptions flatten;
    vessel::TreeSurfaceOptions surface;
    std::string layout = "fan";
};

template <typename T>
T option_value(const std::string& name, py::handle value, const char* expected)
{
    try
    {
        return value.cast<T>();
    }
    catch (const py::cast_error&)
    {
        throw py::type_error("option '" + name + "' must be " + expected + ", got " +
                             std::string(py::str(py::type::handle_of(value).attr("__name__"))));
    }
}

// A keyword whose value is one of several names, each setting an enum (or a flag) in the options.
template <typename T>
std::function<void(CallOptions&, const std::string&, py::handle)> choice(
    std::map<std::string, T> values, std::function<T&(CallOptions&)> field)
{
    return [values = std::move(values), field](CallOptions& o, const std::string& name,
                                               py::handle value) {
        const std::string v = option_value<std::string>(name, value, "a string");
        const auto it = values.find(v);
        if (it == values.end())
        {
            std::string known;
            for (const auto& [key, unused] : values)
                known += (known.empty() ? "" : ", ") + key;
            throw vessel::InvalidInputError("option " + name + "='" + v + "' is not one of " +
                                            known);
        }
        field(o) = it->second;
    };
}

template <typename T>
std::function<void(CallOptions&, const std::string&, py::handle)> number(
    std::function<T&(CallOptions&)> field)
{
    return [field](CallOptions& o, const std::string& name, py::handle value) {
        if (py::isinstance<py::bool_>(value))
            throw py::type_error("option '" + name + "' must be a number, got bool");
        field(o) = option_value<T>(name, value, "a number");
    };
}

std::function<void(CallOptions&, const std::string&, py::handle)> flag(
    std::function<bool&(CallOptions&)> field)
{
    return [field](CallOptions& o, const std::string& name, py::handle value) {
        field(o) = option_value<bool>(name, value, "True or False");
    };
}

using Setter = std::function<void(CallOptions&, const std::string&, py::handle)>;
using F = vessel::FlattenOptions;

const std::map<std::string, Setter>& setters()
{
    using vessel::CostKind;
    static const std::map<std::string, Setter> table = {
        {"cost", choice<CostKind>({{"curvature", CostKind::Curvature},
                                   {"geodesic", CostKind::Geodesic},
                                   {"blend", CostKind::Blend}},
                                  [](CallOptions& o) -> CostKind& { return o.flatten.cost.kind; })},
        {"blend", number<double>([](CallOptions& o) -> double& { return o.flatten.cost.blend; })},
        {"viewpoint",
         [](CallOptions& o, const std::string& name, py::handle value) {
             if (py::isinstance<py::str>(value))
             {
                 const std::string word = value.cast<std::string>();
                 if (word != "face-on")
                     throw vessel::InvalidInputError("option viewpoint must be 3 numbers (x, y, "
                                                     "z) or \"face-on\", got \"" + word + "\"");
                 o.flatten.cost.face_on = true;
                 return;
             }
             const auto p = option_value<std::vector<double>>(name, value, "3 numbers or \"face-on\"");
             if (p.size() != 3)
                 throw vessel::InvalidInputError("option viewpoint must be 3 numbers (x, y, z), "
                                                 "got " + std::to_string(p.size()));
             o.flatten.cuts.endpoints = std::make_shared<vessel::FarSideEndpoints>(
                 Eigen::Vector3d(p[0], p[1], p[2]));
             o.flatten.cost.viewpoint = Eigen::Vector3d(p[0], p[1], p[2]);
         }},
        {"alpha", number<double>([](CallOptions& o) -> double& { return o.flatten.alpha_deg; })},
        {"layout", [](CallOptions& o, const std::string& name, py::handle value) {
             o.layout = option_value<std::string>(name, value, "a string");
         }},
        {"curvature_scale",
         number<double>([](CallOptions& o) -> double& { return o.flatten.curvature.scale; })},
        {"arap_iterations",
         number<int>([](CallOptions& o) -> int& { return o.flatten.arap.max_iterations; })},
        {"slim_iterations",
         number<int>([](CallOptions& o) -> int& { return o.flatten.injective.max_iterations; })},
        {"slim_momentum",
         number<double>([](CallOptions& o) -> double& { return o.flatten.injective.momentum; })},
        {"scaffold_tolerance", number<double>([](CallOptions& o) -> double& {
             return o.flatten.injective.scaffold_tolerance;
         })},
        {"crossing_patience", number<int>([](CallOptions& o) -> int& {
             return o.flatten.injective.crossing_patience;
         })},
        {"refine", choice<vessel::Refinement>(
                       {{"injective", vessel::Refinement::Injective},
                        {"arap", vessel::Refinement::Arap},
                        {"none", vessel::Refinement::None}},
                       [](CallOptions& o) -> vessel::Refinement& { return o.flatten.refinement; })},
        {"overlaps", choice<vessel::OverlapPolicy>(
                         {{"prevent", vessel::OverlapPolicy::Prevent},
                          {"restart", vessel::OverlapPolicy::Restart},
                          {"keep", vessel::OverlapPolicy::Keep}},
                         [](CallOptions& o) -> vessel::OverlapPolicy& {
                             return o.flatten.overlaps;
                         })},
        {"restart_circle",
         choice<bool>({{"layout", true}, {"tutte", false}},
                      [](CallOptions& o) -> bool& { return o.flatten.restart_on_layout_circle; })},
        {"look_pull", number<double>([](CallOptions& o) -> double& { return o.flatten.look_pull.weight; })},
        {"look_pull_form",
         choice<vessel::LookPullForm>(
             {{"hinges", vessel::LookPullForm::Hinges}, {"rays", vessel::LookPullForm::Rays}},
             [](CallOptions& o) -> vessel::LookPullForm& { return o.flatten.look_pull.form; })},
        {"look_hold", number<double>([](CallOptions& o) -> double& { return o.flatten.look_pull.hold; })},
        {"look_margin",
         number<double>([](CallOptions& o) -> double& { return o.flatten.look_pull.margin_deg; })},
        {"look_retry", choice<vessel::LookRetry>(
                           {{"auto", vessel::LookRetry::Auto},
                            {"off", vessel::LookRetry::Off},
                            {"force", vessel::LookRetry::Force}},
                           [](CallOptions& o) -> vessel::LookRetry& {
                               return o.flatten.look_retry.mode;
                           })},
        {"look_retry_pull",
         number<double>([](CallOptions& o) -> double& { return o.flatten.look_retry.pull; })},
        {"look_retry_inversions", number<double>([](CallOptions& o) -> double& {
             return o.flatten.look_retry.max_walk_inversion_fraction;
         })},
        {"look_retry_area", number<double>([](CallOptions& o) -> double& {
             return o.flatten.look_retry.max_area_over_keep;
         })},
        // area_polish=LAMBDA turns the polish on with that weight; area_polish=False turns it off.
        {"area_polish",
         [](CallOptions& o, const std::string& name, py::handle value) {
             if (py::isinstance<py::bool_>(value))
             {
                 o.flatten.polish_area = value.cast<bool>();
                 return;
             }
             o.flatten.polish_area = true;
             o.flatten.area_polish.area_weight = option_value<double>(name, value, "a number or False");
         }},
        {"arap_solver", choice<vessel::ArapSolver>(
                            {{"local-global", vessel::ArapSolver::LocalGlobal},
                             {"ceres", vessel::ArapSolver::Ceres}},
                            [](CallOptions& o) -> vessel::ArapSolver& {
                                return o.flatten.arap.solver;
                            })},
        {"init", choice<vessel::Initialization>(
                     {{"layout-lscm", vessel::Initialization::LayoutLscm},
                      {"spectral", vessel::Initialization::SpectralConformal},
                      {"tutte", vessel::Initialization::Tutte}},
                     [](CallOptions& o) -> vessel::Initialization& {
                         return o.flatten.initialization;
                     })},
        {"direction_confidence", number<double>([](CallOptions& o) -> double& {
             return o.flatten.direction.confident_anisotropy;
         })},
        {"cut_route", choice<vessel::CutRoute>(
                          {{"aligned", vessel::CutRoute::Aligned},
                           {"streamline", vessel::CutRoute::Streamline},
                           {"shortest", vessel::CutRoute::ShortestPath}},
                          [](CallOptions& o) -> vessel::CutRoute& { return o.flatten.cuts.route; })},
        {"stream_field", choice<vessel::StreamField>(
                             {{"harmonic", vessel::StreamField::Harmonic},
                              {"direction", vessel::StreamField::Direction}},
                             [](CallOptions& o) -> vessel::StreamField& {
                                 return o.flatten.cuts.stream_field;
                             })},
        {"band_rings", number<int>([](CallOptions& o) -> int& { return o.flatten.cuts.band_rings; })},
        {"join_rings", number<int>([](CallOptions& o) -> int& { return o.flatten.cuts.join_rings; })},
        {"join", choice<vessel::CutJoin>({{"approach", vessel::CutJoin::Approach},
                                          {"cheapest", vessel::CutJoin::Cheapest},
                                          {"closest", vessel::CutJoin::Closest}},
                                         [](CallOptions& o) -> vessel::CutJoin& {
                                             return o.flatten.cuts.join;
                                         })},
        {"join_slack",
         number<double>([](CallOptions& o) -> double& { return o.flatten.cuts.join_slack; })},
        {"join_reach",
         number<double>([](CallOptions& o) -> double& { return o.flatten.cuts.join_reach; })},
        {"join_excess",
         number<double>([](CallOptions& o) -> double& { return o.flatten.cuts.join_excess; })},
        {"tie_tolerance",
         number<double>([](CallOptions& o) -> double& { return o.flatten.cuts.tie_tolerance; })},
        {"natural_cuts",
         flag([](CallOptions& o) -> bool& { return o.flatten.cuts.natural_cuts; })},
        {"relief_cuts",
         number<int>([](CallOptions& o) -> int& { return o.flatten.relief.max_cuts; })},
        {"relief_target", number<double>([](CallOptions& o) -> double& {
             return o.flatten.relief.target_mean_abs_log_area;
         })},
        {"largest_component", flag([](CallOptions& o) -> bool& {
             return o.surface.keep_largest_component;
         })},
        {"remove_caps",
         flag([](CallOptions& o) -> bool& { return o.surface.remove_flat_caps; })},
        {"refuse_polygons",
         [](CallOptions& o, const std::string& name, py::handle value) {
             o.surface.triangulate_polygons = !option_value<bool>(name, value, "True or False");
         }},
    };
    return table;
}

// The named starting points of the options; keywords then change single fields.
const std::map<std::string, std::function<vessel::FlattenOptions()>>& presets()
{
    static const std::map<std::string, std::function<vessel::FlattenOptions()>> table = {
        {"default", [] { return vessel::FlattenOptions{}; }},
        {"paper", [] { return vessel::FlattenOptions::paper(); }},
    };
    return table;
}

CallOptions call_options(const std::string& preset, const py::dict& kwargs)
{
    const auto p = presets().find(preset);
    if (p == presets().end())
    {
        std::string known;
        for (const auto& [key, unused] : presets())
            known += (known.empty() ? "" : ", ") + key;
        throw vessel::InvalidInputError("unknown preset '" + preset + "'; known presets: " + known);
    }
    CallOptions o;
    o.flatten = p->second();
    for (const auto& [key, value] : kwargs)
    {
        const std::string name = py::str(key);
        const auto s = setters().find(name);
        if (s == setters().end())
            throw py::type_error("flatten() got an unknown option '" + name +
                                 "'; see vessel.flatten_options() for the known ones");
        s->second(o, name, value);
    }
    o.flatten.layout = vessel::make_layout(o.layout, o.flatten.alpha_deg);
    o.flatten.validate();
    return o;
}

std::vector<std::string> option_names()
{
    std::vector<std::string> names;
    for (const auto& [key, unused] : setters())
        names.push_back(key);
    return names;
}

std::vector<std::string> preset_names()
{
    std::vector<std::string> names;
    for (const auto& [key, unused] : presets())
        names.push_back(key);
    return names;
}

// ---------------------------------------------------------------------------------------------

py::array_t<double> field_array(const vessel::Field& field)
{
    const auto rows = static_cast<py::ssize_t>(field.values.rows());
    const auto cols = static_cast<py::ssize_t>(field.values.cols());
    std::vector<py::ssize_t> shape = {rows};  // scalars (n,), vectors and tensors (n, c)
    if (cols != 1)
        shape.push_back(cols);
    py::array_t<double> a(shape);
    double* out = a.mutable_data();
    for (py::ssize_t i = 0; i < rows; ++i)
        for (py::ssize_t k = 0; k < cols; ++k)
            out[i * cols + k] = field.values(i, k);
    return a;
}

py::dict field_dict(const std::vector<vessel::Field>& fields)
{
    py::dict d;
    for (const auto& f : fields)
        d[py::str(f.name)] = field_array(f);
    return d;
}

// Points, polygon corners (flat, with offsets) and the data arrays, as read() returns them.
py::dict surface_dict(const vessel::PolyData& data)
{
    const auto n = static_cast<py::ssize_t>(data.mesh.points.size());
    py::array_t<double> points({n, py::ssize_t{3}});
    auto p = points.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k)
            p(i, k) = data.mesh.points[static_cast<std::size_t>(i)][k];
    std::vector<long long> corners, offsets = {0};
    for (const auto& face : data.mesh.faces)
    {
        corners.insert(corners.end(), face.begin(), face.end());
        offsets.push_back(static_cast<long long>(corners.size()));
    }
    py::dict out;
    out["points"] = points;
    out["corners"] = py::array_t<long long>(static_cast<py::ssize_t>(corners.size()), corners.data());
    out["offsets"] = py::array_t<long long>(static_cast<py::ssize_t>(offsets.size()), offsets.data());
    out["point_data"] = field_dict(data.point_data);
    out["cell_data"] = field_dict(data.cell_data);
    return out;
}

py::dict read_surface(const std::string& path)
{
    vessel::PolyData data;
    {
        py::gil_scoped_release unlocked;
        if (vessel::is_vtk_path(path))
            data = vessel::read_polydata(path);
        else
            data.mesh = vessel::read_raw_mesh(path);
    }
    return surface_dict(data);
}

// A generated surface (phantom.h), made with the GIL released.
template <typename Make>
py::dict generated(const Make& make)
{
    vessel::PolyData data;
    {
        py::gil_scoped_release unlocked;
        data.mesh = vessel::to_raw_mesh(make());
    }
    return surface_dict(data);
}

py::dict carotid_phantom(double stenosis, double edge_length)
{
    vessel::CarotidPhantomOptions options;
    options.stenosis = stenosis;
    options.edge_length = edge_length;
    return generated([&] { return vessel::carotid_phantom(options); });
}

py::dict aneurysm_phantom(double sac_radius, double edge_length)
{
    vessel::AneurysmPhantomOptions options;
    options.sac_radius = sac_radius;
    options.edge_length = edge_length;
    return generated([&] { return vessel::aneurysm_phantom(options); });
}

py::dict tree_phantom(int outlets, std::uint32_t seed, double edge_length)
{
    vessel::TreePhantomOptions options;
    options.outlets = outlets;
    options.seed = seed;
    options.edge_length = edge_length;
    return generated([&] { return vessel::tree_phantom(options); });
}

// An `int` vertex or face property of the cut mesh (PropHandle: OpenMesh::VPropHandleT<int> or
// FPropHandleT<int>), row `idx()` of each element.
template <typename PropHandle, typename Elements>
py::array_t<long long> int_property(const vessel::Mesh& mesh, const char* property,
                                    const Elements& elements, std::size_t count)
{
    PropHandle h;
    if (!mesh.get_property_handle(h, property))
        throw vessel::InvalidInputError(std::string("the cut mesh has no '") + property +
                                        "' property");
    py::array_t<long long> a(static_cast<py::ssize_t>(count));
    long long* out = a.mutable_data();
    for (const auto e : elements)
        out[e.idx()] = mesh.property(h, e);
    return a;
}

// The vertices of a cut, outlet to end, as indices of the input points.
py::array_t<long long> cut_vertices(const vessel::Mesh& mesh, const vessel::CutPath& path,
                                    const py::array_t<long long>& origin)
{
    std::vector<long long> v;
    const auto o = origin.unchecked<1>();
    for (const auto h : path.halfedges)
        v.push_back(o(mesh.from_vertex_handle(h).idx()));
    if (!path.halfedges.empty())
        v.push_back(o(mesh.to_vertex_handle(path.halfedges.back()).idx()));
    return py::array_t<long long>(static_cast<py::ssize_t>(v.size()), v.data());
}

py::dict flatten_arrays(const Array2d& points, const Array2i& faces, const std::string& preset,
                 const py::dict& kwargs)
{
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    CallOptions o = call_options(preset, kwargs);
    vessel::RawMesh raw = raw_mesh(points, faces);
    vessel::cli::PreparedInput in;
    vessel::FlattenResult r;
    std::string report;
    {
        py::gil_scoped_release unlocked;
        in = vessel::cli::prepare_input(std::move(raw), o.surface, std::nullopt);
        const double read_s = std::chrono::duration<double>(Clock::now() - start).count();
        r = vessel::flatten(in.surface.mesh, o.flatten);
        report = vessel::cli::report_json("<numpy arrays>", in, r, read_s, 0.0).dump();
    }
    const vessel::Mesh& mesh = r.mesh;
    const auto n = static_cast<py::ssize_t>(mesh.n_vertices());
    const auto m = static_cast<py::ssize_t>(mesh.n_faces());
    py::array_t<double> cut_points({n, py::ssize_t{3}});
    py::array_t<double> uv({n, py::ssize_t{2}});
    auto p = cut_points.mutable_unchecked<2>();
    auto t = uv.mutable_unchecked<2>();
    for (const auto v : mesh.vertices())
        for (int k = 0; k < 3; ++k)
        {
            p(v.idx(), k) = mesh.point(v)[k];
            if (k < 2)
                t(v.idx(), k) = r.uv(v.idx(), k);
        }
    py::array_t<long long> cut_faces({m, py::ssize_t{3}});
    auto f = cut_faces.mutable_unchecked<2>();
    for (const auto face : mesh.faces())
    {
        int k = 0;
        for (const auto v : face.vertices())
            f(face.idx(), k++) = v.idx();
    }
    const py::array_t<long long> origin = int_property<OpenMesh::VPropHandleT<int>>(
        mesh, vessel::prop::input_index, mesh.vertices(), mesh.n_vertices());
    py::list cuts, relief;
    for (const auto& path : r.plan.paths)
        cuts.append(cut_vertices(mesh, path, origin));
    for (const auto& path : r.plan.relief)
        relief.append(cut_vertices(mesh, path, origin));
    py::dict out;
    out["points"] = cut_points;
    out["faces"] = cut_faces;
    out["uv"] = uv;
    out["origin"] = origin;
    out["face_origin"] = int_property<OpenMesh::FPropHandleT<int>>(
        mesh, vessel::prop::input_face, mesh.faces(), mesh.n_faces());
    out["cut_vertices"] = cuts;
    out["relief_vertices"] = relief;
    out["report"] = report;
    out["input_points"] = points.shape(0);
    out["input_faces"] = faces.shape(0);
    return out;
}

}  // namespace

PYBIND11_MODULE(_vessel, m)
{
    m.doc() = "The compiled core of the vessel package; use the functions of `vessel` itself.";
    py::register_exception_translator(&translate);
    m.def("_set_exceptions", &set_exceptions);
    m.def("read", &read_surface, py::arg("path"));
    m.def("flatten", &flatten_arrays, py::arg("points"), py::arg("faces"), py::arg("preset"),
          py::arg("options"));
    m.def("aneurysm_phantom", &aneurysm_phantom, py::arg("sac_radius"), py::arg("edge_length"));
    m.def("carotid_phantom", &carotid_phantom, py::arg("stenosis"), py::arg("edge_length"));
    m.def("tree_phantom", &tree_phantom, py::arg("outlets"), py::arg("seed"),
          py::arg("edge_length"));
    m.def("option_names", &option_names);
    m.def("preset_names", &preset_names);
}
