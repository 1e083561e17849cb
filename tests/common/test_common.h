#pragma once
// Helpers shared by the verification tests: scene text in units where SI and
// the code's scaled units coincide (sigma = 1 m, m = 1 kg, V0 = 1 m/s), so
// that n = rho and the ideal-gas Euler equations appear literally.
#include <granhydro/driver/simulation.h>
#include <granhydro/scene/scene.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace granhydro::testing
{
  /// the whole text of a file (scene files read by tests)
  inline std::string read_text_file(const std::string &f)
  {
    std::ifstream     in(f);
    std::stringstream ss;
    ss << in.rdbuf();
    if (!in)
      throw std::runtime_error("cannot read " + f);
    return ss.str();
  }
  /// A number as a scene value: 17 significant digits, so that it reads back as the same
  /// double (for overrides built from a test's C++ constants: "Time/End time=" + number(t)).
  inline std::string number(const double x)
  {
    std::ostringstream os;
    os.precision(17);
    os << x;
    return os.str();
  }

  /// the overrides that switch every output off (VTU, profiles, checkpoint, summary, log),
  /// for a scene file of parameters/ run by a test
  inline const std::vector<std::string> no_output = {"Output/Write VTU=false", "Output/Write profiles=false",
                                                     "Output/Write checkpoint=false",
                                                     "Output/Write summary=false", "Output/Verbose=false"};

#ifdef GRANHYDRO_TEST_DIR
  /// The path of a test's scene file, a .prm beside the test's source: the folder is
  /// GRANHYDRO_TEST_DIR, defined by granhydro_add_test(... SCENES) (tests/granhydro_add_test.cmake).
  inline std::string test_scene_file(const std::string &name)
  {
    return std::string(GRANHYDRO_TEST_DIR) + "/" + name;
  }

  /// A test's scene: the base scene file `name` beside the test with the case's
  /// modifications, each an override in the form of the command line's -p,
  /// "Section/Name=value" (applied by read_scene(), as granhydro applies -p).
  inline scene::Scene test_scene(const std::string &name, const std::vector<std::string> &overrides = {})
  {
    return scene::read_scene(test_scene_file(name), overrides);
  }
#endif

  /// A number that a scene sets as a plain constant expression (e.g. 'Initial state/
  /// Temperature = 1e-8'), for a test's exact formula; throws if it is not a plain number.
  inline double constant_expression(const std::string &expression)
  {
    std::size_t  used = 0;
    const double x    = std::stod(expression, &used);
    if (expression.find_first_not_of(" \t", used) != std::string::npos)
      throw std::runtime_error("expected a plain number, got the expression '" + expression + "'");
    return x;
  }

  /// a scene file as a test runs it: read as granhydro reads it, with every output (VTU,
  /// profiles, checkpoint, summary, log) switched off by overrides
  inline scene::Scene read_scene_quietly(const std::string &file)
  {
    return scene::read_scene(file, no_output);
  }

  /// A case of the ideal gas in a box (tests/data/ideal_gas_box.prm): what it changes of
  /// that scene. make_scene() reads the file with these values as overrides.
  struct SceneSpec
  {
    unsigned int                dim = 1;
    std::array<unsigned int, 3> cells{{100, 1, 1}};
    std::array<double, 3>       lower{{0, 0, 0}}, upper{{1, 1, 1}};
    std::array<std::string, 6>  boundary{
      {"outflow", "outflow", "periodic", "periodic", "periodic", "periodic"}};
    double       gamma          = 5. / 3.;
    double       end_time       = 0.1;
    double       fixed_dt       = 0;
    double       cfl            = 0.4;
    std::string  reconstruction = "weno5", quadrature = "gauss", flux = "musta";
    unsigned int max_steps = 0;
  };

  /// the overrides ("Section/Name=value", as the command line's -p) that make
  /// tests/data/ideal_gas_box.prm the case s (every value of s, numbers to 17 digits)
  inline std::vector<std::string> scene_overrides(const SceneSpec &s)
  {
    const char *sides[6] = {"x-", "x+", "y-", "y+", "z-", "z+"};
    auto        list     = [&](const auto &a) {
      std::string l;
      for (unsigned int d = 0; d < s.dim; ++d)
        {
          std::ostringstream v;
          v.precision(17);
          v << a[d];
          l += (d ? ", " : "") + v.str();
        }
      return l;
    };
    std::vector<std::string> o = {"Dimension=" + std::to_string(s.dim),
                                  "Domain/Lower corner=" + list(s.lower),
                                  "Domain/Upper corner=" + list(s.upper), "Domain/Cells=" + list(s.cells)};
    for (unsigned int i = 0; i < 2 * s.dim; ++i)
      o.push_back(std::string("Domain/Boundary ") + sides[i] + "=" + s.boundary[i]);
    const std::vector<std::string> rest = {"Material/Adiabatic index=" + number(s.gamma),
                                           std::string("Initial state/Velocity=") +
                                             (s.dim == 1 ? "0" : (s.dim == 2 ? "0; 0" : "0; 0; 0")),
                                           "Numerics/Reconstruction=" + s.reconstruction,
                                           "Numerics/Face quadrature=" + s.quadrature,
                                           "Numerics/Flux=" + s.flux,
                                           "Numerics/CFL number=" + number(s.cfl),
                                           "Numerics/Fixed time step=" + number(s.fixed_dt),
                                           "Time/End time=" + number(s.end_time),
                                           "Time/Maximum steps=" + std::to_string(s.max_steps)};
    o.insert(o.end(), rest.begin(), rest.end());
    return o;
  }

#ifdef GRANHYDRO_TEST_DATA_DIR
  /// the case s of tests/data/ideal_gas_box.prm, with further overrides `more` (applied
  /// after those of s)
  inline scene::Scene make_scene(const SceneSpec &s, const std::vector<std::string> &more = {})
  {
    std::vector<std::string> o = scene_overrides(s);
    o.insert(o.end(), more.begin(), more.end());
    return scene::read_scene(std::string(GRANHYDRO_TEST_DATA_DIR) + "/ideal_gas_box.prm", o);
  }
#endif

  /// primitive (rho, u vector, p) -> conservative state for the ideal gas
  template <int dim>
  physics::State<dim> conservative(double rho, const double *u, double p, double gamma)
  {
    physics::State<dim> U;
    U[0]      = rho;
    double ke = 0;
    for (int d = 0; d < dim; ++d)
      {
        U[1 + d] = rho * u[d];
        ke += 0.5 * rho * u[d] * u[d];
      }
    U[dim + 1] = ke + p / (gamma - 1);
    return U;
  }

  /// failure counter with messages; main returns failures() != 0
  struct Checker
  {
    int  failed = 0;
    bool root   = true;
    void check(bool ok, const std::string &what)
    {
      if (!ok)
        ++failed;
      if (root)
        (ok ? std::cout : std::cerr) << (ok ? "  ok    " : "  FAIL  ") << what << std::endl;
    }
  };

  /// Every cell's SI state gathered on rank 0 of comm, keyed by its octree leaf key
  /// (the key names the same cell whatever the partition, so runs on different rank
  /// counts compare cell by cell); empty on the other ranks.
  template <int dim, class Description>
  std::map<long long, physics::State<dim>> gather_state(const driver::Simulation<dim, Description> &sim,
                                                        const MPI_Comm                              comm)
  {
    std::vector<double> mine;
    for (unsigned int c = 0; c < sim.patch().n_owned(); ++c)
      {
        mine.push_back(double(sim.patch().leaf_key(c)));
        const auto S = sim.state_si(c);
        mine.insert(mine.end(), S.begin(), S.end());
      }
    const auto                               all = dealii::Utilities::MPI::gather(comm, mine, 0);
    std::map<long long, physics::State<dim>> out;
    for (const auto &v : all)
      for (std::size_t i = 0; i < v.size(); i += dim + 3)
        {
          physics::State<dim> S;
          std::copy(v.begin() + i + 1, v.begin() + i + dim + 3, S.begin());
          out[static_cast<long long>(v[i])] = S;
        }
    return out;
  }

  /// Two gathered states compared cell by cell: whether they hold the same cells, and
  /// the largest relative difference of a component (relative to the component, with a
  /// floor of 1e-3 of the density so that near-zero momenta do not divide by zero).
  template <int dim>
  std::pair<bool, double> compare_states(const std::map<long long, physics::State<dim>> &a,
                                         const std::map<long long, physics::State<dim>> &b)
  {
    double diff = 0;
    bool   same = a.size() == b.size();
    for (const auto &[key, S] : b)
      {
        const auto it = a.find(key);
        if (it == a.end())
          {
            same = false;
            continue;
          }
        for (unsigned int c = 0; c < dim + 2; ++c)
          diff = std::max(diff, std::abs(it->second[c] - S[c]) / (std::abs(S[c]) + std::abs(S[0]) * 1e-3));
      }
    return {same, diff};
  }
} // namespace granhydro::testing
