/**
 * @file split_step.cc
 * SplitStep (driver/split_step.h): the convective part, the temperature repair, the
 * diffusion step and their Strang splitting.
 */
#include <granhydro/driver/split_step.h>
#include <granhydro/physics/models.h>

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace granhydro::driver
{
  template <int dim, class Description>
  SplitStep<dim, Description>::SplitStep(const Description &desc, const bool convection,
                                         const double time_unit, const double max_body_acceleration,
                                         const double velocity_unit, dealii::TimerOutput &timers,
                                         const dealii::ConditionalOStream &pcout)
    : desc(desc)
    , convection_(convection)
    , time_unit_(time_unit)
    , max_body_acceleration_(max_body_acceleration)
    , velocity_unit_(velocity_unit)
    , timers_(timers)
    , pcout(pcout)
  {}

  template <int dim, class Description>
  void SplitStep<dim, Description>::set_operators(const mesh::CartesianPatch<dim>                  &patch,
                                                  convection::ConvectionOperator<dim, Description> &conv,
                                                  diffusion::ImplicitIntegrator<dim> *integrator,
                                                  diffusion::ContactStep<dim>        *contact)
  {
    patch_      = &patch;
    conv_       = &conv;
    integrator_ = integrator;
    contact_    = contact;
  }

  template <int dim, class Description>
  void SplitStep<dim, Description>::repair(Vector &V)
  {
    // a cooling pile under the dense closure may end a part of the step with T slightly
    // below zero (GranularGas::admissible): set T to the floor there, counted
    if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
      {
        // cells in the linear continuations of chi and of the contact potential beyond
        // phi_c - delta (doc/physics.md 2): admissible, but no longer the pole's law; counted
        const double n_max = desc.model.pair_correlation().phi_max() / desc.phi_per_n;
        for (unsigned int s = 0; s < patch_->n_owned(); ++s)
          counters_.continuation_cells += V.local_element(std::size_t(s) * (dim + 2)) > n_max;
      }
    if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
      if (desc.contact.active)
        for (unsigned int s = 0; s < patch_->n_owned(); ++s)
          {
            physics::State<dim> S;
            double             *u = &V.local_element(std::size_t(s) * (dim + 2));
            std::copy(u, u + dim + 2, S.begin());
            const double added = desc.repair_temperature(S, repair_energy_);
            if (added > 0)
              {
                ++counters_.temperature_repairs;
                counters_.max_repair = std::max(counters_.max_repair, added / S[0]);
                u[dim + 1]           = S[dim + 1];
              }
          }
  }

  template <int dim, class Description>
  const double *SplitStep<dim, Description>::contact_energy(const Vector &U)
  {
    if (!contact_)
      return nullptr;
    double *const w = patch_->scratch(mesh::Scratch::owned_0, std::size_t(patch_->n_owned()) * (dim + 2));
    contact_->contact_energies(U, w);
    return w;
  }

  template <int dim, class Description>
  double SplitStep<dim, Description>::max_rate(const Vector &U)
  {
    return conv_->max_rate(U, contact_energy(U));
  }

  template <int dim, class Description>
  bool SplitStep<dim, Description>::admissible(const Vector &U, std::string *what)
  {
    return conv_->admissible(U, what, contact_energy(U));
  }

  template <int dim, class Description>
  bool SplitStep<dim, Description>::convect(Vector &V, const double h, const unsigned int pieces)
  {
    const dealii::TimerOutput::Scope scope(timers_, "convection");
    bool                             ok = true;
    for (unsigned int i = 0; i < pieces && ok; ++i)
      {
        // with the implicit contact step the convective step works on E without the contact
        // energy n w(n) (its description has no dense closure), which the state regains from
        // its new density after it: the contact pressure's work is the contact step's alone
        if (contact_)
          contact_->begin_convective_step(V);
        ok = conv_->ssp_rk3_step(V, h / pieces, repair_energy_);
        ++counters_.convective_pieces; // every step taken (also without splitting, also retried ones)
        if (contact_)
          contact_->shift_energy(V, 1.);
        if (ok && contact_) // the contact pressure and gravity of the same step, implicitly
          {
            ok = contact_->step(V, h / pieces);
            if (!ok)
              pcout << "  " << contact_->last_failure() << " (dt = " << h / pieces * time_unit_ << " s)\n";
          }
        if (ok)
          repair(V);
        ok = ok && admissible(V);
      }
    return ok;
  }

  template <int dim, class Description>
  bool SplitStep<dim, Description>::synchronised_state(const Vector &U, Vector &V)
  {
    V = U;
    if (owed_ > 0 && !convect(V, owed_))
      {
        V = U;
        return false;
      }
    return true;
  }

  template <int dim, class Description>
  bool SplitStep<dim, Description>::advance(Vector &U, const double t, const double dt, const bool sync,
                                            const double max_convective_step)
  {
    if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
      repair_energy_ =
        Description::splitting_repair_energy(max_body_acceleration_ * dt * time_unit_ / velocity_unit_);
    if (!integrator_) // nothing is ever owed without the diffusion step
      return convect(U, dt);
    if (convection_)
      {
        // the owed half of the previous step merged with this step's first half, in
        // pieces of at most max_convective_step (the CFL limit)
        const double h      = owed_ + 0.5 * dt;
        const double limit  = max_convective_step > 0 ? max_convective_step : dt;
        const auto   pieces = static_cast<unsigned int>(std::max(1., std::ceil(h / limit * (1 - 1e-12))));
        if (!convect(U, h, pieces))
          return false;
      }
    const auto switches = integrator_->statistics().switches_to_midpoint;
    bool       ok;
    {
      const dealii::TimerOutput::Scope scope(timers_, "diffusion");
      ok = integrator_->step(U, t, dt, repair_energy_);
    }
    if (integrator_->statistics().switches_to_midpoint > switches)
      pcout << "  diffusion step: Gauss-Legendre Newton iteration did not converge, step "
            << (ok ? "done with implicit midpoint" : "failed with both methods")
            << " (dt = " << dt * time_unit_ << " s)\n";
    if (!ok)
      return false;
    repair(U);
    if (convection_ && sync)
      {
        if (!convect(U, 0.5 * dt))
          return false;
      }
    return true;
  }

#define GRANHYDRO_SPLIT_STEP_INSTANCE(d, D) template class SplitStep<d, D>;
  GRANHYDRO_FOR_EACH_MODEL(GRANHYDRO_SPLIT_STEP_INSTANCE)
} // namespace granhydro::driver
