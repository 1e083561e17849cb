#pragma once
/**
 * @file checkpoint.h
 * The checkpoint file: format, collective atomic write and verified streaming read.
 * Mesh- and scene-free: the driver fills a header and each rank's rows of (lattice key,
 * values) and checks the meaning of what it reads (mesh, material, time) itself.
 *
 * Layout (format v6, little-endian, this machine's doubles): one file, one part per
 * writing rank:
 *   magic "granhydro checkpoint v6\n" | CheckpointHeader | uint64 n_parts |
 *   n_parts CheckpointPart (offset, rows, first and last key, FNV-1a checksum of the
 *   part's bytes) | uint64 FNV-1a checksum of every byte before it |
 *   part 0 | part 1 | ... (contiguous; the file ends with the last part)
 * A part holds its writer's rows sorted by key: (int64 key, n_values doubles). A row
 * holds the state (dim + 2 values) and, when the header says so, the state the implicit
 * step's kept Newton matrix was built from (another dim + 2 values), so that a run
 * interrupted between output times continues exactly as the uninterrupted run. Keys are
 * unique over the file; parts may interleave in key order (a rank's cells are not a
 * key range), a reader merges them.
 * Format v6 is v5 with the run record appended to the header (CheckpointHeader::
 * run_record: the counts of the run up to the checkpoint, summed over its segments, so
 * that the summary of a restarted run covers the whole run). A v5 file (the header
 * without the run record, 240 bytes) is still read, with an empty run record.
 *
 * Writing (collective): rank 0 creates <file>.tmp and writes the header and the table
 * (O(ranks) bytes, gathered from each rank's offset, row count and checksum); every rank
 * writes its own part at its offset (an exclusive prefix sum of the part sizes), fsyncs
 * it, reads it back and verifies its checksum; all ranks agree, and only then does rank 0
 * rename the previous checkpoint to <file>.bak and the new one to <file>. No rank holds
 * more than its own part and the O(ranks) table. A failure anywhere leaves the previous
 * checkpoint in place and raises the same CheckpointError (with the OS reason) on every
 * rank.
 */
#include <granhydro/base/errors.h>

#include <mpi.h>

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace granhydro::io
{
  /// a checkpoint could not be written, or a file is not a valid checkpoint (base/errors.h)
  using granhydro::CheckpointError;

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
    double            time = 0;                           ///< scaled
    std::uint64_t     step = 0, n_cells = 0, outputs = 0;
    char              model[16] = {};
    std::int32_t      n_values  = 0; ///< doubles per row: n_components, or 2 n_components with history
    IntegratorHistory history;
    /// scaled convective time the state still owes: with merged Strang half-steps a run
    /// interrupted between output times stops after V, before the second C(dt/2)
    double convection_owed = 0;
    /// v6: the run record, "key value" lines of text (NUL-padded; empty in a v5 file):
    /// what the run counted up to this checkpoint (driver/run_summary.h). Keys the reader
    /// does not know are ignored, missing ones read as absent, so the record can grow
    char run_record[4096] = {};
  };

  /// bytes of the header of format `version` (5 or 6) in the file
  std::size_t header_bytes(const int version);

  /// the run record of the header as (key, value) pairs, in the order written
  std::vector<std::pair<std::string, double>> run_record(const CheckpointHeader &h);
  /// sets the header's run record (values with 17 significant digits, exact); throws
  /// CheckpointError if it does not fit
  void set_run_record(CheckpointHeader &h, const std::vector<std::pair<std::string, double>> &record);

  /// one entry of the part table
  struct CheckpointPart
  {
    std::uint64_t offset = 0, n_rows = 0;        ///< byte offset in the file, rows
    std::int64_t  first_key = -1, last_key = -1; ///< key range (-1: empty part)
    std::uint64_t checksum = 0;                  ///< FNV-1a of the part's bytes
  };

  /// the magic line of the current format
  const std::string &checkpoint_magic();

  /// writes the checkpoint atomically and collectively (see the file comment): keys are
  /// this rank's, strictly increasing, values hold h.n_values per key; h.n_cells is filled
  /// here. Throws the same CheckpointError on every rank of comm.
  void write_checkpoint_file(const std::string &file, CheckpointHeader h,
                             const std::vector<std::int64_t> &keys, const std::vector<double> &values,
                             const MPI_Comm comm);

  /// a row as read: its key and its n_values values
  using RowFunction = std::function<void(std::int64_t key, const double *values)>;

  /// an opened checkpoint: the constructor reads and verifies the magic and format
  /// version, the header and the part table (checksum, file size, row counts, units,
  /// time, counts); the parts are read by streaming with bounded buffers, each verified
  /// as it is read: checksum, keys strictly increasing within the part's range, every
  /// value finite with n > 0 and energy > 0. Failures throw CheckpointError with the
  /// reason ("... is truncated", "checksum mismatch", ...).
  class CheckpointReader
  {
  public:
    explicit CheckpointReader(const std::string &file);

    const CheckpointHeader &header() const { return h_; }
    /// the file's format version (5 or 6)
    int                                version() const { return version_; }
    const std::vector<CheckpointPart> &parts() const { return parts_; }

    /// streams part p's rows in key order and verifies the part
    void read_part(const std::size_t p, const RowFunction &f) const;

    /// streams every row in global key order (a merge of the parts, one bounded buffer per
    /// part) and verifies every part and that no key appears twice
    void read_merged(const RowFunction &f) const;

  private:
    std::string                 file_;
    int                         version_ = 6;
    CheckpointHeader            h_;
    std::vector<CheckpointPart> parts_;
  };

  /// FNV-1a digest of the keys and the state values only, in key order (not the header,
  /// not the history, not the parts): two checkpoints with the same digest hold the same
  /// state bit for bit, whatever number of ranks wrote them. Verifies every part.
  std::uint64_t state_digest(const CheckpointReader &r);

  /// Output/Keep checkpoints = keep > 1, on one process after the checkpoint `file`
  /// (<stem>.checkpoint) of step `step` is written and verified: keeps it also as
  /// <stem>_checkpoint_<step>.checkpoint (step with at least 8 digits; a hard link, a
  /// copy where the file system has none) and deletes the oldest of those numbered files
  /// of steps up to `step` beyond the `keep` most recent (numbered files of later steps,
  /// left by a run that went further before this one restarted from an earlier
  /// checkpoint, are neither counted nor deleted). Empty, or why the copy failed (a
  /// file that cannot be deleted is left and not reported)
  std::string keep_recent_checkpoints(const std::string &file, const std::uint64_t step,
                                      const unsigned int keep);

  /// the first non-empty error of the ranks of comm (the lowest rank's), or empty: a
  /// failure on one rank stops every rank with the same message
  std::string first_error(const std::string &error, const MPI_Comm comm);
} // namespace granhydro::io
