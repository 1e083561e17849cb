#pragma once
/**
 * @file history.h
 * The run's time series <base>_history.csv: a header row, then one row per history
 * time (Output/History interval), written by rank 0 and flushed line by line, so that
 * the file can be followed while the run goes on. The driver decides the columns and
 * computes the values (driver/time_loop.cc); this file decides how they are written
 * and how a restarted run continues the file.
 */
#include <mpi.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <variant>
#include <vector>

namespace granhydro::io
{
  /// one value of a history row: a count, a number (written with 17 significant digits,
  /// enough to read back the same double; NaN as "nan") or a word
  using HistoryValue = std::variant<unsigned long long, double, std::string>;

  class HistoryFile
  {
  public:
    /// the file (its folder is created if missing) with these column names; the column
    /// named "step" says which rows a restart keeps
    HistoryFile(const std::string &directory, const std::string &file, std::vector<std::string> columns,
                const MPI_Comm comm);

    /// a run from its initial state: the file is started anew with its header
    void start();

    /// a run restarted from a checkpoint of step `step`: the rows up to that step are
    /// kept and new rows are appended. Rows beyond it (written by a run that went on after
    /// that checkpoint, e.g. killed later) are dropped, so no row is written twice. A file
    /// with other columns (another scene, an older version) is kept as <file>.old and a
    /// new file started; a missing one is started anew.
    void resume(const unsigned long long step);

    /// one row (one value per column); only rank 0 writes, the other ranks return at
    /// once. A failed write is remembered (check())
    void write(const std::vector<HistoryValue> &row);

    /// collective: throws OutputError on every rank if a write on rank 0 has failed
    void check() const;

  private:
    std::string              directory_, file_;
    std::vector<std::string> columns_;
    MPI_Comm                 comm_;
    bool                     root_;
    std::ofstream            out_;
    std::string              error_;
  };
} // namespace granhydro::io
