#include "run.hpp"

#include <fmt/core.h>
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "cycle.hpp"
#include <mpmice/halo/reduce.hpp>

#include "checkpoint.hpp"
#include "diagnostics.hpp"
#include "input_echo.hpp"
#include "output_hdf5.hpp"
#include "problem.hpp"

namespace mpmice {

std::unique_ptr<Problem> run(const Input& input, const RunOptions& options, MPI_Comm comm) {
  using clock = std::chrono::steady_clock;
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);

  auto problem = make_problem(input, comm);
  Problem& pb = *problem;
  Cycle cycle(pb);
  if (rank == 0) {
    std::error_code ec;
    std::filesystem::create_directories(options.output_dir, ec);
    // The run's input with every default filled in, beside its outputs (post-processing
    // scripts read the problem's parameters from it).
    const std::string path = options.output_dir + "/input.yaml", tmp = path + ".tmp";
    std::ofstream(tmp) << "# resolved input of " << input.file << "\n" << resolved_yaml(input);
    std::rename(tmp.c_str(), path.c_str());
  }
  MPI_Barrier(comm);
  double dt = std::min(input.time.dt_initial, input.time.dt_max);
  const bool restarted = !options.restart.empty();
  if (restarted) {
    const std::string file = options.restart == "latest" ? latest_checkpoint(options.output_dir) : options.restart;
    dt = read_checkpoint(pb, file);
    if (rank == 0 && options.report)
      fmt::print("mpmice: restarted from {} at step {}, t = {:.6g} s\n", file, pb.step, pb.time);
  }
  Diagnostics diagnostics(pb, options.output_dir, restarted ? pb.step : -1);
  const long field_interval = input.output.field_interval;
  FieldOutput fields(pb, options.output_dir);
  if (field_interval > 0 && !restarted) fields.write(pb);
  const auto& ck = input.checkpoint;
  auto last_checkpoint = clock::now();

  const double t_end = options.end_time >= 0 ? options.end_time : input.time.end;
  const long max_steps = options.max_steps >= 0 ? options.max_steps : input.time.max_steps;
  const auto& tin = input.time;
  const auto& grid = pb.patch().grid;
  if (rank == 0 && options.report)
    fmt::print("mpmice: {} | {} x {} x {} cells on {} rank{} ({} x {} x {}), {} fluid{}, {} solid{}, to t = {:g} s\n",
               input.file, grid.cells[0], grid.cells[1], grid.cells[2], ranks, ranks == 1 ? "" : "s",
               pb.decomposition->dims()[0], pb.decomposition->dims()[1], pb.decomposition->dims()[2],
               pb.ice.size(), pb.ice.size() == 1 ? "" : "s", pb.solid_count(),
               pb.solid_count() == 1 ? "" : "s", t_end);
  if (!restarted) diagnostics.record(pb, 0.0);

  const auto start = clock::now();
  auto last_print = start;
  long redone = 0, reported_lost = 0;
  std::string last_redo_reason;
  while (pb.time < t_end * (1 - 1e-14) && pb.step < max_steps) {
    if (pb.time + dt > t_end) dt = t_end - pb.time;
    try {
      cycle.advance(pb.time, dt);
    } catch (const InvariantError& e) {
      // The state at the start of the step is intact: write it for inspection.
      std::string where = "at step " + std::to_string(pb.step + 1) + " (t = " + fmt::format("{:.6g}", pb.time) + " s)";
      try {
        where += "; the last good state is in " + fields.write(pb);
      } catch (...) {
      }
      throw InvariantError(std::string(e.what()).empty() ? std::string() : std::string(e.what()) + ", " + where);
    } catch (const RedoStep& e) {
      ++redone;
      last_redo_reason = e.what();
      dt *= 0.5;
      if (dt < tin.dt_min) {
        std::string where;
        try {
          where = "; the last good state is in " + fields.write(pb);
        } catch (...) {
        }
        throw InvariantError(std::string("step ") + std::to_string(pb.step + 1) + ": " + e.what() +
                             " even with dt below time.dt_min" + where);
      }
      continue;
    }
    pb.time += dt;
    pb.step += 1;
    if (pb.particles_left_domain > reported_lost) {
      if (rank == 0)
        fmt::print("mpmice: warning: {} particle{} left the domain by step {} (removed)\n",
                   pb.particles_left_domain - reported_lost, pb.particles_left_domain - reported_lost == 1 ? "" : "s",
                   pb.step);
      reported_lost = pb.particles_left_domain;
    }
    diagnostics.record(pb, dt);
    if (field_interval > 0 && pb.step % field_interval == 0) fields.write(pb);
    const double next = cycle.stable_timestep();
    dt = std::min({next, dt * (1.0 + tin.max_increase), tin.dt_max});
    // Checkpoints every `interval` steps or `wall_interval` seconds (rank 0's clock
    // decides, so that all ranks write together).
    int wall_due = ck.wall_interval > 0 &&
                   std::chrono::duration<double>(clock::now() - last_checkpoint).count() >= ck.wall_interval;
    MPI_Bcast(&wall_due, 1, MPI_INT, 0, comm);
    if ((ck.interval > 0 && pb.step % ck.interval == 0) || wall_due) {
      write_checkpoint(pb, dt, options.output_dir, ck.keep);
      last_checkpoint = clock::now();
    }

    const auto now = clock::now();
    if (options.progress && rank == 0 && now - last_print > std::chrono::seconds(1)) {
      last_print = now;
      const double wall = std::chrono::duration<double>(now - start).count();
      const double frac = std::min(pb.time / t_end, 1.0);
      const double eta = frac > 0 ? wall * (1 - frac) / frac : 0;
      fmt::print("  step {:>8}  t {:.6e} s  dt {:.3e} s  {:5.1f}%  wall {:.1f} s  eta {:.1f} s\n", pb.step,
                 pb.time, dt, 100 * frac, wall, eta);
      std::fflush(stdout);
    }
  }
  const double wall = std::chrono::duration<double>(clock::now() - start).count();
  // The final state is always among the field outputs.
  if (field_interval > 0 && pb.step % field_interval != 0) fields.write(pb);
  if (input.output.final_fields && pb.has_cells())
    Diagnostics::write_fields_csv(pb, options.output_dir + "/fields.csv");
  std::cout << std::flush;
  if (options.report) cycle.runner().print_timings(std::cout);
  // Halo traffic: the largest bytes any rank sent per step (0 on one rank).
  const double halo_bytes = pb.step > 0 ? global_max(comm, pb.halo->bytes_sent()) / double(pb.step) : 0.0;
  if (rank == 0 && options.report && ranks > 1)
    fmt::print("mpmice: halo exchange: {:.3g} MB sent per step by the busiest rank\n", halo_bytes / 1e6);
  long particles = 0;
  for (const auto& ps : pb.particles) particles += long(ps.size());
  particles = global_sum(comm, particles);
  if (rank == 0 && options.report) {
    const double cell_steps = double(grid.cell_count()) * pb.step;
    if (particles > 0)
      fmt::print("mpmice: {} particles, {:.3g} particle-steps/s\n", particles,
                 wall > 0 ? double(particles) * pb.step / wall : 0.0);
    fmt::print("mpmice: {} steps to t = {:.6g} s in {:.2f} s ({:.3g} cell-steps/s{}); output in {}\n",
               pb.step, pb.time, wall, wall > 0 ? cell_steps / wall : 0.0,
               redone ? fmt::format(", {} steps redone with a smaller dt, the last because {}", redone, last_redo_reason)
                      : "",
               options.output_dir);
  }
  return problem;
}

}  // namespace mpmice
