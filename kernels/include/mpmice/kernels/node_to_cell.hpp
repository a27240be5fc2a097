#pragma once
/// \file node_to_cell.hpp
/// \brief Step 2 of MPMICE: the MPM materials' cell mass, velocity and temperature
///        from their node values (E10, E13), so that solids join the pressure
///        equilibration and the exchange.
#include <mpmice/kernels/boundary_conditions.hpp>
#include <mpmice/kernels/constants.hpp>
#include <mpmice/kernels/eos.hpp>
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/particle_grid.hpp>

namespace mpmice {

/// w_i = 1/8, doubled once per symmetry plane the node lies on (E10): such nodes get
/// mass from one side only. Over every node of the patch.
inline void node_cell_weights(const Patch& patch, const FaceBcs& velocity_bcs, const Field3& weight) {
  const int G = patch.ghosts;
  int plane[3][2];
  for (int d = 0; d < 3; ++d)
    for (int side = 0; side < 2; ++side)
      plane[d][side] = patch.on_domain_boundary(d, side) && velocity_bcs[2 * d + side].kind == BcKind::symmetry
                           ? (side == 0 ? G : G + patch.owned_cells(d))
                           : -1;
  const int px0 = plane[0][0], px1 = plane[0][1], py0 = plane[1][0], py1 = plane[1][1], pz0 = plane[2][0],
            pz1 = plane[2][1];
  Kokkos::parallel_for(
      "mpmice::node_cell_weights", patch.ghosted_nodes(G).policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        double w = 0.125;
        if (i == px0 || i == px1) w *= 2.0;
        if (j == py0 || j == py1) w *= 2.0;
        if (k == pz0 || k == pz1) w *= 2.0;
        weight(i, j, k) = w;
      });
}

/// Adds over the 8 nodes of cell (i, j, k), a outermost, c innermost, for node slot s:
/// sum w m to `mass`, sum w m v to `mom`, sum w m c T to `heat` (w the node's weight
/// of E10; E13, E27).
KOKKOS_FORCEINLINE_FUNCTION void add_weighted_node_sums(const ConstField3& weight, const ConstField4& node_mass,
                                                        const ConstVectorField4& node_vel,
                                                        const ConstField4& node_temp, int s, long i, long j, long k,
                                                        double c, double& mass, double* mom, double& heat) {
  unrolled_for<8>([&](int n) {
    const long ni = i + corner(n, 0), nj = j + corner(n, 1), nk = k + corner(n, 2);
    const double wm = weight(ni, nj, nk) * node_mass(s, ni, nj, nk);
    mass += wm;
    unrolled_for<3>([&](int d) { mom[d] += wm * node_vel[d](s, ni, nj, nk); });
    heat += wm * c * node_temp(s, ni, nj, nk);
  });
}

/// (E13) for MPM node slot s, cell material m: m_r = m_small + sum_i w_i m_i,
/// u_r = sum w m v / m_r, T_r = (1 - z) T_r^n + z sum w m T / m_r with
/// z = (m_r - m_small)/m_r, rho_r = m_r / V. The specific volume is set from the
/// solid's equation of state at last step's pressure, rhoM_CM(p^n, T) (pitfall P1),
/// which is where the equilibration starts. Every cell gets what eos_density gives. On
/// the host the cells where the modified law in tension applies get it in a second
/// pass, scalar (pow): in the first loop its pow kept that loop from vectorising (the
/// two passes: 1.3-1.6x faster; docs/performance.md, session 18). A GPU backend takes
/// eos_density in the one loop.
inline void node_to_cell(const IndexBox& cells, double cell_volume, int s, int m, const Eos& eos,
                         const ConstField3& weight, const ConstField4& node_mass,
                         const ConstVectorField4& node_vel, const ConstField4& node_temp,
                         const ConstField3& press, const Field4& rho, const VectorField4& vel,
                         const Field4& temp, const Field4& sp_vol) {
  const double m_small = tiny_rho * cell_volume;
  for_each_index("mpmice::node_to_cell", cells, KOKKOS_LAMBDA(long i, long j, long k) {
    double mass = m_small, mom[3] = {0, 0, 0}, heat = 0;
    add_weighted_node_sums(weight, node_mass, node_vel, node_temp, s, i, j, k, 1.0, mass, mom, heat);
    const double z = (mass - m_small) / mass;
    const double t = (1.0 - z) * temp(m, i, j, k) + z * heat / mass;
    temp(m, i, j, k) = t;
    unrolled_for<3>([&](int d) { vel[d](m, i, j, k) = mom[d] / mass; });
    rho(m, i, j, k) = mass / cell_volume;
#if defined(MPMICE_DEVICE_BACKEND)
    sp_vol(m, i, j, k) = 1.0 / eos_density(eos, press(i, j, k), t);
#else
    sp_vol(m, i, j, k) = 1.0 / eos_density_outside_tension(eos, press(i, j, k), t);
#endif
  });
#if !defined(MPMICE_DEVICE_BACKEND)
  if (!eos_has_tension_law(eos)) return;
  for_each_index("mpmice::node_to_cell_tension", cells, KOKKOS_LAMBDA(long i, long j, long k) {
    const double p = press(i, j, k);
    if (eos_tension_law(eos, p)) sp_vol(m, i, j, k) = 1.0 / eos_density(eos, p, temp(m, i, j, k));
  });
#endif
}

/// The heaviest particle of a set (0 if empty): the driver makes it global and takes
/// 2^-40 of it as the mass unit of rigid_particle_to_cell.
inline double max_particle_mass(long count, const ParticleData& data) {
  double m_max = 0;
  Kokkos::parallel_reduce(
      "mpmice::max_particle_mass", Kokkos::RangePolicy<ExecSpace>(0, count),
      KOKKOS_LAMBDA(long p, double& mx) {
        const double mp = data(p, column(ParticleField::mass));
        if (mp > mx) mx = mp;
      },
      Kokkos::Max<double>(m_max));
  return m_max;
}

/// A rigid body's cell density, velocity and temperature from its particles
/// (particle-to-cell): rho_r = (m_small + sum of the masses of its particles in the
/// cell)/V. Its velocity is prescribed, so no momentum has to match node sums; and its
/// surface then lies where its particles are instead of being spread over half a cell
/// by (E13). An addition to the algorithm document (docs/design.md). The body moves as
/// one: every cell, with or without particles, gets its prescribed `velocity` at this
/// time (not a node average that rounds differently on other decompositions). The
/// temperature is the particles' mass-weighted mean, blended with the old one in
/// nearly empty cells as (E13) does. All sums are exact integers - masses in units of
/// `mass_quantum` (the driver passes 2^-40 of the heaviest particle on any rank),
/// temperatures as whole kelvin plus 2^-20 K units, weighted by 2^-20 of the heaviest
/// mass - so they do not depend on the order in which threads or ranks add: the same
/// run on any decomposition, and its restarts, give the same cells bit for bit. The
/// specific volume is set as in node_to_cell. Replaces node_to_cell for rigid bodies.
inline void rigid_particle_to_cell(const IndexBox& cells, double cell_volume, int m, const Eos& eos,
                                   const double* lower, const double* inv_h, double mass_quantum,
                                   Kokkos::Array<double, 3> velocity, long count,
                                   const ParticleData& data, const ConstField3& press, const Field4& rho,
                                   const VectorField4& vel, const Field4& temp, const Field4& sp_vol) {
  const double m_small = tiny_rho * cell_volume;
  const double q_m = mass_quantum, q_t = 0x1p-20;
  const std::size_t n0 = rho.extent(1), n1 = rho.extent(2), n2 = rho.extent(3);
  // Per cell: mass, temperature weight, weighted whole kelvin, weighted 2^-20 K units.
  enum { mass_units, weight_units, kelvin_units, fraction_units };
  Kokkos::View<long long****, MemSpace> units("mpmice::rigid_particle_units", 4, n0, n1, n2);
  const double l0 = lower[0], l1 = lower[1], l2 = lower[2], i0 = inv_h[0], i1 = inv_h[1], i2 = inv_h[2];
  Kokkos::parallel_for(
      "mpmice::rigid_particle_sums", Kokkos::RangePolicy<ExecSpace>(0, count), KOKKOS_LAMBDA(long p) {
        const int i = int(math::floor((data(p, column(ParticleField::x)) - l0) * i0));
        const int j = int(math::floor((data(p, column(ParticleField::y)) - l1) * i1));
        const int k = int(math::floor((data(p, column(ParticleField::z)) - l2) * i2));
        const long long mu = (long long)(data(p, column(ParticleField::mass)) / q_m + 0.5);
        const long long wu = (mu + (1LL << 19)) >> 20;  // <= 2^20 for the heaviest particle
        const double t = data(p, column(ParticleField::temperature));
        const double whole = math::floor(t);
        Kokkos::atomic_add(&units(mass_units, i, j, k), mu);
        Kokkos::atomic_add(&units(weight_units, i, j, k), wu);
        Kokkos::atomic_add(&units(kelvin_units, i, j, k), wu * (long long)whole);
        Kokkos::atomic_add(&units(fraction_units, i, j, k), wu * (long long)((t - whole) / q_t + 0.5));
      });
  Kokkos::parallel_for(
      "mpmice::rigid_particle_to_cell", cells.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        const double mass = m_small + double(units(mass_units, i, j, k)) * q_m;
        rho(m, i, j, k) = mass / cell_volume;
        for (int d = 0; d < 3; ++d) vel[d](m, i, j, k) = velocity[d];
        const long long w = units(weight_units, i, j, k);
        if (w > 0) {
          const double kelvin = double(units(kelvin_units, i, j, k));
          const double mean = (kelvin + q_t * double(units(fraction_units, i, j, k))) / double(w);
          const double z = (mass - m_small) / mass;
          temp(m, i, j, k) = (1.0 - z) * temp(m, i, j, k) + z * mean;
        }
        sp_vol(m, i, j, k) = 1.0 / eos_density(eos, press(i, j, k), temp(m, i, j, k));
      });
}

}  // namespace mpmice
