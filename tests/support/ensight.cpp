#include "support/ensight.h"

#include <doctest/doctest.h>

#include <vtkGenericEnSightReader.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkStreamingDemandDrivenPipeline.h>

namespace vessel::test {

EnSightCase::EnSightCase(const std::string& path) : path_(path)
{
    vtkNew<vtkGenericEnSightReader> reader;
    reader->SetCaseFileName(path.c_str());
    REQUIRE(reader->CanReadFile(path.c_str()));
    reader->UpdateInformation();
    vtkInformation* info = reader->GetOutputInformation(0);
    const auto key = vtkStreamingDemandDrivenPipeline::TIME_STEPS();
    if (info->Has(key))
        times_.assign(info->Get(key), info->Get(key) + info->Length(key));
}

vtkSmartPointer<vtkUnstructuredGrid> EnSightCase::step(int k) const
{
    // A reader per step, so that each step is read as a fresh program would read it.
    vtkNew<vtkGenericEnSightReader> reader;
    reader->SetCaseFileName(path_.c_str());
    reader->ReadAllVariablesOn();
    reader->UpdateInformation();
    REQUIRE(k < static_cast<int>(times_.size()));
    reader->UpdateTimeStep(times_[static_cast<std::size_t>(k)]);
    auto* blocks = vtkMultiBlockDataSet::SafeDownCast(reader->GetOutput());
    REQUIRE(blocks != nullptr);
    REQUIRE(blocks->GetNumberOfBlocks() == 1);
    vtkSmartPointer<vtkUnstructuredGrid> grid = vtkUnstructuredGrid::SafeDownCast(blocks->GetBlock(0));
    REQUIRE(grid != nullptr);
    return grid;
}

}  // namespace vessel::test
