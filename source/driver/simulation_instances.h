#pragma once
/**
 * @file simulation_instances.h
 * The models and dimensions Simulation is built for. Its member functions are defined
 * over several files (simulation.cc, split_step.cc, time_loop.cc, ...); each of them
 * ends with GRANHYDRO_SIMULATION_INSTANCES to instantiate the members it defines.
 */
#include <granhydro/driver/simulation.h>
#include <granhydro/physics/models.h>

#define GRANHYDRO_SIMULATION_INSTANCE(d, D) template class Simulation<d, D>;
#define GRANHYDRO_SIMULATION_INSTANCES GRANHYDRO_FOR_EACH_MODEL(GRANHYDRO_SIMULATION_INSTANCE)
