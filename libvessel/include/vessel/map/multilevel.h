#pragma once
// Coarse-to-fine one-to-one maps: the nonlinear map (SLIM, its scaffold, the area polish, the
// look retry) is solved on a decimated copy of the cut mesh, carried to every vertex of the
// full mesh by undoing the decimation's collapses (Sander et al. 2001, "Texture mapping
// progressive meshes"), and finished there with local steps that cannot flip a triangle. Each
// full-size factorization of the single-level path is replaced by one of a mesh
// `coarse_vertices` large, so stage F's cost no longer grows with the number of nonlinear
// iterations times the mesh size (as in Hormann, Labsik and Greiner 2001, "Remeshing
// triangulated surfaces with optimal parameterizations", and Liu et al. 2018, "Progressive
// parameterizations"). The map is carried up a hierarchy of levels, local steps at each
// removing the error of its own wavelength; what is left is the error of wavelengths no level's
// steps converge (docs/benchmarks.md "Coarse-to-fine"). A look retry kept on the coarse mesh is
// carried up with its pulls (look_retry.h, LookRetryOptions::pull).

#include "vessel/core/mesh.h"
#include "vessel/layout/pins.h"
#include "vessel/map/centre_pull.h"

#include <array>
#include <functional>
#include <vector>

namespace vessel {

//! When and how stage F solves the map on a coarse mesh first (FlattenOptions::multilevel).
struct MultilevelOptions
{
    //! Vertices of the coarse mesh, besides the boundary vertices where it keeps the whole
    //! boundary (coarsen_levels()). Cut meshes with more than twice as many vertices are
    //! flattened coarse-to-fine; smaller ones directly. 0 = never: every map is solved at full
    //! resolution. Coarse-to-fine trades some area distortion (within max_energy_ratio of the
    //! isometric energy) for several times less time on large meshes; where neither hierarchy
    //! gives a one-to-one carried map within max_energy_ratio, the map is solved at full
    //! resolution as well (noted), which then takes longer than 0 would (docs/benchmarks.md
    //! "Coarse-to-fine"). CLI `--coarse-vertices N`.
    int coarse_vertices = 4000;
    //! Gauss-Seidel sweeps of relax_area() on each level, at most; they stop earlier once a
    //! sweep (with the coarse-grid correction after it, if any) lowers the energy by less than
    //! `tolerance` of its excess over the isometric minimum. The sweeps remove the carry's
    //! short-wavelength error; the corrections the long-wavelength error that sweeps alone remove
    //! only over hundreds of sweeps (docs/benchmarks.md "Coarse-to-fine"). Stage F's carry
    //! finishes its finest level with three Newton steps of the whole map where they stopped
    //! short: the energy still above 1.001 times its isometric minimum, and the last sweep
    //! still lowering it by more than a hundredth of that excess, or the sweeps stalled above
    //! 1.01 times it, held by the boundary's near contacts, or the map's mean |log area| still
    //! above its coarse map's (a map carried with the look pulls, whose energy does not see the
    //! area's error, by this test alone); three more at a time, up to nine,
    //! while the last three removed a third of what was left above 1.001 times the minimum
    //! (docs/benchmarks.md "The carry finished by Newton steps where it stops short").
    int relax_sweeps = 16;
    double tolerance = 3e-4;  //!< relax_area()'s stopping rule (see relax_sweeps)
    //! relax_area() stops after a coarse-grid correction that leaves the map's mean |log area|
    //! (FlatQuality::mean_abs_log_area_normalized) at most this; >= 0, 0 = never (the whole
    //! schedule). Stage F's carry applies it to the finest level only (a coarser level's area
    //! is not the map's), and a carry stopped by it is not finished by Newton steps. The area error
    //! falls by a few percent per sweep to the schedule's end; at a mean of 0.15% a region's
    //! area on the map, or a per-area field summed over it, is off by far less than wall shear
    //! stress differs between CFD pipelines on one geometry (Valen-Sendstad et al. 2018,
    //! "Real-world variability in the prediction of intracranial aneurysm wall shear stress",
    //! Cardiovasc. Eng. Technol. 9(4)), so the last sweeps buy nothing a reader of the map
    //! sees. Maps that end above it (trees, aneurysms) are relaxed as without it
    //! (docs/benchmarks.md, "The finest level stops at the area tolerance").
    //! CLI `--area-tolerance T`.
    double area_tolerance = 0.0015;
    //! Coarse-grid corrections of relax_area() on each level, at most: one after every second
    //! sweep. 0 = none (Gauss-Seidel alone, every vertex in every sweep: about 80 sweeps for the
    //! same area distortion). Stage F's carry makes none on the finest level of a map carried
    //! with the look pulls, whose coarse step they do not see (docs/benchmarks.md, "A pulled
    //! carry's finest level").
    int coarse_corrections = 8;
    //! Vertices of the coarser level above which the coarse-grid corrections' system is solved
    //! iteratively (conjugate gradients preconditioned by V-cycles over that level and the
    //! one below it, detail/coarse_correction.h) instead of by a sparse Cholesky factorization,
    //! whose fill grows faster than the level: on the largest meshes its factorizations
    //! dominate the relaxation (docs/benchmarks.md "Coarse-to-fine"). Only where relax_area()
    //! is given the level below (the carry gives it to every level it relaxes but the one
    //! carried from the coarsest mesh). 0 = iteratively wherever the level below is given.
    int direct_correction_vertices = 50000;
    //! A carried map whose relaxed energy (relax_area()'s, at the finest level) ends above
    //! this multiple of its isometric minimum (twice the surface area) is polished at full
    //! resolution (FlattenOptions::area_polish, the boundary kept simple), whose Newton steps
    //! remove what local steps and coarse-grid corrections stall on; still above, it is
    //! refused and the map solved again as after a carry that crosses (the coarse solve stopped
    //! far from its minimum: SLIM's scaffold steps stalling on a decimated many-outlet tree).
    //! Relaxed maps mostly end near 1 (docs/benchmarks.md "Coarse-to-fine"). Must be > 1.
    double max_energy_ratio = 1.05;
    //! On trees of at least six outlets, the coarse map's restart from the layout circle is
    //! solved first on a decimation of the coarse mesh to a quarter of its vertices and carried
    //! up to it, so that most of SLIM's iterations, which unroll the branches, are made on the
    //! smaller mesh (not the look retry's pulled map, nor a map pulled from the start: carried
    //! up, they kept less of the look). Where that solve stalls above twice its isometric
    //! minimum, or its carried map has a flip or a crossing, the restart starts from the circle
    //! (noted). false = always from the circle on the coarse mesh itself (docs/benchmarks.md,
    //! "The coarse map's start solved coarser").
    bool coarser_start = true;
    //! Called by relax_area() after each sweep with the number of sweeps made (progress).
    std::function<void(int sweeps)> on_sweep;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! One halfedge collapse of coarsen(): v0 went into v1. Indices are the fine mesh's.
struct Collapse
{
    int v0 = -1, v1 = -1;
    int across = -1;  //!< for a boundary v0, its other boundary neighbour; else -1
    //! v0's faces just before the collapse, each as the (a, b) of the counter-clockwise (v0, a, b)
    std::vector<std::array<int, 2>> faces;
};

//! A decimated copy of a mesh whose vertices are a subset of the fine mesh's (halfedge
//! collapses: every kept vertex stays where it was).
struct CoarseMesh
{
    Mesh mesh;
    std::vector<Collapse> collapses;  //!< in the order made
    //! Index in `collapses` of each round's first collapse: no two collapses of a round are
    //! within one ring of each other (prolongate() undoes a round's interior ones on two threads).
    std::vector<std::size_t> rounds;
    std::vector<int> fine_of;    //!< per coarse vertex, its fine vertex index
    std::vector<int> coarse_of;  //!< per fine vertex, its coarse vertex index or -1 (removed)
};

//! \brief Decimate \p fine to about \p target_vertices by rounds of shortest-edge halfedge
//! collapses on independent sets (the kept vertices spread evenly over the surface), each
//! keeping the topology (a disk stays a disk) and turning no face normal by more than 60
//! degrees. Boundary vertices are removed only along the boundary, so the coarse boundary is a
//! subsequence of the fine one; those in \p keep are never removed.
//! Ties between equally short edges break as OpenMesh's halfedge numbering and circulation
//! order break them on a copy of \p fine built face by face: the coarse mesh, its vertex and
//! face order and the collapses are those of OpenMesh's collapse() and garbage_collection()
//! (docs/benchmarks.md, "The decimation on arrays, OpenMesh's ties kept").
//! The coarse mesh carries none of the fine mesh's custom properties.
//! \param no_new_chords if true, no collapse joins two boundary vertices by a new interior edge
//! (a chord; the fine mesh's own chords stay). A face with its three corners on the boundary is
//! a sliver in a Tutte start on a circle, where it is wide in 3D (an outlet's tube end
//! triangulated across): on many-outlet trees such slivers held the coarse SLIM's first steps
//! to nothing. On the carotid phantoms chords did not raise the start's energy, and without
//! them the finest level's relaxation took longer (docs/benchmarks.md "No new chords on
//! many-outlet trees").
CoarseMesh coarsen(const Mesh& fine, int target_vertices, const std::vector<VertexHandle>& keep,
                   bool no_new_chords = false);

//! \brief A hierarchy of coarsen() calls, each level about a quarter of the vertices of the one
//! above it, down to \p coarse_vertices: levels[0] coarsens \p fine, levels[l] coarsens
//! levels[l - 1].mesh. A map solved on the last level is carried up one level at a time
//! (cascadic multigrid, Bornemann and Deuflhard 1996, "The cascadic multigrid method for
//! elliptic problems"), so that local steps at each level remove the error of that level's
//! wavelength. \p keep as in coarsen(), kept on every level.
//! The first \p boundary_levels levels keep every boundary vertex of the mesh they coarsen, so
//! that carrying a map up to them inserts interior vertices only: the carried map keeps the
//! coarser map's boundary polygon, and with it its simplicity, as long as no boundary vertex
//! moves (a flip-free map of a disk with a simple boundary is one-to-one). On those levels
//! \p coarse_vertices counts the vertices besides the boundary's. \p no_new_chords as in
//! coarsen(), on every level.
//! \throw InvalidInputError if \p coarse_vertices < 3.
std::vector<CoarseMesh> coarsen_levels(const Mesh& fine, int coarse_vertices,
                                       std::vector<VertexHandle> keep,
                                       std::size_t boundary_levels = 0,
                                       bool no_new_chords = false);

//! \brief Carry a map of the coarse mesh to every fine vertex: kept vertices keep their coarse
//! (u, v); the collapses are undone in reverse order (Sander et al. 2001, "Texture mapping
//! progressive meshes"), each interior vertex placed where an affine fit of the map over its
//! one ring puts it, each boundary vertex on the boundary edge it was cut from (at its 3D
//! fraction, else at another fraction, else lifted off the edge by the least that keeps its
//! star positive), at the first of these places where its two edges meet no other boundary
//! edge. A flip-free coarse map gives a flip-free fine map (each star is kept positive; near
//! the target it is); boundary vertices on their edges keep the coarse boundary's shape, and
//! so its simplicity, except where no point near the edge keeps the star positive (a sharp
//! turn of the coarse boundary at the target: then the vertex goes to the point of its star's
//! kernel nearest the edge's that meets no other boundary edge). The boundary check is what
//! keeps a vertex lifted off its edge at the tip of a narrow slit between two boundary parts
//! (branches laid side by side) from landing across the slit's other side. Each re-inserted
//! interior vertex then takes a few of relax_area()'s Newton steps in its star.
//! \return |V_fine| x 2, row `v.idx()`.
//! \param area_weight lambda of the energy each re-inserted interior vertex is settled with
//! (relax_area()).
//! \param keep_boundary_simple false for a map allowed to overlap itself (OverlapPolicy::Keep):
//! a boundary vertex's places are not tested against the other boundary edges.
Eigen::MatrixX2d prolongate(const Mesh& fine, const CoarseMesh& coarse,
                            const Eigen::MatrixX2d& coarse_uv, double area_weight,
                            bool keep_boundary_simple = true);

//! What relax_area() did.
struct RelaxSummary
{
    int sweeps = 0;
    int corrections = 0;  //!< coarse-grid corrections made
    double energy_before = 0.0, energy_after = 0.0;  //!< the energy of area_polish.h
    //! What the last sweep (with the coarse-grid correction after it, if any) lowered the
    //! energy by: against energy_after's excess over the isometric minimum, how far from
    //! converged the sweeps stopped.
    double last_decrease = 0.0;
    //! Stopped at MultilevelOptions::area_tolerance (the map's mean |log area| at most it).
    bool area_within_tolerance = false;
};

//! \brief Lower the area-weighted distortion energy of area_polish() (weight \p area_weight) of
//! a flip-free map by Gauss-Seidel sweeps of per-vertex projected Newton steps, each with a line
//! search that keeps every incident face's orientation (the energy's barrier), so no face flips.
//! A sweep visits the free interior vertices colour by colour (no two of a colour in one face,
//! so each colour's steps are independent and made on two threads on large meshes; the map does
//! not depend on the thread count), then the boundary vertices one after another.
//! Pinned vertices stay put; boundary vertices move, none so that the boundary crosses itself
//! or two of its edges come nearer each other than a hundredth of the mean boundary edge (or,
//! where they were that near already, any nearer): a contact would make the written map, its
//! coordinates rounded, overlap itself. Each sweep costs O(|F|): it removes the
//! short-wavelength error a prolongation leaves, not the long-wavelength one. Given the level
//! the map was carried from (\p coarser, its map \p coarser_uv), the sweeps alternate with
//! coarse-grid corrections (two-grid multigrid; Briggs, Henson and McCormick 2000, "A multigrid
//! tutorial"): the projected Newton system restricted to the coarse level's interpolation
//! (Galerkin), its step line searched under the same guarantees (no flip; near boundary
//! contacts held). One factorization of twice the coarse level's vertex count per level, again
//! after each step that holds more coarse vertices; given the level below a coarse level of more
//! than `options.direct_correction_vertices` vertices, that of the level below instead, the
//! coarse level's system solved iteratively. With corrections, a sweep steps only the vertices
//! that lowered the energy much in the last one and their neighbours, and every vertex after a
//! correction, which moves them all; without them (none asked, or no coarser level), every vertex
//! steps in every sweep.
//! \param uv |V| x 2, row `v.idx()`, without flipped faces; updated in place.
//! \param coarser the level \p mesh was decimated to (its `coarse_of` indexes \p mesh), or null
//! \param coarser_uv the map of `coarser->mesh` that \p uv was carried from
//! \param keep_boundary_simple false for a map allowed to overlap itself (OverlapPolicy::Keep):
//! boundary vertices then move as interior ones do, with no guard (a guard would hold every
//! vertex whose edges cross another part already, and the map far from its minimum).
//! \param below the level \p coarser was decimated to (its `coarse_of` indexes
//! `coarser->mesh`), or null, and \p below_uv the map of `below->mesh` that \p coarser_uv was
//! carried from: where the coarser level has more than `options.direct_correction_vertices`
//! vertices, the corrections' system is then solved iteratively with V-cycles over the two
//! levels instead of factorized.
//! \param pulls if not null and \p keep_boundary_simple: look pulls (centre_pull.h, indices of
//! \p mesh) added to the energy; their vertices step one after another with the pulls'
//! gradient and Gauss-Newton curvature by each vertex, the corrections' line searches count
//! them, and the summary's energies include them.
//! \throw InvalidInputError if \p uv has a flipped face or its size is not |V| x 2, or the
//! coarser level (or the level below it) does not match, or a pull's vertex is out of range.
RelaxSummary relax_area(const Mesh& mesh, Eigen::MatrixX2d& uv, const Pins& pins,
                        double area_weight, const MultilevelOptions& options = {},
                        const CoarseMesh* coarser = nullptr,
                        const Eigen::MatrixX2d* coarser_uv = nullptr,
                        bool keep_boundary_simple = true, const CoarseMesh* below = nullptr,
                        const Eigen::MatrixX2d* below_uv = nullptr,
                        const std::vector<CentrePull>* pulls = nullptr);

}  // namespace vessel
