#include <granhydro/io/diagnostics.h>
#include <granhydro/physics/packing_fraction.h>

#include <deal.II/base/mpi.h>

#include <cstdlib>
#include <iomanip>
#include <sstream>

namespace granhydro::io
{
  using namespace dealii;

  template <int dim>
  std::string overpacking_report(const CartesianPatch<dim>                              &patch,
                                 const LinearAlgebra::distributed::Vector<double> &V,
                                 const double phi_c, const MPI_Comm comm)
  {
    constexpr unsigned int NC = dim + 2;
    // local: max phi and its cell; grains in cells with phi >= 0.99 phi_c; all grains
    double       max_phi = 0, dense = 0, all = 0;
    unsigned int where = 0, n_dense = 0;
    for (unsigned int s = 0; s < patch.n_owned(); ++s)
      {
        const double n   = V.local_element(std::size_t(s) * NC);
        const double phi = physics::packing_fraction(n);
        all += n;
        if (phi > max_phi)
          {
            max_phi = phi;
            where   = s;
          }
        if (phi >= 0.99 * phi_c)
          {
            dense += n;
            ++n_dense;
          }
      }
    const auto mm = Utilities::MPI::min_max_avg(max_phi, comm);
    if (mm.max < 0.99 * phi_c)
      return {};
    // the centre of the densest cell, from its owner
    double x[3] = {0, 0, 0};
    if (Utilities::MPI::this_mpi_process(comm) == mm.max_index)
      for (unsigned int d = 0; d < dim; ++d)
        x[d] = patch.center(where)[d];
    Utilities::MPI::sum(ArrayView<const double>(x, 3), comm, ArrayView<double>(x, 3));
    const double dense_sum = Utilities::MPI::sum(dense, comm), all_sum = Utilities::MPI::sum(all, comm);
    const unsigned int n_dense_sum = Utilities::MPI::sum(n_dense, comm);
    std::ostringstream os;
    os << "the packing fraction reached close packing (phi_c = " << phi_c
       << "): the last admissible state has phi = " << std::setprecision(8) << mm.max
       << std::setprecision(6) << " at x = (";
    for (unsigned int d = 0; d < dim; ++d)
      os << (d ? ", " : "") << x[d];
    os << ") m, and " << n_dense_sum << " cell(s) at phi >= " << 0.99 * phi_c << " hold "
       << 100 * dense_sum / all_sum << " % of the grains.";
    return os.str();
  }

  std::string inadmissible_step_message(const unsigned int step, const double t_si,
                                        const unsigned int max_retries, const double dt_si,
                                        const std::string                      &why,
                                        const std::optional<unsigned long long> newton_failures)
  {
    std::ostringstream os;
    os << "step " << step << " at t = " << t_si << " s stays inadmissible (n <= 0, "
       << "T <= 0 or phi >= phi_c) after " << max_retries
       << " retries with halved time step (last dt = " << dt_si << " s)";
    if (!why.empty())
      os << "; first bad " << why;
    // the likely cause where the first bad cell tells it, with the parameter that helps
    const auto   at  = why.find("packing fraction ");
    const double phi = at == std::string::npos ? -1 : std::strtod(why.c_str() + at + 17, nullptr);
    if (why.find("Newton") != std::string::npos && phi >= 0 && phi < 1e-3)
      os << ". Likely cause: a nearly empty granular cell (packing fraction " << phi
         << "), whose mean free path makes the transport coefficients so large that the "
            "implicit step's Newton iteration cannot follow; cap them with 'Material/Maximum "
            "mean free path' (e.g. the grain diameter), or raise the packing fraction there";
    else if (why.find("convective") != std::string::npos && why.find("T = -") != std::string::npos)
      os << ". Likely cause: the kinetic energy swamps the thermal energy in a convective "
            "stage (a fast no-slip wall, 'Domain/Wall velocity', a strong 'Effects/Gravity' "
            "or a cold gas, 'Initial state/Temperature'); lower 'Numerics/CFL number', use "
            "'Numerics/Reconstruction = first order' or raise the temperature";
    else
      os << ". Lower 'Numerics/CFL number' or use a more diffusive reconstruction"
         << (newton_failures ? ", or check the diffusion step (Newton failures: " +
                                 std::to_string(*newton_failures) +
                                 "; 'Material/Maximum mean free path' caps the transport of "
                                 "dilute cells)" :
                               std::string());
    os << ".";
    return os.str();
  }

  std::string overpacking_message(const double t_si, const std::string &report,
                                  const std::string &details)
  {
    return "over-packing at t = " + std::to_string(t_si) + " s: " + report +
           " Kinetic theory gives no pressure to a pile at rest (T -> 0), so a "
           "settling layer reaches phi_c in finite time; switch on 'Dense "
           "closure/Model = johnson-jackson' (doc/user-guide.md, 'Dense closure'). Details: " +
           details;
  }

  template std::string overpacking_report<1>(const CartesianPatch<1> &,
                                             const LinearAlgebra::distributed::Vector<double> &,
                                             const double, const MPI_Comm);
  template std::string overpacking_report<2>(const CartesianPatch<2> &,
                                             const LinearAlgebra::distributed::Vector<double> &,
                                             const double, const MPI_Comm);
  template std::string overpacking_report<3>(const CartesianPatch<3> &,
                                             const LinearAlgebra::distributed::Vector<double> &,
                                             const double, const MPI_Comm);
} // namespace granhydro::io
