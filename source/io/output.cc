#include <granhydro/io/output.h>
#include <granhydro/physics/energy_parts.h>
#include <granhydro/physics/models.h>
#include <granhydro/physics/packing_fraction.h>

#include <deal.II/base/mpi.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/data_postprocessor.h>

#include <sys/statvfs.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <type_traits>

namespace granhydro::io
{
  using namespace dealii;

  namespace
  {
    using physics::contact_energy_density;

    /// the granular temperature T/m [m^2/s^2] of a temperature T in scaled units: T [J]
    /// over the grain mass m [kg] (the two-fluid codes' temperature; doc/user-guide.md)
    double granular_temperature(const Units &units, const double T)
    {
      return T * units.energy() / units.mass;
    }

    /// deal.II's generic ExcIO paragraph ("An input/output error has occurred. There are a
    /// number of reasons ...", from a failed VTU write) replaced by the OS reason: the
    /// errno of the failed write, or a full file system under `directory`
    std::string os_reason_of(const std::string &message, const int error, const std::string &directory)
    {
      if (message.find("An input/output error has occurred") == std::string::npos)
        return message;
      struct statvfs fs
      {};
      if (::statvfs(directory.empty() ? "." : directory.c_str(), &fs) == 0 && fs.f_bavail == 0)
        return std::strerror(ENOSPC);
      if (error != 0)
        return std::strerror(error);
      return "an input/output error (deal.II's VTU writer gives no reason)";
    }

    /// a stream's data reached the file system (flushed); else the OS reason
    void check_written(std::ofstream &out, const std::string &file)
    {
      out.flush();
      if (!out)
        throw std::runtime_error("cannot write '" + file + "': " + std::strerror(errno));
    }

    /// n u.v + n |v|^2/2: what a kinetic (and so the total) energy density gains from the
    /// container frame to the lab frame, where the velocity is u + v (v = ds/dt of a
    /// vibrated container; all in scaled units, n and n u may be sums over cells)
    template <int dim>
    double lab_frame_energy(const double n, const double *nu, const std::array<double, 3> &v)
    {
      double e = 0;
      for (unsigned int d = 0; d < dim; ++d)
        e += nu[d] * v[d] + 0.5 * n * v[d] * v[d];
      return e;
    }

    /// derived SI fields from the DG0 conserved variables (scaled units)
    template <int dim, class Description>
    class Fields : public DataPostprocessor<dim>
    {
    public:
      Fields(const Units &u, const Description &desc, const std::array<double, 3> &frame_velocity)
        : units(u)
        , desc(desc)
        , frame_velocity(frame_velocity)
      {
        for (unsigned int d = 0; d < 3; ++d)
          frame_velocity_scaled[d] = frame_velocity[d] / u.velocity;
      }

      void evaluate_vector_field(const DataPostprocessorInputs::Vector<dim> &in,
                                 std::vector<Vector<double>>                &out) const override
      {
        for (unsigned int q = 0; q < in.solution_values.size(); ++q)
          {
            physics::State<dim> U;
            for (unsigned int c = 0; c < dim + 2; ++c)
              U[c] = in.solution_values[q][c];
            const double n = U[0], p = desc.pressure(U), T = desc.temperature(U);
            unsigned int k = 0;
            out[q][k++]    = physics::packing_fraction(n);
            out[q][k++]    = n * units.number_density();
            out[q][k++]    = n * units.number_density() * units.mass;
            for (unsigned int d = 0; d < dim; ++d)
              out[q][k++] = U[1 + d] / n * units.velocity + frame_velocity[d];
            out[q][k++] = T * units.energy();
            out[q][k++] = granular_temperature(units, T);
            out[q][k++] = p * units.pressure();
            // nE = kinetic + thermal + contact; kinetic and total in the lab frame like
            // the velocity (thermal and contact energy do not depend on the frame)
            const double lab = lab_frame_energy<dim>(n, &U[1], frame_velocity_scaled);
            out[q][k++]      = (desc.kinetic_energy(U) + lab) * units.pressure();
            out[q][k++]      = desc.heat_capacity() * n * T * units.pressure();
            out[q][k++]      = contact_energy_density<dim>(desc, n) * units.pressure();
            out[q][k++]      = (U[dim + 1] + lab) * units.pressure();
          }
      }

      std::vector<std::string> get_names() const override
      {
        std::vector<std::string> names{"packing_fraction", "number_density", "mass_density"};
        for (unsigned int d = 0; d < dim; ++d)
          names.push_back("velocity");
        names.push_back("temperature");
        names.push_back("granular_temperature");
        names.push_back("pressure");
        for (const char *part : {"kinetic", "thermal", "contact", "total"})
          names.push_back(std::string(part) + "_energy_density");
        return names;
      }

      std::vector<DataComponentInterpretation::DataComponentInterpretation>
      get_data_component_interpretation() const override
      {
        std::vector<DataComponentInterpretation::DataComponentInterpretation> v(
          3, DataComponentInterpretation::component_is_scalar);
        for (unsigned int d = 0; d < dim; ++d)
          v.push_back(DataComponentInterpretation::component_is_part_of_vector);
        v.insert(v.end(), 3 + 4, DataComponentInterpretation::component_is_scalar);
        return v;
      }

      UpdateFlags get_needed_update_flags() const override { return update_values; }

    private:
      Units                 units;
      const Description    &desc;
      std::array<double, 3> frame_velocity;        // lab frame = container frame + ds/dt [m/s]
      std::array<double, 3> frame_velocity_scaled; // the same in scaled units
    };
  } // namespace

  template <int dim, class Description>
  Output<dim, Description>::Output(const OutputSettings &settings, const mesh::CartesianPatch<dim> &patch,
                                   const Description &desc)
    : settings(settings)
    , patch(patch)
    , desc(desc)
    , units(settings.units)
  {
    std::string err;
    if (Utilities::MPI::this_mpi_process(patch.communicator()) == 0 &&
        (settings.write_vtu || settings.write_profiles || settings.write_checkpoint ||
         settings.section_direction >= 0))
      {
        std::error_code ec;
        std::filesystem::create_directories(settings.directory, ec);
        if (ec || !std::filesystem::is_directory(settings.directory))
          err = "parameter 'Output/Directory': cannot create directory '" + settings.directory + "'" +
                (ec ? ": " + ec.message() : std::string());
        else
          {
            // a folder we cannot write into (read-only file system): refuse now, not at the
            // first VTU write
            const std::string probe = settings.directory + "/.granhydro_write_test";
            bool              ok    = bool(std::ofstream(probe) << "x");
            std::filesystem::remove(probe, ec);
            if (!ok)
              err = "parameter 'Output/Directory': cannot write into '" + settings.directory + "'";
          }
      }
    err = Utilities::MPI::broadcast(patch.communicator(), err, 0);
    if (!err.empty())
      throw SceneError(err);
  }

  template <int dim, class Description>
  std::array<double, 3> Output<dim, Description>::frame_velocity(const double time_si) const
  {
    // vibrated container (doc/physics.md 5.3): ds/dt of the frame (boundary/moving_frame.h)
    return settings.container_motion.velocity(time_si);
  }

  template <int dim, class Description>
  void Output<dim, Description>::write(const Vector &U, const double time_si, const unsigned int step)
  {
    // every part is collective; a failure on any rank stops every rank (never a hang)
    std::string error;
    try
      {
        if (settings.write_vtu)
          write_vtu(U, time_si, step);
        if (settings.write_profiles)
          write_profiles(U, time_si);
        if (settings.section_direction >= 0)
          write_cross_section(U, time_si);
      }
    catch (const std::exception &e)
      {
        error = os_reason_of(human_message(e.what()), errno, settings.directory);
      }
    for (const auto &e : Utilities::MPI::all_gather(patch.communicator(), error))
      if (!e.empty())
        throw OutputError("cannot write the output at t = " + std::to_string(time_si) + " s to '" +
                          settings.directory + "' (disk full or no permission?): " + e);
    ++counter;
  }

  template <int dim, class Description>
  void Output<dim, Description>::resume(const unsigned int outputs, const double time_si)
  {
    counter          = outputs;
    profiles_started = section_started = true;
    pvd_records.clear();
    unsigned int dropped = 0;
    // the PVD of the interrupted run: <DataSet timestep="t" group="" part="0" file="name"/>
    std::ifstream in(settings.file(".pvd"));
    std::string   line;
    while (std::getline(in, line))
      {
        const auto t0 = line.find("timestep=\""), f0 = line.find("file=\"");
        if (t0 == std::string::npos || f0 == std::string::npos)
          continue;
        // a damaged record (edited or torn file) is dropped, never a reason to crash
        const char  *begin = line.c_str() + t0 + 10;
        char        *end   = nullptr;
        const double t     = std::strtod(begin, &end);
        const auto   f1    = line.find('"', f0 + 6);
        if (end == begin || *end != '"' || !std::isfinite(t) || f1 == std::string::npos)
          {
            ++dropped;
            continue;
          }
        if (t <= time_si * (1 + 1e-12))
          pvd_records.emplace_back(t, line.substr(f0 + 6, f1 - f0 - 6));
      }
    if (dropped > 0 && Utilities::MPI::this_mpi_process(patch.communicator()) == 0)
      std::cout << "  warning: " << dropped << " damaged record(s) in " << settings.file(".pvd")
                << " dropped; it is rewritten at the next output\n";
  }

  unsigned int vtu_groups(const unsigned int files_per_output, const unsigned int n_ranks)
  {
    // 0 for deal.II means one file per rank, each written by its rank alone; so is any
    // bound the ranks do not exceed (deal.II would otherwise write K = ranks files through
    // MPI-IO: the same pieces, but not the same bytes as the plain write)
    return files_per_output == 0 || files_per_output >= n_ranks ? 0 : files_per_output;
  }

  /// the SI unit of every VTU array (empty: dimensionless)
  static std::map<std::string, std::string> physical_units()
  {
    return {{"packing_fraction", ""},
            {"number_density", "1/m^3"},
            {"mass_density", "kg/m^3"},
            {"velocity", "m/s"},
            {"temperature", "J"},
            {"granular_temperature", "m^2/s^2"},
            {"pressure", "Pa"},
            {"kinetic_energy_density", "J/m^3"},
            {"thermal_energy_density", "J/m^3"},
            {"contact_energy_density", "J/m^3"},
            {"total_energy_density", "J/m^3"}};
  }

  template <int dim, class Description>
  void Output<dim, Description>::write_vtu(const Vector &U, const double time_si, const unsigned int step)
  {
    Fields<dim, Description> fields(units, desc, frame_velocity(time_si));
    DataOut<dim>             data_out;
    data_out.attach_dof_handler(patch.dof_handler());
    U.update_ghost_values();
    data_out.add_data_vector(U, fields);
    dealii::Vector<float> rank(patch.triangulation().n_active_cells());
    const float           me = Utilities::MPI::this_mpi_process(patch.communicator());
    for (const unsigned int i : patch.owned_active_cell_index())
      rank[i] = me;
    data_out.add_data_vector(rank, "mpi_rank");
    // refinement level above Domain/Cells, and whether the cell's reconstruction box is
    // all leaves of its level (1) or used virtual cells next to a level change (0)
    dealii::Vector<float> level(rank.size()), uniform(rank.size());
    for (unsigned int s = 0; s < patch.n_owned(); ++s)
      {
        const unsigned int i = patch.owned_active_cell_index()[s];
        level[i]             = patch.level(s);
        uniform[i]           = patch.uniform(s) ? 1.f : 0.f;
      }
    data_out.add_data_vector(level, "refinement_level");
    data_out.add_data_vector(uniform, "uniform_stencil");
    data_out.build_patches();
    // plain array names (ParaView's Calculator takes them unquoted); the SI units travel
    // beside them as VTK metadata
    DataOutBase::VtkFlags flags(time_si, step);
    flags.physical_units = physical_units();
    data_out.set_flags(flags);
    const std::string name = data_out.write_vtu_with_pvtu_record(
      settings.directory + "/", settings.base_name, counter, patch.communicator(), 4,
      vtu_groups(settings.vtu_files, Utilities::MPI::n_mpi_processes(patch.communicator())));
    if (Utilities::MPI::this_mpi_process(patch.communicator()) == 0)
      {
        pvd_records.emplace_back(time_si, name);
        std::ofstream pvd(settings.file(".pvd"));
        DataOutBase::write_pvd_record(pvd, pvd_records);
        check_written(pvd, settings.file(".pvd"));
      }
  }

  template <int dim, class Description>
  void Output<dim, Description>::write_profiles(const Vector &U, const double time_si)
  {
    const unsigned int pd = settings.profile_direction < 0 ? dim - 1 : settings.profile_direction;
    // layers of the finest lattice; a cell adds to each layer it spans with the weight
    // of its volume there (on a uniform mesh: one layer, weight 1)
    const unsigned int  nl   = patch.cells(pd) << patch.max_level();
    constexpr unsigned  NC   = dim + 2;
    const unsigned int  ncol = NC + 5; // conserved, phi, T, kinetic, thermal, contact energy
    std::vector<double> sum(std::size_t(nl) * ncol, 0.), count(nl, 0.);
    for (unsigned int s = 0; s < patch.n_owned(); ++s)
      {
        physics::State<dim> S;
        for (unsigned int c = 0; c < NC; ++c)
          S[c] = U.local_element(std::size_t(s) * NC + c);
        const unsigned int span = patch.fine_span(s);
        const double       w    = std::pow(double(span), dim - 1);
        const double       T    = desc.temperature(S);
        // the parts of nE (container frame; the layer sums are moved to the lab frame below)
        const double ke = desc.kinetic_energy(S), th = desc.heat_capacity() * S[0] * T,
                     nw = contact_energy_density<dim>(desc, S[0]);
        for (unsigned int l = patch.fine_begin(s, pd); l < patch.fine_begin(s, pd) + span; ++l)
          {
            for (unsigned int c = 0; c < NC; ++c)
              sum[l * ncol + c] += w * S[c];
            sum[l * ncol + NC] += physics::packing_fraction(w * S[0]);
            sum[l * ncol + NC + 1] += w * T;
            sum[l * ncol + NC + 2] += w * ke;
            sum[l * ncol + NC + 3] += w * th;
            sum[l * ncol + NC + 4] += w * nw;
            count[l] += w;
          }
      }
    Utilities::MPI::sum(sum, patch.communicator(), sum);
    Utilities::MPI::sum(count, patch.communicator(), count);
    if (Utilities::MPI::this_mpi_process(patch.communicator()) != 0)
      return;
    const std::string fname = settings.file("_profiles.csv");
    std::ofstream     out(fname, profiles_started ? std::ios::app : std::ios::trunc);
    const char       *ax = "xyz";
    if (!profiles_started)
      {
        // the VTU fields' names (units: doc/user-guide.md, "Profiles and cross-sections")
        out << "time," << ax[pd] << ",number_density";
        for (unsigned int d = 0; d < dim; ++d)
          out << ",number_flux_" << ax[d];
        out << ",total_energy_density,packing_fraction,temperature,granular_temperature,"
               "kinetic_energy_density,thermal_energy_density,contact_energy_density\n";
        profiles_started = true;
      }
    const double          nu = units.number_density();
    std::array<double, 3> v  = frame_velocity(time_si); // scaled units
    for (double &vd : v)
      vd /= units.velocity;
    // the energy densities with all digits, so that the parts add up to the total in the
    // file too (to round-off, not to the 10 digits of the other columns)
    const auto energy = [&](const double e) {
      out << ',' << std::setprecision(std::numeric_limits<double>::max_digits10) << e * units.pressure()
          << std::setprecision(10);
    };
    out << std::setprecision(10);
    for (unsigned int l = 0; l < nl; ++l)
      {
        const double *a = &sum[l * ncol];
        const double  k = count[l];
        if (k == 0) // a layer of solid lattice points (mesh file)
          continue;
        out << time_si << ',' << patch.lower(pd) + (l + 0.5) * patch.cell_size(pd) / (1u << patch.max_level())
            << ',' << a[0] / k * nu;
        for (unsigned int d = 0; d < dim; ++d)
          out << ',' << a[1 + d] / k * nu * units.velocity + a[0] / k * nu * frame_velocity(time_si)[d];
        const double lab = lab_frame_energy<dim>(a[0], &a[1], v);
        energy((a[NC - 1] + lab) / k);
        out << ',' << a[NC] / k << ',' << a[NC + 1] / k * units.energy() << ','
            << granular_temperature(units, a[NC + 1] / k);
        energy((a[NC + 2] + lab) / k);
        energy(a[NC + 3] / k);
        energy(a[NC + 4] / k);
        out << '\n';
      }
    check_written(out, fname);
  }

  template <int dim, class Description>
  void Output<dim, Description>::write_cross_section(const Vector &U, const double time_si)
  {
    if constexpr (dim == 3)
      {
        const unsigned int sd = settings.section_direction, a = (sd + 1) % 3, b = (sd + 2) % 3;
        const unsigned int ia = std::min(a, b), ib = std::max(a, b);
        const unsigned int ml = patch.max_level();
        const unsigned int na = patch.cells(ia) << ml, nb = patch.cells(ib) << ml;
        // n, n u (3), phi, T, count, nE, kinetic, thermal, contact energy (container frame)
        constexpr unsigned int ncol = 11;
        std::vector<double>    sum(std::size_t(na) * nb * ncol, 0.);
        const auto             fv = frame_velocity(time_si);
        for (unsigned int s = 0; s < patch.n_owned(); ++s)
          {
            physics::State<3> S;
            for (unsigned int c = 0; c < 5; ++c)
              S[c] = U.local_element(std::size_t(s) * 5 + c);
            const unsigned int span = patch.fine_span(s);
            const double       T = desc.temperature(S), w = span;
            const double       ke = desc.kinetic_energy(S), th = desc.heat_capacity() * S[0] * T,
                         nw = contact_energy_density<3>(desc, S[0]);
            for (unsigned int j = 0; j < span; ++j)
              for (unsigned int i = 0; i < span; ++i)
                {
                  double *v = &sum[(std::size_t(patch.fine_begin(s, ia) + i) +
                                    std::size_t(na) * (patch.fine_begin(s, ib) + j)) *
                                   ncol];
                  v[0] += w * S[0];
                  for (unsigned int d = 0; d < 3; ++d)
                    v[1 + d] += w * S[1 + d];
                  v[4] += physics::packing_fraction(w * S[0]);
                  v[5] += w * T;
                  v[6] += w;
                  v[7] += w * S[4];
                  v[8] += w * ke;
                  v[9] += w * th;
                  v[10] += w * nw;
                }
          }
        Utilities::MPI::sum(sum, patch.communicator(), sum);
        if (Utilities::MPI::this_mpi_process(patch.communicator()) != 0)
          return;
        std::ofstream out(settings.file("_cross_section.csv"),
                          section_started ? std::ios::app : std::ios::trunc);
        const char   *ax = "xyz";
        if (!section_started)
          {
            // the VTU fields' names (units: doc/user-guide.md, "Profiles and cross-sections")
            out << "time," << ax[ia] << ',' << ax[ib] << ",number_density,velocity_x,velocity_y,velocity_z,"
                << "packing_fraction,temperature,granular_temperature,total_energy_density,"
                << "kinetic_energy_density,thermal_energy_density,contact_energy_density\n";
            section_started = true;
          }
        std::array<double, 3> vs = fv; // scaled units
        for (double &vd : vs)
          vd /= units.velocity;
        const auto energy = [&](const double e) { // all digits, as in profiles.csv
          out << ',' << std::setprecision(std::numeric_limits<double>::max_digits10) << e * units.pressure()
              << std::setprecision(10);
        };
        out << std::setprecision(10);
        for (unsigned int j = 0; j < nb; ++j)
          for (unsigned int i = 0; i < na; ++i)
            {
              const double *v = &sum[(std::size_t(i) + std::size_t(na) * j) * ncol];
              const double  k = v[6], n = v[0] / k;
              if (k == 0) // only solid lattice points (mesh file)
                continue;
              out << time_si << ',' << patch.lower(ia) + (i + 0.5) * patch.cell_size(ia) / (1u << ml) << ','
                  << patch.lower(ib) + (j + 0.5) * patch.cell_size(ib) / (1u << ml) << ','
                  << n * units.number_density();
              for (unsigned int d = 0; d < 3; ++d)
                out << ',' << v[1 + d] / k / n * units.velocity + fv[d];
              out << ',' << v[4] / k << ',' << v[5] / k * units.energy() << ','
                  << granular_temperature(units, v[5] / k);
              const double lab = lab_frame_energy<3>(v[0], &v[1], vs);
              energy((v[7] + lab) / k);
              energy((v[8] + lab) / k);
              energy(v[9] / k);
              energy(v[10] / k);
              out << '\n';
            }
        check_written(out, settings.file("_cross_section.csv"));
      }
    else
      {
        (void)U;
        (void)time_si;
      }
  }

#define GRANHYDRO_INSTANTIATE(d, D) template class Output<d, D>;
  GRANHYDRO_FOR_EACH_MODEL(GRANHYDRO_INSTANTIATE)
#undef GRANHYDRO_INSTANTIATE
} // namespace granhydro::io
