#pragma once
/// \file cell_to_node.hpp
/// \brief Cell-to-node averages (E11): the pressure on the nodes (Step 11) and the
///        Lagrangian cell rates of the MPM materials carried to their nodes (E34).
#include <mpmice/kernels/grid.hpp>

namespace mpmice {

/// p_i = (1/8) sum of the 8 cells around node i (E11), on `nodes`.
inline void pressure_to_nodes(const IndexBox& nodes, const ConstField3& press, const Field3& press_node) {
  Kokkos::parallel_for(
      "mpmice::pressure_to_nodes", nodes.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        double s = 0;
        for (int a = 0; a < 2; ++a)
          for (int b = 0; b < 2; ++b)
            for (int c = 0; c < 2; ++c) s += press(i - a, j - b, k - c);
        press_node(i, j, k) = 0.125 * s;
      });
}

/// (E34) for node slot s: v*_i += dt (1/8) sum aV, a_i += (1/8) sum aV,
/// aT_i = (1/8) sum aT over the 8 cells around node i (cell rates in slot s).
inline void cell_rates_to_nodes(const IndexBox& nodes, int s, double dt, const ConstVectorField4& cell_acc,
                                const ConstField4& cell_temp_rate, const VectorField4& vel_star,
                                const VectorField4& acc, const Field4& temp_rate) {
  Kokkos::parallel_for(
      "mpmice::cell_rates_to_nodes", nodes.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        double av[3] = {0, 0, 0}, at = 0;
        for (int a = 0; a < 2; ++a)
          for (int b = 0; b < 2; ++b)
            for (int c = 0; c < 2; ++c) {
              for (int d = 0; d < 3; ++d) av[d] += cell_acc[d](s, i - a, j - b, k - c);
              at += cell_temp_rate(s, i - a, j - b, k - c);
            }
        for (int d = 0; d < 3; ++d) {
          vel_star[d](s, i, j, k) += dt * 0.125 * av[d];
          acc[d](s, i, j, k) += 0.125 * av[d];
        }
        temp_rate(s, i, j, k) = 0.125 * at;
      });
}

}  // namespace mpmice
