#pragma once
/**
 * @file stencil_tables.h
 * The slot numbering shared by the table builders of CartesianPatch (an internal part
 * of the patch; the builders are its private members, source/mesh/stencil_tables.cc).
 */
#include <granhydro/mesh/lattice.h>

#include <vector>

namespace granhydro
{
  /// slot of each key (lattice.h) and key of each slot (no_slot_key for virtual cells)
  struct SlotIndex
  {
    FlatKeyMap<unsigned int> slot_of;
    std::vector<long long>   keys;
    /// the first virtual cell's slot (virtual cells come last)
    unsigned int first_virtual = 0;
    /// the slot of a key, or -1
    int operator()(const long long key) const
    {
      if (key == no_slot_key)
        return -1;
      const unsigned int *s = slot_of.find(key);
      return s ? int(*s) : -1;
    }
  };
} // namespace granhydro
