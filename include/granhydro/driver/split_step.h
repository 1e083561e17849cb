#pragma once
/**
 * @file split_step.h
 * One time step of a run: the convective part (SSP-RK3 in pieces, then the temperature
 * repair), the diffusion step, and their Strang splitting, symmetric or with adjacent
 * convective halves merged (doc/user-guide.md, "Numerics"). The module owns the convective
 * time the state still owes and its counters; the run's composition root (Simulation)
 * hands it the operators after every mesh change.
 */
#include <granhydro/convection/convection_operator.h>
#include <granhydro/diffusion/contact_step.h>
#include <granhydro/diffusion/implicit_integrator.h>
#include <granhydro/mesh/cartesian_patch.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>
#include <deal.II/lac/la_parallel_vector.h>

namespace granhydro::driver
{
  /// what the split step counts over a run (this rank's share; the run summary sums them)
  struct SplitStepCounters
  {
    unsigned long long temperature_repairs = 0;
    /// cell updates that ended beyond phi_c - delta (the continuations of chi and w)
    unsigned long long continuation_cells = 0;
    unsigned long long convective_pieces  = 0; ///< SSP-RK3 steps taken (convect())
    double             max_repair         = 0; ///< largest thermal energy added per grain (scaled)
  };

  template <int dim, class Description>
  class SplitStep
  {
  public:
    using Vector = dealii::LinearAlgebra::distributed::Vector<double>;

    /// convection: Numerics/Convection (false: the diffusion step only); time_unit [s]
    /// for the messages; max_body_acceleration [m/s^2] (gravity plus the container's
    /// largest acceleration) and velocity_unit [m/s] for the splitting allowance of the
    /// temperature repair; timers: the sections "convection" and "diffusion" are timed in it
    SplitStep(const Description &desc, const bool convection, const double time_unit,
              const double max_body_acceleration, const double velocity_unit, dealii::TimerOutput &timers,
              const dealii::ConditionalOStream &pcout);

    /// the operators of the current mesh (integrator may be null: no diffusion step;
    /// contact may be null: the contact pressure is in the convective flux)
    void set_operators(const mesh::CartesianPatch<dim>                  &patch,
                       convection::ConvectionOperator<dim, Description> &conv,
                       diffusion::ImplicitIntegrator<dim>               *integrator,
                       diffusion::ContactStep<dim>                      *contact = nullptr);

    /// one time step of size dt (scaled) from time t: Strang splitting C(dt/2) V(dt)
    /// C(dt/2), eq. 3.5, or only the active part. With the merged splitting the first C
    /// also takes the convective time still owed by the previous step (owed()), and
    /// without sync the closing C(dt/2) is left owed to the next step: C(dt0/2) V(dt0)
    /// C((dt0 + dt1)/2) V(dt1) ... C(dtn/2), the same scheme with half the convective
    /// steps. false if a part failed (U then undefined; the owed time is not changed: the
    /// caller commits it with set_owed()). max_convective_step (scaled; 0 = dt): the CFL
    /// limit, the longest convective step. The step's splitting allowance of the
    /// temperature repair (repair_energy()) is set from dt here.
    bool advance(Vector &U, const double t, const double dt, const bool sync = true,
                 const double max_convective_step = 0);

    /// SSP-RK3 over convective time h in `pieces` equal steps, then the temperature
    /// repair, with the splitting allowance of the last advance() (0 before the first);
    /// false if a stage failed or the result is inadmissible
    bool convect(Vector &V, const double h, const unsigned int pieces = 1);

    /// V = U with the owed convective time applied; false (and V = U) if that convective
    /// step fails
    bool synchronised_state(const Vector &U, Vector &V);

    /// the convective operator's largest rate sum_d (|u_d| + c)/dx_d over the cells of U
    /// (ConvectionOperator::max_rate), and its admissibility test outside a step: with the
    /// implicit contact step both see U as the convective step does, without the contact energy
    double max_rate(const Vector &U);
    bool   admissible(const Vector &U, std::string *what = nullptr);
    /// scaled convective time the state still owes (0 after a synchronised step)
    double owed() const { return owed_; }
    void   set_owed(const double h) { owed_ = h; }

    /// the splitting allowance per grain (scaled) of the temperature repair in the last
    /// advance(): physics::GranularGas::splitting_repair_energy() of |g_eff| dt (0 before
    /// the first step, and for an ideal gas). The states a step leaves may carry a thermal
    /// deficit it allowed before their repair: the mesh adaptation's prolongation tests
    /// its children with it.
    double repair_energy() const { return repair_energy_; }

    const SplitStepCounters &counters() const { return counters_; }
    void                     reset_counters()
    {
      counters_ = SplitStepCounters();
      if (contact_)
        contact_->reset_counts();
    }
    /// what the implicit contact step did since reset_counters() (zeros without it)
    diffusion::ContactStepCounts contact_counts() const
    {
      return contact_ ? contact_->counts() : diffusion::ContactStepCounts();
    }

  private:
    /// the dense closure's temperature floor on V (counted), GranularGas only
    void repair(Vector &V);

    const Description                                &desc;
    const bool                                        convection_;
    const double                                      time_unit_;
    const double                                      max_body_acceleration_, velocity_unit_;
    double                                            repair_energy_ = 0;
    dealii::TimerOutput                              &timers_;
    const dealii::ConditionalOStream                 &pcout;
    const mesh::CartesianPatch<dim>                  *patch_      = nullptr;
    convection::ConvectionOperator<dim, Description> *conv_       = nullptr;
    diffusion::ImplicitIntegrator<dim>               *integrator_ = nullptr;
    diffusion::ContactStep<dim>                      *contact_    = nullptr;
    double                                            owed_       = 0;
    SplitStepCounters                                 counters_;
    /// with the implicit contact step, the contact energy of each owned cell of U, which the
    /// convective operator's view of U leaves out (in the patch's work array
    /// mesh::Scratch::owned_0, valid until the next step); without it nullptr
    const double *contact_energy(const Vector &U);
  };
} // namespace granhydro::driver
