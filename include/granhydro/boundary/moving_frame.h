#pragma once
/**
 * @file moving_frame.h
 * The moving frame of a vibrated container (doc/physics.md 5.3): the container moves as
 * s(t) = A sin(w t) e_s and the equations are solved in its frame, where every wall is
 * at rest. Two things follow from the frame: the inertial force per unit mass -s''(t) =
 * A w^2 sin(w t) e_s joins gravity in the body force (the diffusion step's source,
 * g_eff = g - s''), and lab-frame velocities are the solved ones plus ds/dt =
 * A w cos(w t) e_s (the output). The body force's source S(U) is physics
 * (physics/body_force.h).
 */
#include <granhydro/physics/body_force.h>

#include <array>
#include <cmath>

namespace granhydro::boundary
{
  struct MovingFrame
  {
    double       amplitude = 0; ///< A (scaled A / L0, or [m])
    double       omega     = 0; ///< w (scaled w t0, or [rad/s])
    unsigned int direction = 0; ///< e_s

    /// true if the frame accelerates
    bool active() const { return amplitude != 0 && omega != 0; }

    /// the same motion in scaled units: A / length_unit, w time_unit
    MovingFrame scaled(const double length_unit, const double time_unit) const
    {
      return {amplitude / length_unit, omega * time_unit, direction};
    }

    /// adds the inertial force per unit mass -s''(t) at the time t to g
    void add_inertial_force(const double t, std::array<double, 3> &g) const
    {
      if (amplitude != 0)
        g[direction] += amplitude * omega * omega * std::sin(omega * t);
    }

    /// the frame's velocity ds/dt at the time t (lab frame = container frame + this)
    std::array<double, 3> velocity(const double t) const
    {
      std::array<double, 3> v{{0, 0, 0}};
      if (amplitude != 0)
        v[direction] = amplitude * omega * std::cos(omega * t);
      return v;
    }
  };

  /// the body force per unit mass in the frame at the time t: g_eff(t) = g - s''(t)
  inline std::array<double, 3> effective_body_force(const physics::BodyForce &body, const MovingFrame &frame,
                                                    const double t)
  {
    std::array<double, 3> g = body.gravity;
    frame.add_inertial_force(t, g);
    return g;
  }
} // namespace granhydro::boundary
