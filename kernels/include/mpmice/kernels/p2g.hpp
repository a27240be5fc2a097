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

#include <mpmice/kernels/loops.hpp>
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

/// The sums of one particle loop: a row per node of the patch, (i, j, k) at row
/// (i n_j + j) n_k + k (`block_stencil`), with the node's F fields side by side. A
/// particle finds a node's row once for all its fields; the block is unpacked into the
/// fields after the loop.
using NodeBlock = Kokkos::View<double**, Kokkos::LayoutRight, MemSpace>;

/// The one scatter: a particle loop adds into a NodeBlock through it. On OpenMP each
/// thread adds into its own copy, summed after the loop (docs/performance.md).
using NodeScatter = Kokkos::Experimental::ScatterView<double**, Kokkos::LayoutRight, ExecSpace>;

/// A zeroed block of `fields` fields over the nodes of the node field `like`.
inline NodeBlock node_block(const char* label, const ConstField4& like, int fields) {
  return NodeBlock(std::string(label), like.extent(1) * like.extent(2) * like.extent(3), std::size_t(fields));
}

/// Where a particle's nodes are in a NodeBlock over the nodes of `like`.
template <int Nodes>
NodeStencil<Nodes> block_stencil(const ConstField4& like) {
  return NodeStencil<Nodes>(0, long(like.extent(2) * like.extent(3)), long(like.extent(3)), 1);
}

/// Add what the scatter gathered into `block`, then dest[f](m, .) = start[f] + block(., f).
template <int F>
void unpack_block(NodeBlock block, const NodeScatter& scatter, const Kokkos::Array<Field4, F>& dest, int m,
                  const Kokkos::Array<double, F>& start) {
  Kokkos::Experimental::contribute(block, scatter);
  const IndexBox nodes{{0, 0, 0}, {int(dest[0].extent(1)), int(dest[0].extent(2)), int(dest[0].extent(3))}};
  const long nj = nodes.hi[1], nk = nodes.hi[2];
  for_each_index("mpmice::unpack_block", nodes, KOKKOS_LAMBDA(long i, long j, long k) {
    const long row = (i * nj + j) * nk + k;
    for (int f = 0; f < F; ++f) dest[f](m, i, j, k) = start[f] + block(row, f);
  });
}

/// (E12) for the `count` particles of `data` into material slot m of `sums` (which the
/// call first resets over the whole patch, ghost nodes included). With quanta `q` each
/// contribution is rounded to them (quanta.hpp: sums independent of their order).
template <class Shape>
void p2g(const NodeGrid& grid, long count, const ParticleData& data, int m, const NodeSums& sums,
         const SumQuanta& q = SumQuanta()) {
  constexpr int n = Shape::nodes, F = 9;
  // Fields: mass, momentum (3), m T, volume, external force (3); mass and volume start
  // at 1e-200 so that no node divides by zero.
  const Kokkos::Array<Field4, F> dest = {sums.mass,    sums.mom[0], sums.mom[1], sums.mom[2], sums.heat,
                                         sums.volume,  sums.fext[0], sums.fext[1], sums.fext[2]};
  const Kokkos::Array<Quantum, F> quantum = {q.mass,   q.momentum, q.momentum,       q.momentum,       q.heat,
                                            q.volume, q.external_force, q.external_force, q.external_force};
  const NodeBlock block = node_block("mpmice::p2g", sums.mass, F);
  const NodeStencil<n> rows = block_stencil<n>(sums.mass);
  const NodeScatter scatter(block);
  scatter_from_particles(
      "mpmice::p2g", count, KOKKOS_LAMBDA(long p) {
        double x[3], half[3];
        particle_position(data, p, x, half);
        const ParticleWeights<Shape> wt(x, grid.origin, grid.inv_h, grid.first_node, half);
        const long first = rows.at(wt.first);
        const double mp = data(p, column(ParticleField::mass));
        const double value[F] = {mp,
                                 mp * data(p, column(ParticleField::vx)),
                                 mp * data(p, column(ParticleField::vy)),
                                 mp * data(p, column(ParticleField::vz)),
                                 mp * data(p, column(ParticleField::temperature)),
                                 data(p, column(ParticleField::volume)),
                                 data(p, column(ParticleField::fext_x)),
                                 data(p, column(ParticleField::fext_y)),
                                 data(p, column(ParticleField::fext_z))};
        auto node = scatter.access();
        unrolled_for<n>([&](int a) {
          unrolled_for<n>([&](int b) {
            unrolled_for<n>([&](int c) {
              const double S = wt.weight(a, b, c);
              // A node whose share of the mass rounds to zero gets nothing at all, so
              // that no node has momentum or force without mass (internal_force skips it too).
              if (quantum[0].round(S * mp) == 0.0) return;
              const long row = first + rows.step(a, b, c);
              for (int f = 0; f < F; ++f) node(row, f) += quantum[f].round(S * value[f]);
            });
          });
        });
      });
  unpack_block<F>(block, scatter, dest, m, {1e-200, 0, 0, 0, 0, 1e-200, 0, 0, 0});
}

/// Node velocity v = sum S m v / m and temperature T = sum S m T / m (E12) on `nodes`.
inline void node_velocity_temperature(const IndexBox& nodes, int m, const ConstField4& mass,
                                      const ConstVectorField4& mom, const ConstField4& heat,
                                      const VectorField4& vel, const Field4& temp) {
  for_each_index("mpmice::node_velocity_temperature", nodes, KOKKOS_LAMBDA(long i, long j, long k) {
    const double inv = 1.0 / mass(m, i, j, k);
    for (int d = 0; d < 3; ++d) vel[d](m, i, j, k) = mom[d](m, i, j, k) * inv;
    temp(m, i, j, k) = heat(m, i, j, k) * inv;
  });
}

}  // namespace mpmice
