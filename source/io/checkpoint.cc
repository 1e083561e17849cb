#include <granhydro/io/checkpoint.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>

namespace granhydro::io
{
  namespace
  {
    /// the magic line of an older format ("granhydro checkpoint vK\n", K < 4), or empty
    std::string older_format(const std::string &buf)
    {
      for (const char *v : {"2", "3"})
        {
          const std::string m = std::string("granhydro checkpoint v") + v + "\n";
          if (buf.compare(0, m.size(), m) == 0)
            return v;
        }
      return "";
    }

    /// FNV-1a, 64 bit: detects flipped bits and torn writes (not an adversary)
    std::uint64_t fnv1a(const char *p, const std::size_t n)
    {
      std::uint64_t h = 14695981039346656037ull;
      for (std::size_t i = 0; i < n; ++i)
        {
          h ^= static_cast<unsigned char>(p[i]);
          h *= 1099511628211ull;
        }
      return h;
    }

    std::string os_reason(const int e) { return std::strerror(e); }

    /// test hook (README, "Checkpoints"): GRANHYDRO_FAIL_CHECKPOINT_WRITE=K makes the K-th
    /// checkpoint this process writes stop half-way with "No space left on device", as a
    /// full disk would; unset in normal runs
    bool inject_failure()
    {
      static const long k = [] {
        const char *v = std::getenv("GRANHYDRO_FAIL_CHECKPOINT_WRITE");
        return v ? std::strtol(v, nullptr, 10) : 0L;
      }();
      static long calls = 0;
      return k > 0 && ++calls == k;
    }

    /// test hook (README, "Checkpoints"): GRANHYDRO_HOLD_AFTER_CHECKPOINT=K makes the
    /// process stop after its K-th checkpoint is in place and wait until it is killed, so
    /// a test can kill a run at a known checkpoint however fast the run is; unset in
    /// normal runs
    void hold_if_asked()
    {
      static const long k = [] {
        const char *v = std::getenv("GRANHYDRO_HOLD_AFTER_CHECKPOINT");
        return v ? std::strtol(v, nullptr, 10) : 0L;
      }();
      static long calls = 0;
      if (k > 0 && ++calls == k)
        {
          std::cerr << "granhydro: test hook: holding after checkpoint " << k << " until killed"
                    << std::endl;
          for (;;)
            ::sleep(1);
        }
    }

    /// write all of buf to path, fsync'ed; false and errno on failure
    bool write_file(const std::string &path, const std::string &buf, const bool fail_half)
    {
      const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
      if (fd < 0)
        return false;
      const std::size_t n    = fail_half ? buf.size() / 2 : buf.size();
      std::size_t       done = 0;
      while (done < n)
        {
          const ssize_t w = ::write(fd, buf.data() + done, n - done);
          if (w < 0 && errno == EINTR)
            continue;
          if (w <= 0)
            {
              const int e = w < 0 ? errno : ENOSPC;
              ::close(fd);
              errno = e;
              return false;
            }
          done += std::size_t(w);
        }
      if (fail_half)
        {
          ::close(fd);
          errno = ENOSPC;
          return false;
        }
      if (::fsync(fd) != 0)
        {
          const int e = errno;
          ::close(fd);
          errno = e;
          return false;
        }
      return ::close(fd) == 0;
    }

    std::string read_all(const std::string &path, bool &ok)
    {
      std::ifstream in(path, std::ios::binary);
      ok = bool(in);
      if (!ok)
        return {};
      std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      ok = !in.bad();
      return s;
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
  } // namespace

  const std::string &checkpoint_magic()
  {
    static const std::string m = "granhydro checkpoint v4\n";
    return m;
  }

  void write_checkpoint_file(const std::string &file, const CheckpointHeader &h,
                             const std::vector<std::int64_t> &keys, const std::vector<double> &values)
  {
    const std::size_t nv = std::size_t(h.n_values);
    std::string       buf;
    buf.reserve(checkpoint_magic().size() + sizeof(h) + keys.size() * (8 + 8 * nv) + 8);
    buf.append(checkpoint_magic());
    buf.append(reinterpret_cast<const char *>(&h), sizeof(h));
    for (std::size_t i = 0; i < keys.size(); ++i)
      {
        buf.append(reinterpret_cast<const char *>(&keys[i]), sizeof(std::int64_t));
        buf.append(reinterpret_cast<const char *>(&values[i * nv]), nv * sizeof(double));
      }
    const std::uint64_t sum = fnv1a(buf.data(), buf.size());
    buf.append(reinterpret_cast<const char *>(&sum), sizeof(sum));

    const std::string tmp = file + ".tmp";
    if (!write_file(tmp, buf, inject_failure()))
      {
        const std::string why = os_reason(errno);
        ::unlink(tmp.c_str()); // never leave a torn file behind
        throw CheckpointError("cannot write the checkpoint '" + tmp + "': " + why +
                              "; the previous checkpoint '" + file + "' is kept");
      }
    // verify what the file system holds before it replaces the previous checkpoint
    bool              ok   = false;
    const std::string back = read_all(tmp, ok);
    if (!ok || back.size() != buf.size() ||
        fnv1a(back.data(), back.size() - 8) != sum)
      {
        ::unlink(tmp.c_str());
        throw CheckpointError("the checkpoint '" + tmp + "' did not read back as written (" +
                              std::to_string(back.size()) + " of " + std::to_string(buf.size()) +
                              " bytes); the previous checkpoint '" + file + "' is kept");
      }
    struct stat st;
    if (::stat(file.c_str(), &st) == 0 && std::rename(file.c_str(), (file + ".bak").c_str()) != 0)
      {
        const std::string why = os_reason(errno);
        ::unlink(tmp.c_str());
        throw CheckpointError("cannot keep the previous checkpoint as '" + file + ".bak': " + why);
      }
    if (std::rename(tmp.c_str(), file.c_str()) != 0)
      {
        const std::string why = os_reason(errno);
        std::rename((file + ".bak").c_str(), file.c_str()); // put the previous one back
        throw CheckpointError("cannot rename '" + tmp + "' to '" + file + "': " + why);
      }
    fsync_directory_of(file);
    hold_if_asked();
  }

  CheckpointData read_checkpoint_file(const std::string &file)
  {
    struct stat st;
    if (::stat(file.c_str(), &st) != 0)
      throw CheckpointError("cannot be read: " + os_reason(errno));
    if (!S_ISREG(st.st_mode))
      throw CheckpointError("is not a regular file (a folder or a device)");
    bool        ok = false;
    std::string buf;
    try
      {
        buf = read_all(file, ok);
      }
    catch (const std::exception &)
      {
        ok = false;
      }
    if (!ok)
      throw CheckpointError("cannot be read");
    const auto &magic = checkpoint_magic();
    if (const std::string v = older_format(buf); !v.empty())
      throw CheckpointError("was written by an older granhydro (checkpoint format v" + v +
                            "; this version writes v4); restart it with that version or start "
                            "from the scene");
    if (buf.size() < magic.size() || buf.compare(0, magic.size(), magic) != 0)
      throw CheckpointError("is not a granhydro checkpoint file");
    CheckpointData d;
    CheckpointHeader &h = d.header;
    const std::size_t fixed = magic.size() + sizeof(h) + sizeof(std::uint64_t);
    if (buf.size() < fixed)
      throw CheckpointError("is truncated (" + std::to_string(buf.size()) + " bytes)");
    std::memcpy(&h, buf.data() + magic.size(), sizeof(h));
    if (h.dim < 1 || h.dim > 3 || h.n_components != h.dim + 2 ||
        (h.n_values != h.n_components && h.n_values != 2 * h.n_components))
      throw CheckpointError("has a corrupted header (dimension " + std::to_string(h.dim) +
                            ", components " + std::to_string(h.n_components) + ")");
    const std::size_t row = sizeof(std::int64_t) + sizeof(double) * std::size_t(h.n_values);
    if (h.n_cells == 0 || h.n_cells > (buf.size() - fixed) / row ||
        buf.size() != fixed + h.n_cells * row)
      throw CheckpointError("is truncated or corrupted: " + std::to_string(buf.size()) +
                            " bytes, but its header announces " + std::to_string(h.n_cells) + " cells" +
                            (h.n_cells < (1ull << 40) ?
                               " (" + std::to_string(fixed + h.n_cells * row) + " bytes)" :
                               std::string()));
    std::uint64_t stored = 0;
    std::memcpy(&stored, buf.data() + buf.size() - sizeof(stored), sizeof(stored));
    if (fnv1a(buf.data(), buf.size() - sizeof(stored)) != stored)
      throw CheckpointError("is corrupted (checksum mismatch): a bit flipped or a write was torn");
    const auto positive = [](const double v) { return std::isfinite(v) && v > 0; };
    if (!positive(h.length) || !positive(h.mass) || !positive(h.velocity))
      throw CheckpointError("has invalid units in its header");
    if (!std::isfinite(h.time) || h.time < 0)
      {
        std::ostringstream os;
        os << "holds an invalid time (" << h.time << ", scaled)";
        throw CheckpointError(os.str());
      }
    if (h.step > (1ull << 40) || h.outputs > (1ull << 32))
      throw CheckpointError("holds an invalid step or output count");
    if (std::memchr(h.model, '\0', sizeof(h.model)) == nullptr)
      throw CheckpointError("has a corrupted header (material model name)");
    const auto &hs = h.history;
    if (hs.rkl2_blocked < 0 || hs.rkl2_blocked > 1000 || hs.matrix_age < 0 ||
        (hs.matrix_valid != 0) != (h.n_values == 2 * h.n_components) ||
        (hs.matrix_valid && (hs.matrix_stages < 1 || hs.matrix_stages > 2 || !positive(hs.matrix_dt) ||
                             !std::isfinite(hs.matrix_t))))
      throw CheckpointError("has a corrupted header (implicit-step history)");
    if (!std::isfinite(h.convection_owed) || h.convection_owed < 0)
      throw CheckpointError("has a corrupted header (convective time owed)");
    const unsigned int nc = h.n_components, nv = h.n_values;
    d.keys.resize(h.n_cells);
    d.values.resize(h.n_cells * nv);
    const char *p = buf.data() + magic.size() + sizeof(h);
    for (std::uint64_t i = 0; i < h.n_cells; ++i, p += row)
      {
        std::memcpy(&d.keys[i], p, sizeof(std::int64_t));
        std::memcpy(&d.values[i * nv], p + sizeof(std::int64_t), nv * sizeof(double));
        if (d.keys[i] < 0 || (i > 0 && d.keys[i] <= d.keys[i - 1]))
          throw CheckpointError("is corrupted: cell keys out of order at row " + std::to_string(i));
        for (unsigned int k = 0; k < nv; k += nc)
          {
            const double *v = &d.values[i * nv + k];
            bool          finite = true;
            for (unsigned int c = 0; c < nc; ++c)
              finite = finite && std::isfinite(v[c]);
            if (!finite || !(v[0] > 0) || !(v[nc - 1] > 0))
              throw CheckpointError("holds an invalid state at row " + std::to_string(i) +
                                    " (not finite, n <= 0 or energy <= 0)");
          }
      }
    return d;
  }

  std::uint64_t state_digest(const CheckpointData &d)
  {
    const unsigned int nc = d.header.n_components, nv = d.header.n_values;
    std::string        bytes;
    bytes.reserve(d.keys.size() * (8 + 8 * nc));
    for (std::size_t i = 0; i < d.keys.size(); ++i)
      {
        bytes.append(reinterpret_cast<const char *>(&d.keys[i]), sizeof(std::int64_t));
        bytes.append(reinterpret_cast<const char *>(&d.values[i * nv]), nc * sizeof(double));
      }
    return fnv1a(bytes.data(), bytes.size());
  }
} // namespace granhydro::io
