/**
 * @file refinement_indicator.cc
 * refinement_flags() (mesh/adaptivity.h): the indicator, the buffer and the coarsening
 * test of an adaptive mesh.
 */
#include <granhydro/mesh/adaptivity.h>
#include <granhydro/physics/packing_fraction.h>

#include <deal.II/lac/la_parallel_vector.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace granhydro::mesh
{
  template <int dim>
  std::vector<signed char> refinement_flags(const CartesianPatch<dim> &P, const std::vector<double> &n,
                                            const std::vector<double>         &p,
                                            const RefinementIndicatorSettings &settings, const bool initial)
  {
    constexpr unsigned int NC      = dim + 2; // the state's components: the partitioner's block
    const unsigned int     n_owned = P.n_owned();
    auto                   jump    = [](const double a, const double b) {
      const double lo = std::min(a, b);
      return lo > 0 ? std::abs(a - b) / lo : std::numeric_limits<double>::infinity();
    };
    // Loehner's indicator: the second difference over the first differences along each
    // direction (gradient neighbours: same level or coarser), in [0, 1], ~1 at
    // discontinuities and kinks, ~h |a''| / |a'| in smooth regions
    auto loehner = [&](const std::vector<double> &a, const unsigned int s, const unsigned int d) {
      const int m = P.gradient_neighbor(s, d, 0), q = P.gradient_neighbor(s, d, 1);
      if (m < 0 || q < 0)
        return 0.;
      // the neighbours' values at the distance h_s (linear along the line of centres)
      const double h = P.cell_size(s, d), dm = -P.gradient_offset(s, d, 0), dq = P.gradient_offset(s, d, 1);
      const double sm = (a[s] - a[m]) * h / dm, sq = (a[q] - a[s]) * h / dq;
      const double den =
        std::abs(sq) + std::abs(sm) + 0.05 * (std::abs(a[q]) + 2 * std::abs(a[s]) + std::abs(a[m]));
      return den > 0 ? std::abs(sq - sm) / den : 0.;
    };
    dealii::LinearAlgebra::distributed::Vector<double> mark(P.partitioner()); // component 0: 1 = refine
    std::vector<double>                                eta(n_owned, 0.);
    for (unsigned int s = 0; s < n_owned; ++s)
      {
        for (unsigned int d = 0; d < dim; ++d)
          if (settings.indicator == RefinementIndicator::second_differences)
            eta[s] = std::max({eta[s], loehner(n, s, d), loehner(p, s, d)});
          else if (settings.indicator == RefinementIndicator::packing_fraction) // phi linear in n: its jump
            {
              const auto [b, e] = P.cell_faces(d, s);
              for (auto cf = b; cf != e; ++cf)
                eta[s] = std::max(eta[s], physics::packing_fraction(std::abs(n[s] - n[P.across(d, *cf)])));
            }
          else
            {
              const auto [b, e] = P.cell_faces(d, s);
              for (auto cf = b; cf != e; ++cf)
                {
                  const unsigned int t = P.across(d, *cf);
                  eta[s]               = std::max({eta[s], jump(n[s], n[t]), jump(p[s], p[t])});
                }
            }
        mark.local_element(std::size_t(s) * NC) = eta[s] > settings.refine_threshold ? 1. : 0.;
      }
    // buffer: the refine mark spreads over face neighbours, one layer per pass
    for (unsigned int pass = 0; pass < settings.buffer; ++pass)
      {
        mark.update_ghost_values();
        std::vector<char> next(n_owned, 0);
        for (unsigned int s = 0; s < n_owned; ++s)
          for (unsigned int d = 0; d < dim && !next[s]; ++d)
            {
              const auto [b, e] = P.cell_faces(d, s);
              for (auto cf = b; cf != e; ++cf)
                if (const unsigned int t = P.across(d, *cf);
                    P.is_cell(t) && mark.local_element(std::size_t(t) * NC) > 0)
                  next[s] = 1;
            }
        mark.zero_out_ghost_values();
        for (unsigned int s = 0; s < n_owned; ++s)
          if (next[s])
            mark.local_element(std::size_t(s) * NC) = 1.;
      }
    std::vector<signed char> flags(n_owned, 0);
    for (unsigned int s = 0; s < n_owned; ++s)
      if (mark.local_element(std::size_t(s) * NC) > 0)
        flags[s] = 1;
      else if (!initial && eta[s] < settings.coarsen_threshold)
        flags[s] = -1;
    return flags;
  }

  template std::vector<signed char> refinement_flags<1>(const CartesianPatch<1> &,
                                                        const std::vector<double> &,
                                                        const std::vector<double> &,
                                                        const RefinementIndicatorSettings &, const bool);
  template std::vector<signed char> refinement_flags<2>(const CartesianPatch<2> &,
                                                        const std::vector<double> &,
                                                        const std::vector<double> &,
                                                        const RefinementIndicatorSettings &, const bool);
  template std::vector<signed char> refinement_flags<3>(const CartesianPatch<3> &,
                                                        const std::vector<double> &,
                                                        const std::vector<double> &,
                                                        const RefinementIndicatorSettings &, const bool);
} // namespace granhydro::mesh
