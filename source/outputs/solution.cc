// The 'solution' output: solution.vtu (or, on several MPI ranks,
// solution.pvtu and a piece per rank) with every model's displacement and the
// scene's labels for ParaView ('Output/Write VTU').

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/lac/la_parallel_vector.h>
#include <deal.II/numerics/data_out.h>

#include <softface/core/distributed_layout.h>
#include <softface/core/error.h>
#include <softface/io/output_file.h>
#include <softface/outputs/interface.h>
#include <softface/outputs/solution.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>

namespace softface
{
  namespace Outputs
  {
    namespace
    {
      /// A vertex's join flag (1: a join point) and segment id (-1: free)
      /// of its segment @p s.
      template <typename Number>
      void
      set_vertex_flags(const unsigned int s, Number &join, Number &segment)
      {
        join    = (s == numbers::invalid_unsigned_int) ? 0. : 1.;
        segment = (s == numbers::invalid_unsigned_int) ? -1. : s;
      }

      /**
       * The fields of write_vtu(), named and ordered as it writes them, into
       * @p data_out (attached to their mesh): each successful run's
       * displacement (@p displacements, in the runs' order) on
       * @p vector_dofs, the join flags and segment ids on @p scalar_dofs, the
       * cells' material ids. Patches built, ready to write; DataOut refers
       * to the vectors.
       */
      template <typename Displacement, typename PerVertex>
      void
      add_fields(DataOut<3>                              &data_out,
                 const DoFHandler<3>                     &vector_dofs,
                 const std::vector<Report::ModelRun>     &runs,
                 const std::vector<const Displacement *> &displacements,
                 const DoFHandler<3>                     &scalar_dofs,
                 const PerVertex                         &join_flag,
                 const PerVertex                         &segment_id,
                 const Vector<float>                     &material,
                 const Mapping<3>                        &mapping)
      {
        const std::vector<
          DataComponentInterpretation::DataComponentInterpretation>
          vector(3, DataComponentInterpretation::component_is_part_of_vector);
        unsigned int next = 0;
        for (const Report::ModelRun &run : runs)
          if (!run.failed)
            data_out.add_data_vector(vector_dofs,
                                     *displacements[next++],
                                     std::vector<std::string>(3,
                                                              "displacement_" +
                                                                file_name_of(
                                                                  run.label())),
                                     vector);
        data_out.add_data_vector(scalar_dofs, join_flag, "join_point");
        data_out.add_data_vector(scalar_dofs, segment_id, "segment_id");
        data_out.add_data_vector(material, "material_id");
        data_out.build_patches(mapping);
        // zlib at its strongest spends seconds on large meshes for little
        // gain.
        DataOutBase::VtkFlags flags;
        flags.compression_level = DataOutBase::VtkFlags::best_speed;
        data_out.set_flags(flags);
      }

      /**
       * The fields of write_vtu() on the cells [first_cell, end_cell) of the
       * scene's order, ready to write (DataOut refers to the vectors here).
       */
      struct Fields
      {
        Fields(const Scene                         &scene,
               const std::vector<Report::ModelRun> &runs,
               const unsigned int                   first_cell,
               const unsigned int                   end_cell);

        // Per-vertex flags live on a scalar P1 layout beside the vector one.
        DoFHandler<3>  scalar_dofs;
        Vector<double> join_flag, segment_id;
        Vector<float>  material;
        DataOut<3>     data_out;
      };

      Fields::Fields(const Scene                         &scene,
                     const std::vector<Report::ModelRun> &runs,
                     const unsigned int                   first_cell,
                     const unsigned int                   end_cell)
      {
        scalar_dofs.reinit(scene.triangulation);
        scalar_dofs.distribute_dofs(FE_SimplexP<3>(1));
        join_flag.reinit(scalar_dofs.n_dofs());
        segment_id.reinit(scalar_dofs.n_dofs());
        for (const auto &cell : scalar_dofs.active_cell_iterators())
          for (const unsigned int v : cell->vertex_indices())
            {
              const auto dof = cell->vertex_dof_index(v, 0);
              set_vertex_flags(scene.vertex_segment()[cell->vertex_index(v)],
                               join_flag[dof],
                               segment_id[dof]);
            }
        material.reinit(scene.triangulation.n_active_cells());
        for (const auto &cell : scene.triangulation.active_cell_iterators())
          material[cell->active_cell_index()] = cell->material_id();

        std::vector<const Vector<double> *> displacements;
        for (const Report::ModelRun &run : runs)
          if (!run.failed)
            displacements.push_back(&run.displacement);
        using Cell          = typename Triangulation<3>::cell_iterator;
        const auto in_range = [first_cell, end_cell](const Cell &cell) {
          return cell->is_active() && cell->active_cell_index() >= first_cell &&
                 cell->active_cell_index() < end_cell;
        };
        const auto next_in_range = [in_range](const Triangulation<3> &tria,
                                              const Cell             &cell) {
          Cell next = cell;
          for (++next; next != tria.end() && !in_range(next); ++next)
            ;
          return next;
        };
        data_out.set_cell_selection(
          [in_range, next_in_range](const Triangulation<3> &tria) {
            const Cell first = tria.begin();
            return in_range(first) ? first : next_in_range(tria, first);
          },
          next_in_range);
        data_out.attach_triangulation(scene.triangulation);
        add_fields(data_out,
                   scene.dof_handler,
                   runs,
                   displacements,
                   scalar_dofs,
                   join_flag,
                   segment_id,
                   material,
                   scene.mapping);
      }
    } // namespace

    namespace
    {
      /// The fields of an earlier run on another number of ranks, which
      /// ParaView would otherwise open beside this run's: for a run on
      /// @p n_ranks ranks (1: serial) <stem>.vtu, or <stem>.pvtu, or the
      /// pieces <stem>.<r>.vtu from rank n_ranks on.
      void
      remove_stale_fields(const std::string &stem, const unsigned int n_ranks)
      {
        std::filesystem::remove(stem + (n_ranks > 1 ? ".vtu" : ".pvtu"));
        for (unsigned int r = n_ranks > 1 ? n_ranks : 0;
             std::filesystem::remove(stem + "." + std::to_string(r) + ".vtu");
             ++r)
          ;
      }
    } // namespace

    namespace
    {
      /// This rank's piece <stem>.<rank>.vtu of @p data_out and, on rank 0,
      /// the record <stem>.pvtu of every rank's (stale fields removed).
      void
      write_piece_and_record(const DataOut<3>  &data_out,
                             const std::string &stem,
                             const MPI_Comm     communicator)
      {
        const unsigned int n_ranks =
          Utilities::MPI::n_mpi_processes(communicator);
        const unsigned int rank =
          Utilities::MPI::this_mpi_process(communicator);
        const std::string name =
          std::filesystem::path(stem).filename().string();
        {
          std::ofstream out =
            open_output_file(stem + "." + std::to_string(rank) + ".vtu");
          data_out.write_vtu(out);
        }
        if (rank == 0)
          {
            remove_stale_fields(stem, n_ranks);
            std::vector<std::string> pieces;
            for (unsigned int r = 0; r < n_ranks; ++r)
              pieces.push_back(name + "." + std::to_string(r) + ".vtu");
            std::ofstream out = open_output_file(stem + ".pvtu");
            data_out.write_pvtu_record(out, pieces);
          }
      }
    } // namespace

    void
    write_vtu(const Scene                         &scene,
              const std::vector<Report::ModelRun> &runs,
              const std::string                   &filename)
    {
      if (filename.size() > 4 &&
          filename.compare(filename.size() - 4, 4, ".vtu") == 0)
        remove_stale_fields(filename.substr(0, filename.size() - 4), 1);
      const Fields fields(scene, runs, 0, scene.triangulation.n_active_cells());
      std::ofstream out = open_output_file(filename);
      fields.data_out.write_vtu(out);
    }

    void
    write_pvtu(const DistributedLayout             &layout,
               const std::vector<Report::ModelRun> &runs,
               const std::string                   &stem)
    {
      const MPI_Comm communicator = layout.communicator;
      const auto     vertex_cell =
        [&layout](const DoFHandler<3>::active_cell_iterator &cell) {
          return DoFHandler<3>::active_cell_iterator(&layout.triangulation,
                                                     cell->level(),
                                                     cell->index(),
                                                     &layout.dof_handler);
        };

      // The values at the DoFs this rank owns, from the whole answers every
      // rank holds; DataOut fetches those at the ghost DoFs of its cells
      // itself (it copies the owned entries into a ghosted vector).
      using Values = LinearAlgebra::distributed::Vector<double>;
      std::vector<Values> displacements;
      for (const Report::ModelRun &run : runs)
        if (!run.failed)
          {
            Values u(layout.locally_owned_dofs, communicator);
            for (const auto dof : layout.locally_owned_dofs)
              u(dof) = run.displacement[layout.serial_dof(dof)];
            displacements.push_back(std::move(u));
          }
      // Every owned vertex is a vertex of an owned cell.
      DoFHandler<3> scalar_dofs(layout.triangulation);
      scalar_dofs.distribute_dofs(FE_SimplexP<3>(1));
      const IndexSet &scalar_owned = scalar_dofs.locally_owned_dofs();
      Values          join_flag(scalar_owned, communicator);
      Values          segment_id(join_flag);
      Vector<float>   material(layout.triangulation.n_active_cells());
      for (const auto &cell : scalar_dofs.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            material[cell->active_cell_index()] = cell->material_id();
            const auto with_vector_dofs         = vertex_cell(cell);
            for (const unsigned int v : cell->vertex_indices())
              if (const auto dof = cell->vertex_dof_index(v, 0);
                  scalar_owned.is_element(dof))
                set_vertex_flags(layout.join_segment_of_dof(
                                   with_vector_dofs->vertex_dof_index(v, 0)),
                                 join_flag(dof),
                                 segment_id(dof));
          }

      std::vector<const Values *> pointers;
      for (const Values &u : displacements)
        pointers.push_back(&u);
      DataOut<3> data_out;
      data_out.attach_triangulation(layout.triangulation);
      add_fields(data_out,
                 layout.dof_handler,
                 runs,
                 pointers,
                 scalar_dofs,
                 join_flag,
                 segment_id,
                 material,
                 layout.scene.mapping);

      write_piece_and_record(data_out, stem, communicator);
    }

    void
    write_pvtu(const Scene                         &scene,
               const std::vector<Report::ModelRun> &runs,
               const std::string                   &stem,
               const MPI_Comm                       communicator)
    {
      const unsigned int n_ranks =
        Utilities::MPI::n_mpi_processes(communicator);
      const unsigned int  rank = Utilities::MPI::this_mpi_process(communicator);
      const std::uint64_t n_cells = scene.triangulation.n_active_cells();
      // The cells c with c * n_ranks / n_cells == rank, as the 'cell order'
      // partition gives them.
      const auto first_of = [&](const unsigned int r) {
        return static_cast<unsigned int>(
          (std::uint64_t(r) * n_cells + n_ranks - 1) / n_ranks);
      };
      const Fields fields(scene, runs, first_of(rank), first_of(rank + 1));
      write_piece_and_record(fields.data_out, stem, communicator);
    }

    namespace
    {
      class Solution : public Interface
      {
      public:
        static void
        declare_parameters(ParameterHandler &prm)
        {
          prm.declare_entry("Write VTU",
                            "true",
                            Patterns::Bool(),
                            "Write solution.vtu: every model's displacement, "
                            "the join flag and segment id per vertex, "
                            "material ids.");
        }

        void
        parse_parameters(ParameterHandler &prm, const std::string &) override
        {
          asked = prm.get_bool("Write VTU");
        }

        bool
        requested() const override
        {
          return asked;
        }

        void
        write(const Run &run, std::ostream &) override
        {
          if (Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) == 1)
            {
              write_vtu(run.scene, run.runs, run.directory + "/solution.vtu");
              return;
            }
          // On several ranks each writes its piece of the fields, in rank
          // 0's folder (the only one made).
          const std::string stem =
            Utilities::MPI::broadcast(MPI_COMM_WORLD, run.directory, 0) +
            "/solution";
          // From the ranks' parts where a model made them (or a rank holds
          // no cells); a partition for output alone would cost seconds.
          if (run.layout->built() || run.members_without_cells)
            write_pvtu(run.layout->get(run.scene), run.runs, stem);
          else
            write_pvtu(run.scene, run.runs, stem, MPI_COMM_WORLD);
        }

        std::string
        files(const Run &) const override
        {
          return Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1 ?
                   "solution.pvtu with a piece per rank" :
                   "solution.vtu";
        }

      private:
        bool asked = true;
      };
    } // namespace

    SOFTFACE_REGISTER_OUTPUT(Solution,
                             "solution",
                             "solution.vtu ('Write VTU'; .pvtu and a piece per "
                             "rank on several ranks): every model's "
                             "displacement and the scene's labels")
  } // namespace Outputs
} // namespace softface
