#pragma once
/**
 * @file initial_state.h
 * The initial state of a run from the scene's expressions (Initial state/Packing
 * fraction, Velocity, Temperature, in SI with x, y, z in m and the scene's constants),
 * and the cell averages of a state function over the owned cells of a patch.
 */
#include <granhydro/base/units.h>
#include <granhydro/mesh/cartesian_patch.h>
#include <granhydro/physics/euler_flux.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/base/mpi.h>
#include <deal.II/lac/la_parallel_vector.h>

#include <functional>
#include <map>
#include <string>

namespace granhydro::driver
{
  /// what the initial state reads of the scene
  struct InitialStateSettings
  {
    std::string                   packing_fraction, temperature;      ///< expressions
    std::string                   velocity;                           ///< components separated by ';'
    std::map<std::string, double> constants;                          ///< the expressions' named constants
    double                        grain_mass = 1, grain_diameter = 1; ///< [kg], [m]
    unsigned int                  quadrature = 2; ///< Gauss points per direction of the cell averages
    std::string                   source;         ///< the scene file, for messages
  };

  /// the state function of the scene's expressions for the model Description
  template <int dim, class Description>
  class InitialState
  {
  public:
    using State = physics::State<dim>;

    InitialState(const InitialStateSettings &settings, const Description &desc, const Units &units);

    /// the conservative state in SI with a *number* momentum n u [1/(m^2 s)] at x [m];
    /// a packing fraction or temperature <= 0 is remembered for check()
    State operator()(const dealii::Point<dim> &x);

    /// throws SceneError naming the parameter if a packing fraction or a temperature
    /// evaluated so far (on any rank) was not positive (collective)
    void check(const MPI_Comm comm) const;

  private:
    const InitialStateSettings &settings;
    const Description          &desc;
    const Units                &units;
    dealii::FunctionParser<dim> phi, T, vel;
    bool                        bad_phi = false, bad_T = false;
  };

  /// the cell averages of f (SI, number momentum: InitialState) over the owned cells of
  /// the patch by Gauss quadrature with nq points per direction, scaled, into U
  template <int dim>
  void set_cell_averages(const mesh::CartesianPatch<dim>                                      &patch,
                         const std::function<physics::State<dim>(const dealii::Point<dim> &)> &f,
                         const unsigned int nq, const Units &units,
                         dealii::LinearAlgebra::distributed::Vector<double> &U);
} // namespace granhydro::driver
