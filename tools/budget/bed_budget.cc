// granhydro_bed_budget: the stress and temperature budget of the lowest layers of a
// vibrated bed through take-off, from a run's profiles (<base>_profiles.csv, profile
// direction along gravity, outputs dense in time). For every output time in [--from, --to]:
//   - the floor: the literal viscous normal stress on the wall face, (gamma + 4 eta/3) 2 v/dy
//     (v the lowest layer's velocity relative to the floor; > 0 moving away: a suction),
//     the pressure of the layer p = n T Z + p_f (what a cohesionless wall may at most
//     take back, doc/physics.md 4.7), and the weight per area of the bed above it,
//     sum m n |g_eff| dy (container frame: g_eff = -g + A w^2 sin(w t));
//   - the granular temperature of the lowest layer: viscous production
//     (gamma + 4 eta/3)(dv/dy)^2, pressure work -n T Z dv/dy (the contact pressure's work goes
//     to the contact potential, not to T), conduction -dq/dy and the cooling -(3/2) n T zeta0
//     (with e_eff for frictional grains), in W/m^3.
// The coefficients are the solver's own (physics/garzo_dufty.h, physics/contact_pressure.h).
//   granhydro_bed_budget PROFILES.csv [--from t0] [--to t1] [--eps 0.9] [--friction 0]
//       [--diameter 1e-3] [--density 2600] [--phi-min 0.62] [--coefficient 0.05]
//       [--amplitude 0.004] [--frequency 12] [--gravity 9.81]
#include <granhydro/physics/contact_pressure.h>
#include <granhydro/physics/garzo_dufty.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace granhydro::physics;

int main(int argc, char **argv)
{
  if (argc < 2 || std::string(argv[1]) == "--help")
    {
      std::cout << "usage: granhydro_bed_budget PROFILES.csv [--from t0] [--to t1] [--eps e] [--friction mu]\n"
                   "       [--diameter d] [--density rho_s] [--phi-min p] [--coefficient F] [--amplitude A]\n"
                   "       [--frequency f] [--gravity g]   (SI; defaults: the bouncing bed scene)\n";
      return argc < 2 ? 2 : 0;
    }
  std::map<std::string, double> o{{"from", 0},         {"to", 1e30},       {"eps", 0.9},      {"friction", 0},
                                  {"diameter", 1e-3},  {"density", 2600},  {"phi-min", 0.62}, {"coefficient", 0.05},
                                  {"amplitude", 0.004}, {"frequency", 12}, {"gravity", 9.81}};
  for (int i = 2; i + 1 < argc; i += 2)
    {
      const std::string k = std::string(argv[i]).substr(2);
      if (std::string(argv[i]).rfind("--", 0) != 0 || !o.count(k))
        {
          std::cerr << "granhydro_bed_budget: unknown option " << argv[i] << "\n";
          return 2;
        }
      o[k] = std::stod(argv[i + 1]);
    }
  std::ifstream in(argv[1]);
  if (!in)
    {
      std::cerr << "granhydro_bed_budget: cannot read " << argv[1] << "\n";
      return 2;
    }
  std::string line;
  std::getline(in, line);
  std::vector<std::string> head;
  {
    std::stringstream ss(line);
    std::string       c;
    while (std::getline(ss, c, ','))
      head.push_back(c);
  }
  // a column by its name, or by the name older runs gave it (the unit in the name)
  auto col = [&](const std::string &name, const std::string &old_name) {
    for (std::size_t i = 0; i < head.size(); ++i)
      if (head[i] == name || head[i] == old_name)
        return int(i);
    return -1;
  };
  const int ct = col("time", "time_s"), cy = col("y", "y_m"), cn = col("number_density", "n_1/m3"),
            cv = col("number_flux_y", "n*u_y_1/(m2 s)"), cT = col("temperature", "temperature_J");
  if (ct < 0 || cy < 0 || cn < 0 || cv < 0 || cT < 0)
    {
      std::cerr << "granhydro_bed_budget: " << argv[1]
                << " lacks time, y, number_density, number_flux_y or temperature\n";
      return 2;
    }
  const double sigma = o["diameter"], m = o["density"] * M_PI * sigma * sigma * sigma / 6;
  GarzoDufty1999 gd(o["eps"]);
  if (o["friction"] > 0)
    gd.set_friction(o["friction"]);
  // the contact pressure in the closure's scaled units (sigma = 1, m = 1, velocity 1 m/s)
  const double          p_unit = m / (sigma * sigma * sigma);
  const ContactPressure contact(o["coefficient"] / p_unit, o["phi-min"], 0.64, 2, 5, 1e-3, FrictionalStress{});
  const double          w = 2 * M_PI * o["frequency"], A = o["amplitude"], g = o["gravity"];
  std::printf("# t[s] phase | v0_rel[m/s] v_cm_rel[m/s] phi0 T0[J] | wall: tau_nn(literal)[Pa] p0[Pa] weight[Pa] | "
              "p_max[Pa] at y[mm] | layer 0 [W/m^3]: production pressure_work conduction cooling\n");
  std::map<double, std::vector<std::array<double, 4>>> rows; // t -> (y, n, v_lab, T)
  while (std::getline(in, line))
    {
      std::vector<double> v;
      std::stringstream   ss(line);
      std::string         c;
      while (std::getline(ss, c, ','))
        v.push_back(std::stod(c));
      if (v[ct] >= o["from"] - 1e-12 && v[ct] <= o["to"] + 1e-12)
        rows[v[ct]].push_back({v[cy], v[cn], v[cv] / v[cn], v[cT]});
    }
  for (const auto &[t, L] : rows)
    {
      if (L.size() < 3)
        continue;
      const double dy = L[1][0] - L[0][0], frame = A * w * std::cos(w * t), g_eff = -g + A * w * w * std::sin(w * t);
      auto         coef = [&](const std::array<double, 4> &s) { return gd.transport(s[1], std::max(s[3], 0.), m, sigma); };
      auto         pressure = [&](const std::array<double, 4> &s, const bool with_contact) {
        return s[1] * std::max(s[3], 0.) * gd.Z(s[1] * M_PI * sigma * sigma * sigma / 6) +
               (with_contact ? contact.pressure(s[1] * sigma * sigma * sigma) * p_unit : 0.);
      };
      const auto   c0 = coef(L[0]);
      const double v0 = L[0][2] - frame, v1 = L[1][2] - frame;
      const double tau_wall = (c0.gamma + 4. / 3. * c0.eta) * 2 * v0 / dy;
      double       weight = 0, mass = 0, momentum = 0, p_max = 0, y_max = 0;
      for (const auto &s : L)
        {
          weight += m * s[1] * std::abs(g_eff) * dy;
          mass += s[1];
          momentum += s[1] * (s[2] - frame);
          if (const double p = pressure(s, true); p > p_max)
            {
              p_max = p;
              y_max = s[0];
            }
        }
      // the lowest layer: dv/dy from the wall (v = 0) to the layer above, centred
      const double dvdy = (0.5 * (v0 + v1) - 0) / dy;
      const double prod = (c0.gamma + 4. / 3. * c0.eta) * dvdy * dvdy;
      const double work = -pressure(L[0], false) * dvdy;
      // heat flux through the upper face of layer 0 (the wall face is adiabatic by the mirror)
      const std::array<double, 4> f{0.5 * (L[0][0] + L[1][0]), 0.5 * (L[0][1] + L[1][1]), 0, 0.5 * (L[0][3] + L[1][3])};
      const auto   cf   = coef(f);
      const double q    = -cf.kappa * (L[1][3] - L[0][3]) / dy - cf.mu * (L[1][1] - L[0][1]) / dy;
      const double cond = -q / dy;
      const double cool = -1.5 * L[0][1] * std::max(L[0][3], 0.) * gd.zeta0(L[0][1], std::max(L[0][3], 0.), m, sigma);
      std::printf("%.5f %.3f | %+.4f %+.4f %.3f %.2e | %+.3e %.3e %.3e | %.3e %.1f | %+.3e %+.3e %+.3e %+.3e\n", t,
                  std::fmod(t * o["frequency"], 1.), v0, momentum / mass, L[0][1] * M_PI * sigma * sigma * sigma / 6,
                  L[0][3], tau_wall, pressure(L[0], true), weight, p_max, y_max * 1e3, prod, work, cond, cool);
    }
  return 0;
}
