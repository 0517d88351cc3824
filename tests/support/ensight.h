#pragma once

#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <string>
#include <vector>

namespace vessel::test {

//! An EnSight Gold case read by VTK's vtkGenericEnSightReader (what ParaView uses).
class EnSightCase
{
public:
    //! Reads the case file's information; a doctest REQUIRE fails if VTK cannot.
    explicit EnSightCase(const std::string& path);
    //! The time values VTK reports (TIME_STEPS).
    const std::vector<double>& times() const { return times_; }
    //! The single part at times()[k]; REQUIREs one block, an unstructured grid.
    vtkSmartPointer<vtkUnstructuredGrid> step(int k) const;

private:
    std::string path_;
    std::vector<double> times_;
};

}  // namespace vessel::test
