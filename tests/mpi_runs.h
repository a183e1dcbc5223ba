#ifndef softface_tests_mpi_runs_h
#define softface_tests_mpi_runs_h

// What the simulator's tests on several MPI ranks compare a run with: its
// models' own word that they ran on the ranks, and the same models run
// serially (MPI_COMM_SELF) on the same scene in the same process.

#include <softface/core/scene.h>
#include <softface/models/interface.h>
#include <softface/models/linear_fem.h>
#include <softface/simulator/report.h>

#include <string>

namespace softface_tests
{
  using namespace softface;

  /// Does @p run say (its "MPI ranks" figure) that it ran on @p n_ranks?
  inline bool
  ran_on_the_ranks(const Report::ModelRun &run, const unsigned int n_ranks)
  {
    bool distributed = false;
    for (const auto &detail : run.statistics.details)
      distributed |= detail.name == "MPI ranks" && detail.value == n_ranks;
    return distributed;
  }

  /// The serial linear FEM answer, CG to 1e-12.
  inline Vector<double>
  serial_linear_fem(const Scene &scene, const Vector<double> &prescribed)
  {
    Models::LinearFEM model;
    model.set_communicator(MPI_COMM_SELF);
    model.set_solver("cg amg", 1e-12);
    model.setup(scene);
    Vector<double> u;
    model.solve(prescribed, u);
    return u;
  }

  /// Model @p name with the run's parameters @p prm, on one rank.
  inline Vector<double>
  serial_answer(const std::string    &name,
                ParameterHandler     &prm,
                const Scene          &scene,
                const Vector<double> &prescribed)
  {
    auto model = Models::create(name, prm);
    model->set_communicator(MPI_COMM_SELF);
    model->setup(scene);
    Vector<double> u;
    model->solve(prescribed, u);
    return u;
  }

  /// The largest |a_i - b_i|.
  inline double
  largest_difference(const Vector<double> &a, const Vector<double> &b)
  {
    Vector<double> difference = a;
    difference -= b;
    return difference.linfty_norm();
  }
} // namespace softface_tests

#endif
