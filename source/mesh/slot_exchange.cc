#include <granhydro/mesh/slot_exchange.h>

#include <deal.II/base/exceptions.h>

#include <algorithm>

namespace granhydro::mesh
{
  using namespace dealii;

  namespace
  {
    constexpr int mask_tag    = 4711;
    constexpr int channel_tag = 4712; // + channel

    /// Copies m doubles per listed slot between a slot array and a packed buffer: gather
    /// (pack = true: buffer block j <- slot sl[j]) or scatter (slot sl[j] <- block j). The
    /// convective stages move 2, 2P or 2P^2 values of NC = dim + 2 components per slot
    /// (P = 2 points per direction): 10, 20, 40 doubles in 3D, 8, 16 in 2D; with m known at
    /// compile time each copy is a few vector moves instead of a call to memmove per slot
    template <unsigned int M, bool pack>
    void move_fixed(const std::vector<unsigned int> &sl, const unsigned int m, const double *from, double *to)
    {
      const unsigned int len = M > 0 ? M : m; // M = 0: the length known only at run time
      for (std::size_t j = 0; j < sl.size(); ++j)
        {
          const double *src = from + (pack ? std::size_t(sl[j]) : j) * len;
          double *const dst = to + (pack ? j : std::size_t(sl[j])) * len;
          for (unsigned int i = 0; i < len; ++i)
            dst[i] = src[i];
        }
    }

    template <bool pack>
    void move_slots(const std::vector<unsigned int> &sl, const unsigned int m, const double *from, double *to)
    {
      switch (m)
        {
          case 8:
            return move_fixed<8, pack>(sl, m, from, to);
          case 10:
            return move_fixed<10, pack>(sl, m, from, to);
          case 16:
            return move_fixed<16, pack>(sl, m, from, to);
          case 20:
            return move_fixed<20, pack>(sl, m, from, to);
          case 40:
            return move_fixed<40, pack>(sl, m, from, to);
          default:
            return move_fixed<0, pack>(sl, m, from, to);
        }
    }
  } // namespace

  SlotExchange::~SlotExchange()
  {
    for (unsigned int k = 0; k < max_channels; ++k)
      wait_sends(k);
    if (comm_ != MPI_COMM_NULL)
      Utilities::MPI::free_communicator(comm_);
  }

  void SlotExchange::setup(const Utilities::MPI::Partitioner &part, const unsigned int NC,
                           const unsigned int n_owned, const std::vector<std::uint16_t> &need)
  {
    AssertThrow(need.size() * NC == part.n_ghost_indices(),
                ExcMessage("SlotExchange: one need mask per ghost cell expected"));
    // a communicator of our own: our tags cannot meet deal.II's messages
    if (comm_ == MPI_COMM_NULL)
      comm_ = Utilities::MPI::duplicate_communicator(part.get_mpi_communicator());
    for (unsigned int k = 0; k < max_channels; ++k)
      {
        AssertThrow(recv_req_[k].empty(), ExcMessage("SlotExchange: setup() with a channel in flight"));
        wait_sends(k);
      }
    send_.clear();
    recv_.clear();

    // receivers: the ghosts of each owner are consecutive, in the partitioner's order
    std::vector<MPI_Request> requests;
    unsigned int             g0 = 0;
    for (const auto &[rank, n_dofs] : part.ghost_targets())
      {
        AssertThrow(n_dofs % NC == 0, ExcMessage("SlotExchange: a ghost cell split between ranks"));
        const unsigned int n = n_dofs / NC;
        Peer               p;
        p.rank = rank;
        for (unsigned int g = g0; g < g0 + n; ++g)
          for (unsigned int k = 0; k < max_channels; ++k)
            if (need[g] >> k & 1u)
              p.slots[k].push_back(n_owned + g);
        recv_.push_back(std::move(p));
        requests.emplace_back();
        const int ierr =
          MPI_Isend(need.data() + g0, int(n), MPI_UINT16_T, int(rank), mask_tag, comm_, &requests.back());
        AssertThrowMPI(ierr);
        g0 += n;
      }

    // senders: the owned cells each rank holds as ghosts, in that rank's ghost order
    std::vector<unsigned int> dofs;
    dofs.reserve(part.n_import_indices());
    for (const auto &[b, e] : part.import_indices())
      for (unsigned int i = b; i < e; ++i)
        dofs.push_back(i);
    std::vector<std::vector<std::uint16_t>> masks(part.import_targets().size());
    std::vector<std::vector<unsigned int>>  cells(part.import_targets().size());
    std::size_t                             pos = 0;
    for (std::size_t t = 0; t < part.import_targets().size(); ++t)
      {
        const auto [rank, n_dofs] = part.import_targets()[t];
        AssertThrow(n_dofs % NC == 0, ExcMessage("SlotExchange: an exported cell split"));
        for (unsigned int j = 0; j < n_dofs; j += NC)
          {
            AssertThrow(dofs[pos + j] % NC == 0 && dofs[pos + j] / NC < n_owned,
                        ExcMessage("SlotExchange: exported entries are not whole cells"));
            cells[t].push_back(dofs[pos + j] / NC);
          }
        pos += n_dofs;
        masks[t].resize(n_dofs / NC);
        requests.emplace_back();
        const int ierr = MPI_Irecv(masks[t].data(), int(masks[t].size()), MPI_UINT16_T, int(rank), mask_tag,
                                   comm_, &requests.back());
        AssertThrowMPI(ierr);
      }
    const int ierr = MPI_Waitall(int(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
    AssertThrowMPI(ierr);
    for (std::size_t t = 0; t < cells.size(); ++t)
      {
        Peer p;
        p.rank = part.import_targets()[t].first;
        for (std::size_t j = 0; j < cells[t].size(); ++j)
          for (unsigned int k = 0; k < max_channels; ++k)
            if (masks[t][j] >> k & 1u)
              p.slots[k].push_back(cells[t][j]);
        send_.push_back(std::move(p));
      }
    for (unsigned int k = 0; k < max_channels; ++k)
      {
        sbuf_[k].resize(send_.size());
        rbuf_[k].resize(recv_.size());
      }
  }

  void SlotExchange::exchange(const unsigned int k, double *array, const unsigned int m) const
  {
    start(k, array, m);
    finish(k, array, m);
  }

  void SlotExchange::start(const unsigned int k, const double *array, const unsigned int m) const
  {
    AssertIndexRange(k, max_channels);
    AssertThrow(recv_req_[k].empty(), ExcMessage("SlotExchange: the channel is still in flight"));
    wait_sends(k);
    for (std::size_t i = 0; i < recv_.size(); ++i)
      if (const auto &sl = recv_[i].slots[k]; !sl.empty())
        {
          rbuf_[k][i].resize(sl.size() * m);
          recv_req_[k].emplace_back();
          const int ierr = MPI_Irecv(rbuf_[k][i].data(), int(rbuf_[k][i].size()), MPI_DOUBLE,
                                     int(recv_[i].rank), channel_tag + int(k), comm_, &recv_req_[k].back());
          AssertThrowMPI(ierr);
        }
    for (std::size_t i = 0; i < send_.size(); ++i)
      if (const auto &sl = send_[i].slots[k]; !sl.empty())
        {
          auto &buf = sbuf_[k][i];
          buf.resize(sl.size() * m);
          move_slots<true>(sl, m, array, buf.data());
          send_req_[k].emplace_back();
          const int ierr = MPI_Isend(buf.data(), int(buf.size()), MPI_DOUBLE, int(send_[i].rank),
                                     channel_tag + int(k), comm_, &send_req_[k].back());
          AssertThrowMPI(ierr);
        }
  }

  void SlotExchange::finish(const unsigned int k, double *array, const unsigned int m) const
  {
    const int ierr = MPI_Waitall(int(recv_req_[k].size()), recv_req_[k].data(), MPI_STATUSES_IGNORE);
    AssertThrowMPI(ierr);
    recv_req_[k].clear();
    for (std::size_t i = 0; i < recv_.size(); ++i)
      if (const auto &sl = recv_[i].slots[k]; !sl.empty())
        move_slots<false>(sl, m, rbuf_[k][i].data(), array);
  }

  void SlotExchange::wait_sends(const unsigned int k) const
  {
    if (send_req_[k].empty())
      return;
    const int ierr = MPI_Waitall(int(send_req_[k].size()), send_req_[k].data(), MPI_STATUSES_IGNORE);
    AssertThrowMPI(ierr);
    send_req_[k].clear();
  }

  void SlotExchange::mark_sent(const unsigned int k, std::vector<char> &mark) const
  {
    for (const auto &p : send_)
      for (const unsigned int s : p.slots[k])
        mark[s] = 1;
  }

} // namespace granhydro::mesh
