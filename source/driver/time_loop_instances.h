#pragma once
/**
 * @file time_loop_instances.h
 * The models and dimensions TimeLoop is built for. Its member functions are defined over
 * time_loop.cc, run_history.cc and phase_times.cc; each ends with
 * GRANHYDRO_TIME_LOOP_INSTANCES to instantiate the members it defines.
 */
#include <granhydro/driver/time_loop.h>
#include <granhydro/physics/models.h>

#define GRANHYDRO_TIME_LOOP_INSTANCE(d, D) template class TimeLoop<d, D>;
#define GRANHYDRO_TIME_LOOP_INSTANCES GRANHYDRO_FOR_EACH_MODEL(GRANHYDRO_TIME_LOOP_INSTANCE)
