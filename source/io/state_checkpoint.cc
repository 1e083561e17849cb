#include <granhydro/io/output.h>
#include <granhydro/io/state_checkpoint.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace granhydro::io
{
  namespace
  {
    /// runs f on this rank; a CheckpointError on any rank is thrown on every rank
    template <class F>
    void on_every_rank(const MPI_Comm comm, const F &f)
    {
      std::string error;
      try
        {
          f();
        }
      catch (const CheckpointError &e)
        {
          error = e.what();
        }
      error = first_error(error, comm);
      if (!error.empty())
        throw CheckpointError(error);
    }
  } // namespace

  void write_state_checkpoint(const std::string &file, CheckpointHeader h,
                              const std::vector<std::int64_t> &keys, const double *state,
                              const double *history_state, const MPI_Comm comm)
  {
    const unsigned int NC           = h.n_components;
    const std::size_t  n            = keys.size();
    const bool         with_history = h.history.matrix_valid;
    const unsigned int NV           = with_history ? 2 * NC : NC; // values per row
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](const std::size_t a, const std::size_t b) { return keys[a] < keys[b]; });
    std::vector<std::int64_t> sorted_keys(n);
    std::vector<double>       values(n * NV);
    for (std::size_t i = 0; i < n; ++i)
      {
        const std::size_t s = order[i];
        sorted_keys[i]      = keys[s];
        std::copy(state + s * NC, state + (s + 1) * NC, &values[i * NV]);
        if (with_history)
          std::copy(history_state + s * NC, history_state + (s + 1) * NC, &values[i * NV + NC]);
      }
    h.n_values = NV;
    try
      {
        write_checkpoint_file(file, h, sorted_keys, values, comm);
      }
    catch (const CheckpointError &e) // the same message on every rank
      {
        throw OutputError(e.what());
      }
  }

  bool same_units(const CheckpointHeader &h, const Units &units)
  {
    return h.length == units.length && h.mass == units.mass && h.velocity == units.velocity;
  }

  std::size_t read_state_checkpoint(const CheckpointReader &r, const std::vector<std::int64_t> &keys,
                                    const Units &units, double *state, double *history_state,
                                    const MPI_Comm comm)
  {
    const CheckpointHeader &h  = r.header();
    const unsigned int      NC = h.n_components;
    // values are in the writer's scaled units: convert only if ours differ (restart with the
    // same material is then bitwise exact)
    const bool   same = same_units(h, units);
    const double sn   = std::pow(units.length / h.length, 3); // n' = n L'^3 / L^3
    const double sm   = sn * units.velocity / h.velocity;
    const double se   = (h.mass * h.velocity * h.velocity / std::pow(h.length, 3)) / units.pressure();
    // this rank's keys sorted, with their slots
    std::vector<std::pair<std::int64_t, unsigned int>> slot_of(keys.size());
    for (unsigned int s = 0; s < keys.size(); ++s)
      slot_of[s] = {keys[s], s};
    std::sort(slot_of.begin(), slot_of.end());
    std::vector<char> seen(keys.size(), 0);
    std::size_t       found = 0;
    on_every_rank(comm, [&] {
      if (slot_of.empty())
        return;
      const std::int64_t lo = slot_of.front().first, hi = slot_of.back().first;
      for (std::size_t p = 0; p < r.parts().size(); ++p)
        {
          const auto &t = r.parts()[p];
          if (t.n_rows == 0 || t.last_key < lo || t.first_key > hi)
            continue;
          r.read_part(p, [&](const std::int64_t key, const double *v) {
            const auto it = std::lower_bound(slot_of.begin(), slot_of.end(), std::make_pair(key, 0u));
            if (it == slot_of.end() || it->first != key)
              return;
            const unsigned int s = it->second;
            if (seen[s])
              throw CheckpointError("is corrupted: cell key " + std::to_string(key) + " is in two parts");
            seen[s] = 1;
            ++found;
            for (unsigned int c = 0; c < NC; ++c)
              {
                const double f = same ? 1. : (c == 0 ? sn : (c == NC - 1 ? se : sm));
                state[std::size_t(s) * NC + c] = v[c] * f;
                if (history_state)
                  history_state[std::size_t(s) * NC + c] = v[NC + c];
              }
          });
        }
    });
    return found;
  }

  std::vector<long long> checkpoint_keys(const CheckpointReader &r, const MPI_Comm comm)
  {
    std::vector<long long> keys;
    on_every_rank(comm, [&] {
      keys.reserve(r.header().n_cells);
      r.read_merged([&](const std::int64_t key, const double *) { keys.push_back(key); });
    });
    return keys;
  }

  void verify_checkpoint(const CheckpointReader &r, const MPI_Comm comm)
  {
    int me = 0, n_ranks = 1;
    MPI_Comm_rank(comm, &me);
    MPI_Comm_size(comm, &n_ranks);
    on_every_rank(comm, [&] {
      for (std::size_t p = me; p < r.parts().size(); p += n_ranks)
        r.read_part(p, [](const std::int64_t, const double *) {});
    });
  }
} // namespace granhydro::io
