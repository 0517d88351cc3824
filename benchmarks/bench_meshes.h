#pragma once

// The meshes the Google Benchmark executables (vessel-cut-bench, vessel-factor-bench) run on:
// the valid real trees of ../shared/data/real and the carotid phantoms of vessel-bench-table at
// 44k and 300k triangles, each handed to the caller as a name and a maker (made lazily: the
// 300k phantom takes seconds).

#include "vessel/phantom/phantom.h"

#include <benchmark/benchmark.h>
#include "vessel/check/validation.h"
#include "vessel/io/vtk_io.h"  // inputs may be .vtp/.vtk

#include <functional>
#include <string>
#include <utility>

namespace vessel_bench {

inline void for_each_bench_mesh(
    const std::function<void(const std::string&, std::function<vessel::Mesh()>)>& add_mesh)
{
    const std::string real = VESSEL_SHARED_DATA;
    for (const char* file :
         {"vampy/artery-coarse.ply", "x-ray-angio-data/coronary-clinical-branch-fine.ply",
          "vampy/artery.ply", "vmtk-test-data/aorta-surface-open-ends.ply",
          "x-ray-angio-data/coronary-phantom-tri3-coarse.ply", "simvascular-tests/demo-model-open.ply",
          "vmtk-old-website/aneurisk-id1-lateral-aneurysm.ply",
          "svfsi-tests/pulmonary-glenn-wall.ply", "svfsi-tests/pulmonary-glenn-wall-split4.ply"})
    {
        const std::string path = real + "/" + file;
        add_mesh(file, [path] { return vessel::load_tree_surface(path).mesh; });
    }
    for (const auto& [name, edge] : {std::pair{"carotid-44k", 0.263}, {"carotid-300k", 0.1013}})
    {
        const double e = edge;
        add_mesh(name, [e] {
            vessel::CarotidPhantomOptions o;
            o.edge_length = e;
            return vessel::carotid_phantom(o);
        });
    }
}

//! main() of a Google Benchmark executable: \p add_mesh registers its benchmarks of each mesh,
//! then the command line's filter and options run them.
inline int run_on_bench_meshes(
    int argc, char** argv,
    const std::function<void(const std::string&, std::function<vessel::Mesh()>)>& add_mesh)
{
    for_each_bench_mesh(add_mesh);
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}

}  // namespace vessel_bench
