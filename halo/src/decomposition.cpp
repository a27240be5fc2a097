#include <mpmice/halo/decomposition.hpp>

#include <algorithm>
#include <limits>
#include <set>
#include <string>

#include <mpmice/kernels/errors.hpp>

namespace mpmice {
namespace {

const char* axis_name(int d) { return d == 0 ? "x" : (d == 1 ? "y" : "z"); }

// Smallest patch a direction split into p blocks may have: a ghost layer of depth G
// (node-like fields: G+1 layers) must come from the adjacent patch alone.
bool split_fits(int cells, int p, bool periodic, int ghosts) {
  if (p == 1 && !periodic) return true;
  return cells / p >= ghosts + 1;
}

}  // namespace

std::array<int, 3> Decomposition::choose_dims(const Grid& grid,
                                              const DecompositionOptions& options,
                                              int nranks) {
  const auto& want = options.ranks;
  for (int d = 0; d < 3; ++d)
    if (want[d] < 0)
      throw InputError("decomposition.ranks",
                       std::string("ranks in ") + axis_name(d) + " must be >= 0 (0: choose)");
  // Every factorisation px*py*pz = nranks that honours fixed entries and leaves
  // patches large enough; the one with the least interface area wins (ties: split x
  // first, as MPI_Dims_create orders its result).
  std::array<int, 3> best{0, 0, 0};
  double best_cost = std::numeric_limits<double>::max();
  for (int px = 1; px <= nranks; ++px) {
    if (nranks % px) continue;
    for (int py = 1; py <= nranks / px; ++py) {
      if ((nranks / px) % py) continue;
      const std::array<int, 3> p{px, py, nranks / px / py};
      bool ok = true;
      for (int d = 0; d < 3; ++d) {
        if (want[d] > 0 && want[d] != p[d]) ok = false;
        if (!split_fits(grid.cells[d], p[d], options.periodic[d], options.ghosts)) ok = false;
      }
      if (!ok) continue;
      double cost = 0;
      for (int d = 0; d < 3; ++d)
        cost += double(p[d] - 1) * grid.cells[(d + 1) % 3] * grid.cells[(d + 2) % 3];
      cost += 1e-6 * (p[1] + 2.0 * p[2]);  // tie-break
      if (cost < best_cost) {
        best_cost = cost;
        best = p;
      }
    }
  }
  if (best[0] == 0) {
    std::string msg = "cannot split the grid of " + std::to_string(grid.cells[0]) + " x " +
                      std::to_string(grid.cells[1]) + " x " + std::to_string(grid.cells[2]) +
                      " cells over " + std::to_string(nranks) + " ranks";
    if (want[0] || want[1] || want[2])
      msg += " as " + std::to_string(want[0]) + " x " + std::to_string(want[1]) + " x " +
             std::to_string(want[2]);
    msg += ": every split or periodic direction needs at least " +
           std::to_string(options.ghosts + 1) + " cells per rank (ghost layers + 1)";
    throw InputError("decomposition.ranks", msg);
  }
  return best;
}

Decomposition::Decomposition(MPI_Comm comm, const Grid& grid, const DecompositionOptions& options)
    : m_periodic(options.periodic) {
  for (int d = 0; d < 3; ++d) {
    if (grid.cells[d] < 1)
      throw InputError("grid.cells", std::string("cell count in ") + axis_name(d) + " must be >= 1");
    if (!(grid.spacing[d] > 0))
      throw InputError("grid.spacing", std::string("spacing in ") + axis_name(d) + " must be > 0");
  }
  if (options.ghosts < 1) throw InputError("ghosts", "the ghost width must be >= 1");
  int size = 1;
  MPI_Comm_size(comm, &size);
  m_dims = choose_dims(grid, options, size);

  int dims[3] = {m_dims[0], m_dims[1], m_dims[2]};
  int periods[3] = {m_periodic[0], m_periodic[1], m_periodic[2]};
  MPI_Cart_create(comm, 3, dims, periods, /*reorder=*/0, &m_comm);
  MPI_Comm_rank(m_comm, &m_rank);
  MPI_Comm_size(m_comm, &m_size);
  int coords[3];
  MPI_Cart_coords(m_comm, m_rank, 3, coords);
  m_coords = {coords[0], coords[1], coords[2]};

  m_patch.grid = grid;
  m_patch.ghosts = options.ghosts;
  for (int d = 0; d < 3; ++d) {
    m_patch.lo[d] = block_start(d, m_coords[d]);
    m_patch.hi[d] = block_start(d, m_coords[d] + 1);
    m_patch.owns_high_boundary[d] = !m_periodic[d] && m_coords[d] == m_dims[d] - 1;
    m_patch.periodic[d] = m_periodic[d];
  }

  std::set<int> distinct;
  for (int di = -1; di <= 1; ++di)
    for (int dj = -1; dj <= 1; ++dj)
      for (int dk = -1; dk <= 1; ++dk) {
        const int off[3] = {di, dj, dk};
        std::array<int, 3> c{};
        bool outside = false;
        for (int d = 0; d < 3; ++d) {
          c[d] = m_coords[d] + off[d];
          if (c[d] < 0 || c[d] >= m_dims[d]) {
            if (m_periodic[d])
              c[d] = (c[d] + m_dims[d]) % m_dims[d];
            else
              outside = true;
          }
        }
        const int r = outside ? MPI_PROC_NULL : rank_of(c);
        m_neighbors[(di + 1) * 9 + (dj + 1) * 3 + (dk + 1)] = r;
        if (r != MPI_PROC_NULL && r != m_rank) distinct.insert(r);
      }
  m_neighbor_ranks.assign(distinct.begin(), distinct.end());
}

Decomposition::~Decomposition() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (m_comm != MPI_COMM_NULL && !finalized) MPI_Comm_free(&m_comm);
}

int Decomposition::block_start(int d, int c) const {
  const int n = m_patch.grid.cells[d], p = m_dims[d];
  const int base = n / p, extra = n % p;
  return c * base + std::min(c, extra);
}

}  // namespace mpmice
