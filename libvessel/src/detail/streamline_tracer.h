#pragma once

// The traced cut of the streamline routes (CutRoute::Streamline and Aligned,
// route_streamline.cpp and route_aligned.cpp): a streamline of the stream field from a cut's
// start toward the root, and the cheapest path in a band around it.

#include "detail/tree_distance.h"
#include "vessel/cut/cut_step.h"

#include <optional>
#include <vector>

namespace vessel::detail {

// One plan's tracer: the join rings (where a later cut's streamline stops), the distance to the
// cut tree, and the band's scratch arrays, kept across the cuts so that a band's search costs
// only the band.
class StreamlineTracer
{
public:
    // \throw InvalidInputError if the context's stream field has not one row per vertex.
    explicit StreamlineTracer(const CutPlanContext& context);

    // Trace \p field (|V| x 3; null = the context's stream field) from \p start until a face
    // touches the join rings of the tree (CutPlanOptions::join_rings; for the first cut, the
    // inlet's targets), then take the cheapest path of the step's query from \p start inside
    // the band of CutPlanOptions::band_rings rings around the crossed faces. For a later cut the
    // trace is cut back to where it first comes within join_rings mean edge lengths of its nearest
    // approach to the tree, and the band also covers the shortest bridge from there to the
    // tree. Empty when the trace does not arrive or the band holds no route.
    std::optional<GraphPath> trace(const CutStep& step, VertexHandle start,
                                   const Eigen::MatrixX3d* field = nullptr);

    // \p cut is part of the tree: its join rings and tree distance serve later cuts.
    void added(const CutStep& step, const CutPath& cut);

    double mean_edge() const { return mean_edge_; }

private:
    double mean_edge_ = 0.0;
    std::vector<int> join_;      // edge rings to the nearest interior cut vertex, -1 beyond
    std::vector<char> stop_at_;  // where a trace stops
    std::vector<int> joined_;    // vertices given a join value since the last trace
    std::vector<int> ring_;      // the band's rings: -1 everywhere between calls
    std::vector<int> in_band_;   // the vertices with ring_ >= 0 during a call
    PathQuery band_;             // is_blocked 1 everywhere between calls
    TreeDistance tree_;
};

}  // namespace vessel::detail
