#pragma once
/**
 * @file settings.h
 * What the convective step needs to know, and nothing else: the reconstruction, the
 * face quadrature, the numerical flux with its MUSTA parameters, and the wall-flux
 * choices (the walls themselves are the mesh's, CartesianPatch::wall_settings()). scene/ fills it (Scene::convection_settings()); the convection kernel never
 * sees the scene.
 */
#include <granhydro/base/enum_names.h>

#include <array>

namespace granhydro::convection
{
  enum class ReconstructionType
  {
    first_order,
    muscl,
    weno3,
    weno5
  };
  /// Numerics/Reconstruction
  constexpr auto enum_names(ReconstructionType)
  {
    return enum_table(
      EnumName{ReconstructionType::first_order, "first order"}, EnumName{ReconstructionType::muscl, "muscl"},
      EnumName{ReconstructionType::weno3, "weno3"}, EnumName{ReconstructionType::weno5, "weno5"});
  }
  static_assert(check_enum_names(enum_names(ReconstructionType{})));

  enum class FaceQuadrature
  {
    gauss,
    midpoint
  };
  /// Numerics/Face quadrature
  constexpr auto enum_names(FaceQuadrature)
  {
    return enum_table(EnumName{FaceQuadrature::gauss, "gauss"},
                      EnumName{FaceQuadrature::midpoint, "midpoint"});
  }
  static_assert(check_enum_names(enum_names(FaceQuadrature{})));

  enum class FluxType
  {
    musta,
    rusanov,
    hll
  };
  /// Numerics/Flux
  constexpr auto enum_names(FluxType)
  {
    return enum_table(EnumName{FluxType::musta, "musta"}, EnumName{FluxType::rusanov, "rusanov"},
                      EnumName{FluxType::hll, "hll"});
  }
  static_assert(check_enum_names(enum_names(FluxType{})));

  struct ConvectionSettings
  {
    ReconstructionType reconstruction  = ReconstructionType::weno5;
    FaceQuadrature     face_quadrature = FaceQuadrature::gauss;
    FluxType           flux            = FluxType::musta;
    /// MUSTA: stage cap, minimum stages (2: the 1 % rule compares stages; 1: also the
    /// first-stage test on the jump), the 1 % tolerance and the local Courant number
    unsigned int musta_max_stages = 4;
    unsigned int musta_min_stages = 2;
    double       musta_tolerance  = 0.01;
    double       musta_local_cfl  = 0.9;
    /// no-slip walls: only the wall pressure in the normal momentum (paper eq. 6.1a)
    /// instead of the mirror-ghost flux (boundary/convective_wall_flux.h)
    bool no_slip_pressure_flux = false;
    /// cohesionless grains: a wall pushes, never pulls - the normal momentum flux (wall
    /// pressure) of a wall face is at least 0 (boundary/convective_wall_flux.h)
    bool no_wall_tension = false;
    /// the length unit of the scaled units [m] (messages in metres)
    double length_unit = 1;
    /// well-balanced gravity (Numerics/Gravity scheme = well-balanced): the body force
    /// (scaled units, set by the driver), a source of the convective step in equilibrium
    /// form; all 0: gravity is not the convective step's (a source of the diffusion step)
    std::array<double, 3> gravity{{0, 0, 0}};
  };
} // namespace granhydro::convection
