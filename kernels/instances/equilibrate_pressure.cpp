// The pressure equilibration for 1-8 materials, ideal gases alone or not, compiled once
// for the project's programs (equilibrate_pressure.hpp, MPMICE_KERNEL_INSTANCES;
// docs/design.md, "Build time").
#include <mpmice/kernels/equilibrate_pressure.hpp>

namespace mpmice::detail {
#define MPMICE_INSTANCE(N, AllIdeal) template MPMICE_EQUILIBRATE_PRESSURE_N(N, AllIdeal);
MPMICE_EACH_COUNT_AND_FLAG(MPMICE_INSTANCE)
}
