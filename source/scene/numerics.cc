#include <granhydro/scene/numerics.h>
#include <granhydro/scene/scene.h>

#include "parameter_tools.h"

#include <cmath>
#include <string>

namespace granhydro::scene
{
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;
  using namespace detail;

  void NumericsParameters::declare_parameters(ParameterHandler &prm)
  {
    const NumericsParameters defaults;
    prm.enter_subsection("Numerics");
    {
      prm.declare_entry("Reconstruction", to_string(defaults.reconstruction),
                        selection_of<convection::ReconstructionType>(),
                        "Reconstruction of the conservative variables to face points: "
                        "weno5 (paper section 4, Jiang-Shu weights), weno3, muscl (MC "
                        "limiter), first order.");
      prm.declare_entry("Face quadrature", to_string(defaults.face_quadrature),
                        selection_of<convection::FaceQuadrature>(),
                        "gauss: 2 Gauss points per face direction (paper eq. 4.6, "
                        "Titarev-Toro), midpoint: one point per face (face average used "
                        "as point value, second order on nonlinear fluxes).");
      prm.declare_entry("No-slip wall flux", "mirror", Patterns::Selection("mirror|pressure"),
                        "Convective flux through no-slip walls. mirror: the numerical flux "
                        "between the cell and its mirror ghost (velocity reflected about the "
                        "wall velocity), mass and energy parts set to 0; its tangential "
                        "momentum part is a numerical wall friction that shrinks with the "
                        "mesh. pressure: the paper's eq. 6.1a, zero mass and energy flux and "
                        "only the wall pressure (the normal momentum of the same flux) - no "
                        "tangential momentum; the wall shear stress then comes from the "
                        "diffusion step alone.");
      prm.declare_entry("Flux", to_string(defaults.flux), selection_of<convection::FluxType>(),
                        "Numerical flux: musta (multi-stage FORCE, paper eqs. 4.7-4.9 with "
                        "dx/dt in the dissipation term, doc/physics.md P12), rusanov, hll.");
      prm.declare_entry("MUSTA maximum stages", default_text(defaults.musta_max_stages),
                        Patterns::Integer(1, 20),
                        "Cap on the number of FORCE stages of the MUSTA flux (1 = FORCE).");
      prm.declare_entry("MUSTA minimum stages", default_text(defaults.musta_min_stages),
                        Patterns::Integer(1, 2),
                        "2: the stopping rule compares the fluxes of consecutive stages, so "
                        "every face takes at least 2 stages. 1: after the first stage a face "
                        "keeps the FORCE flux where the change of a further stage, estimated "
                        "as S_max |U_R - U_L| for mass, momentum and energy, is below the "
                        "tolerance (smooth regions): 35-40 % less convective time, larger "
                        "errors (doc/performance.md, 'Cost of the diffusion step and of the "
                        "convective kernel').");
      prm.declare_entry("MUSTA tolerance", default_text(defaults.musta_tolerance), Patterns::Double(0, 1),
                        "Stopping rule: stop when the FORCE flux changes between stages by "
                        "less than this in mass, momentum (as a vector) and energy, each "
                        "relative to max(|F|, S_max (|U_L| + |U_R|)/2) (paper: 1 %).");
      prm.declare_entry("MUSTA local CFL", default_text(defaults.musta_local_cfl), Patterns::Double(0, 1),
                        "Local Courant number of the MUSTA predictor stages (Titarev-Toro).");
      prm.declare_entry("CFL number", default_text(defaults.cfl), Patterns::Double(0, 1),
                        "Courant number: dt = CFL / max_cells sum_d (|u_d| + c)/dx_d.");
      prm.declare_entry("Fixed time step", default_text(defaults.fixed_time_step),
                        Patterns::Double(0, Patterns::Double::max_double_value),
                        "Fixed time step [s]; 0 = from the CFL number. A fixed step is "
                        "still reduced if it would exceed the CFL limit.");
      prm.declare_entry("Reference velocity", default_text(defaults.reference_velocity),
                        Patterns::Double(0, Patterns::Double::max_double_value),
                        "Velocity unit of the internal scaled units [m/s]; 0 = sqrt(g sigma), "
                        "g = 9.81 m/s^2.");
      prm.declare_entry("Strang splitting", "merged", Patterns::Selection("merged|symmetric"),
                        "How the convective step C and the diffusion step V are composed "
                        "(eq. 3.5). symmetric: C(dt/2) V(dt) C(dt/2) every step. merged: the "
                        "same scheme with adjacent convective halves taken as one step, "
                        "C(dt0/2) V(dt0) C((dt0 + dt1)/2) V(dt1) ... C(dtn/2), synchronised at "
                        "every output time: half the convective work, second order as well.");
      prm.declare_entry("Gravity scheme", "split", Patterns::Selection("split|well-balanced"),
                        "Where the body force (gravity, and nothing of a vibrated container's "
                        "frame, whose inertial force stays in the diffusion step) acts. split: "
                        "a source of the diffusion step, Strang-split from the convective step "
                        "(the paper's scheme); a pile at rest is then steady only up to the "
                        "splitting error. well-balanced: a source of the convective step in "
                        "the form of Kaeppeli & Mishra (2014): each cell reconstructs its "
                        "deviation from its local isothermal equilibrium, so a pile at rest "
                        "with uniform temperature stays at rest to round-off (granular model "
                        "only; doc/user-guide.md, 'Well-balanced gravity').");
      prm.declare_entry("Contact pressure", "explicit", Patterns::Selection("explicit|implicit"),
                        "Where the dense closure's contact pressure p_f acts. explicit: in the "
                        "convective flux, so its sound speed (metres per second in a settled "
                        "pile) sets the CFL step. implicit: the convective flux and its wave "
                        "speeds leave p_f out, and after each convective step a linearly "
                        "implicit correction (backward Euler, Newton-GMRES) moves mass and "
                        "momentum by the contact pressure's gradient net of gravity; the CFL "
                        "step is then set by the flow and the kinetic sound speed "
                        "(doc/user-guide.md, 'Implicit contact pressure'). Needs a "
                        "'Dense closure/Model' and 'Gravity scheme = split'.");
      prm.declare_entry("Maximum step retries", default_text(defaults.max_step_retries),
                        Patterns::Integer(0, 30),
                        "A step whose result is inadmissible (n <= 0 or T <= 0) is retried "
                        "with half the time step at most this many times, then the run stops. "
                        "The first step of a run, sized only by the initial state's CFL "
                        "limit, may halve up to 30 times.");
    }
    prm.leave_subsection();
  }

  void NumericsParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Numerics");
    {
      reconstruction            = get_enum<convection::ReconstructionType>(prm, "Numerics", "Reconstruction");
      face_quadrature           = get_enum<convection::FaceQuadrature>(prm, "Numerics", "Face quadrature");
      no_slip_pressure_flux     = prm.get("No-slip wall flux") == "pressure";
      flux                      = get_enum<convection::FluxType>(prm, "Numerics", "Flux");
      musta_max_stages          = prm.get_integer("MUSTA maximum stages");
      musta_tolerance           = prm.get_double("MUSTA tolerance");
      musta_min_stages          = prm.get_integer("MUSTA minimum stages");
      musta_local_cfl           = prm.get_double("MUSTA local CFL");
      cfl                       = prm.get_double("CFL number");
      fixed_time_step           = prm.get_double("Fixed time step");
      reference_velocity        = prm.get_double("Reference velocity");
      max_step_retries          = prm.get_integer("Maximum step retries");
      merge_strang              = prm.get("Strang splitting") == "merged";
      well_balanced_gravity     = prm.get("Gravity scheme") == "well-balanced";
      implicit_contact_pressure = prm.get("Contact pressure") == "implicit";
    }
    prm.leave_subsection();
  }

  void NumericsParameters::check_cfl(const Scene &s)
  {
    if (!(s.cfl >= 1e-3 && s.cfl <= 1))
      fail(s, "Numerics/CFL number",
           "must lie in [1e-3, 1] (SSP-RK3 stability; smaller steps only "
           "creep: use 'Numerics/Fixed time step' for a tiny fixed step)");
  }

  void NumericsParameters::check_musta(const Scene &s)
  {
    if (s.musta_local_cfl <= 0 || s.musta_local_cfl > 1)
      fail(s, "Numerics/MUSTA local CFL", "must lie in (0, 1]");
    if (s.musta_tolerance <= 0)
      fail(s, "Numerics/MUSTA tolerance", "must be positive");
  }

  void NumericsParameters::check_gravity_scheme(const Scene &s)
  {
    if (!s.well_balanced_gravity)
      return;
    if (s.model != physics::Model::granular)
      fail(s, "Numerics/Gravity scheme",
           "well-balanced needs 'Material/Model = granular' (the equilibrium is the granular "
           "equation of state's); use split");
    if (!s.convection)
      fail(s, "Numerics/Gravity scheme",
           "well-balanced puts gravity into the convective step, which this scene switches off; "
           "use split");
  }

  void NumericsParameters::check_contact_pressure(const Scene &s)
  {
    if (!s.implicit_contact_pressure)
      return;
    if (s.model != physics::Model::granular || s.dense_closure == DenseClosure::none)
      fail(s, "Numerics/Contact pressure",
           "implicit needs the granular model with a dense closure ('Dense closure/Model'); "
           "use explicit");
    if (!s.convection)
      fail(s, "Numerics/Contact pressure",
           "implicit corrects the convective step, which this scene switches off; use explicit");
    if (s.well_balanced_gravity)
      fail(s, "Numerics/Contact pressure",
           "implicit balances the contact pressure against gravity itself: it needs "
           "'Numerics/Gravity scheme = split'");
  }

  void NumericsParameters::check_reference_velocity(const Scene &s)
  {
    // the scaled units keep the state's numbers near 1; a velocity unit far from the
    // default sqrt(g sigma) moves them towards the fixed thresholds (floors, tolerances)
    if (s.reference_velocity > 0)
      {
        const double v0 = std::sqrt(9.81 * s.grain_diameter);
        if (!(s.reference_velocity >= 1e-3 * v0 && s.reference_velocity <= 1e3 * v0))
          fail(s, "Numerics/Reference velocity",
               fmt(s.reference_velocity) + " m/s; allowed 0 (= sqrt(g sigma) = " + fmt(v0) +
                 " m/s) or within 1e-3 .. 1e3 times that");
      }
  }
} // namespace granhydro::scene
