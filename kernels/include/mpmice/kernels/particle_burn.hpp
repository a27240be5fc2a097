#pragma once
/// \file particle_burn.hpp
/// \brief The reaction's transfer (E46) done on the particles: the reactant's particles
///        in a burning cell lose the mass Simple Burn decided (E45), and the product gas
///        gains, in that cell, exactly what they lose - mass, momentum, internal energy -
///        plus the heat of reaction. Burned-out particles are then removed (Step 24).
///
/// Why on the particles and not on the cells: the solid's cell mass, momentum and energy
/// are sums over its particles (E12, E13, E27). Taking dm from the particles before they
/// are interpolated keeps those sums, and hence the exact non-reacting balance of
/// (E27)-(E35), unchanged; the reactant needs no cell source, and every kilogram the gas
/// gains is one a particle lost (docs/design.md, "Reactions").
#include <mpmice/kernels/materials.hpp>
#include <mpmice/kernels/particle_grid.hpp>
#include <mpmice/kernels/particle_totals.hpp>
#include <mpmice/kernels/quanta.hpp>
#include <mpmice/kernels/simple_burn.hpp>

namespace mpmice {

/// What the product gains per cell (slot `product`): mass (kg), momentum (kg m/s),
/// internal energy including the heat of reaction (J).
struct ProductSources {
  Field4 mass;
  VectorField4 momentum;
  Field4 energy;
};

/// (E46) on the particles of the reactant `burn.reactant`: with M_c the mass of its
/// particles in cell c and dm_c = `burn_dm`(reactant, c), every particle in c loses the
/// fraction f = min(dm_c / M_c, 1) of its mass, and its volume in proportion (f within
/// 1e-12 of 1 is 1: the particle burns out, mass exactly 0). The product gains, in c,
/// the lost mass m_l, its momentum m_l v_p and energy
/// m_l (c_v,s T_p + dh + |v_p|^2 / 2) + (m_l / m_p) W_p, added into `src` (zeroed by the
/// caller): all the energy the burned solid had, thermal, chemical, kinetic and the
/// strain energy W_p it stored (`model`). The product's own kinetic energy comes from
/// the momentum; what the burned solid brought beyond it is heat (add_product_sources).
/// `cell_mass` is scratch of the patch's cell extent. A particle's cell is `grid.cell`
/// (from the grid's origin, the same on every decomposition). Returns the mass the
/// particles lost on this rank (kg; times dh: the heat of reaction released).
/// With quanta `q` (quanta.hpp) every sum is independent of the particles' order: the
/// particle masses must then be multiples of q.mass, and the lost mass is rounded to it,
/// so a particle still loses exactly what its cell's product gains.
inline double burn_particles(const NodeGrid& grid, long count, const ParticleData& data, double reactant_cv,
                             const SolidModel& model, const SimpleBurn& burn, const ConstField4& burn_dm,
                             const Field3& cell_mass, const ProductSources& src, const SumQuanta& q = SumQuanta()) {
  if (count == 0) return 0.0;
  const SimpleBurn b = burn;
  const ProductSources out = src;
  auto cell_of = KOKKOS_LAMBDA(long p, int c[3]) {
    for (int d = 0; d < 3; ++d)
      c[d] = grid.cell(data(p, column(ParticleField::x) + d), d);
  };
  Kokkos::deep_copy(cell_mass, 0.0);
  Kokkos::parallel_for(
      "mpmice::burn_cell_mass", Kokkos::RangePolicy<ExecSpace>(0, count), KOKKOS_LAMBDA(long p) {
        int c[3];
        cell_of(p, c);
        Kokkos::atomic_add(&cell_mass(c[0], c[1], c[2]), data(p, column(ParticleField::mass)));
      });
  double lost_mass = 0;
  Kokkos::parallel_reduce(
      "mpmice::burn_particles", Kokkos::RangePolicy<ExecSpace>(0, count),
      KOKKOS_LAMBDA(long p, double& lost_sum) {
        int c[3];
        cell_of(p, c);
        const double dm = burn_dm(b.reactant, c[0], c[1], c[2]);
        const double M = cell_mass(c[0], c[1], c[2]);
        if (!(dm > 0) || !(M > 0)) return;
        const double f = dm / M;
        const double m = data(p, column(ParticleField::mass));
        const double strain = particle_strain_energy(model, data, p);
        double lost = on_grid(f * m, q.mass), kept = m - lost;
        if (f >= 1.0 - 1e-12 || !(kept > 0)) {  // burned out
          lost = m;
          kept = 0.0;
        }
        data(p, column(ParticleField::mass)) = kept;
        data(p, column(ParticleField::volume)) *= kept / m;
        const int g = b.product;
        Kokkos::atomic_add(&out.mass(g, c[0], c[1], c[2]), lost);
        double speed2 = 0;
        for (int d = 0; d < 3; ++d) {
          const double v = data(p, column(ParticleField::vx) + d);
          speed2 += v * v;
          Kokkos::atomic_add(&out.momentum[d](g, c[0], c[1], c[2]), on_grid(lost * v, q.momentum));
        }
        const double specific = reactant_cv * data(p, column(ParticleField::temperature)) + b.enthalpy + 0.5 * speed2;
        Kokkos::atomic_add(&out.energy(g, c[0], c[1], c[2]), on_grid(lost * specific + (lost / m) * strain, q.energy));
        lost_sum += lost;
      },
      lost_mass);
  return lost_mass;
}

/// The specific volume the new gas takes where it is created (m^3/kg; 0 where a material
/// gained no mass): at the cell's pressure p_eq and its own temperature
/// T_new = dE / (dm c_v), v = 1 / rhoM(p_eq, T_new). (dE includes the burned solid's
/// kinetic energy, part of which stays kinetic in the merged gas: at 300 m/s, 2% of
/// c_v T_new here; the next equilibration corrects the volume.) The gas leaves a
/// burning surface at about the surrounding pressure (a deflagration is nearly
/// isobaric); creating it at a smaller volume would compress it for free and let it
/// lose that energy when it expands. Used for dP_mx (E20) and the new volume in (E32).
inline void new_gas_specific_volume(const IndexBox& cells, const MaterialTable& mats, const ConstField4& mass_source,
                                    const ConstField4& energy_source, const ConstField3& press_eq,
                                    const Field4& sp_vol_new) {
  Kokkos::parallel_for(
      "mpmice::new_gas_specific_volume", cells.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        for (int m = 0; m < mats.count; ++m) {
          const double dm = mass_source(m, i, j, k);
          double v = 0;
          if (dm > 0) {
            const double t_new = energy_source(m, i, j, k) / (dm * mats.eos[m].cv);
            v = 1.0 / eos_density(mats.eos[m], press_eq(i, j, k), t_new);
          }
          sp_vol_new(m, i, j, k) = v;
        }
      });
}

/// Removes the particles whose mass is not positive (burned out), keeping the order of
/// the others. Returns how many were removed.
inline long remove_massless_particles(ParticleSet& particles) {
  const long n = long(particles.size());
  const ParticleData data = particles.data();
  long alive = 0;
  Kokkos::parallel_reduce(
      "mpmice::count_massive", Kokkos::RangePolicy<ExecSpace>(0, n),
      KOKKOS_LAMBDA(long p, long& a) { a += data(p, column(ParticleField::mass)) > 0 ? 1 : 0; }, alive);
  if (alive == n) return 0;
  Kokkos::View<long*, MemSpace> rows("mpmice::massive_rows", alive);
  Kokkos::parallel_scan(
      "mpmice::massive_rows", Kokkos::RangePolicy<ExecSpace>(0, n),
      KOKKOS_LAMBDA(long p, long& slot, bool final) {
        if (!(data(p, column(ParticleField::mass)) > 0)) return;
        if (final) rows(slot) = p;
        ++slot;
      });
  particles = gather_particles(particles, rows, alive);
  return n - alive;
}

}  // namespace mpmice
