#pragma once
/**
 * @file slot_exchange.h
 * Sends per-slot values of owned cells to the ranks that hold those cells as
 * MPI ghosts, for a subset of the ghosts chosen per channel.
 *
 * The state vector's partitioner already knows, per neighbouring rank, which
 * owned cells are its ghosts (import targets and indices) and which ghosts
 * come from it (ghost targets), both in the ghosts' order. A SlotExchange
 * narrows that to the ghosts each receiver actually reads on each channel
 * (one bit per channel and ghost, agreed once per mesh in setup()) and moves
 * m doubles per slot of any slot-indexed array. The convective operator uses
 * it to receive the reconstruction stages of halo cells from their owners
 * instead of recomputing them on every rank that holds them: the owner's
 * values are the same formula on the same inputs, so results stay bitwise
 * those of one rank.
 */
#include <deal.II/base/mpi.h>
#include <deal.II/base/partitioner.h>

#include <cstdint>
#include <vector>

namespace granhydro::mesh
{
  class SlotExchange
  {
  public:
    /// at most this many channels (bits of a need mask)
    static constexpr unsigned int max_channels = 16;

    SlotExchange()                                = default;
    SlotExchange(const SlotExchange &)            = delete;
    SlotExchange &operator=(const SlotExchange &) = delete;
    ~SlotExchange();

    /**
     * Collective. part: the state vector's partitioner (NC entries per cell, owned cells
     * = slots [0, n_owned) and ghosts = slots n_owned + g in the partitioner's order);
     * need[g]: bit k set if ghost g is read on channel k. Replaces an earlier setup.
     */
    void setup(const dealii::Utilities::MPI::Partitioner &part, const unsigned int NC,
               const unsigned int n_owned, const std::vector<std::uint16_t> &need);

    /// Collective. Channel k: the owners' values array[s m, (s + 1) m) of owned slots s
    /// overwrite those of the ghosts that need them. Same as start() then finish()
    void exchange(const unsigned int k, double *array, const unsigned int m) const;
    /// post channel k's messages (the sent values are copied here: the owned slots may
    /// change afterwards); several channels may be in flight, each finished once
    void start(const unsigned int k, const double *array, const unsigned int m) const;
    /// wait for channel k's messages to this rank and write the received ghosts into
    /// array. This rank's own sends complete later (at the next start(k)): waiting for them
    /// here would wait until the receivers reach their finish(), a barrier per channel
    void finish(const unsigned int k, double *array, const unsigned int m) const;
    /// set mark[s] = 1 for the owned slots s this rank sends on channel k
    void mark_sent(const unsigned int k, std::vector<char> &mark) const;

  private:
    struct Peer
    {
      unsigned int              rank;
      std::vector<unsigned int> slots[max_channels];
    };
    std::vector<Peer> send_, recv_;
    MPI_Comm          comm_ = MPI_COMM_NULL;
    /// per channel: buffers per peer, and the requests in flight
    mutable std::vector<std::vector<double>> sbuf_[max_channels], rbuf_[max_channels];
    mutable std::vector<MPI_Request>         recv_req_[max_channels], send_req_[max_channels];
    /// complete the sends of channel k (their buffers are reused by the next start(k))
    void wait_sends(const unsigned int k) const;
  };
} // namespace granhydro::mesh
