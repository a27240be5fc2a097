#pragma once
/// \file particle_pressure.hpp
/// \brief Step 11: the gas gauge pressure at each particle, pp_p = sum_i S_ip p_i - p_ref,
///        which the internal force adds to the stress (E24, pitfall P5).
#include <mpmice/kernels/particle_grid.hpp>
#include <mpmice/kernels/shape.hpp>

namespace mpmice {

template <class Shape>
void particle_pressure(const NodeGrid& grid, long count, const ParticleData& data, double p_ref,
                       const ConstField3& press_node) {
  Kokkos::parallel_for(
      "mpmice::particle_pressure", Kokkos::RangePolicy<ExecSpace>(0, count), KOKKOS_LAMBDA(long p) {
        const ParticleWeights<Shape> wt = particle_weights<Shape>(grid, data, p);
        double sum = 0;
        for (int a = 0; a < Shape::nodes; ++a)
          for (int b = 0; b < Shape::nodes; ++b)
            for (int c = 0; c < Shape::nodes; ++c)
              sum += wt.weight(a, b, c) * press_node(wt.first[0] + a, wt.first[1] + b, wt.first[2] + c);
        data(p, column(ParticleField::gas_pressure)) = sum - p_ref;
      });
}

}  // namespace mpmice
