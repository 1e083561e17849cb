#pragma once
/**
 * @file state_checkpoint.h
 * The state of a distributed mesh in a checkpoint file (io/checkpoint.h): every rank
 * holds the rows of its owned cells, keyed by their lattice key; rank 0 writes all rows
 * sorted by key, so that any number of ranks can read the file back.
 */
#include <granhydro/base/units.h>
#include <granhydro/io/checkpoint.h>

#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

namespace granhydro::io
{
  /// writes the state as one checkpoint: keys of this rank's owned cells, their values
  /// (h.n_components per cell, cell after cell) and, when h.history.matrix_valid, the
  /// state the implicit step's kept Newton matrix was built from (same layout). Rank 0
  /// gathers the rows, sorts them by key and writes the file with the header h (n_values
  /// and n_cells are filled here). A failure throws OutputError on every rank.
  void write_state_checkpoint(const std::string &file, CheckpointHeader h,
                              const std::vector<std::int64_t> &keys, const double *state,
                              const double *history_state, const MPI_Comm comm);

  /// the checkpoint's values are in the scaled units units (same length, mass, velocity)
  bool same_units(const CheckpointHeader &h, const Units &units);

  /// the owned cells' values from a checkpoint: state (n_components per key, converted to
  /// units unless same_units()) and, when history_state is given, the implicit step's
  /// history state (as written). Returns how many of the keys the checkpoint holds.
  std::size_t scatter_checkpoint(const CheckpointData &data, const std::vector<std::int64_t> &keys,
                                 const Units &units, double *state, double *history_state);
} // namespace granhydro::io
