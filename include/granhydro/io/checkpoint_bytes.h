#pragma once
/**
 * @file checkpoint_bytes.h
 * Byte-level helpers shared by the checkpoint writer and reader (io/checkpoint.h):
 * the FNV-1a checksum, the sizes of the format's pieces and a complete pread.
 */
#include <granhydro/io/checkpoint.h>

#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <string>

namespace granhydro::io::checkpoint_bytes
{
  constexpr std::uint64_t fnv_basis = 14695981039346656037ull;

  /// FNV-1a, 64 bit, continued from h: detects flipped bits and torn writes (not an
  /// adversary); fnv1a(b, fnv1a(a)) is the checksum of a followed by b
  inline std::uint64_t fnv1a(const char *p, const std::size_t n, std::uint64_t h = fnv_basis)
  {
    for (std::size_t i = 0; i < n; ++i)
      {
        h ^= static_cast<unsigned char>(p[i]);
        h *= 1099511628211ull;
      }
    return h;
  }

  /// bytes of a row: the key and n_values doubles
  inline std::uint64_t row_bytes(const std::uint64_t n_values) { return 8 + 8 * n_values; }

  /// bytes before the first part: magic, header (of format version), part count, table,
  /// checksum
  inline std::uint64_t head_bytes(const std::uint64_t n_parts, const int version = 6)
  {
    return checkpoint_magic().size() + header_bytes(version) + 8 + n_parts * sizeof(CheckpointPart) + 8;
  }

  /// reads exactly n bytes at offset off; false on an error or a short file
  inline bool pread_all(const int fd, char *p, const std::size_t n, const std::uint64_t off)
  {
    std::size_t done = 0;
    while (done < n)
      {
        const ssize_t r = ::pread(fd, p + done, n - done, off_t(off + done));
        if (r < 0 && errno == EINTR)
          continue;
        if (r <= 0)
          return false;
        done += std::size_t(r);
      }
    return true;
  }
} // namespace granhydro::io::checkpoint_bytes
