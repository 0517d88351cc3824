// vessel-factor-bench: one numeric Cholesky factorization of the kind the flattening repeats
// (LSCM once; SLIM and the area polish once per iteration): CHOLMOD's own supernodal
// factorization against the library's SubtreeFactorization on one and two threads, on the valid
// real trees and the carotid phantoms. The matrix: detail::paired_laplacian_system() (the paired
// (u, v) pattern of those systems, definite). The symbolic analysis (PairedCholmod's paired AMD)
// runs once per mesh, outside the timing; each iteration is one numeric factorization. Wall
// time is the figure (Google Benchmark's CPU time counts the calling thread only).
// See docs/benchmarks.md.
#include "bench_meshes.h"
#include "solve/paired_cholmod.h"
#include "solve/paired_system.h"
#include "vessel/phantom/phantom.h"
#include "vessel/check/validation.h"

#include <benchmark/benchmark.h>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace {

using CholmodOwn = Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper>;

struct System
{
    Eigen::SparseMatrix<double> upper;  // upper triangle, compressed
    vessel::detail::PairedCholmod solver;
};

// Made at the first benchmark of a mesh (the 300k phantom takes seconds), then kept.
std::shared_ptr<System> system_of(const std::string& name, const std::function<vessel::Mesh()>& make)
{
    static std::map<std::string, std::shared_ptr<System>> made;
    auto& system = made[name];
    if (!system)
    {
        system = std::make_shared<System>();
        system->upper = vessel::detail::paired_laplacian_system(make());
        system->solver.analyze_pairs(system->upper);
    }
    return system;
}

void add_mesh(const std::string& name, std::function<vessel::Mesh()> make)
{
    for (int mode = 0; mode < 3; ++mode)
    {
        const std::string label = mode == 0 ? "Factor/cholmod/" : mode == 1 ? "Factor/ours-1/"
                                                                            : "Factor/ours-2/";
        benchmark::RegisterBenchmark((label + name).c_str(), [name, make, mode](benchmark::State& state) {
            const std::shared_ptr<System> s = system_of(name, make);
            s->solver.set_threads(mode == 2 ? 2 : 1);
            for (auto _ : state)
            {
                if (mode == 0)
                {
                    const vessel::detail::SerialOpenMp serial;  // as the library calls it
                    s->solver.CholmodOwn::factorize(s->upper);
                }
                else
                    s->solver.factorize(s->upper);
                if (s->solver.info() != Eigen::Success)
                {
                    state.SkipWithError("not positive definite");
                    break;
                }
            }
            state.counters["unknowns"] = static_cast<double>(s->upper.rows());
        })->Unit(benchmark::kMillisecond)->UseRealTime();
    }
}

}  // namespace

int main(int argc, char** argv)
{
    return vessel_bench::run_on_bench_meshes(argc, argv, add_mesh);
}
