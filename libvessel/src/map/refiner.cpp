#include "vessel/map/refiner.h"

#include "vessel/core/errors.h"

namespace vessel {

ArapRefiner::ArapRefiner(const ArapOptions& options) : options_(options)
{
    options_.validate();
    if (options_.prefactored)
        throw InvalidInputError("ArapRefiner: ArapOptions::prefactored must be null; the "
                                "refiner factors each mesh it is given");
}

void ArapRefiner::refine(const RefineInput& input, Eigen::MatrixX2d& uv,
                         std::vector<std::string>& notes) const
{
    if (input.mesh == nullptr)
        throw InvalidInputError("ArapRefiner: RefineInput::mesh is null");
    if (options_.max_iterations == 0)
        return;
    notes.push_back("arap refiner: " + arap(*input.mesh, uv, input.pins, options_).report);
}

}  // namespace vessel
