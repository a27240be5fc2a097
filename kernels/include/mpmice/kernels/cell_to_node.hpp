#pragma once
/// \file cell_to_node.hpp
/// \brief Cell-to-node averages (E11): the pressure on the nodes (Step 11) and the
///        Lagrangian cell rates of the MPM materials carried to their nodes (E34).
#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/materials.hpp>

namespace mpmice {

/// p_i = (1/8) sum of the 8 cells around node i (E11), on `nodes`. Little work per node:
/// small boxes run on the calling thread (for_each_index_light).
inline void pressure_to_nodes(const IndexBox& nodes, const ConstField3& press, const Field3& press_node) {
  for_each_index_light("mpmice::pressure_to_nodes", nodes, KOKKOS_LAMBDA(long i, long j, long k) {
    double s = 0;
    unrolled_for<8>([&](int n) { s += press(i - corner(n, 0), j - corner(n, 1), k - corner(n, 2)); });
    press_node(i, j, k) = 0.125 * s;
  });
}

namespace detail {
template <bool Transfer>
void cell_rates_to_nodes_n(const IndexBox& nodes, int s, double dt, const ConstVectorField4& cell_acc,
                           const ConstField4& cell_temp_rate, const VectorField4& vel_star, const VectorField4& acc,
                           const Field4& temp_rate, const Field4& transfer_energy) {
  for_each_index("mpmice::cell_rates_to_nodes", nodes, KOKKOS_LAMBDA(long i, long j, long k) {
    double av[3] = {0, 0, 0}, at = 0, square = 0;
    // The 8 cells (i - a, j - b, k - c), a outermost, c innermost.
    unrolled_for<8>([&](int n) {
      const long ci = i - corner(n, 0), cj = j - corner(n, 1), ck = k - corner(n, 2);
      unrolled_for<3>([&](int d) {
        const double rate = cell_acc[d](s, ci, cj, ck);
        av[d] += rate;
        square += rate * rate;
      });
      at += cell_temp_rate(s, ci, cj, ck);
    });
    double mean2 = 0;
    unrolled_for<3>([&](int d) {
      const double dv = dt * 0.125 * av[d];
      vel_star[d](s, i, j, k) += dv;
      acc[d](s, i, j, k) += 0.125 * av[d];
      mean2 += dv * dv;
    });
    temp_rate(s, i, j, k) = 0.125 * at;
    if (Transfer) transfer_energy(s, i, j, k) = 0.5 * 0.125 * dt * dt * square - mean2;  // folded (not constexpr: nvcc)
  });
}
}  // namespace detail

/// (E34) for node slot s: v*_i += dt (1/8) sum aV, a_i += (1/8) sum aV,
/// aT_i = (1/8) sum aT over the 8 cells around node i (cell rates in slot s). With
/// `transfer_energy` (MPMICE) also its part of the energy the transfers owe the
/// particles as heat (an addition to mpmice-algorithm.md, for energy conservation;
/// docs/design.md, "Energy of the solids' transfers"):
///   q_i = <|du_c|^2> / 2 - |dv_i|^2
/// with du_c = dt aV_c the increments of the 8 cells (E33) and dv_i their mean. g2p adds
/// sum_i S_ip (q_i + |D_i|^2) - |Dv_p|^2 / 2 to c_v T_p, with D_i = dt a_i the node's
/// whole increment after the node conditions (internal force and dv) and
/// Dv_p = sum_i S_ip D_i the particle's (E35). Per particle that is the sum of
/// - what the two averages smooth away: the cells were charged (1/2) m_c |du_c|^2 and the
///   nodes (1/2) m_i |D_i|^2, the particle gets (1/2) m_p |Dv_p|^2 (variances, >= 0);
/// - the internal force's work made to match what was charged for it: the strain follows
///   the end velocity v_i + D_i (E36), so the stress works f_i . (v_i + D_i) dt, while
///   the force's own kinetic energy is f_i . (v_i + a dt / 2) dt (a = D_i / dt - dv_i / dt)
///   and the cells charged the exchange at v_i + a dt; the difference per node is
///   (1/2) m_i (|D_i|^2 - |dv_i|^2).
/// Where a trace of a solid is locked to its gas by the stiff drag, the internal force
/// and the exchange nearly cancel on its nodes, each large; without this heat a whole
/// burn of problems/burn_box.yaml made 40% of its initial energy from nothing.
inline void cell_rates_to_nodes(const IndexBox& nodes, int s, double dt, const ConstVectorField4& cell_acc,
                                const ConstField4& cell_temp_rate, const VectorField4& vel_star,
                                const VectorField4& acc, const Field4& temp_rate,
                                const Field4& transfer_energy = Field4()) {
  with_flag(transfer_energy.data() != nullptr, [&](auto transfer) {
    detail::cell_rates_to_nodes_n<decltype(transfer)::value>(nodes, s, dt, cell_acc, cell_temp_rate, vel_star, acc,
                                                             temp_rate, transfer_energy);
  });
}

}  // namespace mpmice
