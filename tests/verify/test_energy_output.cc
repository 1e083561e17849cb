// The split of the energy density in the output (source/io/output.cc): profiles.csv
// has kinetic, thermal and contact energy density columns that add up to the total
// energy density column, which is the conserved nE (n|u|^2/2 + 3/2 n T + n w(phi)).
// Short 1D runs with profiles and VTU written:
//  - the sedimentation column (parameters/sedimentation_column_1d.prm) with the dense
//    closure to 150 ms: kinetic + thermal + contact == total per row to 1e-12 relative
//    (the definition; the energy columns carry all 17 digits), the contact energy is
//    most of the total at the floor, and the last block's total equals the state's nE;
//  - the same column with the closure off (50 ms): contact column exactly 0;
//  - the column in a vibrated container (closure off): the kinetic and total energy
//    densities are in the lab frame like the velocities, kinetic = m (n u)^2 / (2 n)
//    from the lab-frame flux column of the same row (1D: one cell per layer);
//  - the ideal gas (parameters/sod_1d.prm): contact 0, thermal = total - kinetic; a
//    convection-only run, whose summary counts one SSP-RK3 step per time step
//    (convective_steps, also without splitting).
// The VTU files carry the four energy fields and granular_temperature; profiles.csv has the
// VTU fields' names (identifier-safe, units in doc/user-guide.md), and its
// granular_temperature column is temperature / m (m the grain mass).
//   test_energy_output <parameters directory>
#include "common/test_common.h"

#include <cctype>
#include <filesystem>
#include <iomanip>
#include <map>
#include <vector>

using namespace granhydro;
using namespace granhydro::testing;

namespace
{
  const std::string energy_names[4] = {"kinetic_energy_density", "thermal_energy_density",
                                       "contact_energy_density", "total_energy_density"};

  /// the header of a 1D run's profiles.csv along x: the VTU fields' names
  const std::vector<std::string> profile_columns_1d = {"time",
                                                       "x",
                                                       "number_density",
                                                       "number_flux_x",
                                                       "total_energy_density",
                                                       "packing_fraction",
                                                       "temperature",
                                                       "granular_temperature",
                                                       "kinetic_energy_density",
                                                       "thermal_energy_density",
                                                       "contact_energy_density"};

  struct Csv
  {
    std::string                         file;
    std::map<std::string, unsigned int> column;
    std::vector<std::string>            names; ///< the header, in the file's order
    std::vector<std::vector<double>>    rows;
    double get(const std::vector<double> &r, const std::string &name) const { return r.at(column.at(name)); }
  };

  Csv read_csv(const std::string &file)
  {
    std::ifstream in(file);
    if (!in)
      throw std::runtime_error("cannot read " + file);
    Csv         csv;
    std::string line;
    csv.file    = file;
    bool header = true;
    while (std::getline(in, line))
      {
        if (line.empty() || line[0] == '#')
          continue;
        std::stringstream   ss(line);
        std::string         cell;
        std::vector<double> r;
        for (unsigned int i = 0; std::getline(ss, cell, ','); ++i)
          if (header)
            {
              csv.column[cell] = i;
              csv.names.push_back(cell);
            }
          else
            r.push_back(std::stod(cell));
        if (!header)
          csv.rows.push_back(r);
        header = false;
      }
    return csv;
  }

  /// the scene file with these overrides (-p form), writing profiles and VTU to
  /// directory
  scene::Scene make_scene(const std::string &file, std::vector<std::string> overrides,
                          const std::string &directory)
  {
    std::filesystem::remove_all(directory);
    overrides.insert(overrides.end(),
                     {"Output/Directory=" + directory, "Output/Write VTU=true", "Output/Write profiles=true",
                      "Output/Write checkpoint=false", "Output/Write summary=false", "Output/Verbose=false"});
    return scene::read_scene(file, overrides);
  }

  struct Split
  {
    double       worst_sum   = 0; ///< max |kinetic + thermal + contact - total| / |total|
    double       max_contact = 0; ///< max |contact|
    double       floor_share = 0; ///< contact / total in the first layer of the last block
    double       worst_ideal = 0; ///< max |thermal - (total - kinetic)| / |total|
    unsigned int rows        = 0;
  };

  Split split(const Csv &csv)
  {
    Split  s;
    double last_time = -1;
    for (const auto &r : csv.rows)
      {
        const double k = csv.get(r, energy_names[0]), th = csv.get(r, energy_names[1]),
                     c = csv.get(r, energy_names[2]), tot = csv.get(r, energy_names[3]);
        s.worst_sum   = std::max(s.worst_sum, std::abs(k + th + c - tot) / std::abs(tot));
        s.worst_ideal = std::max(s.worst_ideal, std::abs(th - (tot - k)) / std::abs(tot));
        s.max_contact = std::max(s.max_contact, std::abs(c));
        if (r[0] > last_time) // first row of a block: the floor layer
          s.floor_share = c / tot;
        last_time = r[0];
        ++s.rows;
      }
    return s;
  }

  std::string sci(const double x)
  {
    std::ostringstream os;
    os << std::scientific << std::setprecision(2) << x;
    return os.str();
  }

  /// the field appears in the directory's first VTU file under its plain name (ParaView's
  /// Calculator takes it unquoted) with its SI unit as metadata
  bool vtu_has_field(const std::string &directory, const std::string &name, const std::string &unit)
  {
    const std::string text = read_text_file(directory + "/solution_0000.0.vtu");
    const auto        at   = text.find("Name=\"" + name + "\"");
    if (at == std::string::npos)
      return false;
    const auto end = text.find('>', at), u = text.find("units=\"" + unit + "\"", at);
    return u != std::string::npos && u < end;
  }

  /// all four energy fields and the granular temperature T/m
  bool vtu_has_energy_fields(const std::string &directory)
  {
    for (const char *part : {"kinetic", "thermal", "contact", "total"})
      if (!vtu_has_field(directory, std::string(part) + "_energy_density", "J/m^3"))
        return false;
    return vtu_has_field(directory, "granular_temperature", "m^2/s^2");
  }

  /// the header is profile_columns_1d, every name an identifier (numpy's record arrays,
  /// pandas' attributes and ParaView's Calculator take it as it is), and
  /// granular_temperature = temperature / m in every row: both columns have 10
  /// significant digits (relative rounding <= 5e-10 each), so 1e-9 relative
  void check_columns(const Csv &csv, const double m, const std::string &what, Checker &chk)
  {
    bool identifiers = true;
    for (const auto &name : csv.names)
      for (unsigned int i = 0; i < name.size(); ++i)
        identifiers = identifiers && (name[i] == '_' || std::isalpha(static_cast<unsigned char>(name[i])) ||
                                      (i > 0 && std::isdigit(static_cast<unsigned char>(name[i]))));
    std::string header;
    for (const auto &name : csv.names)
      header += (header.empty() ? "" : ",") + name;
    chk.check(csv.names == profile_columns_1d && identifiers, what + ": " + csv.file + " columns " + header);
    double worst = 0;
    for (const auto &r : csv.rows)
      {
        const double T = csv.get(r, "temperature");
        worst          = std::max(worst, std::abs(csv.get(r, "granular_temperature") * m - T) /
                                           std::max(std::abs(T), 1e-300));
      }
    chk.check(!csv.rows.empty() && worst <= 1e-9,
              what + ": granular_temperature = temperature / m to " + sci(worst) + " relative (<= 1e-9)");
  }
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Checker                                  chk;
  const std::string                        dir    = argc > 1 ? argv[1] : "parameters";
  const std::string                        column = dir + "/sedimentation_column_1d.prm";

  { // the paper's column with the dense closure
    const std::string                              out = "energy_output_closure";
    const scene::Scene                             s   = make_scene(column, {}, out);
    driver::Simulation<1, physics::GranularGas<1>> sim(s, MPI_COMM_SELF, std::cout);
    sim.setup();
    sim.run();
    const Csv   csv = read_csv(out + "/solution_profiles.csv");
    const Split e   = split(csv);
    check_columns(csv, sim.units().mass, "closure on", chk);
    chk.check(e.rows == 16 * 100 && e.worst_sum <= 1e-12,
              "closure on, " + std::to_string(e.rows) +
                " rows: max |kinetic + thermal + contact - total| / total = " + sci(e.worst_sum) +
                " (<= 1e-12)");
    chk.check(e.floor_share > 0.5 && e.floor_share < 1,
              "closure on: contact energy at the floor at 150 ms is " + sci(e.floor_share) + " of the total");
    // the total is the conserved nE of the state (as the former n*E column)
    double worst = 0, scale = 0;
    for (unsigned int c = 0; c < sim.patch().n_owned(); ++c)
      {
        const auto &r = csv.rows[csv.rows.size() - 100 + sim.patch().lattice(c)[0]];
        worst         = std::max(worst, std::abs(csv.get(r, energy_names[3]) - sim.state_si(c)[2]));
        scale         = std::max(scale, std::abs(sim.state_si(c)[2]));
      }
    chk.check(worst <= 1e-14 * scale,
              "closure on: total column = nE of the final state, max difference / max nE = " +
                sci(worst / scale));
    chk.check(
      vtu_has_energy_fields(out),
      "closure on: VTU has the kinetic, thermal, contact and total energy fields and granular_temperature");
  }

  const std::vector<std::string> no_closure = {"Dense closure/Model=none", "Time/End time=0.05"};
  { // closure off
    const std::string                              out = "energy_output_no_closure";
    driver::Simulation<1, physics::GranularGas<1>> sim(make_scene(column, no_closure, out), MPI_COMM_SELF,
                                                       std::cout);
    sim.setup();
    sim.run();
    const Split e = split(read_csv(out + "/solution_profiles.csv"));
    chk.check(e.rows > 0 && e.max_contact == 0 && e.worst_sum <= 1e-12,
              "closure off, " + std::to_string(e.rows) + " rows: contact column 0 (max " +
                sci(e.max_contact) + "), sum = total to " + sci(e.worst_sum));
  }

  { // vibrated container (closure off): kinetic energy in the lab frame
    const std::string        out      = "energy_output_vibrated";
    std::vector<std::string> vibrated = no_closure;
    vibrated.insert(vibrated.end(), {"Effects/Vibration amplitude=0.0005", "Effects/Vibration frequency=30",
                                     "Effects/Vibration direction=x"});
    const scene::Scene                             s = make_scene(column, vibrated, out);
    driver::Simulation<1, physics::GranularGas<1>> sim(s, MPI_COMM_SELF, std::cout);
    sim.setup();
    sim.run();
    const Csv    csv   = read_csv(out + "/solution_profiles.csv");
    const Split  e     = split(csv);
    const double m     = sim.units().mass;
    double       worst = 0, frame = 0;
    for (const auto &r : csv.rows)
      {
        frame = std::max(frame, csv.get(r, energy_names[0]));
      }
    // relative per row, for the rows that carry >= 1e-6 of the largest kinetic energy: below
    // that, u_lab = u + ds/dt nearly cancels and the flux's and the kinetic energy's own
    // roundings of that sum (each 1e-16 of |u| + |ds/dt|) dominate the relative difference
    for (const auto &r : csv.rows)
      {
        const double n = csv.get(r, "number_density"), flux = csv.get(r, "number_flux_x");
        const double k = csv.get(r, energy_names[0]);
        worst          = std::max(worst, std::abs(k - 0.5 * m * flux * flux / n) / std::max(k, 1e-6 * frame));
      }
    chk.check(e.rows > 0 && e.worst_sum <= 1e-12 && worst <= 1e-8 && frame > 0,
              "vibrated, " + std::to_string(e.rows) + " rows: sum = total to " + sci(e.worst_sum) +
                ", kinetic = m (n u_lab)^2 / 2n to " + sci(worst) + " (largest kinetic " + sci(frame) +
                " J/m3)");
  }

  { // ideal gas: no contact energy, thermal = total - kinetic
    const std::string                           out = "energy_output_ideal";
    driver::Simulation<1, physics::IdealGas<1>> sim(
      make_scene(dir + "/sod_1d.prm", {"Time/End time=0.05"}, out), MPI_COMM_SELF, std::cout);
    sim.setup();
    const driver::RunSummary sum = sim.run();
    const Csv                csv = read_csv(out + "/solution_profiles.csv");
    const Split              e   = split(csv);
    check_columns(csv, sim.units().mass, "ideal gas", chk);
    // no diffusion step, no splitting: each attempt at a time step is one SSP-RK3 step
    // (a rejected attempt too; this short run has none), so the count is the step count
    chk.check(sum.steps > 10 && sum.rejected_steps == 0 && sum.convective_steps == sum.steps,
              "ideal gas (convection only): convective_steps " + std::to_string(sum.convective_steps) +
                " = steps " + std::to_string(sum.steps) + " (rejected " + std::to_string(sum.rejected_steps) +
                ")");
    chk.check(e.rows > 0 && e.max_contact == 0 && e.worst_sum <= 1e-12 && e.worst_ideal <= 1e-12,
              "ideal gas, " + std::to_string(e.rows) + " rows: contact 0, thermal = total - kinetic to " +
                sci(e.worst_ideal));
    chk.check(vtu_has_energy_fields(out),
              "ideal gas: VTU has the four energy fields and granular_temperature");
  }
  return chk.failed != 0;
}
