#pragma once
/**
 * @file checkpointing.h
 * What of a run goes into a checkpoint besides the state (time, step, the convective time
 * owed by the merged splitting, the output count, the run's record, the implicit step's
 * history), and the checks of a checkpoint against the run on restart. The file format
 * itself: io/checkpoint.h, io/state_checkpoint.h.
 */
#include <granhydro/base/units.h>
#include <granhydro/diffusion/implicit_integrator.h>
#include <granhydro/driver/run_settings.h>
#include <granhydro/driver/run_summary.h>
#include <granhydro/mesh/cartesian_patch.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/lac/la_parallel_vector.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace granhydro::driver
{
  template <int dim>
  class Checkpointing
  {
  public:
    using Vector  = dealii::LinearAlgebra::distributed::Vector<double>;
    using History = typename diffusion::ImplicitIntegrator<dim>::History;

    Checkpointing(const CheckpointIdentity &identity, const Units &units, const MPI_Comm comm);

    /// what a checkpoint holds besides the state (times scaled)
    struct Contents
    {
      double                                      time = 0, convection_owed = 0;
      unsigned int                                step = 0, outputs = 0;
      std::vector<std::pair<std::string, double>> record;  ///< io::CheckpointHeader::run_record
      History                                     history; ///< matrix_valid = false: none
    };

    /// write U of the patch and c to file (rank 0 writes all cells, sorted by lattice key,
    /// atomically and verified); a failure throws OutputError on every rank
    void write(const std::string &file, const mesh::CartesianPatch<dim> &patch, const Vector &U,
               const Contents &c) const;

    /// where a restarted run continues
    struct Restart
    {
      Contents     contents;             ///< times in this run's units
      bool         with_history = false; ///< contents.history holds the implicit step's history
      bool         same_units   = false; ///< the rkl2_blocked count applies
      bool         has_record   = false; ///< contents.record is the earlier segments' (format v6)
      unsigned int version      = 0;     ///< the file's format version
    };

    /// read file into U (an adaptive patch is first rebuilt from the file's leaves, then
    /// mesh_changed() is called and U re-initialised); keep_history: the run has an
    /// implicit integrator. Throws SceneError naming 'Initial state/Checkpoint' if the file
    /// is unreadable or does not match the run (mesh, model)
    Restart read(const std::string &file, mesh::CartesianPatch<dim> &patch, Vector &U,
                 const bool keep_history, const std::function<void()> &mesh_changed) const;

  private:
    const CheckpointIdentity &identity;
    const Units              &units_;
    const MPI_Comm            comm;
  };
} // namespace granhydro::driver
