/**
 * @file run_records.cc
 * <base>_parameters.prm and <base>.log of a run (driver/run_records.h).
 */
#include <granhydro/base/version.h>
#include <granhydro/driver/run_records.h>
#include <granhydro/io/output.h>

#include <deal.II/base/mpi.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <streambuf>

namespace granhydro::driver
{
  /// a stream buffer that passes everything to the terminal and keeps a copy: in memory
  /// until open(), then in the log file, flushed at every line end so that the file can
  /// be followed while the run goes on and keeps what was printed if the run is killed.
  /// Unbuffered: every write goes through xsputn(), in the order it was made
  class RunRecords::Tee : public std::streambuf
  {
  public:
    explicit Tee(std::streambuf *terminal)
      : terminal(terminal)
    {}

    /// the log file `name`, starting with what was printed so far; false if it cannot be
    /// written
    bool open(const std::string &name)
    {
      file.open(name);
      file << pending;
      file.flush();
      pending.clear();
      pending.shrink_to_fit();
      return bool(file);
    }

    bool is_open() const { return file.is_open(); }

    void write_to_file(const std::string &text)
    {
      file << text;
      file.flush();
    }

  protected:
    int overflow(int c) override
    {
      if (traits_type::eq_int_type(c, traits_type::eof()))
        return traits_type::not_eof(c);
      const char ch = traits_type::to_char_type(c);
      xsputn(&ch, 1);
      return c;
    }

    std::streamsize xsputn(const char *s, const std::streamsize n) override
    {
      // a terminal that fails (closed stdout) must not end the log file's copy: the
      // count the stream sees is always n
      terminal->sputn(s, n);
      if (file.is_open())
        {
          file.write(s, n);
          if (std::memchr(s, '\n', n) != nullptr)
            file.flush();
        }
      else
        pending.append(s, n);
      return n;
    }

    int sync() override
    {
      terminal->pubsync();
      if (file.is_open())
        file.flush();
      return 0;
    }

  private:
    std::streambuf *terminal;
    std::string     pending;
    std::ofstream   file;
  };

  RunRecords::RunRecords(const RunFiles &files, const RunReportSettings &report, const MPI_Comm comm,
                         std::ostream &terminal)
    : files(files)
    , report(report)
    , comm(comm)
    , logging(dealii::Utilities::MPI::this_mpi_process(comm) == 0 && files.summary && report.verbose)
    , log_(&terminal)
  {
    if (logging)
      {
        tee        = std::make_unique<Tee>(terminal.rdbuf());
        tee_stream = std::make_unique<std::ostream>(tee.get());
        log_       = tee_stream.get();
      }
  }

  RunRecords::~RunRecords()
  {
    if (tee_stream)
      tee_stream->flush();
  }

  namespace
  {
    /// text for a comment line of the .prm: no line break may end the comment early
    std::string one_line(std::string text)
    {
      for (char &c : text)
        if (c == '\n' || c == '\r')
          c = ' ';
      return text;
    }
  } // namespace

  void RunRecords::start()
  {
    std::string error;
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0 && files.summary)
      {
        std::error_code ec;
        std::filesystem::create_directories(files.directory, ec);
        const std::string file = files.file("_parameters.prm");
        std::ofstream     out(file);
        out << "# granhydro " << version() << " (git " << git_revision() << "): the scene "
            << one_line(report.source) << " as it ran";
        if (!report.overrides.empty())
          {
            out << ", with";
            for (const auto &o : report.overrides)
              out << " -p \"" << one_line(o) << '"';
          }
        out << ".\n# Every parameter, the includes and -p overrides applied. To run it again (from the same\n"
               "# working directory: Output/Directory and Initial state/Checkpoint are relative to it):\n"
               "#   granhydro "
            << one_line(file) << "\n#\n"
            << report.expanded_text;
        out.close();
        if (!out) // with the OS's reason ("File too large", "No space left on device")
          error = "cannot write " + file + " (Output/Directory): " + std::strerror(errno);
        else if (logging && !tee->open(files.file(".log")))
          error = "cannot write " + files.file(".log") + " (Output/Directory)";
      }
    // every rank stops if rank 0 could not write them (the others would wait for it)
    if (dealii::Utilities::MPI::max(error.empty() ? 0u : 1u, comm) != 0)
      throw io::OutputError(error.empty() ? "rank 0 could not write the run records" : error);
  }

  void RunRecords::note(const std::string &line)
  {
    if (tee && tee->is_open())
      tee->write_to_file(line + "\n");
  }
} // namespace granhydro::driver
