#pragma once
/**
 * @file run_records.h
 * The records a run leaves in its output directory beside <base>_summary.csv (rank 0,
 * only when the scene writes its summary, Output/Write summary):
 *   <base>_parameters.prm  the scene as run (includes and -p overrides applied; every
 *                          parameter): `granhydro <base>_parameters.prm` runs it again
 *   <base>.log             what rank 0 prints (a copy of the terminal; Output/Verbose)
 * Both are written once the mesh and the initial state are set up, so that a scene
 * refused there leaves no files; the log then starts with the lines printed so far.
 */
#include <granhydro/driver/run_settings.h>

#include <mpi.h>

#include <memory>
#include <ostream>
#include <string>

namespace granhydro::driver
{
  class RunRecords
  {
  public:
    /// the records of a run writing `files`, described by `report` (run_settings() of its
    /// scene); `terminal` is where rank 0 prints (std::cout)
    RunRecords(const RunFiles &files, const RunReportSettings &report, const MPI_Comm comm,
               std::ostream &terminal);
    ~RunRecords();

    /// the stream the run prints to: the terminal, and on rank 0 also <base>.log
    std::ostream &log() { return *log_; }

    /// write <base>_parameters.prm and <base>.log with the lines printed so far (from now
    /// on the log goes to the file as it is printed); on every rank, collectively. Throws
    /// io::OutputError on every rank if rank 0 cannot write them
    void start();

    /// a line the terminal gets elsewhere (main's "run stopped" message on stderr), into
    /// the log file only; nothing before start()
    void note(const std::string &line);

  private:
    class Tee;
    const RunFiles                files; ///< copies: main's messages may outlive its scene
    const RunReportSettings       report;
    const MPI_Comm                comm;
    const bool                    logging; ///< rank 0 of a run that writes its records and log
    std::unique_ptr<Tee>          tee;
    std::unique_ptr<std::ostream> tee_stream;
    std::ostream                 *log_;
  };
} // namespace granhydro::driver
