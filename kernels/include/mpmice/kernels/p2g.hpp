#pragma once
/// \file p2g.hpp
/// \brief Step 1: particle-to-grid of mass, momentum, m T, volume and external force
///        (E12), and the node velocity and temperature from them.
///
/// The scatter: Kokkos ScatterView (duplicated per thread on OpenMP, atomic on GPUs)
/// is the one way particles add into nodes (`NodeScatter` below); bench_scatter.cpp
/// measures it against the alternatives.
#include <string>

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

/// The sums of one particle loop, a node's F fields side by side: (i, j, k, f). A
/// particle computes a node's index once for all its fields; the block is unpacked into
/// the fields' slots after the loop.
using NodeBlock = Kokkos::View<double****, Kokkos::LayoutRight, MemSpace>;

/// The one scatter: a particle loop adds into a NodeBlock through it. On OpenMP each
/// thread adds into its own copy, summed after the loop (docs/performance.md).
using NodeScatter = Kokkos::Experimental::ScatterView<double****, Kokkos::LayoutRight, ExecSpace>;

/// A zeroed block of `fields` fields over the nodes of `like`.
inline NodeBlock node_block(const char* label, const NodeSlot& like, int fields) {
  return NodeBlock(std::string(label), like.extent(0), like.extent(1), like.extent(2), std::size_t(fields));
}

/// Add what the scatter gathered into `block`, then dest[f] = start[f] + block(., f).
template <int F>
void unpack_block(NodeBlock block, const NodeScatter& scatter, const Kokkos::Array<NodeSlot, F>& dest,
                  const Kokkos::Array<double, F>& start) {
  Kokkos::Experimental::contribute(block, scatter);
  const IndexBox nodes{{0, 0, 0}, {int(block.extent(0)), int(block.extent(1)), int(block.extent(2))}};
  Kokkos::parallel_for(
      "mpmice::unpack_block", nodes.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        for (int f = 0; f < F; ++f) dest[f](i, j, k) = start[f] + block(i, j, k, f);
      });
}

/// (E12) for the `count` particles of `data` into material slot m of `sums` (which the
/// call first resets over the whole patch, ghost nodes included). With quanta `q` each
/// contribution is rounded to them (quanta.hpp: sums independent of their order).
template <class Shape>
void p2g(const NodeGrid& grid, long count, const ParticleData& data, int m, const NodeSums& sums,
         const SumQuanta& q = SumQuanta()) {
  // Fields: mass, momentum (3), m T, volume, external force (3); mass and volume start
  // at 1e-200 so that no node divides by zero.
  const Kokkos::Array<NodeSlot, 9> slot = {
      material_slot(sums.mass, m),    material_slot(sums.mom[0], m),  material_slot(sums.mom[1], m),
      material_slot(sums.mom[2], m),  material_slot(sums.heat, m),    material_slot(sums.volume, m),
      material_slot(sums.fext[0], m), material_slot(sums.fext[1], m), material_slot(sums.fext[2], m)};
  const NodeBlock block = node_block("mpmice::p2g", slot[0], 9);
  const NodeScatter scatter(block);
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
        auto node = scatter.access();
        for (int a = 0; a < Shape::nodes; ++a)
          for (int b = 0; b < Shape::nodes; ++b)
            for (int c = 0; c < Shape::nodes; ++c) {
              const double S = wt.weight(a, b, c);
              // A node whose share of the mass rounds to zero gets nothing at all, so
              // that no node has momentum or force without mass (internal_force skips it too).
              const double ms = on_grid(S * mp, q.mass);
              if (ms == 0.0) continue;
              const int i = wt.first[0] + a, j = wt.first[1] + b, k = wt.first[2] + c;
              node(i, j, k, 0) += ms;
              node(i, j, k, 1) += on_grid(S * px, q.momentum);
              node(i, j, k, 2) += on_grid(S * py, q.momentum);
              node(i, j, k, 3) += on_grid(S * pz, q.momentum);
              node(i, j, k, 4) += on_grid(S * mt, q.heat);
              node(i, j, k, 5) += on_grid(S * vp, q.volume);
              node(i, j, k, 6) += on_grid(S * fx, q.external_force);
              node(i, j, k, 7) += on_grid(S * fy, q.external_force);
              node(i, j, k, 8) += on_grid(S * fz, q.external_force);
            }
      });
  unpack_block<9>(block, scatter, slot, {1e-200, 0, 0, 0, 0, 1e-200, 0, 0, 0});
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
