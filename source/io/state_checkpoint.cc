#include <granhydro/io/output.h>
#include <granhydro/io/state_checkpoint.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace granhydro::io
{
  using namespace dealii;

  void write_state_checkpoint(const std::string &file, CheckpointHeader h,
                              const std::vector<std::int64_t> &keys, const double *state,
                              const double *history_state, const MPI_Comm comm)
  {
    const unsigned int  NC = h.n_components;
    const unsigned int  n  = keys.size();
    const bool          with_history = h.history.matrix_valid;
    const unsigned int  NV = with_history ? 2 * NC : NC; // values per row
    std::vector<double> mine(std::size_t(n) * (NV + 1));
    for (unsigned int s = 0; s < n; ++s)
      {
        mine[s * (NV + 1)] = double(keys[s]);
        for (unsigned int c = 0; c < NC; ++c)
          mine[s * (NV + 1) + 1 + c] = state[std::size_t(s) * NC + c];
        if (with_history)
          for (unsigned int c = 0; c < NC; ++c)
            mine[s * (NV + 1) + 1 + NC + c] = history_state[std::size_t(s) * NC + c];
      }
    const auto  all = Utilities::MPI::gather(comm, mine, 0);
    std::string error;
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      {
        std::vector<std::pair<double, const double *>> rows;
        for (const auto &part : all)
          for (std::size_t i = 0; i < part.size(); i += NV + 1)
            rows.emplace_back(part[i], &part[i + 1]);
        std::sort(rows.begin(), rows.end(), [](const auto &a, const auto &b) { return a.first < b.first; });
        h.n_values = NV;
        h.n_cells  = rows.size();
        std::vector<std::int64_t> sorted_keys(rows.size());
        std::vector<double>       values(rows.size() * NV);
        for (std::size_t i = 0; i < rows.size(); ++i)
          {
            sorted_keys[i] = std::int64_t(rows[i].first);
            std::copy(rows[i].second, rows[i].second + NV, &values[i * NV]);
          }
        try
          {
            write_checkpoint_file(file, h, sorted_keys, values);
          }
        catch (const CheckpointError &e)
          {
            error = e.what();
          }
      }
    // every rank stops together (a throw on rank 0 alone would leave the others waiting)
    error = Utilities::MPI::broadcast(comm, error, 0);
    if (!error.empty())
      throw OutputError(error);
  }

  bool same_units(const CheckpointHeader &h, const Units &units)
  {
    return h.length == units.length && h.mass == units.mass && h.velocity == units.velocity;
  }

  std::size_t scatter_checkpoint(const CheckpointData &data, const std::vector<std::int64_t> &keys,
                                 const Units &units, double *state, double *history_state)
  {
    const CheckpointHeader &h  = data.header;
    const unsigned int      NC = h.n_components, NV = h.n_values;
    // values are in the writer's scaled units: convert only if ours differ (restart with the
    // same material is then bitwise exact)
    const bool   same = same_units(h, units);
    const double sn   = std::pow(units.length / h.length, 3); // n' = n L'^3 / L^3
    const double sm   = sn * units.velocity / h.velocity;
    const double se   = (h.mass * h.velocity * h.velocity / std::pow(h.length, 3)) / units.pressure();
    std::map<std::int64_t, unsigned int> slot_of;
    for (unsigned int s = 0; s < keys.size(); ++s)
      slot_of[keys[s]] = s;
    std::size_t found = 0;
    for (std::uint64_t i = 0; i < h.n_cells; ++i)
      {
        const auto it = slot_of.find(data.keys[i]);
        if (it == slot_of.end())
          continue;
        ++found;
        for (unsigned int c = 0; c < NC; ++c)
          {
            const double f = same ? 1. : (c == 0 ? sn : (c == NC - 1 ? se : sm));
            state[std::size_t(it->second) * NC + c] = data.values[i * NV + c] * f;
            if (history_state)
              history_state[std::size_t(it->second) * NC + c] = data.values[i * NV + NC + c];
          }
      }
    return found;
  }
} // namespace granhydro::io
