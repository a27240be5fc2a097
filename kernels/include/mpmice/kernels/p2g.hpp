#pragma once
/// \file p2g.hpp
/// \brief Step 1: particle-to-grid of mass, momentum, m T, volume and external force
///        (E12), and the node velocity and temperature from them.
///
/// The scatter: Kokkos ScatterView (duplicated per thread on OpenMP, atomic on GPUs)
/// is the one way particles add into nodes (`scatter_add` below); the benchmark issue
/// measures it against the alternatives.
#include <Kokkos_ScatterView.hpp>

#include <mpmice/kernels/particle_grid.hpp>
#include <mpmice/kernels/quanta.hpp>
#include <mpmice/kernels/shape.hpp>

namespace mpmice {

/// Node sums of one MPM material, indexed (m, i, j, k) on the patch's nodes.
struct NodeSums {
  Field4 mass;      ///< sum S m_p, kg (starts at 1e-200)
  VectorField4 mom; ///< sum S m_p v_p, kg m/s
  Field4 heat;      ///< sum S m_p T_p, kg K
  Field4 volume;    ///< sum S V_p, m^3 (starts at 1e-200)
  VectorField4 fext;///< sum S f_ext,p, N
};

/// One material's nodes of a node field (slot m of the (m, i, j, k) array), contiguous:
/// a particle loop scatters into its own material's slot only.
using NodeSlot = Kokkos::View<double***, Kokkos::LayoutRight, MemSpace>;

inline NodeSlot material_slot(const Field4& f, int m) {
  return Kokkos::subview(f, m, Kokkos::ALL, Kokkos::ALL, Kokkos::ALL);
}

/// The one scatter: every node field gets its particles' contributions summed in. On
/// OpenMP each thread adds into its own copy of the slot, summed after the loop.
using NodeScatter = Kokkos::Experimental::ScatterView<double***, Kokkos::LayoutRight, ExecSpace>;

/// Add what a scatter gathered into its node slot.
inline void contribute(NodeSlot dest, const NodeScatter& scatter) {
  Kokkos::Experimental::contribute(dest, scatter);
}

/// (E12) for the `count` particles of `data` into material slot m of `sums` (which the
/// call first resets over the whole patch, ghost nodes included). With quanta `q` each
/// contribution is rounded to them (quanta.hpp: sums independent of their order).
template <class Shape>
void p2g(const NodeGrid& grid, long count, const ParticleData& data, int m, const NodeSums& sums,
         const SumQuanta& q = SumQuanta()) {
  const NodeSlot slot[9] = {material_slot(sums.mass, m),    material_slot(sums.mom[0], m),
                            material_slot(sums.mom[1], m),  material_slot(sums.mom[2], m),
                            material_slot(sums.heat, m),    material_slot(sums.volume, m),
                            material_slot(sums.fext[0], m), material_slot(sums.fext[1], m),
                            material_slot(sums.fext[2], m)};
  for (int f = 0; f < 9; ++f) Kokkos::deep_copy(slot[f], f == 0 || f == 5 ? 1e-200 : 0.0);
  NodeScatter s_mass(slot[0]), s_px(slot[1]), s_py(slot[2]), s_pz(slot[3]), s_heat(slot[4]), s_vol(slot[5]),
      s_fx(slot[6]), s_fy(slot[7]), s_fz(slot[8]);
  Kokkos::parallel_for(
      "mpmice::p2g", Kokkos::RangePolicy<ExecSpace>(0, count), KOKKOS_LAMBDA(long p) {
        double x[3], half[3];
        particle_position(data, p, x, half);
        const ParticleWeights<Shape> wt(x, grid.origin, grid.inv_h, grid.first_node, half);
        const double mp = data(p, column(ParticleField::mass));
        const double vp = data(p, column(ParticleField::volume));
        const double px = mp * data(p, column(ParticleField::vx)), py = mp * data(p, column(ParticleField::vy)),
                     pz = mp * data(p, column(ParticleField::vz));
        const double mt = mp * data(p, column(ParticleField::temperature));
        const double fx = data(p, column(ParticleField::fext_x)), fy = data(p, column(ParticleField::fext_y)),
                     fz = data(p, column(ParticleField::fext_z));
        auto a_mass = s_mass.access();
        auto a_px = s_px.access();
        auto a_py = s_py.access();
        auto a_pz = s_pz.access();
        auto a_heat = s_heat.access();
        auto a_vol = s_vol.access();
        auto a_fx = s_fx.access();
        auto a_fy = s_fy.access();
        auto a_fz = s_fz.access();
        for (int a = 0; a < Shape::nodes; ++a)
          for (int b = 0; b < Shape::nodes; ++b)
            for (int c = 0; c < Shape::nodes; ++c) {
              const double S = wt.weight(a, b, c);
              // A node whose share of the mass rounds to zero gets nothing at all, so
              // that no node has momentum or force without mass (internal_force skips it too).
              const double ms = on_grid(S * mp, q.mass);
              if (ms == 0.0) continue;
              const int i = wt.first[0] + a, j = wt.first[1] + b, k = wt.first[2] + c;
              a_mass(i, j, k) += ms;
              a_px(i, j, k) += on_grid(S * px, q.momentum);
              a_py(i, j, k) += on_grid(S * py, q.momentum);
              a_pz(i, j, k) += on_grid(S * pz, q.momentum);
              a_heat(i, j, k) += on_grid(S * mt, q.heat);
              a_vol(i, j, k) += on_grid(S * vp, q.volume);
              a_fx(i, j, k) += on_grid(S * fx, q.external_force);
              a_fy(i, j, k) += on_grid(S * fy, q.external_force);
              a_fz(i, j, k) += on_grid(S * fz, q.external_force);
            }
      });
  const NodeScatter* scatters[9] = {&s_mass, &s_px, &s_py, &s_pz, &s_heat, &s_vol, &s_fx, &s_fy, &s_fz};
  for (int f = 0; f < 9; ++f) contribute(slot[f], *scatters[f]);
}

/// Node velocity v = sum S m v / m and temperature T = sum S m T / m (E12) on `nodes`.
inline void node_velocity_temperature(const IndexBox& nodes, int m, const ConstField4& mass,
                                      const ConstVectorField4& mom, const ConstField4& heat,
                                      const VectorField4& vel, const Field4& temp) {
  Kokkos::parallel_for(
      "mpmice::node_velocity_temperature", nodes.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        const double inv = 1.0 / mass(m, i, j, k);
        for (int d = 0; d < 3; ++d) vel[d](m, i, j, k) = mom[d](m, i, j, k) * inv;
        temp(m, i, j, k) = heat(m, i, j, k) * inv;
      });
}

}  // namespace mpmice
