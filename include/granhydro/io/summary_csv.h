#pragma once
/**
 * @file summary_csv.h
 * The run's summary file <base>_summary.csv: "key,value" lines, written whole to a
 * temporary file of this process and renamed over the previous one, so that a reader
 * never sees half a file. The driver decides the keys and values (plain entries); this
 * file decides how they are written.
 */
#include <string>
#include <variant>
#include <vector>

namespace granhydro::io
{
  /// one line of the summary: a key and its value (a count, a number or a word)
  struct SummaryEntry
  {
    std::string                                           key;
    std::variant<unsigned long long, double, std::string> value;
  };

  /// the summary of a run that has started ("status,running", then `entries`: what
  /// identifies the run): a summary that still says so after the process has gone means
  /// the run died (killed, out of memory), never a stale "completed" from an earlier run
  /// in the folder. Failures are ignored.
  void write_running_summary(const std::string &file, const std::vector<SummaryEntry> &entries = {});

  /// the summary file (in directory, created if missing): "key,value" and one line per
  /// entry, numbers with 10 significant digits, a word in double quotes if it holds a
  /// comma, a quote or a line break (RFC 4180, as Python's csv module reads it). Throws
  /// OutputError ("cannot write ...")
  void write_summary_csv(const std::string &directory, const std::string &file,
                         const std::vector<SummaryEntry> &entries);
} // namespace granhydro::io
