#pragma once
// Map refinement as a policy (step 7 of the method): a researcher's own solver in place of the
// library's built-in refinements (FlattenOptions::refinement).

#include "vessel/layout/layout.h"
#include "vessel/map/arap.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace vessel {

//! What a refinement policy sees: the cut mesh, the layout's input and result, and the pins
//! the built-in refinements hold (the inlet loop's vertices at their layout positions, or at
//! the initial map's own positions when FlattenOptions::initialization does not use the
//! layout). For an input that is a disk already (one loop: no cuts, no layout) `layout` and
//! `placed` are null and `pins` holds one loop vertex where the initial map put it.
struct RefineInput
{
    const Mesh* mesh = nullptr;  //!< the cut (disk) mesh; `prop::origin` maps to the input
    const LayoutInput* layout = nullptr;
    const LayoutResult* placed = nullptr;
    Pins pins;
};

//! \brief A refinement policy: improves the initial map (FlattenOptions::initialization) in
//! place, chosen like Layout: FlattenOptions::refiner holds any subclass and then replaces
//! FlattenOptions::refinement. Whatever it returns is measured (FlattenResult::quality) and
//! goes through the relief cuts like a built-in map. Must be safe to call more than once
//! (each relief cut solves the map again) and from the thread that called flatten().
class MapRefiner
{
public:
    virtual ~MapRefiner() = default;
    virtual std::string name() const = 0;
    //! \param uv |V| x 2, row `v.idx()`: the initial map in, the refined map out.
    //! \param notes lines for FlattenResult::notes (fallbacks taken, iterations), may stay empty.
    //! \throw any vessel::Error subclass, which flatten() passes on.
    virtual void refine(const RefineInput& input, Eigen::MatrixX2d& uv,
                        std::vector<std::string>& notes) const = 0;
};

//! The paper's refinement as a policy: ARAP \cite liu_2008_local with the pins held
//! (arap.h); the map of Refinement::Arap with the same ArapOptions, up to rounding (the
//! pipeline factors that system in the elimination order it shares with LSCM).
class ArapRefiner : public MapRefiner
{
public:
    explicit ArapRefiner(const ArapOptions& options = {});
    std::string name() const override { return "arap"; }
    void refine(const RefineInput& input, Eigen::MatrixX2d& uv,
                std::vector<std::string>& notes) const override;

private:
    ArapOptions options_;
};

}  // namespace vessel
