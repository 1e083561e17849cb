// unit.frictional_stress: the dense regime's stresses of cohesionless, frictional grains.
//  A. The Srivastava-Sundaresan frictional viscosity (physics/frictional_stress.h) against
//     values computed by hand from the formulas of Srivastava & Sundaresan, Powder
//     Technol. 129, 72 (2003) (an independent Python transcription, friction angle 28.5
//     degrees): mu_f / P_c for six strain rates (simple shear, uniaxial dilation,
//     compression), to 1e-14 relative (double round-off of a few operations and pow);
//     the Coulomb bound tau_xy <= P_c sin(phi) in simple shear (exact at Theta = 0);
//     zero stress in uniaxial dilation at Theta = 0; the Newtonian bound t_f sin(phi) P_c
//     and its flag; the Newtonian law.
//  B. A layer pulled apart (doc/physics.md 4.7): a 1D column between slip walls whose
//     halves move apart (a tear in the middle) and, in a second state, away from both
//     walls (the walls would suck). With cohesionless grains no face of the diffusion
//     operator carries a tensile normal stress above the face's pressure (to 1e-13
//     relative), the bound acts (counted), and the total energy of f is conserved:
//     sum_cells f_E dx + frictional power = 0 to 1e-13 of the energy-flux scale. With the
//     paper's literal stress (Cohesionless = false) the same states do pull (the test is
//     not vacuous). With and without the dense closure's frictional stress.
#include <granhydro/diffusion/diffusion_operator.h>
#include <granhydro/physics/frictional_stress.h>

#include "common/test_common.h"

#include <iomanip>

using namespace granhydro;
using namespace granhydro::testing;

namespace
{
  int hand_values()
  {
    Checker                   chk;
    physics::FrictionalStress fs;
    fs.law     = physics::FrictionalLaw::srivastava_sundaresan;
    fs.sin_phi = std::sin(28.5 * M_PI / 180.);
    fs.t_f     = 1e6; // the bound far away: the law itself
    struct Case
    {
      const char *name;
      double      G[3][3]; // grad_u[j][l] = d u_l / d x_j
      double      theta;   // Theta / d^2
      double      f;       // mu_f / P_c by hand
    };
    const Case cases[] = {
      {"simple shear 10/s, Theta = 0", {{0, 0, 0}, {10, 0, 0}, {0, 0, 0}}, 0.0, 0.04771587602596085},
      {"simple shear 1/s, Theta/d^2 = 0.5", {{0, 0, 0}, {1, 0, 0}, {0, 0, 0}}, 0.5, 0.33740219508213526},
      {"uniaxial dilation 2/s, Theta = 0", {{0, 0, 0}, {0, 2, 0}, {0, 0, 0}}, 0.0, 0.0},
      {"dilation and shear", {{0.3, 0, 0}, {4, 0.5, 0}, {0, 0, 0}}, 0.2, 0.11235717648123146},
      {"compression and shear", {{-0.3, 0.1, 0}, {2, -0.7, 0.2}, {0, 0.4, -0.1}}, 0.05, 0.20645097417387762},
      {"strong compression", {{-50, 0, 0}, {0.1, 0, 0}, {0, 0, 0}}, 0.0, 0.008069987976492879}};
    for (const Case &c : cases)
      {
        double div, SS;
        physics::strain_rate_invariants<3, double>(c.G, div, SS);
        bool               capped = true;
        const double       f      = fs.viscosity(1., div, SS, c.theta, &capped);
        const double       err    = c.f > 0 ? std::abs(f / c.f - 1) : std::abs(f) / fs.sin_phi;
        std::ostringstream os;
        os << "Srivastava-Sundaresan, " << c.name << ": mu_f/P_c = " << std::setprecision(17) << f << " vs "
           << c.f << " by hand (rel. " << std::setprecision(2) << err << ")";
        // uniaxial dilation: the bracket is 0 up to round-off, raised to n - 1 = 0.815
        chk.check(err <= (c.f > 0 ? 1e-14 : 1e-12) && !capped, os.str());
      }
    // Coulomb bound in simple shear: tau_xy = mu_f gamma_dot -> P_c sin(phi) at Theta = 0
    for (const double gdot : {1e-3, 1., 1e3})
      {
        const double G[2][2] = {{0, 0}, {gdot, 0}};
        double       div, SS;
        physics::strain_rate_invariants<2, double>(G, div, SS);
        const double       tau  = fs.viscosity(1., div, SS, 0.) * gdot;
        const double       tau1 = fs.viscosity(1., div, SS, 0.3 * gdot * gdot) * gdot;
        std::ostringstream os;
        os << "simple shear " << gdot << "/s: tau_xy/P_c = " << std::setprecision(17) << tau
           << " (sin phi = " << fs.sin_phi << "), with fluctuations " << tau1;
        chk.check(std::abs(tau / fs.sin_phi - 1) <= 1e-15 && tau1 < tau, os.str());
      }
    // the Newtonian bound: a slow shear is held at t_f sin(phi) P_c, flagged
    {
      physics::FrictionalStress b = fs;
      b.t_f                       = 0.5;
      bool         capped         = false;
      const double f              = b.viscosity(2., 0., 0.5 * 0.01 * 0.01, 0., &capped); // 0.01/s
      chk.check(capped && f == 0.5 * fs.sin_phi * 2.,
                "Srivastava-Sundaresan at 0.01/s: held at t_f sin(phi) P_c");
      b.law = physics::FrictionalLaw::newtonian;
      chk.check(b.viscosity(2., 3., 5., 1.) == 0.5 * fs.sin_phi * 2., "Newtonian law: t_f sin(phi) P_c");
      b.t_f = 0;
      chk.check(b.viscosity(2., 3., 5., 1.) == 0 && !b.active(), "t_f = 0: no frictional stress");
    }
    return chk.failed;
  }

  /// frictional_column.prm (kinetic stress, cohesionless) with the velocity, the
  /// cohesionless bound and, for the dense case, the closure
  scene::Scene column(const std::string &velocity, const bool cohesionless, const bool closure)
  {
    std::vector<std::string> o{"Initial state/Velocity=" + velocity,
                               std::string("Material/Cohesionless=") + (cohesionless ? "true" : "false")};
    if (closure)
      o.insert(o.end(), {"Dense closure/Model=johnson-jackson", "Initial state/Packing fraction=0.56"});
    return test_scene("frictional_column.prm", o);
  }

  int pulled_apart()
  {
    Checker chk;
    using Sim              = driver::Simulation<1, physics::GranularGas<1>>;
    const std::string tear = "2 * tanh((x - 0.01) / 0.002)", suction = "-2 * tanh((x - 0.01) / 0.002)";
    for (const bool closure : {false, true})
      for (const std::string &v : {tear, suction})
        {
          double pull[2] = {0, 0}; // largest (tau_dd - p)/p over the faces: bounded, literal
          for (const bool cohesionless : {true, false})
            {
              const scene::Scene sc = column(v, cohesionless, closure);
              Sim                sim(sc, MPI_COMM_SELF, std::cout);
              sim.setup();
              const auto         &patch = sim.patch();
              const auto         &desc  = sim.description();
              std::vector<double> W;
              patch.gather(sim.state(), W);
              diffusion::DiffusionSettings s;
              s.no_tension = cohesionless;
              diffusion::DiffusionOperator<1> op(patch, desc, s, sim.units().length);
              op.setup();
              std::vector<double> f(std::size_t(patch.n_owned()) * 3);
              op.residual(W.data(), f.data());
              const auto &faces = patch.faces(0);
              const auto &F     = op.last_face_fluxes(0);
              double      worst = -1, flux_scale = 0;
              for (std::size_t k = 0; k < faces.size(); ++k)
                {
                  // the face state of the operator: the mean of the two thermal states
                  physics::State<1> Uf;
                  for (unsigned int c = 0; c < 3; ++c)
                    Uf[c] = 0.5 * (W[faces[k].l * 3 + c] + W[faces[k].r * 3 + c]);
                  Uf[2] -= 0.5 * (desc.contact.energy_density(W[faces[k].l * 3]) +
                                  desc.contact.energy_density(W[faces[k].r * 3]));
                  const double n = Uf[0], T = std::max(desc.temperature(Uf, 0.), 0.);
                  const double p = n * T * desc.model.Z(n * M_PI / 6.) + desc.contact.pressure(n);
                  worst          = std::max(worst, (F[k * 3 + 1] - p) / p);
                  flux_scale     = std::max(flux_scale, std::abs(F[k * 3 + 2]));
                }
              pull[cohesionless ? 0 : 1] = worst;
              double energy              = 0; // d/dt of the total energy: the face fluxes telescope
              for (unsigned int c = 0; c < patch.n_owned(); ++c)
                energy += f[c * 3 + 2] * patch.cell_size(c, 0) / sim.units().length;
              energy += op.friction_power();
              const auto         counts = op.face_counts();
              std::ostringstream os;
              os << (closure ? "dense closure + friction, " : "kinetic stress only, ")
                 << (v == tear ? "tear" : "wall suction")
                 << (cohesionless ? ", cohesionless" : ", literal stress")
                 << ": max (tau_nn - p)/p over faces " << std::scientific << std::setprecision(2) << worst
                 << ", bounded faces " << counts.tension_bounded << " (" << counts.tension_bounded_walls
                 << " at walls), sum f_E dx + frictional power " << energy << " (energy-flux scale "
                 << flux_scale << ")";
              // 1e-13: the scaled stress is p/t * t, exact to a few ulp of p
              if (cohesionless)
                chk.check(worst <= 1e-13 && counts.tension_bounded > 0 &&
                            (v == tear || counts.tension_bounded_walls > 0) &&
                            std::abs(energy) <= 1e-13 * flux_scale,
                          os.str());
              else
                chk.check(std::abs(energy) <= 1e-13 * flux_scale && counts.tension_bounded == 0, os.str());
            }
          chk.check(pull[1] > 1,
                    "... the literal stress pulls: (tau_nn - p)/p up to " + std::to_string(pull[1]));
        }
    return chk.failed;
  }
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  return (hand_values() + pulled_apart()) != 0;
}
