#include <granhydro/io/diagnostics.h>
#include <granhydro/physics/energy_parts.h>
#include <granhydro/physics/models.h>
#include <granhydro/physics/packing_fraction.h>

#include <deal.II/base/mpi.h>

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iomanip>
#include <limits>
#include <sstream>
#include <type_traits>
#include <vector>

namespace granhydro::io
{
  using namespace dealii;

  namespace
  {
    /// column sums of rows (n columns) over all ranks, independent of the partition (the
    /// summary's mass_drift was not: the same state on 1 and N ranks gave different
    /// roundings): every value as an integer multiple of 2^-k, k from the column's largest
    /// value (95 bits of headroom below it, so 2^31 cells per rank cannot overflow), summed
    /// exactly in 128-bit integers, across ranks in 32-bit limbs
    void exact_sums(const std::vector<double> &rows, const unsigned int n, const MPI_Comm comm, double *sum)
    {
      __extension__ typedef __int128          i128; // GCC's 128-bit integers
      __extension__ typedef unsigned __int128 u128;
      const std::size_t                       m = n ? rows.size() / n : 0;
      std::vector<double>                     largest(n, 0.);
      for (std::size_t r = 0; r < m; ++r)
        for (unsigned int c = 0; c < n; ++c)
          largest[c] = std::max(largest[c], std::abs(rows[r * n + c]));
      MPI_Allreduce(MPI_IN_PLACE, largest.data(), int(n), MPI_DOUBLE, MPI_MAX, comm);
      std::vector<int>           shift(n, 0);
      std::vector<std::uint64_t> limbs(4 * n, 0);
      std::vector<double>        plain(n, 0.);
      for (unsigned int c = 0; c < n; ++c)
        {
          if (!(std::isfinite(largest[c]) && largest[c] > 0)) // nothing to sum, or not a number
            {
              for (std::size_t r = 0; r < m; ++r)
                plain[c] += rows[r * n + c];
              continue;
            }
          shift[c]   = 94 - std::ilogb(largest[c]);
          i128 local = 0;
          for (std::size_t r = 0; r < m; ++r)
            local += static_cast<i128>(std::ldexp(rows[r * n + c], shift[c]));
          const u128 u = static_cast<u128>(local);
          for (unsigned int l = 0; l < 4; ++l)
            limbs[4 * c + l] = std::uint64_t(u >> (32 * l)) & 0xffffffffu;
        }
      MPI_Allreduce(MPI_IN_PLACE, limbs.data(), int(4 * n), MPI_UINT64_T, MPI_SUM, comm);
      MPI_Allreduce(MPI_IN_PLACE, plain.data(), int(n), MPI_DOUBLE, MPI_SUM, comm);
      for (unsigned int c = 0; c < n; ++c)
        {
          if (!(std::isfinite(largest[c]) && largest[c] > 0))
            {
              sum[c] = plain[c];
              continue;
            }
          u128 u = 0;
          for (unsigned int l = 0; l < 4; ++l)
            u += static_cast<u128>(limbs[4 * c + l]) << (32 * l);
          sum[c] = std::ldexp(double(static_cast<i128>(u)), -shift[c]);
        }
    }
  } // namespace

  template <int dim, class Description>
  StateTotals<dim> state_totals(const mesh::CartesianPatch<dim>                  &patch,
                                const LinearAlgebra::distributed::Vector<double> &V, const Description &desc,
                                const double length, const MPI_Comm comm)
  {
    constexpr unsigned int NC = dim + 2;
    // sums: n, n u (dim), nE, kinetic, thermal, contact, n x (dim)
    constexpr unsigned int NS      = 2 * dim + 5;
    double                 sum[NS] = {};
    std::vector<double>    rows(std::size_t(patch.n_owned()) * NS); // each cell's terms
    // maxima: phi, -T, |u|
    double ext[3] = {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), 0.};
    const double        scale = std::pow(length, dim);
    physics::State<dim> S;
    for (unsigned int s = 0; s < patch.n_owned(); ++s)
      {
        const double *u = V.begin() + std::size_t(s) * NC;
        const double  v = patch.cell_volume(s) / scale;
        for (unsigned int c = 0; c < NC; ++c)
          S[c] = u[c];
        double *row = rows.data() + std::size_t(s) * NS;
        row[0]      = u[0] * v;
        double m2   = 0;
        for (unsigned int d = 0; d < dim; ++d)
          {
            row[1 + d] = u[1 + d] * v;
            m2 += u[1 + d] * u[1 + d];
          }
        row[dim + 1]   = u[dim + 1] * v;
        const double w = physics::contact_energy_density<dim>(desc, u[0]);
        double       T;
        if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
          T = desc.temperature(S, w); // what desc.temperature(S) gives, w evaluated once
        else
          T = desc.temperature(S);
        row[dim + 2] = desc.kinetic_energy(S) * v;
        row[dim + 3] = desc.heat_capacity() * u[0] * T * v;
        row[dim + 4] = w * v;
        const auto x = patch.center(s);
        for (unsigned int d = 0; d < dim; ++d)
          row[dim + 5 + d] = u[0] * x[d] * v;
        ext[0] = std::max(ext[0], physics::packing_fraction(u[0]));
        ext[1] = std::max(ext[1], -T);
        ext[2] = std::max(ext[2], std::sqrt(m2) / u[0]);
      }
    exact_sums(rows, NS, comm, sum);
    MPI_Allreduce(MPI_IN_PLACE, ext, 3, MPI_DOUBLE, MPI_MAX, comm);
    StateTotals<dim> t;
    t.n = sum[0];
    for (unsigned int d = 0; d < dim; ++d)
      {
        t.nu[d] = sum[1 + d];
        t.nx[d] = sum[dim + 5 + d];
      }
    t.energy               = sum[dim + 1];
    t.kinetic              = sum[dim + 2];
    t.thermal              = sum[dim + 3];
    t.contact              = sum[dim + 4];
    t.max_packing_fraction = ext[0];
    t.min_temperature      = -ext[1];
    t.max_speed            = ext[2];
    return t;
  }

  template <int dim>
  std::string overpacking_report(const mesh::CartesianPatch<dim>                  &patch,
                                 const LinearAlgebra::distributed::Vector<double> &V, const double phi_c,
                                 const MPI_Comm comm)
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
    const double       dense_sum = Utilities::MPI::sum(dense, comm), all_sum = Utilities::MPI::sum(all, comm);
    const unsigned int n_dense_sum = Utilities::MPI::sum(n_dense, comm);
    std::ostringstream os;
    os << "the packing fraction reached close packing (phi_c = " << phi_c
       << "): the last admissible state has phi = " << std::setprecision(8) << mm.max << std::setprecision(6)
       << " at x = (";
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
         << (newton_failures ?
               ", or check the diffusion step (Newton failures: " + std::to_string(*newton_failures) +
                 "; 'Material/Maximum mean free path' caps the transport of "
                 "dilute cells)" :
               std::string());
    os << ".";
    return os.str();
  }

  std::string overpacking_message(const double t_si, const std::string &report, const std::string &details)
  {
    return "over-packing at t = " + std::to_string(t_si) + " s: " + report +
           " Kinetic theory gives no pressure to a pile at rest (T -> 0), so a "
           "settling layer reaches phi_c in finite time; switch on 'Dense "
           "closure/Model = johnson-jackson' (doc/user-guide.md, 'Dense closure'). Details: " +
           details;
  }

#define GRANHYDRO_INSTANTIATE(d, D)                                                                         \
  template StateTotals<d> state_totals<d, D>(const mesh::CartesianPatch<d> &,                               \
                                             const LinearAlgebra::distributed::Vector<double> &, const D &, \
                                             const double, const MPI_Comm);
  GRANHYDRO_FOR_EACH_MODEL(GRANHYDRO_INSTANTIATE)
#undef GRANHYDRO_INSTANTIATE

  template std::string overpacking_report<1>(const mesh::CartesianPatch<1> &,
                                             const LinearAlgebra::distributed::Vector<double> &, const double,
                                             const MPI_Comm);
  template std::string overpacking_report<2>(const mesh::CartesianPatch<2> &,
                                             const LinearAlgebra::distributed::Vector<double> &, const double,
                                             const MPI_Comm);
  template std::string overpacking_report<3>(const mesh::CartesianPatch<3> &,
                                             const LinearAlgebra::distributed::Vector<double> &, const double,
                                             const MPI_Comm);
} // namespace granhydro::io
