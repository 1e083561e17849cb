/**
 * @file lattice_distribute.cc
 * Lattice::distribute(): the leaves near the owned ones, from a directory of the mesh
 * distributed over the ranks by level-0 block (the directory, the blocks within reach,
 * the answers, the leaves and their ancestors, the dense window of levels).
 */
#include <deal.II/base/mpi.h>

#include "lattice.h"

#include <algorithm>

namespace granhydro::mesh
{
  using namespace dealii;

  namespace
  {
    /// all-to-all of long long records of `width` entries, bucketed by destination rank
    std::vector<long long> alltoall_records(const std::vector<std::vector<long long>> &out,
                                            const MPI_Comm                             comm)
    {
      const int        P = out.size();
      std::vector<int> scount(P), rcount(P), sdisp(P), rdisp(P);
      for (int r = 0; r < P; ++r)
        {
          AssertThrow(out[r].size() < (1ull << 31), ExcMessage("all-to-all message above 2^31 entries"));
          scount[r] = out[r].size();
        }
      MPI_Alltoall(scount.data(), 1, MPI_INT, rcount.data(), 1, MPI_INT, comm);
      long long ns = 0, nr = 0;
      for (int r = 0; r < P; ++r)
        {
          sdisp[r] = ns;
          rdisp[r] = nr;
          ns += scount[r];
          nr += rcount[r];
        }
      AssertThrow(ns < (1ll << 31) && nr < (1ll << 31), ExcMessage("all-to-all above 2^31 entries"));
      std::vector<long long> send(ns), recv(nr);
      for (int r = 0; r < P; ++r)
        std::copy(out[r].begin(), out[r].end(), send.begin() + sdisp[r]);
      MPI_Alltoallv(send.data(), scount.data(), sdisp.data(), MPI_LONG_LONG, recv.data(), rcount.data(),
                    rdisp.data(), MPI_LONG_LONG, comm);
      return recv;
    }
  } // namespace

  template <int dim>
  int Lattice<dim>::directory_rank(const long long b, const int P) const
  {
    const long long nblocks = (long long)(cells_[0]) * cells_[1] * cells_[2];
    return int((__int128)(b)*P / nblocks);
  }

  template <int dim>
  void Lattice<dim>::distribute(const std::vector<OwnedCell> &owned, const unsigned long long n_global,
                                const MPI_Comm comm)
  {
    std::vector<long long>              dir      = directory(owned, n_global, comm);
    std::vector<std::vector<long long>> requests = blocks_within_reach(owned, comm);
    const std::vector<long long>        got      = fetch_records(dir, requests, comm);
    insert_leaves(got);
    fill_window(got);
  }

  template <int dim>
  std::vector<long long> Lattice<dim>::directory(const std::vector<OwnedCell> &owned,
                                                 const unsigned long long n_global, const MPI_Comm comm) const
  {
    const int       P       = Utilities::MPI::n_mpi_processes(comm);
    const long long nblocks = (long long)(cells_[0]) * cells_[1] * cells_[2];
    auto            home    = [&](const long long b) { return directory_rank(b, P); };
    // 1. the leaves to the directory: (block, key, first DoF, faces)
    std::vector<std::vector<long long>> out(P);
    for (const auto &o : owned)
      {
        const long long b = block_of(o.key >> 3);
        auto           &v = out[home(b)];
        v.insert(v.end(), {b, o.key, (long long)(o.first), o.faces});
      }
    std::vector<long long> dir = alltoall_records(out, comm);
    // the directory's records sorted by (block, key)
    const std::size_t        nrec = dir.size() / 4;
    std::vector<std::size_t> order(nrec);
    for (std::size_t i = 0; i < nrec; ++i)
      order[i] = i;
    std::sort(order.begin(), order.end(), [&](const std::size_t a, const std::size_t b) {
      return dir[4 * a] != dir[4 * b] ? dir[4 * a] < dir[4 * b] : dir[4 * a + 1] < dir[4 * b + 1];
    });
    {
      std::vector<long long> sorted(dir.size());
      for (std::size_t i = 0; i < nrec; ++i)
        std::copy(dir.begin() + 4 * order[i], dir.begin() + 4 * order[i] + 4, sorted.begin() + 4 * i);
      dir.swap(sorted);
      std::vector<std::size_t>().swap(order);
    }
    // checks: the leaves of a block tile it (a box) or are one level-0 cell (a mesh file)
    {
      const long long full          = 1ll << (max_level_ * dim);
      long long       n_blocks_seen = 0;
      for (std::size_t i = 0; i < nrec;)
        {
          std::size_t j   = i;
          long long   vol = 0;
          for (; j < nrec && dir[4 * j] == dir[4 * i]; ++j)
            {
              AssertThrow(j == i || dir[4 * j + 1] != dir[4 * j - 3],
                          ExcMessage("two cells on one lattice point"));
              vol += 1ll << ((max_level_ - (dir[4 * j + 1] & 7)) * dim);
            }
          AssertThrow(vol == full, ExcMessage(subset_ ? "mesh is not the expected lattice" :
                                                        "mesh is not the expected octree"));
          ++n_blocks_seen;
          i = j;
        }
      const unsigned long long n_leaves = Utilities::MPI::sum((unsigned long long)(nrec), comm);
      AssertThrow(n_leaves == n_global, ExcMessage(subset_ ? "mesh is not the expected lattice" :
                                                             "mesh is not the expected octree"));
      if (!subset_)
        AssertThrow(Utilities::MPI::sum((unsigned long long)(n_blocks_seen), comm) ==
                      (unsigned long long)(nblocks),
                    ExcMessage("mesh is not the expected octree"));
    }
    return dir;
  }

  template <int dim>
  std::vector<std::vector<long long>> Lattice<dim>::blocks_within_reach(const std::vector<OwnedCell> &owned,
                                                                        const MPI_Comm                comm)
  {
    const int P    = Utilities::MPI::n_mpi_processes(comm);
    auto      home = [&](const long long b) { return directory_rank(b, P); };
    // 2. the blocks within reach of the owned leaves: a sparse separable dilation, each
    // block carrying the largest radius (blocks) of its leaves
    FlatKeyMap<int> radius;
    const int       R = reach();
    for (const auto &o : owned)
      {
        const int r = (R + (1 << o.level) - 1) >> o.level;
        int      &e = radius[block_of(o.key >> 3)];
        e           = std::max(e, r);
      }
    for (unsigned int d = 0; d < dim; ++d)
      {
        FlatKeyMap<int> grown;
        grown.reserve(radius.size() * 2);
        radius.for_each([&](const long long b, const int r) {
          Position c{{b % cells_[0], (b / cells_[0]) % cells_[1], b / ((long long)(cells_[0]) * cells_[1])}};
          const long long c0 = c[d];
          for (int o = -r; o <= r; ++o)
            {
              long long x = c0 + o;
              if (periodic[d])
                x = ((x % cells_[d]) + cells_[d]) % cells_[d];
              else if (x < 0 || x >= cells_[d])
                continue;
              c[d]   = x;
              int &e = grown[c[0] + (long long)(cells_[0]) * (c[1] + (long long)(cells_[1]) * c[2])];
              e      = std::max(e, r);
            }
        });
        std::swap(radius, grown);
      }
    std::vector<std::vector<long long>> requests(P);
    blocks.clear();
    blocks.reserve(radius.size());
    radius.for_each([&](const long long b, const int) {
      requests[home(b)].push_back(b);
      blocks.insert(b, 1);
    });
    radius.clear();
    return requests;
  }

  template <int dim>
  std::vector<long long> Lattice<dim>::fetch_records(std::vector<long long>              &dir,
                                                     std::vector<std::vector<long long>> &requests,
                                                     const MPI_Comm                       comm) const
  {
    const int         P    = Utilities::MPI::n_mpi_processes(comm);
    const std::size_t nrec = dir.size() / 4;
    // 3. the directory answers: the records of the blocks asked for, to each asker
    std::vector<int> rcount(P), scount(P);
    for (int r = 0; r < P; ++r)
      scount[r] = requests[r].size();
    MPI_Alltoall(scount.data(), 1, MPI_INT, rcount.data(), 1, MPI_INT, comm);
    const std::vector<long long> asked = alltoall_records(requests, comm);
    std::vector<std::vector<long long>>().swap(requests);
    std::vector<std::vector<long long>> answer(P);
    std::size_t                         a = 0;
    for (int r = 0; r < P; ++r)
      for (int i = 0; i < rcount[r]; ++i, ++a)
        {
          const long long b = asked[a];
          // records of block b: binary search in the sorted directory
          std::size_t lo = 0, hi = nrec;
          while (lo < hi)
            {
              const std::size_t mid = (lo + hi) / 2;
              if (dir[4 * mid] < b)
                lo = mid + 1;
              else
                hi = mid;
            }
          for (std::size_t j = lo; j < nrec && dir[4 * j] == b; ++j)
            answer[r].insert(answer[r].end(), {dir[4 * j + 1], dir[4 * j + 2], dir[4 * j + 3]});
        }
    std::vector<long long>().swap(dir);
    const std::vector<long long> got = alltoall_records(answer, comm);
    std::vector<std::vector<long long>>().swap(answer);
    return got;
  }

  template <int dim>
  void Lattice<dim>::insert_leaves(const std::vector<long long> &got)
  {
    leaves.clear();
    leaves.reserve(got.size() / 3 + got.size() / 18);
    for (std::size_t i = 0; i < got.size(); i += 3)
      leaves[got[i]] = {got[i + 1], int(got[i + 2])};
    // the refined positions above the leaves (first DoF -1): a position of level k is
    // then a leaf, refined, or (absent) covered by a coarser leaf, in one lookup
    for (std::size_t i = 0; i < got.size(); i += 3)
      {
        const long long fk = got[i] >> 3;
        const Position  c  = fine_position(fk);
        for (int a = int(got[i] & 7) - 1; a >= 0; --a)
          {
            Position an = c;
            for (unsigned int d = 0; d < dim; ++d)
              an[d] = (c[d] >> (max_level_ - a)) << (max_level_ - a);
            const auto [e, inserted] = leaves.insert(fine_key(an) * 8 + a, Leaf{-1, 0});
            AssertThrow(e->first < 0, ExcMessage("mesh is not the expected octree"));
            if (!inserted) // its ancestors are in already
              break;
          }
      }
  }

  template <int dim>
  void Lattice<dim>::fill_window(const std::vector<long long> &got)
  {
    // a dense window of levels over the bounding box of the fetched blocks, when it is
    // small against the leaves (one rank, compact partitions, few levels): lookups then
    // touch one byte; its size stays a fixed multiple of the local leaves
    window_level.clear();
    {
      Position blo{{0, 0, 0}}, bhi{{0, 0, 0}};
      bool     first = true;
      blocks.for_each([&](const long long b, const char) {
        const Position c{
          {b % cells_[0], (b / cells_[0]) % cells_[1], b / ((long long)(cells_[0]) * cells_[1])}};
        for (unsigned int d = 0; d < 3; ++d)
          {
            blo[d] = first ? c[d] : std::min(blo[d], c[d]);
            bhi[d] = first ? c[d] : std::max(bhi[d], c[d]);
          }
        first = false;
      });
      long long vol = first ? 0 : 1;
      for (unsigned int d = 0; d < 3; ++d)
        {
          window_lo[d] = blo[d] << (d < dim ? max_level_ : 0);
          window_n[d]  = (bhi[d] - blo[d] + 1) << (d < dim ? max_level_ : 0);
          vol *= window_n[d];
        }
      if (vol > 0 && vol <= 8 * (long long)(leaves.size()) + 4096)
        {
          window_level.assign(vol, -2);
          const long long span0 = 1ll << max_level_;
          blocks.for_each([&](const long long b, const char) {
            const Position c{
              {b % cells_[0], (b / cells_[0]) % cells_[1], b / ((long long)(cells_[0]) * cells_[1])}};
            for (long long z = 0; z < (dim > 2 ? span0 : 1); ++z)
              for (long long y = 0; y < (dim > 1 ? span0 : 1); ++y)
                for (long long x = 0; x < span0; ++x)
                  window_level[window_index(
                    {{(c[0] << max_level_) + x, dim > 1 ? (c[1] << max_level_) + y : 0,
                      dim > 2 ? (c[2] << max_level_) + z : 0}})] = -1;
          });
          for (std::size_t i = 0; i < got.size(); i += 3)
            {
              const long long    fk   = got[i] >> 3;
              const unsigned int k    = got[i] & 7;
              const long long    span = 1ll << (max_level_ - k);
              const Position     c    = fine_position(fk);
              for (long long z = 0; z < (dim > 2 ? span : 1); ++z)
                for (long long y = 0; y < (dim > 1 ? span : 1); ++y)
                  for (long long x = 0; x < span; ++x)
                    window_level[window_index({{c[0] + x, c[1] + y, c[2] + z}})] = k;
            }
        }
    }
  }

  template class Lattice<1>;
  template class Lattice<2>;
  template class Lattice<3>;
} // namespace granhydro::mesh
