/**
 * @file history.cc
 * <base>_history.csv (io/history.h): the header, the rows, and the continuation of the
 * file by a restarted run.
 */
#include <granhydro/io/checkpoint.h>
#include <granhydro/io/history.h>
#include <granhydro/io/output.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>

namespace granhydro::io
{
  namespace
  {
    std::string join(const std::vector<std::string> &columns)
    {
      std::string s;
      for (const auto &c : columns)
        s += (s.empty() ? "" : ",") + c;
      return s;
    }
  } // namespace

  HistoryFile::HistoryFile(const std::string &directory, const std::string &file,
                           std::vector<std::string> columns, const MPI_Comm comm)
    : directory_(directory)
    , file_(file)
    , columns_(std::move(columns))
    , comm_(comm)
  {
    int me = 0;
    MPI_Comm_rank(comm, &me);
    root_ = me == 0;
  }

  void HistoryFile::start()
  {
    if (!root_)
      return;
    std::error_code ec;
    std::filesystem::create_directories(directory_, ec);
    out_.open(file_, std::ios::trunc);
    out_ << join(columns_) << '\n';
    out_.flush();
    if (!out_)
      error_ = "cannot write '" + file_ + "': " + std::strerror(errno);
  }

  void HistoryFile::resume(const unsigned long long step)
  {
    if (!root_)
      return;
    std::ifstream in(file_);
    std::string   line;
    if (!in || !std::getline(in, line) || line != join(columns_))
      {
        if (in)
          {
            in.close();
            std::error_code ec;
            std::filesystem::rename(file_, file_ + ".old", ec);
          }
        start();
        return;
      }
    // the rows up to the checkpoint's step, as they are (bytes unchanged)
    std::size_t step_column = 0;
    while (step_column < columns_.size() && columns_[step_column] != "step")
      ++step_column;
    std::ostringstream kept;
    kept << line << '\n';
    while (std::getline(in, line))
      {
        std::size_t begin = 0;
        for (std::size_t c = 0; c < step_column && begin != std::string::npos; ++c)
          {
            begin = line.find(',', begin);
            if (begin != std::string::npos)
              ++begin;
          }
        if (begin == std::string::npos ||
            std::size_t(std::count(line.begin(), line.end(), ',')) + 1 != columns_.size())
          break; // a torn last line (a kill in the middle of a write)
        char                    *end = nullptr;
        const unsigned long long k   = std::strtoull(line.c_str() + begin, &end, 10);
        if (end == line.c_str() + begin || (*end != ',' && *end != '\0') || k > step)
          break; // rows are in step order: the rest is beyond the checkpoint
        kept << line << '\n';
      }
    in.close();
    // written whole to a temporary file and renamed: a failure leaves the old file
    const std::string tmp = file_ + ".tmp";
    {
      std::ofstream o(tmp, std::ios::trunc);
      o << kept.str();
      o.flush();
      if (!o)
        {
          error_ = "cannot write '" + tmp + "': " + std::strerror(errno);
          return;
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, file_, ec);
    if (ec)
      {
        error_ = "cannot rename '" + tmp + "' to '" + file_ + "': " + ec.message();
        return;
      }
    out_.open(file_, std::ios::app);
    if (!out_)
      error_ = "cannot write '" + file_ + "': " + std::strerror(errno);
  }

  void HistoryFile::write(const std::vector<HistoryValue> &row)
  {
    if (!root_ || !error_.empty())
      return;
    out_ << std::setprecision(std::numeric_limits<double>::max_digits10);
    for (std::size_t i = 0; i < row.size(); ++i)
      {
        if (i > 0)
          out_ << ',';
        if (const double *x = std::get_if<double>(&row[i]))
          {
            if (std::isnan(*x))
              out_ << "nan";
            else
              out_ << *x;
          }
        else
          std::visit([this](const auto &v) { out_ << v; }, row[i]);
      }
    out_ << '\n';
    out_.flush();
    if (!out_)
      error_ = "cannot write '" + file_ + "': " + std::strerror(errno);
  }

  void HistoryFile::check() const
  {
    const std::string e = first_error(error_, comm_);
    if (!e.empty())
      throw OutputError(e + " (Output/History interval)");
  }
} // namespace granhydro::io
