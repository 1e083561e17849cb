#pragma once
/**
 * @file pair_correlation.h
 * Pair correlation at contact chi(phi) of hard spheres, Torquato (1995) form,
 * with the C^1 linear continuation beyond phi_max = phi_c - delta
 * (doc/physics.md section 2, "Guard", item 2).
 *
 * Header only, standard library only. All member functions are inline and
 * templated on the number type (double, float, long double, or any scalar type
 * with the usual arithmetic, comparison and std::log overloads).
 */
#include <granhydro/physics/lanes.h>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace granhydro::physics
{
  /**
   * Torquato (1995) contact value of the pair correlation, doc/physics.md section 2:
   *
   *   phi <= phi_f        : chi = (1 - phi/2)/(1 - phi)^3           (Carnahan-Starling)
   *   phi_f < phi <= phi_max : chi = chi_f (phi_c - phi_f)/(phi_c - phi)  (pole at phi_c)
   *   phi > phi_max       : chi = chi(phi_max) + chi'(phi_max)(phi - phi_max)
   *
   * with chi_f = chi_CS(phi_f) and phi_max = phi_c - delta. chi is C^0 at phi_f
   * (its derivative jumps there) and C^1 at phi_max. phi is never clamped: the
   * continuation keeps p = n T Z increasing in n beyond phi_max (restoring
   * pressure, hyperbolicity preserved). A state with phi >= phi_c is
   * inadmissible; detecting and reporting it is the caller's job.
   */
  class PairCorrelationTorquato
  {
  public:
    /**
     * @param phi_f  freezing packing fraction, 0 < phi_f < phi_c (default 0.49)
     * @param phi_c  random close packing, phi_f < phi_c < 1 (default 0.64)
     * @param delta  guard distance, 0 < delta < phi_c - phi_f (default 1e-3)
     * @throws std::invalid_argument naming the offending parameter and its
     *         allowed range.
     */
    explicit PairCorrelationTorquato(const double phi_f = 0.49, const double phi_c = 0.64,
                                     const double delta = 1.e-3)
      : phi_f_(phi_f)
      , phi_c_(phi_c)
      , delta_(delta)
    {
      if (!(phi_c > 0. && phi_c < 1.))
        fail("phi_c", phi_c, "0 < phi_c < 1");
      if (!(phi_f > 0. && phi_f < phi_c))
        fail("phi_f", phi_f, "0 < phi_f < phi_c (phi_c = " + str(phi_c) + ")");
      if (!(delta > 0. && delta < phi_c - phi_f))
        fail("delta", delta, "0 < delta < phi_c - phi_f (= " + str(phi_c - phi_f) + ")");

      phi_max_  = phi_c_ - delta_;
      chi_f_    = carnahan_starling(phi_f_);
      A_        = chi_f_ * (phi_c_ - phi_f_);
      chi_max_  = A_ / (phi_c_ - phi_max_);
      dchi_max_ = A_ / ((phi_c_ - phi_max_) * (phi_c_ - phi_max_));
      X_f_      = integral_cs(phi_f_);
      X_max_    = X_f_ + A_ * std::log((phi_c_ - phi_f_) / (phi_c_ - phi_max_));
    }

    /** @name Parameters and derived constants (doc/physics.md section 2) */
    ///@{
    double phi_f() const { return phi_f_; }
    double phi_c() const { return phi_c_; }
    double delta() const { return delta_; }
    /// start of the linear continuation, phi_c - delta
    double phi_max() const { return phi_max_; }
    /// chi_f = (1 - phi_f/2)/(1 - phi_f)^3 (5.691627 for phi_f = 0.49)
    double chi_f() const { return chi_f_; }
    /// chi(phi_max) (853.744 with the defaults)
    double chi_max() const { return chi_max_; }
    /// dchi/dphi at phi_max, the slope of the continuation (8.53744e5 with the defaults)
    double dchi_max() const { return dchi_max_; }
    ///@}

    /// Carnahan-Starling contact value (1 - phi/2)/(1 - phi)^3 (doc/physics.md section 2).
    template <typename Number>
    static Number carnahan_starling(const Number phi)
    {
      const Number w = lanes::constant<Number>(1.) - phi;
      return (lanes::constant<Number>(1.) - lanes::constant<Number>(0.5) * phi) / (w * w * w);
    }

    /// d chi_CS/d phi = (5/2 - phi)/(1 - phi)^4 (doc/physics.md section 2).
    template <typename Number>
    static Number carnahan_starling_derivative(const Number phi)
    {
      const Number w  = lanes::constant<Number>(1.) - phi;
      const Number w2 = w * w;
      return (lanes::constant<Number>(2.5) - phi) / (w2 * w2);
    }

    /**
     * chi(phi), doc/physics.md section 2 (Torquato 1995 + C^1 guard, item 2).
     * Finite for every phi < 1 on the Carnahan-Starling branch and for every
     * phi > phi_f above (linear beyond phi_max; no clamping).
     */
    template <typename Number>
    __attribute__((always_inline)) inline Number chi(const Number phi) const
    {
      using lanes::constant;
      if constexpr (lanes::is_vector<Number>)
        {
          // every branch in every lane, then the lane's own: each lane is the scalar result
          const Number tq = constant<Number>(A_) / (constant<Number>(phi_c_) - phi);
          const Number lin =
            constant<Number>(chi_max_) + constant<Number>(dchi_max_) * (phi - constant<Number>(phi_max_));
          // carnahan_starling(phi), written out: the vector path calls nothing that could
          // be left out of line (a 4-wide vector function compiled for the default target
          // has another calling convention than the AVX2 kernels that inline this one)
          const Number w  = constant<Number>(1.) - phi;
          const Number cs = (constant<Number>(1.) - constant<Number>(0.5) * phi) / (w * w * w);
          return phi <= constant<Number>(phi_f_) ? cs : (phi <= constant<Number>(phi_max_) ? tq : lin);
        }
      else
        {
          if (phi <= lanes::constant<Number>(phi_f_))
            return carnahan_starling(phi);
          if (phi <= lanes::constant<Number>(phi_max_))
            return lanes::constant<Number>(A_) / (lanes::constant<Number>(phi_c_) - phi);
          return lanes::constant<Number>(chi_max_) +
                 lanes::constant<Number>(dchi_max_) * (phi - lanes::constant<Number>(phi_max_));
        }
    }

    /**
     * dchi/dphi, doc/physics.md section 2: (5/2 - phi)/(1 - phi)^4 up to phi_f
     * (the left derivative at phi_f; the derivative jumps there),
     * chi_f (phi_c - phi_f)/(phi_c - phi)^2 up to phi_max, constant beyond.
     */
    template <typename Number>
    Number dchi_dphi(const Number phi) const
    {
      if (phi <= lanes::constant<Number>(phi_f_))
        return carnahan_starling_derivative(phi);
      if (phi <= lanes::constant<Number>(phi_max_))
        {
          const Number w = lanes::constant<Number>(phi_c_) - phi;
          return lanes::constant<Number>(A_) / (w * w);
        }
      return lanes::constant<Number>(dchi_max_);
    }

    /// chi and dchi/dphi on the Carnahan-Starling branch (phi <= phi_f)
    template <typename Number>
    __attribute__((always_inline)) static inline void carnahan_starling_pair(const Number phi, Number &c,
                                                                             Number &dc)
    {
      const Number w  = lanes::constant<Number>(1.) - phi;
      const Number w3 = w * w * w;
      c               = (lanes::constant<Number>(1.) - lanes::constant<Number>(0.5) * phi) / w3;
      dc              = (lanes::constant<Number>(2.5) - phi) / (w3 * w);
    }

    /// chi and dchi/dphi on the Torquato branch (phi_f < phi <= phi_max)
    template <typename Number>
    __attribute__((always_inline)) inline void torquato_pair(const Number phi, Number &c, Number &dc) const
    {
      const Number w = lanes::constant<Number>(phi_c_) - phi;
      c              = lanes::constant<Number>(A_) / w;
      dc             = c / w;
    }

    /// chi and dchi/dphi together (one branch decision), doc/physics.md section 2.
    template <typename Number>
    __attribute__((always_inline)) inline void chi_and_derivative(const Number phi, Number &chi_value,
                                                                  Number &dchi_value) const
    {
      using lanes::constant;
      if constexpr (lanes::is_vector<Number>)
        {
          // the three branches in every lane, then each lane's own (bit for bit); when all
          // lanes take the same branch (the usual case: a dilute gas or a dense pile), only
          // that one
          const auto lo = phi <= constant<Number>(phi_f_), mid = phi <= constant<Number>(phi_max_);
          if (!lanes::any(!lo))
            return carnahan_starling_pair(phi, chi_value, dchi_value);
          if (!lanes::any(lo || !mid))
            return torquato_pair(phi, chi_value, dchi_value);
          Number c1, d1, c2, d2;
          carnahan_starling_pair(phi, c1, d1);
          torquato_pair(phi, c2, d2);
          const Number c3 =
            constant<Number>(chi_max_) + constant<Number>(dchi_max_) * (phi - constant<Number>(phi_max_));
          chi_value  = lo ? c1 : (mid ? c2 : c3);
          dchi_value = lo ? d1 : (mid ? d2 : constant<Number>(dchi_max_));
        }
      else
        {
          if (phi <= constant<Number>(phi_f_))
            carnahan_starling_pair(phi, chi_value, dchi_value);
          else if (phi <= constant<Number>(phi_max_))
            torquato_pair(phi, chi_value, dchi_value);
          else
            {
              chi_value =
                constant<Number>(chi_max_) + constant<Number>(dchi_max_) * (phi - constant<Number>(phi_max_));
              dchi_value = constant<Number>(dchi_max_);
            }
        }
    }

    /**
     * X(phi) = int_0^phi chi(s) ds, doc/physics.md section 2 (used by the
     * hydrostatic column of section 6(d)):
     *   phi <= phi_f : 1/(4(1-phi)^2) + 1/(2(1-phi)) - 3/4, evaluated in the
     *                  algebraically identical, cancellation-free form
     *                  phi (4 - 3 phi) / (4 (1 - phi)^2);
     *   phi_f < phi <= phi_max : X(phi_f) + chi_f (phi_c - phi_f) ln[(phi_c - phi_f)/(phi_c - phi)];
     *   phi > phi_max : the exact integral of the linear continuation,
     *                  X(phi_max) + chi_max s + dchi_max s^2/2, s = phi - phi_max
     *                  (doc/physics.md 2; this branch keeps X consistent with chi,
     *                  X' = chi everywhere).
     */
    template <typename Number>
    Number integral(const Number phi) const
    {
      using std::log;
      if (phi <= lanes::constant<Number>(phi_f_))
        return integral_cs(phi);
      if (phi <= lanes::constant<Number>(phi_max_))
        return lanes::constant<Number>(X_f_) +
               lanes::constant<Number>(A_) *
                 log(lanes::constant<Number>(phi_c_ - phi_f_) / (lanes::constant<Number>(phi_c_) - phi));
      const Number s = phi - lanes::constant<Number>(phi_max_);
      return lanes::constant<Number>(X_max_) +
             s * (lanes::constant<Number>(chi_max_) +
                  lanes::constant<Number>(0.5) * lanes::constant<Number>(dchi_max_) * s);
    }

  private:
    template <typename Number>
    static Number integral_cs(const Number phi)
    {
      const Number w = lanes::constant<Number>(1.) - phi;
      return phi * (lanes::constant<Number>(4.) - lanes::constant<Number>(3.) * phi) /
             (lanes::constant<Number>(4.) * w * w);
    }

    static std::string str(const double x)
    {
      std::ostringstream s;
      s.precision(17);
      s << x;
      return s.str();
    }

    [[noreturn]] static void fail(const char *name, const double value, const std::string &range)
    {
      throw std::invalid_argument(std::string("PairCorrelationTorquato: parameter ") + name + " = " +
                                  str(value) + " is outside the allowed range " + range);
    }

    double phi_f_, phi_c_, delta_;
    double phi_max_  = 0.; ///< phi_c - delta
    double chi_f_    = 0.; ///< chi_CS(phi_f)
    double A_        = 0.; ///< chi_f (phi_c - phi_f), numerator of the pole branch
    double chi_max_  = 0.; ///< chi(phi_max)
    double dchi_max_ = 0.; ///< chi'(phi_max)
    double X_f_      = 0.; ///< X(phi_f)
    double X_max_    = 0.; ///< X(phi_max)
  };
} // namespace granhydro::physics
