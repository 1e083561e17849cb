/**
 * @file initial_state.cc
 * InitialState and set_cell_averages() (driver/initial_state.h).
 */
#include <granhydro/base/errors.h>
#include <granhydro/driver/initial_state.h>
#include <granhydro/physics/models.h>
#include <granhydro/physics/packing_fraction.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/utilities.h>

#include <type_traits>

namespace granhydro::driver
{
  using namespace dealii;

  namespace
  {
    const char *variables(const int dim)
    {
      return dim == 1 ? "x" : (dim == 2 ? "x,y" : "x,y,z");
    }
  } // namespace

  template <int dim, class Description>
  InitialState<dim, Description>::InitialState(const InitialStateSettings &settings, const Description &desc,
                                               const Units &units)
    : settings(settings)
    , desc(desc)
    , units(units)
    , phi(1)
    , T(1)
    , vel(dim)
  {
    phi.initialize(variables(dim), settings.packing_fraction, settings.constants);
    T.initialize(variables(dim), settings.temperature, settings.constants);
    auto vexpr = Utilities::split_string_list(settings.velocity, ';');
    vexpr.resize(dim);
    vel.initialize(variables(dim), vexpr, settings.constants);
  }

  template <int dim, class Description>
  typename InitialState<dim, Description>::State
  InitialState<dim, Description>::operator()(const Point<dim> &x)
  {
    const double m = settings.grain_mass, sigma = settings.grain_diameter;
    const double p = phi.value(x), t = T.value(x);
    bad_phi        = bad_phi || !(p > 0);
    bad_T          = bad_T || !(t > 0);
    const double n = physics::number_density_si(p, sigma);
    double       u[3];
    for (unsigned int d = 0; d < dim; ++d)
      u[d] = vel.value(x, d);
    State Us;
    Us[0]     = n;
    double ke = 0;
    for (unsigned int d = 0; d < dim; ++d)
      {
        Us[1 + d] = m * n * u[d];
        ke += 0.5 * m * n * u[d] * u[d];
      }
    Us[dim + 1] = ke + n * t * desc.heat_capacity();
    if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>) // contact potential
      Us[dim + 1] +=
        desc.contact.energy_density(n * units.length * units.length * units.length) * units.pressure();
    // this Us is in SI with a *mass* momentum; convert to number momentum
    for (unsigned int d = 0; d < dim; ++d)
      Us[1 + d] /= m;
    return Us;
  }

  template <int dim, class Description>
  void InitialState<dim, Description>::check(const MPI_Comm comm) const
  {
    if (Utilities::MPI::logical_or(bad_phi, comm))
      throw SceneError("in " + settings.source +
                       ": parameter 'Initial state/Packing fraction' "
                       "must be positive everywhere in the domain");
    if (Utilities::MPI::logical_or(bad_T, comm))
      throw SceneError("in " + settings.source +
                       ": parameter 'Initial state/Temperature' must be "
                       "positive everywhere in the domain");
  }

  template <int dim>
  void set_cell_averages(const mesh::CartesianPatch<dim>                              &patch,
                         const std::function<physics::State<dim>(const Point<dim> &)> &f,
                         const unsigned int nq, const Units &units,
                         LinearAlgebra::distributed::Vector<double> &U)
  {
    // SI -> scaled: n [1/m^3] * L^3; number momentum n u [1/(m^2 s)] * L^3 / V; nE [J/m^3] / p0
    const double nscale = 1. / units.number_density(), mscale = nscale / units.velocity,
                 escale = 1. / units.pressure();
    const QGauss<1> q1(nq);
    for (unsigned int s = 0; s < patch.n_owned(); ++s)
      {
        physics::State<dim> avg;
        avg.fill(0.);
        const auto        &ijk = patch.lattice(s);
        const unsigned int nq2 = dim > 1 ? nq : 1, nq3 = dim > 2 ? nq : 1;
        for (unsigned int a = 0; a < nq; ++a)
          for (unsigned int b = 0; b < nq2; ++b)
            for (unsigned int c = 0; c < nq3; ++c)
              {
                Point<dim>         x;
                const unsigned int id[3] = {a, b, c};
                double             w     = 1;
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    x[d] = patch.lower(d) + (ijk[d] + q1.point(id[d])[0]) * patch.cell_size(s, d);
                    w *= q1.weight(id[d]);
                  }
                const physics::State<dim> v = f(x);
                for (unsigned int k = 0; k < dim + 2; ++k)
                  avg[k] += w * v[k];
              }
        U.local_element(std::size_t(s) * (dim + 2)) = avg[0] * nscale;
        for (unsigned int d = 0; d < dim; ++d)
          U.local_element(std::size_t(s) * (dim + 2) + 1 + d) = avg[1 + d] * mscale;
        U.local_element(std::size_t(s) * (dim + 2) + dim + 1) = avg[dim + 1] * escale;
      }
  }

#define GRANHYDRO_INITIAL_STATE_INSTANCE(d, D) template class InitialState<d, D>;
  GRANHYDRO_FOR_EACH_MODEL(GRANHYDRO_INITIAL_STATE_INSTANCE)
  template void set_cell_averages<1>(const mesh::CartesianPatch<1> &,
                                     const std::function<physics::State<1>(const Point<1> &)> &,
                                     const unsigned int, const Units &,
                                     LinearAlgebra::distributed::Vector<double> &);
  template void set_cell_averages<2>(const mesh::CartesianPatch<2> &,
                                     const std::function<physics::State<2>(const Point<2> &)> &,
                                     const unsigned int, const Units &,
                                     LinearAlgebra::distributed::Vector<double> &);
  template void set_cell_averages<3>(const mesh::CartesianPatch<3> &,
                                     const std::function<physics::State<3>(const Point<3> &)> &,
                                     const unsigned int, const Units &,
                                     LinearAlgebra::distributed::Vector<double> &);
} // namespace granhydro::driver
