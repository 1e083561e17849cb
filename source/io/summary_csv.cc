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

    /// "key,value" and the entries: numbers with 10 significant digits, words quoted as
    /// RFC 4180 wants where they hold a comma, a quote or a line break (a scene path,
    /// an override "Domain/Cells=100, 50")
    void write_entries(std::ostream &out, const std::vector<SummaryEntry> &entries)
    {
      out << std::setprecision(10) << "key,value\n";
      for (const auto &e : entries)
        {
          out << e.key << ',';
          if (const auto *word = std::get_if<std::string>(&e.value))
            {
              if (word->find_first_of(",\"\r\n") == std::string::npos)
                out << *word;
              else
                {
                  out << '"';
                  for (const char c : *word)
                    out << (c == '"' ? "\"\"" : std::string(1, c));
                  out << '"';
                }
            }
          else
            std::visit([&out](const auto &v) { out << v; }, e.value);
          out << "\n";
        }
    }
  } // namespace

  void write_running_summary(const std::string &file, const std::vector<SummaryEntry> &entries)
  {
    const std::string tmp = summary_tmp(file);
    {
      std::ofstream out(tmp);
      std::vector<SummaryEntry> all = {{"status", std::string("running")}};
      all.insert(all.end(), entries.begin(), entries.end());
      write_entries(out, all);
    }
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
    write_entries(out, entries);
    out.close();
    std::filesystem::rename(tmp, file, ec);
    if (ec)
      throw OutputError("cannot write " + file + ": " + ec.message());
  }
} // namespace granhydro::io
