#pragma once
/// \file particles.hpp
/// \brief ParticleSet: the particles of one MPM material as a structure of arrays.
///
/// Every double component is one contiguous column of a LayoutLeft 2D view, so
/// `p.get(ParticleField::vx)` is a plain 1D view of all particles' x-velocities
/// and generic code (migration, sorting, output) can loop over the components.
/// Units: SI (m, m/s, kg, m^3, K, Pa).
#include <cstdint>
#include <string>
#include <mpmice/kernels/types.hpp>

namespace mpmice {

/// The particle components (mpmice-algorithm.md section 1.6).
enum class ParticleField : int {
  x, y, z,                      ///< position, m
  vx, vy, vz,                   ///< velocity, m/s
  mass,                         ///< kg
  volume,                       ///< m^3
  temperature,                  ///< K
  size_x, size_y, size_z,       ///< extent / cell size (1/res_d at creation)
  F00, F01, F02, F10, F11, F12, F20, F21, F22,  ///< deformation gradient
  s00, s01, s02, s10, s11, s12, s20, s21, s22,  ///< Cauchy stress, Pa, tension +
  fext_x, fext_y, fext_z,       ///< external force, N
  gas_pressure,                 ///< gauge pressure of the surrounding gas, Pa
  bulk_viscosity,               ///< artificial bulk viscosity q, Pa
  heating_rate,                 ///< constitutive heating rate, K/s
  plastic_strain,               ///< equivalent plastic strain
  L00, L01, L02, L10, L11, L12, L20, L21, L22,  ///< velocity gradient of the last step, 1/s
  be00, be01, be02, be10, be11, be12, be20, be21, be22,  ///< elastic left Cauchy-Green bbar_e
  count                         ///< number of components (not a component)
};
constexpr int particle_field_count = static_cast<int>(ParticleField::count);

using ParticleData = Kokkos::View<double**, Kokkos::LayoutLeft, MemSpace>;
using ParticleIds = Kokkos::View<std::int64_t*, MemSpace>;

/// Component c of the 3 x 3 tensor whose first component is `first` (F00, s00, ...).
KOKKOS_INLINE_FUNCTION int tensor_column(ParticleField first, int i, int j) {
  return static_cast<int>(first) + 3 * i + j;
}
/// Column index of a particle component.
KOKKOS_INLINE_FUNCTION constexpr int column(ParticleField f) { return static_cast<int>(f); }

/// The particles of one MPM material on one patch: `size()` live particles in the
/// first rows of views that hold `capacity()`.
class ParticleSet {
 public:
  ParticleSet() = default;
  explicit ParticleSet(const std::string& label, std::size_t capacity = 0) : ParticleSet(label, capacity, true) {}
  /// A set of `capacity` rows left unset (not zeroed), for a caller that writes them all.
  static ParticleSet unset(const std::string& label, std::size_t capacity) {
    return ParticleSet(label, capacity, false);
  }

  std::size_t size() const { return m_size; }
  std::size_t capacity() const { return m_data.extent(0); }
  const std::string& label() const { return m_label; }

  /// One component of every particle (live and spare rows).
  ParticleComponent get(ParticleField f) const {
    return Kokkos::subview(m_data, Kokkos::ALL, static_cast<int>(f));
  }
  /// All components, (particle, component): for code that treats them alike.
  const ParticleData& data() const { return m_data; }
  /// Global particle ids (unique across ranks, kept through migration).
  const ParticleIds& id() const { return m_id; }

  /// Grow the capacity to at least n, keeping the live particles.
  void reserve(std::size_t n) {
    if (n <= capacity()) return;
    std::size_t cap = capacity() + capacity() / 2;
    if (cap < n) cap = n;
    Kokkos::resize(m_data, cap, particle_field_count);
    Kokkos::resize(m_id, cap);
  }
  /// Set the live count; grows the capacity if needed. New rows hold whatever the
  /// caller writes into them.
  void resize(std::size_t n) {
    reserve(n);
    m_size = n;
  }

 private:
  // The two views of `capacity` rows, zeroed or left unset.
  ParticleSet(const std::string& label, std::size_t capacity, bool zeroed)
      : m_label(label),
        m_data(allocate<ParticleData>(label + "_data", zeroed, capacity, particle_field_count)),
        m_id(allocate<ParticleIds>(label + "_id", zeroed, capacity)) {}
  template <class View, class... Extents>
  static View allocate(const std::string& name, bool zeroed, Extents... extents) {
    if (zeroed) return View(name, extents...);
    return View(Kokkos::view_alloc(Kokkos::WithoutInitializing, name), extents...);
  }

  std::string m_label;
  ParticleData m_data;
  ParticleIds m_id;
  std::size_t m_size = 0;
};

/// A new set holding, in row q, every component and the id of row rows(q) of `from`,
/// for q < n: the one gather behind sorting and removing particles.
template <class Rows>
ParticleSet gather_particles(const ParticleSet& from, const Rows& rows, long n) {
  // Every row is written below: not zeroed first (for 4e6 particles, 2.2 GB zeroed
  // for nothing).
  ParticleSet out = ParticleSet::unset(from.label(), std::size_t(n));
  out.resize(std::size_t(n));
  const ParticleData src = from.data(), dst = out.data();
  const ParticleIds id_in = from.id(), id_out = out.id();
  const int ncomp = particle_field_count;
  Kokkos::parallel_for(
      "mpmice::gather_particles", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(long q) {
        const long p = rows(q);
        for (int c = 0; c < ncomp; ++c) dst(q, c) = src(p, c);
        id_out(q) = id_in(p);
      });
  return out;
}

}  // namespace mpmice
