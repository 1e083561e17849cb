// The sedimentation scene resolved as a 1D column
// (parameters/sedimentation_column_1d.prm) and in 3D (parameters/sedimentation-ci.prm,
// horizontally periodic) agree in their horizontal averages. The 3D state stays
// horizontally uniform, so transverse fluxes cancel exactly and the 3D run performs
// the 1D arithmetic; only the larger linear systems of the implicit step (GMRES
// iterates, Newton stopping at 1e-13) differ, hence agreement to ~1e-12, asserted
// at 1e-8 relative. Both runs use the same fixed time step (the 3D CFL rate sums
// over directions and would otherwise choose a different dt) and the same
// vertical resolution (50 cells), and the same integrator (Gauss-Legendre: the
// default cost-based choice depends on the explicit diffusive limit, whose rate also
// sums over the directions), and the same output times (the merged Strang splitting
// synchronises its convective halves there).
//   test_column_1d3d <parameters directory>
#include "common/test_common.h"

#include <fstream>
#include <iomanip>

using namespace granhydro;
using namespace granhydro::testing;

namespace
{
  /// what both scenes of parameters/ are run with (-p overrides)
  const std::vector<std::string> overrides = {"Numerics/Fixed time step=5e-4",
                                              "Numerics/CFL number=0.9",
                                              "Diffusion step/Integrator=gauss-legendre",
                                              "Diffusion step/Newton tolerance=1e-13",
                                              "Time/End time=0.02",
                                              "Output/Interval=0.005",
                                              "Output/Write VTU=false",
                                              "Output/Write profiles=false",
                                              "Output/Write checkpoint=false",
                                              "Output/Verbose=false"};

  /// layer averages of (n, n u_vertical, nE) [SI]
  template <int dim>
  std::vector<std::array<double, 3>> layers(const scene::Scene &scene, const unsigned int vertical,
                                            unsigned int &steps)
  {
    driver::Simulation<dim, physics::GranularGas<dim>> sim(scene, MPI_COMM_SELF, std::cout);
    sim.setup();
    steps                                = sim.run().steps;
    const unsigned int                 N = scene.cells[vertical];
    std::vector<std::array<double, 3>> avg(N, {{0, 0, 0}});
    std::vector<unsigned int>          count(N, 0);
    for (unsigned int c = 0; c < sim.patch().n_owned(); ++c)
      {
        const auto         S = sim.state_si(c);
        const unsigned int l = sim.patch().lattice(c)[vertical];
        avg[l][0] += S[0];
        avg[l][1] += S[1 + vertical];
        avg[l][2] += S[dim + 1];
        ++count[l];
      }
    for (unsigned int l = 0; l < N; ++l)
      for (auto &v : avg[l])
        v /= count[l];
    return avg;
  }
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Checker                                  chk;
  const std::string                        dir    = argc > 1 ? argv[1] : "parameters";
  std::vector<std::string>                 column = overrides;
  column.push_back("Domain/Cells=50");
  const scene::Scene s1 = scene::read_scene(dir + "/sedimentation_column_1d.prm", column);
  const scene::Scene s3 = scene::read_scene(dir + "/sedimentation-ci.prm", overrides);
  unsigned int       n1, n3;
  const auto         a1       = layers<1>(s1, 0, n1);
  const auto         a3       = layers<3>(s3, 1, n3);
  double             worst[3] = {0, 0, 0}, scale[3] = {0, 0, 0};
  for (unsigned int l = 0; l < a1.size(); ++l)
    for (unsigned int k = 0; k < 3; ++k)
      {
        worst[k] = std::max(worst[k], std::abs(a1[l][k] - a3[l][k]));
        scale[k] = std::max(scale[k], std::abs(a1[l][k]));
      }
  std::ostringstream os;
  os << "1D column vs 3D sedimentation-ci after " << n1 << "/" << n3
     << " steps (t = 0.02 s): max relative difference of layer averages n " << std::scientific
     << std::setprecision(2) << worst[0] / scale[0] << ", n u_y " << worst[1] / scale[1] << ", nE "
     << worst[2] / scale[2];
  chk.check(n1 == n3 && worst[0] <= 1e-8 * scale[0] && worst[1] <= 1e-8 * scale[1] &&
              worst[2] <= 1e-8 * scale[2],
            os.str());
  return chk.failed != 0;
}
