#pragma once

#include "vessel/fields/fields.h"
#include "vessel/core/mesh.h"

#include <string>

namespace vessel {

//! A synthetic wall-shear-stress-like series: a Gaussian pulse that travels from the inlet to
//! the ends of the tree once per heart beat. For tests and examples, not a CFD result.
struct PulseSeriesOptions
{
    std::string name = "WSS";  //!< field name
    double duration_s = 1.8;   //!< length of the series (the paper's two beats)
    int steps = 90;            //!< time steps; step k is at k * duration_s / steps
    double period_s = 0.9;     //!< one beat: the pulse crosses the tree once per period
    double base_pa = 0.5;      //!< value away from the pulse (Pa)
    double peak_pa = 2.5;      //!< added at the pulse's centre (Pa)
    double width = 0.1;        //!< pulse standard deviation, as a fraction of the longest path
    //! A 3-component field instead of a scalar: the value times the unit direction of the
    //! distance's gradient along the wall (away from the inlet, as the shear of a flow from the
    //! inlet points), so that images can draw it as arrows. Where the gradient vanishes (no
    //! direction), the vector is zero.
    bool vector = false;
    //! \throw InvalidInputError naming the bad field.
    void validate() const;
};

//! \brief The pulse on \p mesh: s(v) = heat-geodesic distance from the inlet (the longest
//! boundary loop) over its maximum, centre c(t) = (1 + 6 width) frac(t / period_s) - 3 width,
//! value base_pa + peak_pa exp(-(s - c)^2 / (2 width^2)); with `vector`, that value times the
//! unit vertex gradient of s (vertex_gradient()).
//! \return one Float64 point field per step (scalar, or 3 components with `vector`), rows
//! `v.idx()`.
//! \throw InvalidInputError if the options are invalid or the mesh has no boundary.
TimeSeries travelling_pulse(const Mesh& mesh, const PulseSeriesOptions& options = {});

}  // namespace vessel
