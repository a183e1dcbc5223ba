// The 'evaluation points' output: every model's displacement at points a CSV
// file lists ('Output/Evaluation points'), interpolated with the model's own
// shape functions, into evaluation_<model>.csv.

#include <deal.II/base/mpi.h>

#include <softface/core/error.h>
#include <softface/core/on_rank_0.h>
#include <softface/fe/point_evaluation.h>
#include <softface/io/points_csv.h>
#include <softface/outputs/interface.h>

#include <filesystem>

namespace softface
{
  namespace Outputs
  {
    namespace
    {
      class EvaluationPoints : public Interface
      {
      public:
        static void
        declare_parameters(ParameterHandler &prm)
        {
          prm.declare_entry(
            "Evaluation points",
            "",
            Patterns::Anything(),
            "CSV file whose first three columns are x,y,z (mm, reference "
            "configuration; a header line is skipped), e.g. the "
            "displacements_*.csv of another run. If set, every model's "
            "displacement there is written to evaluation_<model>.csv: "
            "interpolated with the model's shape functions (linear, or "
            "quadratic for 'Polynomial degree = 2'). Relative paths are "
            "taken from the parameter file's folder. Points must lie in the "
            "mesh.");
        }

        void
        parse_parameters(ParameterHandler  &prm,
                         const std::string &input_directory) override
        {
          std::filesystem::path file(prm.get("Evaluation points"));
          if (!file.empty() && file.is_relative() && !input_directory.empty())
            file = std::filesystem::path(input_directory) / file;
          points_file = file.string();
        }

        bool
        requested() const override
        {
          return !points_file.empty();
        }

        void
        prepare(const Run &run, std::ostream &out) override;

        void
        add_answer(const Run              &run,
                   const Report::ModelRun &model_run,
                   Models::Interface      &model,
                   bool                    from_basis) override;

        void
        write(const Run &, std::ostream &) override
        {}

        std::string
        files(const Run &) const override
        {
          return "evaluation_*.csv";
        }

      private:
        std::string points_file;
        /// On the rank that writes (rank 0): the points located in the
        /// scene's cells.
        std::unique_ptr<PointEvaluation> evaluation;
        /// On several MPI ranks, on every rank: the points, their cells and
        /// reference coordinates, for a model whose field lives on the
        /// ranks.
        std::vector<Point<3>>     points;
        std::vector<unsigned int> cells;
        std::vector<Point<3>>     reference_points;
      };

      void
      EvaluationPoints::prepare(const Run &run, std::ostream &out)
      {
        // Rank 0 reads them (its error is every rank's) and sends them.
        on_rank_0(MPI_COMM_WORLD,
                  [&]() { points = read_points_csv(points_file); });
        const bool on_ranks =
          Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1;
        if (on_ranks)
          points = Utilities::MPI::broadcast(MPI_COMM_WORLD, points);
        try
          {
            // Rank 0 writes the values (and may be the only rank with the
            // cells); its error is every rank's.
            on_rank_0(MPI_COMM_WORLD, [&]() {
              evaluation =
                std::make_unique<PointEvaluation>(run.scene.triangulation,
                                                  points);
            });
          }
        catch (const Error &e)
          {
            throw Error("Output/Evaluation points '" + points_file +
                        "': " + e.what());
          }
        if (on_ranks)
          {
            if (evaluation)
              {
                cells            = evaluation->cell_indices();
                reference_points = evaluation->reference_coordinates();
              }
            cells = Utilities::MPI::broadcast(MPI_COMM_WORLD, cells);
            reference_points =
              Utilities::MPI::broadcast(MPI_COMM_WORLD, reference_points);
          }
        out << "  " << points.size() << " evaluation points from "
            << points_file << std::endl;
      }

      void
      EvaluationPoints::add_answer(const Run              &run,
                                   const Report::ModelRun &model_run,
                                   Models::Interface      &model,
                                   const bool              from_basis)
      {
        // A field on the ranks' parts of the mesh (the quadratic reference
        // there) is evaluated by all ranks.
        std::vector<Tensor<1, 3>> values;
        const bool                on_ranks =
          !from_basis && Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1 &&
          model.displacement_field_at(points, cells, reference_points, values);
        const auto [field_dofs, field] = model.displacement_field();
        if (evaluation && run.writes_outputs)
          write_point_values_csv(evaluation->points(),
                                 on_ranks ?
                                   values :
                                 field_dofs != nullptr && !from_basis ?
                                   evaluation->evaluate(*field_dofs, *field) :
                                   evaluation->evaluate(run.scene.dof_handler,
                                                        model_run.displacement),
                                 run.directory + "/evaluation_" +
                                   file_name_of(model_run.label()) + ".csv");
      }
    } // namespace

    SOFTFACE_REGISTER_OUTPUT(EvaluationPoints,
                             "evaluation points",
                             "evaluation_<model>.csv ('Evaluation points'): "
                             "each model's displacement at the points a CSV "
                             "file lists")
  } // namespace Outputs
} // namespace softface
