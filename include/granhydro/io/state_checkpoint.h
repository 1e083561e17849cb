#pragma once
/**
 * @file state_checkpoint.h
 * The state of a distributed mesh in a checkpoint file (io/checkpoint.h): every rank
 * writes the rows of its owned cells, sorted by their lattice key, as its own part of
 * one file; any number of ranks can read the file back, each keeping only its cells.
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
  /// state the implicit step's kept Newton matrix was built from (same layout). Each rank
  /// sorts its rows by key and writes them as its part (n_values and n_cells are filled
  /// here). A failure throws OutputError on every rank.
  void write_state_checkpoint(const std::string &file, CheckpointHeader h,
                              const std::vector<std::int64_t> &keys, const double *state,
                              const double *history_state, const MPI_Comm comm);

  /// the checkpoint's values are in the scaled units units (same length, mass, velocity)
  bool same_units(const CheckpointHeader &h, const Units &units);

  /// the owned cells' values from a checkpoint (collective): each rank streams the parts
  /// whose key range meets its own keys (each part verified whole as it is read) and keeps
  /// the rows of its keys: state (n_components per key, converted to units unless
  /// same_units()) and, when history_state is given, the implicit step's history state
  /// (as written). Returns how many of the keys the checkpoint holds; a key found twice or
  /// a damaged part throws the same CheckpointError on every rank.
  std::size_t read_state_checkpoint(const CheckpointReader &r, const std::vector<std::int64_t> &keys,
                                    const Units &units, double *state, double *history_state,
                                    const MPI_Comm comm);

  /// every cell key of the checkpoint in key order, from a merge of the parts (an
  /// adaptive mesh is rebuilt from its leaves; 8 bytes per cell on every rank).
  /// Collective: a damaged part throws the same CheckpointError on every rank.
  std::vector<long long> checkpoint_keys(const CheckpointReader &r, const MPI_Comm comm);

  /// verifies every part of the checkpoint, shared out over the ranks (part p by rank p
  /// modulo their number); collective, the same CheckpointError on every rank
  void verify_checkpoint(const CheckpointReader &r, const MPI_Comm comm);
} // namespace granhydro::io
