#pragma once
/**
 * @file numerics.h
 * The 'Numerics' subsection of a scene: the convective scheme, the time step and the
 * scaled velocity unit.
 */
#include <granhydro/convection/settings.h>

#include <deal.II/base/parameter_handler.h>

namespace granhydro::scene
{
  struct Scene;

  struct NumericsParameters
  {
    convection::ReconstructionType reconstruction  = convection::ReconstructionType::weno5;
    convection::FaceQuadrature     face_quadrature = convection::FaceQuadrature::gauss;
    /// convective flux through no-slip walls: false = the numerical flux between the cell and
    /// its mirror ghost (mass and energy set to 0); true = the paper's eq. 6.1a: zero mass and
    /// energy flux and only the wall pressure on the normal momentum (no tangential part)
    bool                 no_slip_pressure_flux = false;
    convection::FluxType flux                  = convection::FluxType::musta;
    unsigned int         musta_max_stages      = 4;
    /// 2: the 1 % rule compares stages (at least 2); 1: also a first-stage test on the jump
    unsigned int musta_min_stages   = 2;
    double       musta_tolerance    = 0.01;
    double       musta_local_cfl    = 0.9;
    double       cfl                = 0.4;
    double       fixed_time_step    = 0; // [s], 0: from CFL
    double       reference_velocity = 0; // [m/s], 0: sqrt(g sigma), g = 9.81
    unsigned int max_step_retries   = 6;
    /// Strang splitting with the diffusion step: merged (the closing C(dt/2) of a step and
    /// the opening one of the next taken as one convective step, synchronised at output
    /// times) or symmetric (C(dt/2) V(dt) C(dt/2) every step)
    bool merge_strang = true;
    /// where gravity acts: false = a source of the diffusion step (Strang-split, the
    /// paper's scheme); true = in the convective step in well-balanced form (Käppeli &
    /// Mishra 2014: a pile at rest is a discrete steady state)
    bool well_balanced_gravity = false;
    /// the dense closure's contact pressure: false = in the convective flux (its sound speed
    /// sets the CFL step); true = a linearly implicit correction after each convective step
    /// (doc/user-guide.md, 'Implicit contact pressure')
    bool implicit_contact_pressure = false;

    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(dealii::ParameterHandler &prm);

    // Checks, in the order validate() runs them (the first failure is the message).

    /// the Courant number
    static void check_cfl(const Scene &s);
    /// the MUSTA predictor's Courant number and stopping tolerance
    static void check_musta(const Scene &s);
    /// the velocity unit near the default sqrt(g sigma) of the scene's grains
    static void check_reference_velocity(const Scene &s);
    /// the well-balanced gravity needs the granular model and the convective step
    static void check_gravity_scheme(const Scene &s);
    /// the implicit contact pressure needs the dense closure, the convective step and split gravity
    static void check_contact_pressure(const Scene &s);
  };
} // namespace granhydro::scene
