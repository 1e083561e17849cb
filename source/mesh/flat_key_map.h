#pragma once
/**
 * @file flat_key_map.h
 * A hash map from 64-bit keys (any but the smallest, no_slot_key) to small values, for the table
 * builders of CartesianPatch (an internal part of the patch: source/mesh, not installed):
 * open addressing with linear probing in one array of (key, value) pairs, a power-of-two
 * capacity kept at least twice the size, Fibonacci hashing. About three times faster than
 * std::unordered_map<long long, V> for the lookups of the stencil closure (one cache line
 * per lookup instead of a bucket array and a node). No erase (the tables are rebuilt).
 */
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

namespace granhydro::mesh
{
  template <class V>
  class FlatKeyMap
  {
  public:
    static constexpr long long empty = std::numeric_limits<long long>::min(); ///< no key

    std::size_t size() const { return n_keys; }
    void        clear()
    {
      slots.clear();
      n_keys = 0;
      bits   = 0;
    }
    /// room for at least m keys without rehashing
    void reserve(const std::size_t m)
    {
      unsigned int b = 4;
      while ((std::size_t(1) << b) < 2 * m)
        ++b;
      if (b > bits)
        rehash(b);
    }
    /// the value of key, nullptr if absent
    const V *find(const long long key) const
    {
      if (n_keys == 0)
        return nullptr;
      for (std::size_t i = home(key);; i = (i + 1) & mask())
        {
          const auto &s = slots[i];
          if (s.first == key)
            return &s.second;
          if (s.first == empty)
            return nullptr;
        }
    }
    bool     count(const long long key) const { return find(key) != nullptr; }
    const V &at(const long long key) const
    {
      const V *v = find(key);
      if (!v)
        throw std::out_of_range("FlatKeyMap::at: no such key");
      return *v;
    }
    /// the value of key, inserted as V() if absent; the bool: inserted
    std::pair<V *, bool> insert(const long long key, const V &value = V())
    {
      if (2 * (n_keys + 1) > (std::size_t(1) << bits))
        rehash(bits < 4 ? 4 : bits + 1);
      for (std::size_t i = home(key);; i = (i + 1) & mask())
        {
          auto &s = slots[i];
          if (s.first == key)
            return {&s.second, false};
          if (s.first == empty)
            {
              s = {key, value};
              ++n_keys;
              return {&s.second, true};
            }
        }
    }
    V &operator[](const long long key) { return *insert(key).first; }
    /// f(key, value) for every entry, in slot order
    template <class F>
    void for_each(F &&f) const
    {
      for (const auto &s : slots)
        if (s.first != empty)
          f(s.first, s.second);
    }

  private:
    std::size_t mask() const { return (std::size_t(1) << bits) - 1; }
    std::size_t home(const long long key) const
    {
      return std::size_t((std::uint64_t(key) * 0x9E3779B97F4A7C15ull) >> (64 - bits));
    }
    void rehash(const unsigned int b)
    {
      std::vector<std::pair<long long, V>> old(std::size_t(1) << b, {empty, V()});
      old.swap(slots);
      bits   = b;
      n_keys = 0;
      for (const auto &s : old)
        if (s.first != empty)
          insert(s.first, s.second);
    }

    std::vector<std::pair<long long, V>> slots;
    std::size_t                          n_keys = 0;
    unsigned int                         bits   = 0;
  };
} // namespace granhydro::mesh
