#include <granhydro/io/output.h>
#include <granhydro/io/summary_csv.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iomanip>

namespace granhydro::io
{
  namespace
  {
    /// the summary is written whole to a temporary file and renamed: one per process, so
    /// that two runs sharing an output folder never rename each other's file away (the
    /// last one to finish leaves its summary)
    std::string summary_tmp(const std::string &file)
    {
      return file + ".tmp." + std::to_string(::getpid());
    }
  } // namespace

  void write_running_summary(const std::string &file)
  {
    const std::string tmp = summary_tmp(file);
    std::ofstream(tmp) << "key,value\nstatus,running\n";
    std::error_code ec;
    std::filesystem::rename(tmp, file, ec);
  }

  void write_summary_csv(const std::string &directory, const std::string &file,
                         const std::vector<SummaryEntry> &entries)
  {
    std::error_code ec;
    std::filesystem::create_directories(directory, ec);
    const std::string tmp = summary_tmp(file);
    std::ofstream     out(tmp);
    if (!out)
      throw OutputError("cannot write " + file + " (Output/Directory)");
    out << std::setprecision(10) << "key,value\n";
    for (const auto &e : entries)
      {
        out << e.key << ',';
        std::visit([&out](const auto &v) { out << v; }, e.value);
        out << "\n";
      }
    out.close();
    std::filesystem::rename(tmp, file, ec);
    if (ec)
      throw OutputError("cannot write " + file + ": " + ec.message());
  }
} // namespace granhydro::io
