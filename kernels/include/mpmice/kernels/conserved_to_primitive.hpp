#pragma once
/// \file conserved_to_primitive.hpp
/// \brief Steps 25-26: the advected totals back to density, velocity, temperature and
///        specific volume (E37, E38).
#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/materials.hpp>
#include <mpmice/kernels/math.hpp>

namespace mpmice {

/// m^{n+1} = mL + Adv[m], rho^{n+1} = m^{n+1}/V (E37, E38).
inline void advance_density(const IndexBox& cells, double cell_volume, int m,
                            const ConstField4& mass_L, const ConstField4& adv_mass,
                            const Field4& rho_new) {
  for_each_index(
      "mpmice::advance_density", cells, KOKKOS_LAMBDA(long i, long j, long k) {
        rho_new(m, i, j, k) = (mass_L(m, i, j, k) + adv_mass(m, i, j, k)) / cell_volume;
      });
}

/// A mass-specific quantity after advection: q^{n+1} = (mL q_L + Adv[mL q])/m^{n+1}
/// (E37, E38), with m^{n+1} = rho^{n+1} V.
inline void advance_specific(const IndexBox& cells, double cell_volume, int m,
                             const ConstField4& mass_L, const ConstField4& q_L,
                             const ConstField4& adv_q, const ConstField4& rho_new,
                             const Field4& q_new) {
  for_each_index(
      "mpmice::advance_specific", cells, KOKKOS_LAMBDA(long i, long j, long k) {
        q_new(m, i, j, k) = (mass_L(m, i, j, k) * q_L(m, i, j, k) + adv_q(m, i, j, k)) /
                            (rho_new(m, i, j, k) * cell_volume);
      });
}

/// One state that broke (E38)'s conditions: where, which material, which quantity.
struct BadState {
  long count = 0;        ///< cells with a bad state
  int cell[3] = {0, 0, 0};  ///< one of them (local index)
  int material = 0;
  int quantity = 0;      ///< 0 density, 1 temperature, 2 specific volume, 3 velocity
};

namespace detail {
/// (E38)'s conditions on one material's state in a cell: density and temperature
/// positive and finite, specific volume positive, velocity finite. Comparisons only
/// (x <= the largest double fails for inf and NaN), so that a loop over cells vectorises.
struct StateCheck {
  double rho, temp, sp_vol, vel[3];
  static constexpr double huge = 1.7976931348623157e308;  // the largest double

  KOKKOS_FORCEINLINE_FUNCTION bool density_good() const { return (rho > 0) & (rho <= huge); }
  KOKKOS_FORCEINLINE_FUNCTION bool temperature_good() const { return (temp > 0) & (temp <= huge); }
  KOKKOS_FORCEINLINE_FUNCTION bool specific_volume_good() const { return sp_vol > 0; }
  KOKKOS_FORCEINLINE_FUNCTION bool velocity_good() const {
    return (math::abs(vel[0]) <= huge) & (math::abs(vel[1]) <= huge) & (math::abs(vel[2]) <= huge);
  }
  /// The first bad quantity (BadState::quantity), or -1.
  KOKKOS_FORCEINLINE_FUNCTION int bad_quantity() const {
    return !density_good() ? 0 : !temperature_good() ? 1 : !specific_volume_good() ? 2 : !velocity_good() ? 3 : -1;
  }
};

KOKKOS_FORCEINLINE_FUNCTION StateCheck state_of(const ConstField4& rho, const ConstField4& temp,
                                                const ConstField4& sp_vol, const ConstVectorField4& vel, int m,
                                                long i, long j, long k) {
  return StateCheck{rho(m, i, j, k), temp(m, i, j, k), sp_vol(m, i, j, k),
                    {vel[0](m, i, j, k), vel[1](m, i, j, k), vel[2](m, i, j, k)}};
}

/// The number of cells with a bad state, N materials written out: one pass of vector rows.
template <int N>
double count_bad_states_n(const IndexBox& cells, const ConstField4& rho, const ConstField4& temp,
                          const ConstField4& sp_vol, const ConstVectorField4& vel) {
  return reduce_over_index<Reduction::sum>(
      "mpmice::count_bad_states", cells, KOKKOS_LAMBDA(long i, long j, long k) {
        double bad = 0;
        unrolled_for<N>([&](int m) {
          const StateCheck s = state_of(rho, temp, sp_vol, vel, m, i, j, k);
          // & not &&: every condition evaluated, no branch.
          const bool good = s.density_good() & s.temperature_good() & s.specific_volume_good() & s.velocity_good();
          bad = good ? bad : 1.0;
        });
        return bad;
      });
}
}  // namespace detail

/// Cells where rho, T or v is not positive (or not finite) or a velocity not finite
/// after the step (E38's stop condition): how many, and the last such cell in index
/// order with its material and quantity. The common case, none, is one counting pass.
inline BadState find_bad_states(const IndexBox& cells, int materials, const ConstField4& rho,
                                const ConstField4& temp, const ConstField4& sp_vol,
                                const ConstVectorField4& vel) {
  double bad_cells = 0;
  with_material_count(materials, [&](auto n) {
    bad_cells = detail::count_bad_states_n<decltype(n)::value>(cells, rho, temp, sp_vol, vel);
  });
  if (bad_cells == 0) return BadState();
  // Where: the cell last in index order, its material and quantity.
  const int nj = int(rho.extent(2)), nk = int(rho.extent(3));
  long count = 0, code = -1;  // code: ((cell * materials) + m) * 4 + quantity
  Kokkos::parallel_reduce(
      "mpmice::find_bad_states", cells.policy(),
      KOKKOS_LAMBDA(int i, int j, int k, long& n, long& where) {
        for (int m = 0; m < materials; ++m) {
          const int q = detail::state_of(rho, temp, sp_vol, vel, m, i, j, k).bad_quantity();
          if (q >= 0) {
            ++n;
            const long c = ((long(i) * nj + j) * nk + k) * materials + m;
            if (c * 4 + q > where) where = c * 4 + q;
            return;
          }
        }
      },
      count, Kokkos::Max<long>(code));
  BadState b;
  b.count = count;
  if (count > 0) {
    b.quantity = int(code % 4);
    const long c = code / 4;
    b.material = int(c % materials);
    const long cell = c / materials;
    b.cell[0] = int(cell / (long(nj) * nk));
    b.cell[1] = int((cell / nk) % nj);
    b.cell[2] = int(cell % nk);
  }
  return b;
}

}  // namespace mpmice
