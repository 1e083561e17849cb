#pragma once
/**
 * @file models.h
 * The one list of the models (descriptions) and dimensions granhydro is built for.
 * A class template over a description is explicitly instantiated for each pair by
 * GRANHYDRO_FOR_EACH_MODEL(X), which expands to X(dim, Description) once per pair;
 * a new model is one more line here (and its value and name in material_model.h, and the
 * run dispatch).
 */
#include <granhydro/physics/granular_gas.h>
#include <granhydro/physics/ideal_gas.h>
#include <granhydro/physics/material_model.h>

#define GRANHYDRO_FOR_EACH_MODEL(X)          \
  X(1, ::granhydro::physics::IdealGas<1>)    \
  X(2, ::granhydro::physics::IdealGas<2>)    \
  X(3, ::granhydro::physics::IdealGas<3>)    \
  X(1, ::granhydro::physics::GranularGas<1>) \
  X(2, ::granhydro::physics::GranularGas<2>) \
  X(3, ::granhydro::physics::GranularGas<3>)
