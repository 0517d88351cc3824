#include <doctest/doctest.h>

#include "vessel/cut/boundary.h"
#include "vessel/cut/cut_metrics.h"
#include "vessel/direction/geodesic.h"
#include "vessel/phantom/phantom.h"

#include <dlfcn.h>

using namespace vessel;

namespace {

// OpenBLAS (pthread flavour, when it is the libblas.so.3 alternative) lets its thread count be
// changed at run time; with another BLAS the setter is absent and the test checks plain reruns.
void set_blas_threads(int n)
{
    if (const auto set = reinterpret_cast<void (*)(int)>(
            dlsym(RTLD_DEFAULT, "openblas_set_num_threads")))
        set(n);
}

}  // namespace

TEST_CASE("determinism: geodesic distance and harmonic field do not depend on the BLAS threads")
{
    // `--batch --jobs 2` runs pipelines side by side; a resumed batch must reproduce a fresh
    // one bit for bit, so no factorization may take the BLAS's (process-wide) thread count.
    CarotidPhantomOptions options;
    options.edge_length = 0.4;
    const Mesh mesh = carotid_phantom(options);
    const auto loops = boundary_loops(mesh);
    set_blas_threads(2);
    const Eigen::VectorXd G2 = heat_geodesic_distance(mesh, loops[0].vertices);
    const Eigen::VectorXd H2 = harmonic_longitudinal(mesh, loops, G2);
    set_blas_threads(1);
    const Eigen::VectorXd G1 = heat_geodesic_distance(mesh, loops[0].vertices);
    const Eigen::VectorXd H1 = harmonic_longitudinal(mesh, loops, G1);
    CHECK((G1.array() == G2.array()).all());
    CHECK((H1.array() == H2.array()).all());
}
