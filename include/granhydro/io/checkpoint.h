#pragma once
/**
 * @file checkpoint.h
 * The checkpoint file: format, atomic write and verified read. Mesh- and scene-free:
 * the driver fills a header and rows of (lattice key, conserved values) and checks the
 * meaning of what it reads (mesh, material, time) itself.
 *
 * Layout (little-endian, this machine's doubles):
 *   magic "granhydro checkpoint v4\n" | CheckpointHeader | n_cells rows of
 *   (int64 key, n_values doubles) | uint64 FNV-1a checksum of every byte before it.
 * A row holds the state (dim + 2 values) and, when the header says so, the state the
 * implicit step's kept Newton matrix was built from (another dim + 2 values), so that a
 * run interrupted between output times continues exactly as the uninterrupted run.
 *
 * Writing: the whole file goes to <file>.tmp, is flushed and fsync'ed, read back and
 * verified (size and checksum); only then is the previous checkpoint renamed to
 * <file>.bak and the new one renamed over <file>. A full disk or any other failure leaves
 * the previous checkpoint in place and raises CheckpointError with the OS reason.
 */
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace granhydro::io
{
  /// a checkpoint could not be written, or a file is not a valid checkpoint
  class CheckpointError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// what the implicit step remembers across steps (0 / false / empty: nothing)
  struct IntegratorHistory
  {
    std::int32_t rkl2_blocked = 0; ///< steps the cost model still rests RKL2
    std::int32_t matrix_valid = 0; ///< a Newton matrix is kept for the next step
    std::int32_t matrix_age = 0, matrix_coupled = 0, matrix_stages = 0;
    double       matrix_t = 0, matrix_dt = 0; ///< scaled time and step it was built for
    double       matrix_N[4] = {0, 0, 0, 0};  ///< its Butcher matrix (row-major, stages^2)
  };

  /// fixed-size header (after the magic)
  struct CheckpointHeader
  {
    std::int32_t      dim = 0, n_components = 0;
    std::uint64_t     cells[3] = {0, 0, 0};
    double            lower[3] = {0, 0, 0}, upper[3] = {0, 0, 0};
    double            length = 0, mass = 0, velocity = 0; ///< the scaled units of the values
    double            time = 0;                            ///< scaled
    std::uint64_t     step = 0, n_cells = 0, outputs = 0;
    char              model[16] = {};
    std::int32_t      n_values = 0; ///< doubles per row: n_components, or 2 n_components with history
    IntegratorHistory history;
    /// scaled convective time the state still owes: with merged Strang half-steps a run
    /// interrupted between output times stops after V, before the second C(dt/2)
    double convection_owed = 0;
  };

  /// the magic line of the current format
  const std::string &checkpoint_magic();

  /// writes the checkpoint atomically (see the file comment); keys must be strictly
  /// increasing and values hold n_values per key
  void write_checkpoint_file(const std::string &file, const CheckpointHeader &h,
                             const std::vector<std::int64_t> &keys, const std::vector<double> &values);

  struct CheckpointData
  {
    CheckpointHeader          header;
    std::vector<std::int64_t> keys;
    std::vector<double>       values;
  };

  /// reads and verifies a checkpoint: magic and format version, header (dimension,
  /// components, units, time, counts), file size against the header, checksum, keys
  /// strictly increasing, every value finite with n > 0 and energy > 0. Throws
  /// CheckpointError with the reason ("... is truncated", "checksum mismatch", ...).
  CheckpointData read_checkpoint_file(const std::string &file);

  /// FNV-1a digest of the keys and the state values only (not the header, not the
  /// history): two checkpoints with the same digest hold the same state bit for bit
  std::uint64_t state_digest(const CheckpointData &d);
} // namespace granhydro::io
