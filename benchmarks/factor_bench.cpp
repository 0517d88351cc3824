// vessel-factor-bench: one numeric Cholesky factorization of the kind the flattening repeats
// (LSCM once; SLIM and the area polish once per iteration): CHOLMOD's own supernodal
// factorization against the library's SubtreeFactorization on one and two threads, on the valid
// real trees and the carotid phantoms. The matrix has the paired pattern of those systems (per
// vertex a (u, v) pair; the cotangent Laplacian on both, shifted by 1e-3 on the diagonal to be
// definite as the pipeline's pins make it, and the u-v couplings of neighbours that LSCM's
// conformal term has, stored as explicit zeros). The symbolic analysis (PairedCholmod's paired AMD)
// runs once per mesh, outside the timing; each iteration is one numeric factorization. Wall
// time is the figure (Google Benchmark's CPU time counts the calling thread only).
// See docs/benchmarks.md.
#include "detail/paired_cholmod.h"
#include "vessel/operators.h"
#include "vessel/phantom.h"
#include "vessel/validation.h"

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
        Eigen::SparseMatrix<double> L = vessel::cotan_laplacian(make());
        if (L.coeff(0, 0) < 0.0)
            L = -L;
        std::vector<Eigen::Triplet<double>> t;
        for (int k = 0; k < L.outerSize(); ++k)
            for (Eigen::SparseMatrix<double>::InnerIterator it(L, k); it; ++it)
            {
                const int i = static_cast<int>(it.row()), j = static_cast<int>(it.col());
                if (i > j)
                    continue;
                const double value = it.value() + (i == j ? 1e-3 : 0.0);
                t.emplace_back(2 * i, 2 * j, value);
                t.emplace_back(2 * i + 1, 2 * j + 1, value);
                if (i != j)
                {
                    t.emplace_back(2 * i, 2 * j + 1, 0.0);
                    t.emplace_back(2 * i + 1, 2 * j, 0.0);
                }
            }
        system->upper.resize(2 * L.rows(), 2 * L.rows());
        system->upper.setFromTriplets(t.begin(), t.end());
        system->upper.makeCompressed();
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
    const std::string real = VESSEL_SHARED_DATA;
    for (const char* file :
         {"vampy/artery-coarse.ply", "vmtk-test-data/aorta-surface-open-ends.ply",
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
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
