// The pressure equilibration for 1-8 materials, ideal gases alone or not, compiled once
// for the project's programs (equilibrate_pressure.hpp, MPMICE_KERNEL_INSTANCES;
// docs/design.md, "Build time").
#include <mpmice/kernels/equilibrate_pressure.hpp>

namespace mpmice::detail {
MPMICE_EACH_COUNT_AND_FLAG(template, MPMICE_EQUILIBRATE_PRESSURE_N)
}
