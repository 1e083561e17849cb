#include <granhydro/io/checkpoint.h>
#include <granhydro/io/checkpoint_bytes.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <climits>
#include <cstdlib>
#include <cstddef>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace granhydro::io
{
  using namespace checkpoint_bytes;

  namespace
  {
    std::string os_reason(const int e) { return std::strerror(e); }

    /// test hook (doc/developer.md, "Test hooks"): GRANHYDRO_FAIL_CHECKPOINT_WRITE=K makes the K-th
    /// checkpoint this process writes stop half-way with "No space left on device", as a
    /// full disk would; unset in normal runs. Every rank counts its calls (every rank
    /// takes part in every write), so all ranks fail at the same checkpoint.
    bool inject_failure()
    {
      static const long k = [] {
        const char *v = std::getenv("GRANHYDRO_FAIL_CHECKPOINT_WRITE");
        return v ? std::strtol(v, nullptr, 10) : 0L;
      }();
      static long calls = 0;
      return k > 0 && ++calls == k;
    }

    /// test hook (doc/developer.md, "Test hooks"): GRANHYDRO_HOLD_AFTER_CHECKPOINT=K makes the
    /// process stop after its K-th checkpoint is in place and wait until it is killed, so
    /// a test can kill a run at a known checkpoint however fast the run is; unset in
    /// normal runs
    void hold_if_asked(const bool root)
    {
      static const long k = [] {
        const char *v = std::getenv("GRANHYDRO_HOLD_AFTER_CHECKPOINT");
        return v ? std::strtol(v, nullptr, 10) : 0L;
      }();
      static long calls = 0;
      if (k > 0 && ++calls == k)
        {
          if (root)
            std::cerr << "granhydro: test hook: holding after checkpoint " << k << " until killed"
                      << std::endl;
          for (;;)
            ::sleep(1);
        }
    }

    /// pwrite all n bytes of p at offset off; false and errno on failure
    bool pwrite_all(const int fd, const char *p, const std::size_t n, const std::uint64_t off)
    {
      std::size_t done = 0;
      while (done < n)
        {
          const ssize_t w = ::pwrite(fd, p + done, n - done, off_t(off + done));
          if (w < 0 && errno == EINTR)
            continue;
          if (w <= 0)
            {
              if (w == 0)
                errno = ENOSPC;
              return false;
            }
          done += std::size_t(w);
        }
      return true;
    }

    /// writes this rank's pieces (offset, bytes) into the existing file path, fsync'ed;
    /// fail_half stops half-way through the last piece with ENOSPC. Empty or the OS reason.
    std::string write_pieces(const std::string &path,
                             const std::vector<std::pair<std::uint64_t, const std::string *>> &pieces,
                             const bool fail_half)
    {
      const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
      if (fd < 0)
        return os_reason(errno);
      for (std::size_t i = 0; i < pieces.size(); ++i)
        {
          const std::string &b    = *pieces[i].second;
          const bool         half = fail_half && i + 1 == pieces.size();
          if (!pwrite_all(fd, b.data(), half ? b.size() / 2 : b.size(), pieces[i].first))
            {
              const int e = errno;
              ::close(fd);
              return os_reason(e);
            }
        }
      if (fail_half)
        {
          ::close(fd);
          return os_reason(ENOSPC);
        }
      if (::fsync(fd) != 0)
        {
          const int e = errno;
          ::close(fd);
          return os_reason(e);
        }
      return ::close(fd) == 0 ? std::string() : os_reason(errno);
    }

    /// the FNV-1a checksum of n bytes of path at offset, read back in bounded chunks;
    /// false if fewer bytes could be read
    bool read_back(const std::string &path, const std::uint64_t offset, const std::uint64_t n,
                   std::uint64_t &sum)
    {
      const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
      if (fd < 0)
        return false;
      std::vector<char> buf(std::size_t(std::min<std::uint64_t>(n, 1u << 20)));
      sum = fnv_basis;
      for (std::uint64_t done = 0; done < n;)
        {
          const std::size_t m = std::size_t(std::min<std::uint64_t>(n - done, buf.size()));
          if (!pread_all(fd, buf.data(), m, offset + done))
            {
              ::close(fd);
              return false;
            }
          sum = fnv1a(buf.data(), m, sum);
          done += m;
        }
      ::close(fd);
      return true;
    }

    void fsync_directory_of(const std::string &file)
    {
      const auto        slash = file.find_last_of('/');
      const std::string dir   = slash == std::string::npos ? "." : file.substr(0, slash + 1);
      const int         fd    = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
      if (fd >= 0)
        {
          ::fsync(fd); // best effort: the rename is what makes the file visible
          ::close(fd);
        }
    }

    /// rank 0: the previous checkpoint becomes file.bak, tmp becomes file; empty or why not
    std::string rename_into_place(const std::string &tmp, const std::string &file)
    {
      struct stat st;
      if (::stat(file.c_str(), &st) == 0 && std::rename(file.c_str(), (file + ".bak").c_str()) != 0)
        {
          const std::string why = os_reason(errno);
          ::unlink(tmp.c_str());
          return "cannot keep the previous checkpoint as '" + file + ".bak': " + why;
        }
      if (std::rename(tmp.c_str(), file.c_str()) != 0)
        {
          const std::string why = os_reason(errno);
          std::rename((file + ".bak").c_str(), file.c_str()); // put the previous one back
          return "cannot rename '" + tmp + "' to '" + file + "': " + why;
        }
      fsync_directory_of(file);
      return {};
    }
  } // namespace

  const std::string &checkpoint_magic()
  {
    static const std::string m = "granhydro checkpoint v6\n";
    return m;
  }

  // the v5 header is the v6 header without its run record
  static_assert(offsetof(CheckpointHeader, run_record) == 240, "the v5 header is 240 bytes");
  static_assert(sizeof(CheckpointHeader) == 240 + sizeof(CheckpointHeader::run_record), "no padding after the run record");

  std::size_t header_bytes(const int version)
  {
    return version == 5 ? offsetof(CheckpointHeader, run_record) : sizeof(CheckpointHeader);
  }

  std::vector<std::pair<std::string, double>> run_record(const CheckpointHeader &h)
  {
    std::vector<std::pair<std::string, double>> r;
    const std::size_t n = ::strnlen(h.run_record, sizeof(h.run_record));
    std::istringstream in(std::string(h.run_record, n));
    std::string        key, value;
    while (in >> key >> value)
      r.emplace_back(key, std::strtod(value.c_str(), nullptr));
    return r;
  }

  void set_run_record(CheckpointHeader &h, const std::vector<std::pair<std::string, double>> &record)
  {
    std::ostringstream os;
    os << std::setprecision(17);
    for (const auto &[key, value] : record)
      os << key << ' ' << value << '\n';
    const std::string text = os.str();
    if (text.size() >= sizeof(h.run_record))
      throw CheckpointError("run record of " + std::to_string(text.size()) + " bytes does not fit in the header");
    std::memset(h.run_record, 0, sizeof(h.run_record));
    std::memcpy(h.run_record, text.data(), text.size());
  }

  std::string keep_recent_checkpoints(const std::string &file, const std::uint64_t step, const unsigned int keep)
  {
    namespace fs              = std::filesystem;
    const std::string suffix  = ".checkpoint";
    const std::string stem    = file.size() > suffix.size() && file.compare(file.size() - suffix.size(), suffix.size(), suffix) == 0 ?
                                  file.substr(0, file.size() - suffix.size()) :
                                  file;
    char number[32];
    std::snprintf(number, sizeof(number), "%08llu", static_cast<unsigned long long>(step));
    const std::string copy = stem + "_checkpoint_" + number + suffix;
    std::error_code   ec;
    fs::remove(copy, ec); // one of an abandoned later run at the same step
    if (::link(file.c_str(), copy.c_str()) != 0)
      {
        fs::copy_file(file, copy, fs::copy_options::overwrite_existing, ec);
        if (ec)
          {
            fs::remove(copy, ec);
            return "cannot keep the checkpoint as '" + copy + "': " + ec.message();
          }
      }
    // the numbered checkpoints of this run up to this step, newest first
    const fs::path    dir    = fs::path(stem).has_parent_path() ? fs::path(stem).parent_path() : fs::path(".");
    const std::string prefix = fs::path(stem).filename().string() + "_checkpoint_";
    std::vector<std::pair<std::uint64_t, fs::path>> numbered;
    for (const auto &entry : fs::directory_iterator(dir, ec))
      {
        const std::string name = entry.path().filename().string();
        if (name.size() < prefix.size() + 8 + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
            name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
          continue;
        const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
        if (digits.size() > 19 || digits.find_first_not_of("0123456789") != std::string::npos)
          continue;
        const std::uint64_t k = std::stoull(digits);
        if (k <= step && entry.is_regular_file(ec))
          numbered.emplace_back(k, entry.path());
      }
    std::sort(numbered.begin(), numbered.end(), [](const auto &a, const auto &b) { return a.first > b.first; });
    for (std::size_t i = keep; i < numbered.size(); ++i)
      fs::remove(numbered[i].second, ec);
    return {};
  }

  std::string first_error(const std::string &error, const MPI_Comm comm)
  {
    int me = 0;
    MPI_Comm_rank(comm, &me);
    int first = error.empty() ? INT_MAX : me;
    MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm);
    if (first == INT_MAX)
      return {};
    unsigned long long n = error.size();
    MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, first, comm);
    std::string s = me == first ? error : std::string(n, '\0');
    MPI_Bcast(s.data(), int(n), MPI_CHAR, first, comm);
    return s;
  }

  void write_checkpoint_file(const std::string &file, CheckpointHeader h,
                             const std::vector<std::int64_t> &keys, const std::vector<double> &values,
                             const MPI_Comm comm)
  {
    int me = 0, n_ranks = 1;
    MPI_Comm_rank(comm, &me);
    MPI_Comm_size(comm, &n_ranks);
    const std::size_t nv = std::size_t(h.n_values);
    // this rank's part: its rows, sorted by key
    std::string part;
    part.reserve(keys.size() * row_bytes(nv));
    for (std::size_t i = 0; i < keys.size(); ++i)
      {
        part.append(reinterpret_cast<const char *>(&keys[i]), sizeof(std::int64_t));
        part.append(reinterpret_cast<const char *>(&values[i * nv]), nv * sizeof(double));
      }
    CheckpointPart mine;
    mine.n_rows   = keys.size();
    mine.checksum = fnv1a(part.data(), part.size());
    if (!keys.empty())
      {
        mine.first_key = keys.front();
        mine.last_key  = keys.back();
      }
    // its offset: the header and table, then the parts of the ranks before it
    std::uint64_t size = part.size(), before = 0;
    MPI_Exscan(&size, &before, 1, MPI_UINT64_T, MPI_SUM, comm);
    mine.offset = head_bytes(n_ranks) + (me == 0 ? 0 : before);
    // rank 0 gathers the table (O(ranks)) and writes it with the header
    std::vector<CheckpointPart> table(me == 0 ? n_ranks : 0);
    MPI_Gather(&mine, sizeof(CheckpointPart), MPI_BYTE, table.data(), sizeof(CheckpointPart), MPI_BYTE, 0, comm);
    std::string   head;
    std::uint64_t file_size = 0;
    if (me == 0)
      {
        h.n_cells = 0;
        for (const auto &t : table)
          h.n_cells += t.n_rows;
        const std::uint64_t n_parts = n_ranks;
        head.append(checkpoint_magic());
        head.append(reinterpret_cast<const char *>(&h), sizeof(h));
        head.append(reinterpret_cast<const char *>(&n_parts), sizeof(n_parts));
        head.append(reinterpret_cast<const char *>(table.data()), table.size() * sizeof(CheckpointPart));
        const std::uint64_t sum = fnv1a(head.data(), head.size());
        head.append(reinterpret_cast<const char *>(&sum), sizeof(sum));
        file_size = table.back().offset + table.back().n_rows * row_bytes(nv);
      }

    const std::string tmp       = file + ".tmp";
    const bool        fail_half = inject_failure();
    // what is left: the previous checkpoint, if there is one (the first write has none)
    struct stat       previous{};
    const std::string kept = ::stat(file.c_str(), &previous) == 0 ?
                               "; the previous checkpoint '" + file + "' is kept" :
                               "; there is no previous checkpoint '" + file + "'";
    const auto        cannot    = [&](const std::string &why) {
      return "cannot write the checkpoint '" + tmp + "': " + why + kept;
    };
    const auto stop_if = [&](std::string error) {
      error = first_error(error, comm);
      if (!error.empty())
        {
          if (me == 0)
            ::unlink(tmp.c_str()); // never leave a torn file behind
          throw CheckpointError(error);
        }
    };
    // rank 0 creates the (empty) file; then each rank writes its own bytes
    std::string error;
    if (me == 0)
      {
        const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
        if (fd < 0 || ::close(fd) != 0)
          error = cannot(os_reason(errno));
      }
    stop_if(error);
    std::vector<std::pair<std::uint64_t, const std::string *>> pieces;
    if (me == 0)
      pieces.emplace_back(0, &head);
    if (!part.empty())
      pieces.emplace_back(mine.offset, &part);
    if (!pieces.empty())
      if (const std::string why = write_pieces(tmp, pieces, fail_half); !why.empty())
        error = cannot(why);
    stop_if(error);

    // verify what the file system holds before it replaces the previous checkpoint: each
    // rank its own part, rank 0 the header, the table and the file size
    std::uint64_t sum = 0;
    if (!part.empty() && (!read_back(tmp, mine.offset, part.size(), sum) || sum != mine.checksum))
      error = "the checkpoint '" + tmp + "' did not read back as written (part " + std::to_string(me) +
              ", " + std::to_string(part.size()) + " bytes)" + kept;
    struct stat st{};
    if (me == 0 && error.empty() &&
        (::stat(tmp.c_str(), &st) != 0 || std::uint64_t(st.st_size) != file_size ||
         !read_back(tmp, 0, head.size(), sum) || sum != fnv1a(head.data(), head.size())))
      error = "the checkpoint '" + tmp + "' did not read back as written (" +
              std::to_string(std::uint64_t(st.st_size)) + " of " + std::to_string(file_size) +
              " bytes)" + kept;
    stop_if(error);
    if (me == 0)
      error = rename_into_place(tmp, file);
    error = first_error(error, comm);
    if (!error.empty())
      throw CheckpointError(error);
    hold_if_asked(me == 0);
  }
} // namespace granhydro::io
