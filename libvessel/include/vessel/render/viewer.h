#pragma once

#include "vessel/pipeline.h"

#include <optional>
#include <string>
#include <vector>

namespace vessel {

//! One scalar field on the cut mesh, static or over time, for the HTML viewer.
struct ViewerField
{
    std::string name;  //!< shown in the field selector, e.g. "pressure"
    std::string unit;  //!< e.g. "mm", "Pa"; may be empty
    //! Time of every step in seconds, strictly increasing; a static field has one entry.
    std::vector<double> times;
    //! One vector per time step, |V_cut| values each, entry `v.idx()` of FlattenResult::mesh.
    std::vector<Eigen::VectorXf> steps;
    //! Start with the diverging colormap and a range symmetric about 0 (signed fields).
    bool diverging = false;
};

struct ViewerOptions
{
    std::string title = "libvessel viewer";  //!< page title
    //! The command that re-flattens this input; the page appends `--viewpoint X Y Z` of its
    //! current 3D camera (mesh units) and shows the result with a copy button.
    std::string flatten_command = "vessel-flatten INPUT -o OUT.obj";
    //! The same for a new page (shown as a tooltip of the command).
    std::string view_command = "vessel-view INPUT -o OUT.html";
    //! The viewpoint the cuts were made with, if any: the 3D camera starts there.
    std::optional<Eigen::Vector3d> viewpoint;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! True when the library was built with the viewer's JavaScript bundle (node and npm were found
//! at build time); write_viewer_html() needs it.
bool viewer_available();

//! \brief Write one self-contained HTML page (no network access needed) showing \p result in
//! linked 3D and flattened views, with every field colormapped on both and animated over time.
//! Positions, map, triangles, seam and fields are embedded as base64 typed arrays (fields
//! quantized to 16 bits over their own range, i.e. to 1.5e-5 of it).
//! \param fields at least one; every step has |V_cut| finite values.
//! \throw InvalidInputError if a field is malformed (the message names it and the step).
//! \throw IoError if the library has no viewer bundle or the file cannot be written; a failed
//! run never leaves a partial file.
void write_viewer_html(const std::string& path, const FlattenResult& result,
                       const std::vector<ViewerField>& fields, const ViewerOptions& options = {});

//! The heat-method geodesic distance from the inlet (`prop::geodesic`), a static field in mesh
//! units. \throw InvalidInputError if the mesh has no such property.
ViewerField geodesic_field(const FlattenResult& result, const std::string& unit = "");

//! A synthetic travelling wave for trying the viewer without CFD data.
struct PulseOptions
{
    int steps = 90;            //!< time steps over one period
    double period_s = 1.8;     //!< one heart cycle, seconds
    double wavelengths = 1.5;  //!< waves along the longest geodesic distance from the inlet
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! \brief `sin(2 pi (t / period - wavelengths * d / d_max))` with d the geodesic distance from
//! the inlet: a wave leaving the inlet and travelling down every branch, values in [-1, 1].
//! \throw InvalidInputError if options are invalid or the mesh has no `prop::geodesic`.
ViewerField pulse_field(const FlattenResult& result, const PulseOptions& options = {});

}  // namespace vessel
