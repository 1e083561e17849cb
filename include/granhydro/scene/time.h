#pragma once
/**
 * @file time.h
 * The 'Time' subsection of a scene: when the run stops.
 */
#include <deal.II/base/parameter_handler.h>

namespace granhydro::scene
{
  struct Scene;

  struct TimeParameters
  {
    double       end_time         = 0.2;
    unsigned int max_steps        = 0;
    double       max_wall_seconds = 0; ///< 0 = no limit
    double       steady_tolerance = 0; // stop when KE and centre of mass change less per output interval

    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(dealii::ParameterHandler &prm);
    /// a positive end time
    static void check(const Scene &s);
  };
} // namespace granhydro::scene
