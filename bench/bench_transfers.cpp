// The MPM material's node and cell kernels at 16^3 .. 128^3 cells, one solid: the nodal
// update and the transfers between nodes and cells of MPMICE. Bytes per item (the least a
// structure-of-arrays kernel must move, 8 B per double; a neighbour's value is counted
// once, as every node or cell is read once from memory when its neighbours follow):
//  grid_acceleration (per node, E26): reads m, v (3), f_int (3), f_ext (3); writes
//                        v* (3), a (3)                                    -> 16 x 8 = 128
//  node_to_cell (per cell, E13): reads the node weight, m, v (3), T, the cell's
//                        T^n and p; writes T, u (3), rho, v               -> 14 x 8 = 112
//  cell_rates_to_nodes (per node, E34, with the transfers' heat): reads the cell
//                        rates aV (3), aT (4); reads and writes v* (3), a (3) (12);
//                        writes aT, q (2)                                 -> 18 x 8 = 144
//  pressure_to_nodes (per node, E11): reads p; writes p_i                 ->  2 x 8 = 16
// The nodal update belongs to the MPM sub-step of the goal (at 8 particles per
// cell, one node per 8 particles). The benchmarks run over the owned nodes or cells; the
// driver also covers the extra layers at domain boundaries, the same work per item.
#include <benchmark/benchmark.h>

#include <mpmice/kernels/cell_to_node.hpp>
#include <mpmice/kernels/grid_update.hpp>
#include <mpmice/kernels/node_to_cell.hpp>

#include "bench_setup.hpp"

using namespace mpmice;
using namespace mpmice::bench;

namespace {

ConstVectorField4 as_const(const VectorField4& v) { return {v[0], v[1], v[2]}; }

void BM_grid_acceleration(benchmark::State& state) {
  const Patch p = cube_patch(int(state.range(0)));
  const Field4 mass = node_field(p, 1e-6, 0.5, 1);
  const VectorField4 vel = node_vector(p, 1.0, 1.0, 2), fint = node_vector(p, 1e-3, 1.0, 5),
                     fext = node_vector(p, 1e-4, 1.0, 8);
  const VectorField4 vel_star = node_vector(p, 0, 0, 11), acc = node_vector(p, 0, 0, 14);
  const IndexBox nodes = p.owned_nodes();
  for (auto _ : state)
    state.SetIterationTime(timed([&] {
      grid_acceleration(nodes, 0, 1e-7, {0, 0, -9.81}, 0.0, false, mass, as_const(vel), as_const(fint),
                        as_const(fext), vel_star, acc);
    }));
  report(state, nodes.size(), 128.0);
}

void BM_node_to_cell(benchmark::State& state) {
  const Patch p = cube_patch(int(state.range(0)));
  // Copper as problems/container.yaml has it, with the modified law in tension: about
  // half the cells (pressures within 5% of p_ref) take its branch.
  Eos copper;
  copper.type = EosType::solid;
  copper.rho0 = 8930;
  copper.bulk = 136.35e9;
  copper.modified = true;
  const Field3 weight = make_field("weight", p, Location::node);
  Kokkos::deep_copy(weight, 0.125);
  const Field4 node_mass = node_field(p, 1e-6, 0.5, 1), node_temp = node_field(p, 300, 0.1, 2);
  const VectorField4 node_vel = node_vector(p, 1.0, 1.0, 3);
  const Field3 press = cell_scalar(p, 101325, 0.05, 6);
  const Field4 rho = make_field("rho", p, Location::cell, 1), temp = cell_field(p, 1, 300, 0.1, 7),
               sp_vol = make_field("sp_vol", p, Location::cell, 1);
  const VectorField4 vel{make_field("u", p, Location::cell, 1), make_field("v", p, Location::cell, 1),
                         make_field("w", p, Location::cell, 1)};
  const IndexBox cells = p.owned_cells();
  for (auto _ : state)
    state.SetIterationTime(timed([&] {
      node_to_cell(cells, p.grid.cell_volume(), 0, 0, copper, weight, node_mass, as_const(node_vel), node_temp,
                   press, rho, vel, temp, sp_vol);
    }));
  report(state, cells.size(), 112.0);
}

void BM_cell_rates_to_nodes(benchmark::State& state) {
  const Patch p = cube_patch(int(state.range(0)));
  const VectorField4 cell_acc{cell_field(p, 1, 1.0, 1.0, 1), cell_field(p, 1, 1.0, 1.0, 2),
                              cell_field(p, 1, 1.0, 1.0, 3)};
  const Field4 cell_temp_rate = cell_field(p, 1, 10.0, 1.0, 4);
  const VectorField4 vel_star = node_vector(p, 1.0, 1.0, 5), acc = node_vector(p, 1.0, 1.0, 8);
  const Field4 temp_rate = node_field(p, 0, 0, 11), transfer_energy = node_field(p, 0, 0, 12);
  const IndexBox nodes = p.owned_nodes();
  for (auto _ : state)
    state.SetIterationTime(timed([&] {
      cell_rates_to_nodes(nodes, 0, 1e-7, as_const(cell_acc), cell_temp_rate, vel_star, acc, temp_rate,
                          transfer_energy);
    }));
  report(state, nodes.size(), 144.0);
}

void BM_pressure_to_nodes(benchmark::State& state) {
  const Patch p = cube_patch(int(state.range(0)));
  const Field3 press = cell_scalar(p, 101325, 0.05, 1), press_node = make_field("p", p, Location::node);
  const IndexBox nodes = p.owned_nodes();
  for (auto _ : state) state.SetIterationTime(timed([&] { pressure_to_nodes(nodes, press, press_node); }));
  report(state, nodes.size(), 16.0);
}

}  // namespace

BENCHMARK(BM_grid_acceleration)->Apply(cube_sizes)->UseManualTime();
BENCHMARK(BM_node_to_cell)->Apply(cube_sizes)->UseManualTime();
BENCHMARK(BM_cell_rates_to_nodes)->Apply(cube_sizes)->UseManualTime();
BENCHMARK(BM_pressure_to_nodes)->Apply(cube_sizes)->UseManualTime();
