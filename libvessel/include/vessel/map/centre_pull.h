#pragma once

#include "vessel/layout/layout.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace vessel {

//! What a CentrePull's residual r (a length) measures; its energy is weight x r^2 (Line) or
//! weight x min(r, 0)^2 (the hinges: zero while the centre is where it may be, smooth).
enum class PullKind
{
    //! r = normal . (c - origin): c held on the line through origin perpendicular to normal.
    Line,
    //! r = normal . (c - origin) - margin: c kept on normal's side of that line, margin away.
    HalfPlane,
    //! r = cross(c2 - origin, c - origin) / length - margin, c2 the centre of `second`: c2's
    //! bearing from origin kept clockwise of c's (the order of the map's fan, map_look.h);
    //! for centres about `length` from origin, r / length is about the sine of the angle
    //! between them, so margin / length is the least sine kept.
    Order,
};

//! A soft constraint on the centre c (mean uv) of a set of vertices (and, for PullKind::Order,
//! that of a second set). A Line pull is quadratic in the map; the hinges are smooth (squared)
//! and cost nothing while they hold. injective_refine() adds the pulls to SLIM's energy
//! (InjectiveOptions::centre_pulls), area_polish() to its own.
struct CentrePull
{
    std::vector<int> vertices;  //!< vertex indices (`v.idx()`), not empty
    Eigen::Vector2d origin = Eigen::Vector2d::Zero();
    Eigen::Vector2d normal = Eigen::Vector2d::UnitX();  //!< unit length (Line, HalfPlane)
    double weight = 0.0;  //!< >= 0; multiplies a squared length (an area)
    PullKind kind = PullKind::Line;
    std::vector<int> second;  //!< PullKind::Order: the other set (not empty), else unused
    double margin = 0.0;      //!< HalfPlane, Order: a length (finite)
    double length = 1.0;      //!< PullKind::Order: the scale of the cross product, > 0
};

//! The form of look_pulls()'s outlet terms.
enum class LookPullForm
{
    //! Each outlet's centre held on its ray from the inlet (PullKind::Line; costs area even
    //! where the look holds).
    Rays,
    //! Hinges (zero cost while the look holds): each outlet's centre above the inlet's line and
    //! every two outlets consecutive along the walk in that left-to-right order.
    Hinges,
};

//! How look_pulls() sets its hinges' margins (LookPullForm::Hinges).
enum class HingeMargin
{
    //! At most what the map given has, so that the hinges cost nothing there: for a start that
    //! has the look (the layout circle), which the hinges then keep.
    AtMostTheMap,
    //! The whole margin, also where the map given has less or has lost the look: for a map
    //! whose look is to be mended. With AtMostTheMap an outlet below the inlet's line would be
    //! pulled only onto the line, and the soft hinge, balanced by the map's own energy, leaves
    //! it short of it.
    Whole,
};

//! How a solver's steps take the pulls' curvature (InjectiveOptions::pull_steps,
//! AreaPolishOptions::pull_steps). The gradient and the line searches' energies are exact
//! either way.
enum class PullSteps
{
    //! Every vertex of an active pull drawn with weight W |dr/dc|^2 / |set| in both
    //! coordinates: the solver's matrix keeps its pattern, and a pulled set moves about as a
    //! whole (the proxy majorizes the pull's curvature along any common motion of the set).
    DiagonalProxy,
    //! The pull's own Gauss-Newton term, W u u^T with u = dr/dx over its sets (rank one per
    //! active pull), taken by the Woodbury identity with the solver's factor of the surface's
    //! matrix: one more solve per active pull, and a set is free along the hinge's line and in
    //! every motion that keeps its centre, which the proxy charges in full.
    GaussNewton,
};

//! The soft look terms that keep a restarted map's look while SLIM and the area polish run, and
//! with coarse-to-fine while the map is carried up (FlattenOptions::look_pull; look_pulls()
//! below; docs/overlaps.md, "The look hinges").
struct LookPullOptions
{
    //! The terms' weight, >= 0; it multiplies squared lengths (SLIM's energy is >= 4 x the
    //! area). 0 = no look terms. CLI `--look-pull W`.
    double weight = 0.0;
    //! The outlet terms' form: Hinges (zero cost while each outlet stays above the inlet and in
    //! walk order; default) or Rays (each outlet held on its start ray). CLI
    //! `--look-pull-form hinges|rays`.
    LookPullForm form = LookPullForm::Hinges;
    //! The hinges' margin, degrees in [0, 90): the least angle kept between two consecutive
    //! outlets' bearings and between an outlet and the inlet's line (less where the start has
    //! less). CLI `--look-margin DEG`.
    double margin_deg = 2.0;
    //! The inlet hold's weight with Hinges, if larger than `weight` (a rigid motion, no area
    //! cost), >= 0. 0 = `weight`'s. CLI `--look-hold W`.
    double hold = 0.0;
    //! How SLIM and the area polish step with the hinges. GaussNewton (default): the proxy
    //! charges an outlet loop for every motion of its vertices, and so holds the look from the
    //! start of a many-outlet tree only at more area, or not at all (docs/overlaps.md, "The
    //! steps and the carry"). LookPullForm::Rays takes the proxy whatever this says: a ray is a
    //! line through the inlet's centre, along which the exact steps let an outlet slide through
    //! the inlet to the other side. The look retry's pulled map takes these steps too
    //! (look_retry.h, LookRetryOptions::pull).
    PullSteps steps = PullSteps::GaussNewton;
    //! The steps SLIM and the area polish take with these pulls: `steps`, but the proxy with
    //! LookPullForm::Rays (above).
    PullSteps solver_steps() const;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! \brief Check every pull: vertices, a weight >= 0, a finite origin and a unit normal.
//! \param who the options' name for the message.
//! \throw InvalidInputError naming the bad pull.
void validate_centre_pulls(const std::vector<CentrePull>& pulls, const std::string& who);

//! \brief The pulls that keep a map's look while SLIM runs: the inlet is held where it is in
//! \p uv (its two halves along the walk, each by two pulls, u and v: its centre and its chord's
//! direction stay), and the outlets (a loop split by cuts counts once, all its vertices):
//! LookPullForm::Rays: every outlet loop's centre pulled onto the ray from the inlet's centre
//! through where that centre is in \p uv (its bearing); LookPullForm::Hinges: seen from the
//! middle of the inlet's chord in \p uv (map_look.h's frame), every outlet's centre kept above
//! the chord's line and every two outlets consecutive along the walk kept in that clockwise
//! order, each with a margin of \p margin_deg (as the sine of an angle; less where \p uv itself
//! has less, so the hinges cost nothing at \p uv, unless \p margins is HingeMargin::Whole).
//! Meant for a start that has the layout's look (the layout circle, layout_circle.h), or with
//! HingeMargin::Whole for a map whose look is to be mended.
//! \param segments the cut mesh's boundary segments (BoundarySegment::loop 0 = inlet; the
//! inlet's first vertex is its right end, its last its left end; the walk order is theirs).
//! \param weight every pull's CentrePull::weight: the energy is weight x the sum of the squared
//! residuals (lengths: an area, like SLIM's energy, whose minimum is 4 x the surface's area).
//! \param hold_weight LookPullForm::Hinges: the inlet hold's weight is the larger of it and
//! \p weight (the hinges' hold is a rigid motion only: it costs no area, SLIM's energy does
//! not see it).
//! \throw InvalidInputError if there is no inlet segment or a vertex is out of range.
std::vector<CentrePull> look_pulls(const std::vector<BoundarySegment>& segments,
                                   const Eigen::MatrixX2d& uv, double weight,
                                   LookPullForm form = LookPullForm::Rays, double margin_deg = 2.0,
                                   double hold_weight = 0.0,
                                   HingeMargin margins = HingeMargin::AtMostTheMap);

}  // namespace vessel
