// g2p's particle body with GIMP weights for MPMICE (the nodes' heat rate and the
// transfers' heat), compiled once for the project's programs (g2p.hpp,
// MPMICE_KERNEL_INSTANCES; docs/design.md, "Build time").
#include <mpmice/kernels/g2p.hpp>

namespace mpmice::detail {
template MPMICE_G2P_DEFORMING(GimpShape, true);
}
