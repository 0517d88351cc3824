#pragma once

#include "vessel/cut/boundary.h"
#include "vessel/core/mesh.h"

#include <string>
#include <vector>

namespace vessel {

//! \file Publication images of a scalar field on the flattened map (PNG, SVG or PDF), with a
//! colorbar, the map's outline, labelled inlet and outlets and, optionally, the 3D cut mesh
//! beside it. Rendering uses cairo, which stays out of this header.

//! Colour tables (256 entries each).
enum class Colormap
{
    Auto,      //!< Diverging when the range used straddles 0, Viridis otherwise
    Viridis,   //!< perceptually uniform sequential map (matplotlib's, CC0)
    Diverging  //!< Moreland's cool-warm: blue below the middle, grey at it, red above
};

//! \brief Colour of \p t in [0, 1] (clamped) under \p map, linearly interpolated between the 256
//! table entries; RGB in [0, 1]. Colormap::Auto is treated as Viridis.
Eigen::Vector3d colormap_rgb(Colormap map, double t);

struct MapImageOptions
{
    int width_px = 1200;  //!< image width (for SVG/PDF: points)
    int height_px = 800;  //!< image height
    int margin_px = 24;   //!< free border around the panels
    //! Colour table; Auto picks Diverging when the range straddles 0 (the range is then made
    //! symmetric, [-m, m], unless fixed), Viridis otherwise.
    Colormap colormap = Colormap::Auto;
    //! Automatic range: [min, max] of the finite values. Otherwise [range_min, range_max].
    bool auto_range = true;
    double range_min = 0.0;  //!< lower end of a fixed range (auto_range = false)
    double range_max = 1.0;  //!< upper end of a fixed range (auto_range = false), > range_min
    bool colorbar = true;    //!< draw a vertical colorbar at the right
    std::string field_name = "value";  //!< colorbar title
    std::string units;                 //!< appended to the title as " [units]" when not empty
    bool outline = true;               //!< stroke the boundary of the map
    double outline_width_px = 1.5;     //!< outline line width
    //! Label each boundary loop next to its segment of the map's boundary (and next to its
    //! opening in the 3D view).
    bool loop_labels = true;
    //! Text per loop (same order as the loops passed in); empty = "inlet", "outlet 1", ...
    std::vector<std::string> labels;
    double font_size_px = 16.0;                            //!< labels, ticks and title
    //! Draw a scale bar under the map: a bar of a round length (1, 2 or 5 x 10^k map units,
    //! the largest such at most a fifth of the map's width) labelled with that length and
    //! `length_units`. The map's units are the mesh's: a map that keeps area keeps lengths on
    //! average, so the bar reads as lengths on the wall.
    bool scale_bar = true;
    std::string length_units = "mm";  //!< after the scale bar's length (the mesh's units)
    //! A line of text at the top left of the map panel (e.g. the time of a frame); empty = none.
    std::string caption;
    Eigen::Vector3d background = Eigen::Vector3d::Ones();  //!< RGB in [0, 1]; white
    Eigen::Vector3d nan_color{0.6, 0.6, 0.6};              //!< colour of non-finite values
    //! The values are one per face (row `f.idx()`), each face drawn in one flat colour; otherwise
    //! one per vertex, interpolated across faces.
    bool per_face = false;
    //! Draw the 3D cut mesh, orthographically projected, to the right of the map.
    bool view3d = false;
    //! Direction the 3D view looks along (from the eye into the scene); zero = the direction of
    //! least spread of the vertices (principal axis), which shows a planar-ish tree face-on.
    Eigen::Vector3d view_direction = Eigen::Vector3d::Zero();
    //! Screen "up" of the 3D view; zero = the direction of largest spread.
    Eigen::Vector3d view_up = Eigen::Vector3d::Zero();
    //! Darken 3D faces turned away from the viewer (Lambert, ambient 0.55) so shape reads.
    bool shade3d = true;
    //! Subdivide triangles whose values span more than this fraction of the range (up to 4
    //! levels), so that colours between vertices follow the colormap, not a straight RGB blend.
    double max_color_step = 1.0 / 32.0;
    //! max_color_step for SVG and PDF, whose size grows by about 160 bytes per drawn piece
    //! (PDF viewers blend colours in RGB as Gouraud shading does).
    double vector_max_color_step = 1.0 / 8.0;
    //! With MapImageInput::vectors: distance between the arrows (pixels), on a square grid
    //! (sample_map_arrows()), each centred on its sample point. Lengths grow linearly with the
    //! vectors' from 0.27 x spacing (near zero) to 0.9 x spacing (the longest): no two arrows
    //! meet, the relative size reads, and every arrow stays long enough to show its direction
    //! (the colours usually show the magnitude itself); a zero vector gets no arrow. Black with
    //! a white edge, which reads on every colour of both tables. In [4, 1000].
    double arrow_spacing_px = 28.0;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! Where things were drawn; pixel coordinates have x to the right and y down from the top-left.
struct MapImageLayout
{
    //! Pixel of uv (u, v): (scale * (u - uv_min.x) + map_origin.x,
    //! map_origin.y - scale * (v - uv_min.y)); v points up in the image.
    double scale = 1.0;
    Eigen::Vector2d uv_min = Eigen::Vector2d::Zero();
    Eigen::Vector2d map_origin = Eigen::Vector2d::Zero();
    Eigen::AlignedBox2d map_box;            //!< pixel box of the map panel
    Eigen::AlignedBox2d view3d_box;         //!< pixel box of the 3D view (empty if not drawn)
    Eigen::AlignedBox2d colorbar_box;       //!< pixel box of the colour bar (empty if not drawn)
    Eigen::AlignedBox2d scale_bar_box;      //!< pixel box of the scale bar's bar (empty if not drawn)
    double scale_bar_length = 0.0;          //!< the bar's length in map units (0 if not drawn)
    double range_min = 0.0;                 //!< range used (bottom of the colorbar)
    double range_max = 1.0;                 //!< range used (top of the colorbar)
    Colormap colormap = Colormap::Viridis;  //!< table used (never Auto)
    //! Pixel position of a uv point.
    Eigen::Vector2d to_pixel(const Eigen::Vector2d& uv) const
    {
        return {scale * (uv.x() - uv_min.x()) + map_origin.x(),
                map_origin.y() - scale * (uv.y() - uv_min.y())};
    }
};

struct FlattenResult;

//! The inputs of one image: the flattened (cut, disk) mesh and a field on it.
struct MapImageInput
{
    //! Cut mesh (e.g. FlattenResult::mesh), not owned: it must outlive the input. Its points are
    //! used by the 3D view.
    const Mesh* mesh = nullptr;
    Eigen::MatrixX2d uv;  //!< |V| x 2, row `v.idx()` of *mesh
    //! Boundary loops to label (e.g. FlattenResult::loops; first = inlet); may be empty.
    std::vector<BoundaryLoop> loops;
    //! A vector field drawn as arrows over the colours: one map vector per cut-mesh vertex (row
    //! `v.idx()`), e.g. the wall shear stress pushed through vertex_map_jacobians() (map_fields()
    //! gives it for every 3-component field). Empty = no arrows.
    Eigen::MatrixX2d vectors;
};

//! The map of flatten()'s result: its mesh, uv and (pre-cut) loops, so openings are labelled.
MapImageInput map_image_input(const FlattenResult& result);

//! \brief The map stored in \p mesh's `prop::uv` vertex property (e.g. a mesh cut and flattened
//! stage by stage); no loops, so no labels.
//! \throw InvalidInputError if the property is missing.
MapImageInput map_image_input(const Mesh& mesh);

//! \brief Range and colour table the options give for \p values (what render_map_image() uses).
//! \throw InvalidInputError if the options are invalid.
MapImageLayout map_image_range(const Eigen::VectorXd& values, const MapImageOptions& options);

//! \brief Render \p values (one per cut-mesh vertex, row `v.idx()`, or with `per_face` one per
//! face, row `f.idx()`) on the flattened map and write it to \p path; the format follows the
//! extension: `.png`, `.svg` or `.pdf`.
//!
//! Colours are interpolated per vertex (Gouraud shading through cairo mesh patterns); the 3D
//! view draws the faces back to front (painter's algorithm) with the same colours.
//! \return where the map, 3D view and colorbar were drawn, and the range used.
//! \throw InvalidInputError if the mesh is missing, sizes disagree, the options are invalid, the
//! extension is not one of the three or no value is finite.
//! \throw IoError if the file cannot be written.
MapImageLayout render_map_image(const std::string& path, const MapImageInput& input,
                                const Eigen::VectorXd& values, const MapImageOptions& options = {});

}  // namespace vessel
