#pragma once
/**
 * @file simulation_instances.h
 * The models and dimensions Simulation is built for. Its member functions are defined
 * over several files (simulation.cc, strang_step.cc, time_loop.cc, ...); each of them
 * ends with GRANHYDRO_SIMULATION_INSTANCES to instantiate the members it defines.
 */
#include <granhydro/driver/simulation.h>

#define GRANHYDRO_SIMULATION_INSTANCES                            \
  template class Simulation<1, physics::IdealGas<1>>;             \
  template class Simulation<2, physics::IdealGas<2>>;             \
  template class Simulation<3, physics::IdealGas<3>>;             \
  template class Simulation<1, physics::GranularGas<1>>;          \
  template class Simulation<2, physics::GranularGas<2>>;          \
  template class Simulation<3, physics::GranularGas<3>>;
