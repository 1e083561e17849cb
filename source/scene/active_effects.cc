#include <granhydro/physics/garzo_dufty.h>
#include <granhydro/scene/scene.h>

#include <cmath>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace granhydro::scene
{
  std::vector<std::pair<std::string, std::string>> active_effects(const Scene &s)
  {
    std::vector<std::pair<std::string, std::string>> e;
    auto                                             num = [](double v) {
      std::ostringstream os;
      os << v;
      return os.str();
    };
    if (s.convection)
      e.emplace_back("convection", "Effects/Convection = true");
    if (s.max_level > 0)
      e.emplace_back("adaptive mesh refinement", "Adaptivity/Maximum level = " + std::to_string(s.max_level) +
                                                   ", every " + std::to_string(s.adapt_interval) + " steps");
    if (s.model != physics::Model::granular)
      return e;
    if (s.viscosity)
      e.emplace_back("viscous stress", "granular model, Effects/Viscosity = true");
    if (s.heat_conduction)
      e.emplace_back("heat conduction", "granular model, Effects/Heat conduction = true");
    if (s.cooling && s.restitution < 1 && s.friction == 0)
      e.emplace_back("inelastic cooling", "restitution " + num(s.restitution) + " < 1");
    if (s.cooling && s.friction > 0)
      e.emplace_back("inelastic cooling, frictional grains",
                     "restitution " + num(s.restitution) +
                       ", Material/Friction coefficient = " + num(s.friction) + ": effective restitution " +
                       num(physics::GarzoDufty1999::effective_restitution(s.restitution, s.friction)) +
                       " in the cooling rate");
    if (s.dense_closure != DenseClosure::none)
      e.emplace_back("dense closure: contact pressure" +
                       std::string(s.closure_time > 0 && s.viscosity ? " and frictional viscosity" : ""),
                     "Dense closure/Model = " + to_string(s.dense_closure) + ", F = " + num(s.closure_F) +
                       " Pa, phi_min = " + num(s.closure_phi_min));
    double g2 = 0;
    for (unsigned int d = 0; d < s.dimension; ++d)
      g2 += s.gravity[d] * s.gravity[d];
    if (g2 > 0)
      e.emplace_back(s.well_balanced_gravity ? "gravity, well-balanced in the convective step" : "gravity",
                     "|g| = " + num(std::sqrt(g2)) + " m/s^2" +
                       (s.well_balanced_gravity ? ", Numerics/Gravity scheme = well-balanced" : ""));
    if (s.vibration_amplitude > 0 && s.vibration_frequency > 0)
      {
        const double w = 2 * M_PI * s.vibration_frequency;
        e.emplace_back("wall vibration (inertial body force)",
                       "A = " + num(s.vibration_amplitude) + " m, f = " + num(s.vibration_frequency) +
                         " Hz, A w^2 = " + num(s.vibration_amplitude * w * w) + " m/s^2");
      }
    const char *sides[6] = {"x-", "x+", "y-", "y+", "z-", "z+"};
    for (unsigned int i = 0; i < 2 * s.dimension; ++i)
      if (s.wall_restitution[i] < 1)
        e.emplace_back(std::string("dissipative wall ") + sides[i],
                       "wall restitution " + num(s.wall_restitution[i]) + " < 1");
    return e;
  }

  bool Scene::diffusion_active() const
  {
    if (model != physics::Model::granular)
      return false;
    bool g = false;
    for (unsigned int d = 0; d < dimension; ++d)
      g = g || gravity[d] != 0 || wall_restitution[2 * d] < 1 || wall_restitution[2 * d + 1] < 1;
    g = g || (vibration_amplitude > 0 && vibration_frequency > 0);
    return viscosity || heat_conduction || (cooling && (restitution < 1 || friction > 0)) || g;
  }
} // namespace granhydro::scene
