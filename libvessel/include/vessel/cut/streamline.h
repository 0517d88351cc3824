#pragma once

#include "vessel/core/mesh.h"

#include <vector>

namespace vessel {

//! Limits of trace_streamline().
struct StreamlineOptions
{
    //! Stop (StreamlineStop::Cycle) when the trace enters one face more than this many times:
    //! it circles a sink, a source or a closed orbit of the field.
    int max_face_visits = 2;
    //! Stop (StreamlineStop::Length) after this many face crossings; 0 = 4 x |F|.
    int max_steps = 0;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! Why a streamline ended.
enum class StreamlineStop
{
    Target,    //!< it reached a face with a corner flagged in `stop_at`
    Boundary,  //!< it ran out over the rim (a boundary edge or vertex) before a target
    Singular,  //!< the field vanished, or pointed back at every way on (a sink of the field)
    Cycle,     //!< it entered a face more than StreamlineOptions::max_face_visits times
    Length,    //!< StreamlineOptions::max_steps crossings
};

//! A streamline traced across the faces of a mesh.
struct Streamline
{
    std::vector<Eigen::Vector3d> points;  //!< polyline on the surface, start first
    std::vector<FaceHandle> faces;        //!< faces crossed, in order (a face may repeat)
    std::vector<VertexHandle> vertices;   //!< mesh vertices the trace passed through exactly
    StreamlineStop stop = StreamlineStop::Singular;
    double length = 0.0;  //!< 3D length of `points`
};

//! \brief Trace the streamline of a tangent vector field from a vertex: in each face it runs
//! straight along the face's direction (the mean of its three corner rows projected into the
//! face plane) to the edge it leaves through, then on in the next face. Where both faces of an
//! edge push toward it, the trace slides along the edge to its end vertex; from a vertex it
//! continues into the face whose corner wedge contains that face's direction.
//! \param field |V| x 3 direction per vertex, row `v.idx()` (e.g. the vessel direction z toward
//! the root, or descent_direction() of a longitudinal coordinate); need not be unit or tangent.
//! \param start vertex to start from (e.g. on an outlet loop).
//! \param stop_at |V| flags, `v.idx()`: the trace ends in the first face with a flagged corner.
//! \return the polyline; `stop` says why it ended.
//! \throw InvalidInputError if sizes disagree, \p start is invalid or options are invalid.
Streamline trace_streamline(const Mesh& mesh, const Eigen::MatrixX3d& field, VertexHandle start,
                            const std::vector<char>& stop_at,
                            const StreamlineOptions& options = {});

}  // namespace vessel
