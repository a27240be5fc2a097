#pragma once
/// \file migrate.hpp
/// \brief Particle migration: after particles move, each goes to the patch that owns
///        the cell it is in (Step 27 of mpmice-algorithm.md).
#include <mpmice/halo/decomposition.hpp>
#include <mpmice/kernels/particles.hpp>

namespace mpmice {

/// What one call of `migrate` did on this rank.
struct MigrationStats {
  long sent = 0;         ///< particles handed to other ranks
  long received = 0;     ///< particles taken from other ranks
  long left_domain = 0;  ///< particles past a non-periodic domain boundary, removed
};

/// Move every particle of `particles` to the rank owning its position. Positions
/// are wrapped across periodic boundaries; particles outside the domain in a
/// non-periodic direction are removed and counted. Every component and the id of a
/// moved particle arrive bit for bit; the order of particles is not kept.
/// A particle that moved farther than the neighbouring patch throws
/// mpmice::InvariantError.
MigrationStats migrate(const Decomposition& decomposition, ParticleSet& particles);

}  // namespace mpmice
