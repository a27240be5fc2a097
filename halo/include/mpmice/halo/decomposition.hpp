#pragma once
/// \file decomposition.hpp
/// \brief Cartesian decomposition of the global grid into one patch per MPI rank.
#include <mpi.h>

#include <array>
#include <vector>

#include <mpmice/kernels/grid.hpp>

namespace mpmice {

/// How to split the grid. A zero entry in `ranks` lets the decomposition choose.
struct DecompositionOptions {
  std::array<int, 3> ranks{0, 0, 0};  ///< ranks per direction (0: choose)
  std::array<bool, 3> periodic{false, false, false};
  int ghosts = 2;  ///< G, ghost layers of every patch
};

/// One patch per rank of `comm`; neighbours in the 26 directions.
///
/// The split gives each rank floor(n/p) or floor(n/p)+1 cells (the first n%p get
/// one more). Every split or periodic direction must leave each patch at least G+1
/// cells, so that a ghost layer of depth <= G always comes from the adjacent patch.
/// Bad choices throw mpmice::InputError naming "decomposition.ranks".
class Decomposition {
 public:
  Decomposition(MPI_Comm comm, const Grid& grid, const DecompositionOptions& options);
  ~Decomposition();
  Decomposition(const Decomposition&) = delete;
  Decomposition& operator=(const Decomposition&) = delete;

  const Patch& patch() const { return m_patch; }
  const Grid& grid() const { return m_patch.grid; }
  MPI_Comm comm() const { return m_comm; }
  int rank() const { return m_rank; }
  int size() const { return m_size; }
  const std::array<int, 3>& dims() const { return m_dims; }
  const std::array<int, 3>& coords() const { return m_coords; }
  const std::array<bool, 3>& periodic() const { return m_periodic; }

  /// Rank of the patch at offset (di, dj, dk) in {-1,0,1}^3, or MPI_PROC_NULL past a
  /// non-periodic domain boundary. May be this rank (periodic, one rank across).
  int neighbor(int di, int dj, int dk) const { return m_neighbors[(di + 1) * 9 + (dj + 1) * 3 + (dk + 1)]; }
  /// Distinct ranks among the 26 neighbours, this rank excluded.
  const std::vector<int>& neighbor_ranks() const { return m_neighbor_ranks; }

  /// First global cell of block c in direction d (c = dims[d] gives the cell count).
  int block_start(int d, int c) const;
  /// Rank owning patch coordinates (cx, cy, cz), each in [0, dims).
  int rank_of(const std::array<int, 3>& c) const { return (c[0] * m_dims[1] + c[1]) * m_dims[2] + c[2]; }

  /// The ranks-per-direction the decomposition would choose for `nranks` ranks.
  static std::array<int, 3> choose_dims(const Grid& grid, const DecompositionOptions& options,
                                        int nranks);

 private:
  MPI_Comm m_comm = MPI_COMM_NULL;
  int m_rank = 0, m_size = 1;
  std::array<int, 3> m_dims{1, 1, 1}, m_coords{0, 0, 0};
  std::array<bool, 3> m_periodic{false, false, false};
  Patch m_patch;
  std::array<int, 27> m_neighbors{};
  std::vector<int> m_neighbor_ranks;
};

}  // namespace mpmice
