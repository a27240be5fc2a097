// The pressure work's heat for 1-8 materials, with a rigid one or not, compiled once for
// the project's programs (pressure_work_heat.hpp, MPMICE_KERNEL_INSTANCES;
// docs/design.md, "Build time").
#include <mpmice/kernels/pressure_work_heat.hpp>

namespace mpmice::detail {
MPMICE_EACH_COUNT_AND_FLAG(template, MPMICE_PRESSURE_WORK_HEAT_N)
}
