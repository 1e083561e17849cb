// benchmarks/core_speeds.cc: how fast each core of this machine is, for a latency-bound
// loop (a chain of dependent multiply-adds in registers) and a throughput-bound one (a
// streaming triad over 720 KB, within a core's L2). Run on each core by core_speeds.sh.
// On a virtual machine the two can differ between cores: a host thread sharing a
// physical core with one virtual CPU takes load/store throughput from it, not latency.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

// argument: the share of the latency-bound loop to run (default 1; the throughput-bound
// loop always runs whole; strong_scaling_pairs.sh's GATE=1 probe runs 0.25)
int main(int argc, char **argv)
{
  const double share = argc > 1 ? std::atof(argv[1]) : 1.;
  if (!(share > 0 && share <= 1))
    {
      std::fprintf(stderr, "core_speeds: the argument (share of the latency-bound loop) must lie in (0, 1]\n");
      return 1;
    }
  using clock = std::chrono::steady_clock;
  auto t0     = clock::now();
  double a = 1.0, b = 1e-9;
  for (long i = 0; i < long(share * 1000000000L); ++i)
    a = a * 0.9999999 + b;
  const double latency = std::chrono::duration<double>(clock::now() - t0).count();

  const std::size_t   n = 30000;
  std::vector<double> x(n, 1.), y(n, 2.), z(n, 0.);
  t0 = clock::now();
  for (int r = 0; r < 30000; ++r)
    for (std::size_t i = 0; i < n; ++i)
      z[i] = x[i] + 0.5 * y[i] + z[i] * 1e-9;
  const double stream = std::chrono::duration<double>(clock::now() - t0).count();
  // the results are printed so that the loops are not optimised away
  std::printf("latency-bound %.3f s  throughput-bound %.3f s  (%g %g)\n", latency, stream, a, z[n / 2]);
}
