/**
 * @file checkpoint_read.cc
 * Reading a checkpoint (io/checkpoint.h): the header and part table verified on opening,
 * the parts streamed with bounded buffers and verified as they are read.
 */
#include <granhydro/io/checkpoint.h>
#include <granhydro/io/checkpoint_bytes.h>
#include <granhydro/physics/material_model.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <queue>
#include <sstream>

namespace granhydro::io
{
  using namespace checkpoint_bytes;

  namespace
  {
    /// the version of a refused older format ("granhydro checkpoint vK\n", K < 5), or empty
    std::string older_format(const std::string &buf)
    {
      for (const char *v : {"2", "3", "4"})
        {
          const std::string m = std::string("granhydro checkpoint v") + v + "\n";
          if (buf.compare(0, m.size(), m) == 0)
            return v;
        }
      return "";
    }

    /// a file descriptor closed on scope exit
    struct File
    {
      int fd;
      explicit File(const std::string &path)
        : fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC))
      {
        if (fd < 0)
          throw CheckpointError("cannot be read: " + std::string(std::strerror(errno)));
      }
      ~File() { ::close(fd); }
      File(const File &)            = delete;
      File &operator=(const File &) = delete;
    };

    /// reads one part row by row through a bounded buffer, checking each row and, at its
    /// end, the part's checksum
    class PartCursor
    {
    public:
      PartCursor(const int fd, const CheckpointHeader &h, const CheckpointPart &part, const std::size_t p,
                 const std::size_t buffer_bytes)
        : fd_(fd)
        , part_(part)
        , p_(p)
        , nc_(h.n_components)
        , nv_(h.n_values)
        , row_(row_bytes(h.n_values))
        , buf_(std::size_t(std::max<std::uint64_t>(1, buffer_bytes / row_)) * row_)
        , values_(nv_)
      {}

      /// moves to the next row; false after the last one (the part is then verified)
      bool next()
      {
        if (index_ == part_.n_rows)
          {
            finish();
            return false;
          }
        if (pos_ == end_)
          refill();
        std::memcpy(&key_, buf_.data() + pos_, sizeof(key_));
        std::memcpy(values_.data(), buf_.data() + pos_ + 8, 8 * nv_);
        pos_ += row_;
        if (key_ < 0 || (index_ > 0 && key_ <= previous_) || (index_ == 0 && key_ != part_.first_key) ||
            key_ > part_.last_key)
          fail("is corrupted: cell keys out of order at row " + std::to_string(index_) + where());
        for (unsigned int k = 0; k < nv_; k += nc_)
          {
            const double *v      = &values_[k];
            bool          finite = true;
            for (unsigned int c = 0; c < nc_; ++c)
              finite = finite && std::isfinite(v[c]);
            if (!finite || !(v[0] > 0) || !(v[nc_ - 1] > 0))
              fail("holds an invalid state at row " + std::to_string(index_) + where() +
                   " (not finite, n <= 0 or energy <= 0)");
          }
        previous_ = key_;
        ++index_;
        return true;
      }

      std::int64_t  key() const { return key_; }
      const double *values() const { return values_.data(); }
      std::size_t   part() const { return p_; }

    private:
      std::string where() const { return " of part " + std::to_string(p_); }

      void refill()
      {
        const std::uint64_t rows = std::min<std::uint64_t>(part_.n_rows - index_, buf_.size() / row_);
        end_                     = std::size_t(rows * row_);
        if (!pread_all(fd_, buf_.data(), end_, part_.offset + read_))
          throw CheckpointError("is truncated (part " + std::to_string(p_) + " cannot be read whole)");
        read_ += end_;
        sum_ = fnv1a(buf_.data(), end_, sum_);
        pos_ = 0;
      }

      void finish() const
      {
        if (sum_ != part_.checksum)
          throw CheckpointError("is corrupted (checksum mismatch in part " + std::to_string(p_) +
                                "): a bit flipped or a write was torn");
        if (part_.n_rows > 0 && previous_ != part_.last_key)
          throw CheckpointError("is corrupted: the last key of part " + std::to_string(p_) +
                                " is not the one in its table");
      }

      /// a damaged row: if the part's checksum does not match, that is the reason
      [[noreturn]] void fail(const std::string &reason)
      {
        while (read_ < part_.n_rows * row_)
          {
            const std::uint64_t rows =
              std::min<std::uint64_t>(part_.n_rows * row_ - read_, buf_.size()) / row_;
            end_ = std::size_t(rows * row_);
            if (!pread_all(fd_, buf_.data(), end_, part_.offset + read_))
              break;
            read_ += end_;
            sum_ = fnv1a(buf_.data(), end_, sum_);
          }
        if (read_ == part_.n_rows * row_ && sum_ != part_.checksum)
          throw CheckpointError("is corrupted (checksum mismatch in part " + std::to_string(p_) +
                                "): a bit flipped or a write was torn");
        throw CheckpointError(reason);
      }

      int                   fd_;
      const CheckpointPart &part_;
      std::size_t           p_;
      unsigned int          nc_, nv_;
      std::uint64_t         row_;
      std::vector<char>     buf_;
      std::vector<double>   values_;
      std::size_t           pos_ = 0, end_ = 0;
      std::uint64_t         index_ = 0, read_ = 0, sum_ = fnv_basis;
      std::int64_t          key_ = -1, previous_ = -1;
    };

    /// the semantic checks of a header whose bytes are intact
    void check_header(const CheckpointHeader &h)
    {
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
      // the models granhydro writes (Material/Model): a re-sealed header with another name
      // was reported valid by --checkpoint-info
      if (physics::Model m; !enum_from_name(std::string(h.model), m))
        {
          std::string name(h.model);
          for (char &ch : name)
            if (ch < 32 || ch > 126)
              ch = '?';
          throw CheckpointError("has a corrupted header (unknown material model '" + name +
                                "'; granhydro writes " + enum_alternatives<physics::Model>() + ")");
        }
      const auto &hs = h.history;
      if (hs.rkl2_blocked < 0 || hs.rkl2_blocked > 1000 || hs.matrix_age < 0 ||
          (hs.matrix_valid != 0) != (h.n_values == 2 * h.n_components) ||
          (hs.matrix_valid && (hs.matrix_stages < 1 || hs.matrix_stages > 2 || !positive(hs.matrix_dt) ||
                               !std::isfinite(hs.matrix_t))))
        throw CheckpointError("has a corrupted header (implicit-step history)");
      if (!std::isfinite(h.convection_owed) || h.convection_owed < 0)
        throw CheckpointError("has a corrupted header (convective time owed)");
      if (std::memchr(h.run_record, '\0', sizeof(h.run_record)) == nullptr)
        throw CheckpointError("has a corrupted header (run record)");
    }

    /// the part table against the header and the file size
    void check_table(const CheckpointHeader &h, const std::vector<CheckpointPart> &parts,
                     const std::uint64_t size, const int version)
    {
      const std::uint64_t row    = row_bytes(h.n_values);
      std::uint64_t       offset = head_bytes(parts.size(), version), rows = 0;
      for (std::size_t p = 0; p < parts.size(); ++p)
        {
          const auto &t = parts[p];
          if (t.offset != offset || t.n_rows > size || // (no overflow below)
              (t.n_rows == 0 ? (t.first_key != -1 || t.last_key != -1 || t.checksum != fnv_basis) :
                               (t.first_key < 0 || t.last_key < t.first_key)))
            throw CheckpointError("is truncated or corrupted: part " + std::to_string(p) + " of " +
                                  std::to_string(parts.size()) + " does not fit in its " +
                                  std::to_string(size) + " bytes");
          offset += t.n_rows * row;
          rows += t.n_rows;
        }
      if (size != offset)
        throw CheckpointError("is truncated or corrupted: " + std::to_string(size) +
                              " bytes, but its part table announces " + std::to_string(rows) + " cells (" +
                              std::to_string(offset) + " bytes)");
      if (rows != h.n_cells || rows == 0)
        throw CheckpointError("has a corrupted header: it announces " + std::to_string(h.n_cells) +
                              " cells, its parts hold " + std::to_string(rows));
    }

    /// the buffer of each of n cursors read at the same time: 1 MiB for one, less for
    /// many (a merge of many parts stays within about 64 MiB)
    std::size_t buffer_bytes(const std::size_t n)
    {
      return std::max<std::size_t>(
        4096, std::min<std::size_t>(1u << 20, (64u << 20) / std::max<std::size_t>(n, 1)));
    }
  } // namespace

  CheckpointReader::CheckpointReader(const std::string &file)
    : file_(file)
  {
    struct stat st;
    if (::stat(file.c_str(), &st) != 0)
      throw CheckpointError("cannot be read: " + std::string(std::strerror(errno)));
    if (!S_ISREG(st.st_mode))
      throw CheckpointError("is not a regular file (a folder or a device)");
    const std::uint64_t size = st.st_size;
    const File          f(file);
    const auto         &magic = checkpoint_magic();
    // the magic line tells the version (v5: the header without the run record)
    const std::string v5 = "granhydro checkpoint v5\n";
    std::string       first(std::size_t(std::min<std::uint64_t>(size, magic.size())), '\0');
    if (!pread_all(f.fd, first.data(), first.size(), 0))
      throw CheckpointError("cannot be read");
    version_                 = first == v5 ? 5 : 6;
    const std::size_t hsize  = header_bytes(version_);
    const std::size_t prefix = magic.size() + hsize + 8;
    std::string       buf(std::size_t(std::min<std::uint64_t>(size, prefix)), '\0');
    if (!pread_all(f.fd, buf.data(), buf.size(), 0))
      throw CheckpointError("cannot be read");
    if (const std::string v = older_format(buf); !v.empty())
      throw CheckpointError("was written by an older granhydro (checkpoint format v" + v +
                            "; this version writes v6 and reads v5 and v6); restart it with that "
                            "version or start from the scene");
    if (buf.size() < magic.size() || (buf.compare(0, magic.size(), magic) != 0 && version_ != 5))
      throw CheckpointError("is not a granhydro checkpoint file");
    if (size < prefix + 8)
      throw CheckpointError("is truncated (" + std::to_string(size) + " bytes)");
    std::uint64_t n_parts = 0;
    std::memcpy(&h_, buf.data() + magic.size(), hsize); // a v5 header leaves the run record empty
    std::memcpy(&n_parts, buf.data() + magic.size() + hsize, sizeof(n_parts));
    if (n_parts == 0 || n_parts > (size - prefix - 8) / sizeof(CheckpointPart))
      throw CheckpointError("is truncated or corrupted: its part table (" + std::to_string(n_parts) +
                            " parts) does not fit in its " + std::to_string(size) + " bytes");
    // the header and the table are verified by their checksum before anything is used
    parts_.resize(n_parts);
    std::uint64_t stored = 0;
    if (!pread_all(f.fd, reinterpret_cast<char *>(parts_.data()), n_parts * sizeof(CheckpointPart), prefix) ||
        !pread_all(f.fd, reinterpret_cast<char *>(&stored), 8, prefix + n_parts * sizeof(CheckpointPart)))
      throw CheckpointError("cannot be read");
    std::uint64_t sum = fnv1a(buf.data(), buf.size());
    sum = fnv1a(reinterpret_cast<const char *>(parts_.data()), n_parts * sizeof(CheckpointPart), sum);
    if (sum != stored)
      throw CheckpointError(
        "is corrupted (checksum mismatch in the header or part table): a bit flipped or a "
        "write was torn");
    if (h_.dim < 1 || h_.dim > 3 || h_.n_components != h_.dim + 2 ||
        (h_.n_values != h_.n_components && h_.n_values != 2 * h_.n_components))
      throw CheckpointError("has a corrupted header (dimension " + std::to_string(h_.dim) + ", components " +
                            std::to_string(h_.n_components) + ")");
    check_table(h_, parts_, size, version_);
    check_header(h_);
  }

  void CheckpointReader::read_part(const std::size_t p, const RowFunction &f) const
  {
    const File f_(file_);
    PartCursor c(f_.fd, h_, parts_[p], p, buffer_bytes(1));
    while (c.next())
      f(c.key(), c.values());
  }

  void CheckpointReader::read_merged(const RowFunction &f) const
  {
    const File                               file(file_);
    std::vector<std::unique_ptr<PartCursor>> cursors;
    for (std::size_t p = 0; p < parts_.size(); ++p)
      cursors.push_back(std::make_unique<PartCursor>(file.fd, h_, parts_[p], p, buffer_bytes(parts_.size())));
    // a min-heap of (key, part) over the parts' current rows
    using Entry = std::pair<std::int64_t, std::size_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
    for (auto &c : cursors)
      if (c->next())
        heap.emplace(c->key(), c->part());
    std::int64_t previous      = -1;
    std::size_t  previous_part = 0;
    while (!heap.empty())
      {
        const auto [key, p] = heap.top();
        heap.pop();
        if (key == previous)
          throw CheckpointError("is corrupted: cell key " + std::to_string(key) + " is in parts " +
                                std::to_string(previous_part) + " and " + std::to_string(p));
        f(key, cursors[p]->values());
        previous      = key;
        previous_part = p;
        if (cursors[p]->next())
          heap.emplace(cursors[p]->key(), p);
      }
  }

  std::uint64_t state_digest(const CheckpointReader &r)
  {
    const std::size_t nc  = r.header().n_components;
    std::uint64_t     sum = fnv_basis;
    r.read_merged([&](const std::int64_t key, const double *v) {
      sum = fnv1a(reinterpret_cast<const char *>(&key), sizeof(key), sum);
      sum = fnv1a(reinterpret_cast<const char *>(v), nc * sizeof(double), sum);
    });
    return sum;
  }
} // namespace granhydro::io
