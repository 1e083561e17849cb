#pragma once
/**
 * @file material_model.h
 * The material models a scene chooses from ('Material/Model'), by name: the scene holds
 * one of these, the run dispatches on it to a description (models.h), a checkpoint
 * records its name.
 */
#include <granhydro/base/enum_names.h>

#include <array>

namespace granhydro::physics
{
  enum class Model
  {
    ideal_gas, ///< physics::IdealGas: the verification model, the dilute elastic limit
    granular   ///< physics::GranularGas: hard spheres, Garzo-Dufty transport
  };
  /// Material/Model (and the model name in a checkpoint header)
  constexpr auto enum_names(Model)
  {
    return enum_table(EnumName{Model::ideal_gas, "ideal gas"}, EnumName{Model::granular, "granular"});
  }
  static_assert(check_enum_names(enum_names(Model{})));
} // namespace granhydro::physics
