/**
 * @file checkpointing.cc
 * Checkpointing (driver/checkpointing.h).
 */
#include <granhydro/base/errors.h>
#include <granhydro/driver/checkpointing.h>
#include <granhydro/io/state_checkpoint.h>

#include <deal.II/base/mpi.h>

#include <cmath>
#include <cstdio>
#include <memory>

namespace granhydro::driver
{
  using namespace dealii;

  template <int dim>
  Checkpointing<dim>::Checkpointing(const CheckpointIdentity &identity, const Units &units,
                                    const MPI_Comm comm)
    : identity(identity)
    , units_(units)
    , comm(comm)
  {}

  template <int dim>
  void Checkpointing<dim>::write(const std::string &file, const mesh::CartesianPatch<dim> &patch,
                                 const Vector &U, const Contents &c) const
  {
    constexpr unsigned int    NC      = dim + 2;
    const History            &history = c.history;
    std::vector<std::int64_t> keys(patch.n_owned());
    for (unsigned int s = 0; s < keys.size(); ++s)
      keys[s] = patch.leaf_key(s);
    io::CheckpointHeader h;
    h.dim          = dim;
    h.n_components = NC;
    for (unsigned int d = 0; d < 3; ++d)
      {
        h.cells[d] = d < dim ? identity.cells[d] : 1;
        h.lower[d] = d < dim ? identity.lower[d] : 0;
        h.upper[d] = d < dim ? identity.upper[d] : 0;
      }
    h.length          = units_.length;
    h.mass            = units_.mass;
    h.velocity        = units_.velocity;
    h.time            = c.time;
    h.step            = c.step;
    h.convection_owed = c.convection_owed;
    h.outputs         = c.outputs;
    std::snprintf(h.model, sizeof(h.model), "%s", identity.model.c_str());
    try
      {
        io::set_run_record(h, c.record);
      }
    catch (const CheckpointError &e)
      {
        throw OutputError("cannot write the checkpoint: " + std::string(e.what()));
      }
    auto &hh        = h.history;
    hh.rkl2_blocked = history.rkl2_blocked;
    hh.matrix_valid = history.matrix_valid;
    if (history.matrix_valid)
      {
        hh.matrix_age     = history.matrix_age;
        hh.matrix_coupled = history.matrix_coupled;
        hh.matrix_stages  = history.matrix_N.size();
        hh.matrix_t       = history.matrix_t;
        hh.matrix_dt      = history.matrix_dt;
        for (unsigned int i = 0; i < history.matrix_N.size(); ++i)
          for (unsigned int j = 0; j < history.matrix_N.size(); ++j)
            hh.matrix_N[i * history.matrix_N.size() + j] = history.matrix_N[i][j];
      }
    io::write_state_checkpoint(file, h, keys, U.begin(),
                               history.matrix_valid ? history.state.data() : nullptr, comm);
  }

  template <int dim>
  typename Checkpointing<dim>::Restart
  Checkpointing<dim>::read(const std::string &file, mesh::CartesianPatch<dim> &patch, Vector &U,
                           const bool keep_history, const std::function<void()> &mesh_changed) const
  {
    constexpr unsigned int NC = dim + 2;
    const std::string      what =
      "in " + identity.source + ": parameter 'Initial state/Checkpoint': '" + file + "' ";
    // the header and the part table (O(ranks)); the parts are streamed below
    std::unique_ptr<io::CheckpointReader> reader;
    try
      {
        reader = std::make_unique<io::CheckpointReader>(file);
        if (identity.adaptive && reader->header().dim == dim)
          {
            // an adaptive mesh is rebuilt from the leaves in the file
            patch.refine_to(io::checkpoint_keys(*reader, comm));
            mesh_changed();
            U.reinit(patch.partitioner());
          }
      }
    catch (const CheckpointError &e)
      {
        throw SceneError(what + e.what());
      }
    const io::CheckpointHeader &h = reader->header();
    bool same_mesh = h.dim == dim && h.n_components == int(NC) && h.n_cells == patch.n_global_cells();
    for (unsigned int d = 0; d < dim; ++d)
      {
        const double extent = std::abs(identity.upper[d] - identity.lower[d]);
        same_mesh           = same_mesh && h.cells[d] == identity.cells[d] &&
                    std::abs(h.lower[d] - identity.lower[d]) <= 1e-12 * extent &&
                    std::abs(h.upper[d] - identity.upper[d]) <= 1e-12 * extent;
      }
    if (!same_mesh)
      throw SceneError(what + "was written for another mesh (dimension, Domain/Cells, corners or "
                              "Adaptivity/Maximum level differ)");
    if (std::string(h.model) != identity.model)
      throw SceneError(what + "was written with 'Material/Model = " + std::string(h.model) + "'");
    Restart r;
    r.same_units = io::same_units(h, units_);
    std::vector<std::int64_t> keys(patch.n_owned());
    for (unsigned int s = 0; s < keys.size(); ++s)
      keys[s] = patch.leaf_key(s);
    // the implicit step's history (a checkpoint between output times): only with the same
    // units and an integrator that keeps one
    r.with_history   = h.history.matrix_valid && r.same_units && keep_history;
    History &history = r.contents.history;
    if (r.with_history)
      history.state.resize(std::size_t(patch.n_owned()) * NC);
    std::size_t found = 0;
    try
      {
        found = io::read_state_checkpoint(*reader, keys, units_, U.begin(),
                                          r.with_history ? history.state.data() : nullptr, comm);
      }
    catch (const CheckpointError &e)
      {
        throw SceneError(what + e.what());
      }
    if (Utilities::MPI::sum(found, comm) != patch.n_global_cells() || found != patch.n_owned())
      throw SceneError(what + "does not hold every cell of the mesh");
    r.contents.time = r.same_units ? h.time : h.time * h.length / h.velocity / units_.time();
    r.contents.step = h.step;
    r.contents.convection_owed =
      r.same_units ? h.convection_owed : h.convection_owed * h.length / h.velocity / units_.time();
    r.contents.outputs = h.outputs;
    if (r.same_units)
      {
        history.rkl2_blocked = h.history.rkl2_blocked;
        if (r.with_history)
          {
            history.matrix_valid   = true;
            history.matrix_coupled = h.history.matrix_coupled;
            history.matrix_age     = h.history.matrix_age;
            history.matrix_t       = h.history.matrix_t;
            history.matrix_dt      = h.history.matrix_dt;
            const unsigned int ns  = h.history.matrix_stages;
            history.matrix_N.assign(ns, std::vector<double>(ns));
            for (unsigned int a = 0; a < ns; ++a)
              for (unsigned int b = 0; b < ns; ++b)
                history.matrix_N[a][b] = h.history.matrix_N[a * ns + b];
          }
      }
    r.contents.record = io::run_record(h);
    r.version         = reader->version();
    return r;
  }

  template class Checkpointing<1>;
  template class Checkpointing<2>;
  template class Checkpointing<3>;
} // namespace granhydro::driver
