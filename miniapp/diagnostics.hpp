#pragma once
// What a run records as it goes, in the output directory, one flushed line at a time
// (a crash keeps every line written before it):
//  history.csv  step,time,dt, then per material mass,momentum_x/y/z,energy (energy =
//               internal + kinetic), then the same five for the total;
//  probes.csv   step,time,probe,quantity,material,value (long format).
#include <fstream>
#include <string>
#include <vector>

#include "problem.hpp"

namespace mpmice {

class Diagnostics {
 public:
  /// Opens (rank 0) the two files in `directory`, which must exist. After a restart
  /// from step `restart_step` (>= 0) the files keep their rows up to that step and
  /// grow from there.
  Diagnostics(const Problem& problem, const std::string& directory, long restart_step = -1);
  /// Record the state after `step` (collective over the decomposition).
  void record(const Problem& problem, double dt);
  /// Write every cell's state to `path` (CSV, one row per cell and material, sorted by
  /// cell), through a temporary file renamed when complete. Collective; rank 0 writes.
  static void write_fields_csv(const Problem& problem, const std::string& path);

  /// Totals per material and in all, {mass, p_x, p_y, p_z, energy} (collective).
  static std::vector<std::array<double, 5>> totals(const Problem& problem);

 private:
  int m_rank = 0;
  std::ofstream m_history, m_probes;
  struct ProbeCell {
    bool mine = false;
    int cell[3] = {0, 0, 0};  // local index where mine
  };
  std::vector<ProbeCell> m_probe_cells;
};

}  // namespace mpmice
