/**
 * @file simulation_checkpoint.cc
 * Simulation's checkpoints: what of the run it hands to Checkpointing
 * (driver/checkpointing.h) and what a restart takes back (start time and step, owed
 * convective time, the implicit step's history, the earlier segments' record, the output
 * count).
 */
#include "simulation_instances.h"

namespace granhydro::driver
{
  using namespace dealii;

  template <int dim, class Description>
  void Simulation<dim, Description>::write_checkpoint(const std::string &file, const double t,
                                                      const unsigned int step, const bool with_history) const
  {
    typename Checkpointing<dim>::Contents c;
    if (with_history && integrator)
      c.history = integrator->history();
    c.time            = t;
    c.step            = step;
    c.convection_owed = split_->owed();
    c.outputs         = output ? output->count() : 0;
    c.record          = record_;
    checkpoints_->write(file, *patch_, U, c);
  }

  template <int dim, class Description>
  void Simulation<dim, Description>::read_checkpoint(const std::string &file)
  {
    const typename Checkpointing<dim>::Restart r =
      checkpoints_->read(file, *patch_, U, integrator != nullptr, [this] { mesh_changed(); });
    start_.time = r.contents.time;
    start_.step = r.contents.step;
    split_->set_owed(r.contents.convection_owed);
    if (integrator && r.same_units)
      integrator->restore(r.contents.history);
    // the record of the run's earlier segments (none in a checkpoint of format v5: the
    // counts then start at this checkpoint's step)
    RunSummary earlier;
    if (from_run_record(r.contents.record, record_units(units_, dim), earlier))
      start_.earlier = earlier;
    else
      {
        start_.earlier                   = RunSummary();
        start_.earlier.segments          = 0;
        start_.earlier.counted_from_step = r.contents.step;
        pcout << "  the checkpoint carries no record of the run before it (format v" << r.version
              << "): the summary counts from step " << r.contents.step << "\n";
      }
    output->resume(r.contents.outputs, start_time());
    pcout << "  initial state: checkpoint " << file << " (t = " << start_time() << " s, step " << start_.step
          << (r.with_history ? ", with the implicit step's history" : "") << ")\n";
  }

  GRANHYDRO_SIMULATION_INSTANCES
} // namespace granhydro::driver
