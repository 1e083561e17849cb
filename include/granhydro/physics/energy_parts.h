#pragma once
/**
 * @file energy_parts.h
 * The parts of a cell's energy density nE: kinetic, thermal and the contact potential
 * of the dense closure (scaled units). One place for the split the profiles, the VTU
 * fields and the run's history (<base>_history.csv) all write.
 */
#include <granhydro/physics/granular_gas.h>
#include <granhydro/physics/ideal_gas.h>

#include <type_traits>

namespace granhydro::physics
{
  /// contact potential energy per volume n w(phi) of the dense closure (scaled units):
  /// part of nE for the granular gas (0 with the closure off), none for the ideal gas
  template <int dim, class Description>
  double contact_energy_density(const Description &desc, const double n)
  {
    if constexpr (std::is_same_v<Description, GranularGas<dim>>)
      return desc.contact.energy_density(n);
    else
      {
        (void)desc;
        (void)n;
        return 0.;
      }
  }
} // namespace granhydro::physics
