#include <granhydro/scene/scene.h>

#include <string>

namespace granhydro
{
  std::string to_string(ReconstructionType t)
  {
    switch (t)
      {
        case ReconstructionType::first_order:
          return "first order";
        case ReconstructionType::muscl:
          return "muscl";
        case ReconstructionType::weno3:
          return "weno3";
        default:
          return "weno5";
      }
  }
  std::string to_string(FluxType t)
  {
    return t == FluxType::musta ? "musta" : (t == FluxType::rusanov ? "rusanov" : "hll");
  }
  std::string to_string(FaceQuadrature q)
  {
    return q == FaceQuadrature::gauss ? "gauss" : "midpoint";
  }
  std::string to_string(BoundaryType b)
  {
    return b == BoundaryType::periodic     ? "periodic" :
           b == BoundaryType::slip_wall    ? "slip wall" :
           b == BoundaryType::no_slip_wall ? "no-slip wall" :
                                             "outflow";
  }
} // namespace granhydro
