#include <granhydro/scene/scene.h>
#include <granhydro/scene/time.h>

#include "parameter_tools.h"

namespace granhydro::scene
{
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;
  using namespace detail;

  void TimeParameters::declare_parameters(ParameterHandler &prm)
  {
    const TimeParameters defaults;
    prm.enter_subsection("Time");
    {
      prm.declare_entry("End time", default_text(defaults.end_time),
                        Patterns::Double(0, Patterns::Double::max_double_value), "Simulated end time [s].");
      prm.declare_entry("Maximum wall time", default_text(defaults.max_wall_seconds),
                        Patterns::Double(0, Patterns::Double::max_double_value),
                        "Stop cleanly (final output, checkpoint, <Base name>_summary.csv with status "
                        "'wall time limit') after this many wall-clock seconds; 0 = no limit. "
                        "Restart from the checkpoint to go on.");
      prm.declare_entry("Maximum steps", default_text(defaults.max_steps), Patterns::Integer(0),
                        "Stop after this many steps (0 = no limit).");
      prm.declare_entry("Steady state tolerance", default_text(defaults.steady_tolerance),
                        Patterns::Double(0, 1),
                        "Stop before the end time once a steady state is reached: the total "
                        "kinetic energy and the mean height (centre of mass) change by less "
                        "than this fraction between two output times (needs Output/Interval "
                        "> 0; 0 = off).");
    }
    prm.leave_subsection();
  }

  void TimeParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Time");
    end_time         = prm.get_double("End time");
    max_steps        = prm.get_integer("Maximum steps");
    max_wall_seconds = prm.get_double("Maximum wall time");
    steady_tolerance = prm.get_double("Steady state tolerance");
    prm.leave_subsection();
  }

  void TimeParameters::check(const Scene &s)
  {
    if (s.end_time <= 0)
      fail(s, "Time/End time", "must be positive");
  }
} // namespace granhydro::scene
