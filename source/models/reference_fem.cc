// The reference model (models): the nonlinear FEM equations on quadratic
// tetrahedra on a layout of its own, by quadrature; the accuracy benchmark's
// converged answer. The Newton solve is NonlinearElasticity's.

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_accessor.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <softface/core/release.h>
#include <softface/fe/elasticity.h>
#include <softface/models/reference_fem.h>

#include <algorithm>
#include <array>
#include <map>
#include <set>

namespace softface
{
  namespace Models
  {
    namespace
    {
      // The weights of a tetrahedron's four vertices at the point xi of the
      // unit cell (its barycentric coordinates).
      std::array<double, 4>
      vertex_weights(const Point<3> &xi)
      {
        return {{1. - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]}};
      }

      // The join rules of a cell beyond its vertices' own DoFs, serially and
      // on the ranks: every DoF of a segment's cell, of a segment's boundary
      // face, and of a cell whose four vertices are join points of two or
      // more segments (@p vertex_join(a), @p vertex_segment(a) of its
      // vertex a). Such a cell (across the kerf of an osteotomy, between the
      // teeth) is carried by the bones whole, as on the P1 layout: its edge
      // and face DoFs follow the vertices too. Otherwise it keeps free
      // mid-edge DoFs but no freedom to avoid the shape the bones' relative
      // motion forces on it, and the solve stops where the planning crushes
      // it, which the P1 models pass. A cell on one segment only moves with
      // it rigidly and keeps its free DoFs.
      template <typename Segments,
                typename VertexJoin,
                typename VertexSegment,
                typename Mark>
      void
      mark_cell_join_dofs(const DoFHandler<3>::active_cell_iterator  &cell,
                          const std::vector<types::global_dof_index> &dofs,
                          const Segments                             &segments,
                          const VertexJoin    &vertex_join,
                          const VertexSegment &vertex_segment,
                          const Mark          &mark)
      {
        bool bone_cell = false;
        for (const auto &segment : segments)
          bone_cell |= segment.material_ids.count(cell->material_id()) > 0;
        std::set<unsigned int> segments_of_vertices;
        bool                   vertices_join = true;
        for (const unsigned int a : cell->vertex_indices())
          {
            vertices_join &= vertex_join(a);
            segments_of_vertices.insert(vertex_segment(a));
          }
        if (bone_cell || (vertices_join && segments_of_vertices.size() >= 2))
          {
            for (const auto i : dofs)
              mark(i);
            return;
          }
        std::vector<types::global_dof_index> face_dofs;
        for (const unsigned int f : cell->face_indices())
          if (cell->face(f)->at_boundary())
            for (const auto &segment : segments)
              if (segment.boundary_ids.count(cell->face(f)->boundary_id()))
                {
                  face_dofs.resize(cell->get_fe().n_dofs_per_face(f));
                  cell->face(f)->get_dof_indices(face_dofs);
                  for (const auto i : face_dofs)
                    mark(i);
                }
      }
    } // namespace

    ReferenceFEM::ReferenceFEM()
        : NonlinearElasticity("reference fem")
    {}

    void
    ReferenceFEM::declare_parameters(ParameterHandler &prm)
    {
      NonlinearElasticity::declare_parameters(prm);
      prm.declare_entry("Polynomial degree",
                        "2",
                        Patterns::Integer(1, 2),
                        "Degree of the tetrahedra: 2 (quadratic, the "
                        "reference) or 1 (the nonlinear FEM model's "
                        "discretisation, here by quadrature: a cross-check).");
    }

    void
    ReferenceFEM::parse_parameters(ParameterHandler &prm)
    {
      NonlinearElasticity::parse_parameters(prm);
      degree = prm.get_integer("Polynomial degree");
    }

    unsigned int
    ReferenceFEM::honoured_effects() const
    {
      return SceneEffects::cell_materials | SceneEffects::body_forces;
    }

    void
    ReferenceFEM::set_degree(const unsigned int d)
    {
      degree = d;
    }

    void
    ReferenceFEM::setup_layout()
    {
      const auto timed = phase("layout");
      fe = std::make_unique<FESystem<3>>(FE_SimplexP<3>(degree), 3);
      dof_handler.reset();
      release(at_vertex_dof);
      release(all_join_cell);
      solution.reinit(0);
      has_solution = false;
      release(relevant_solution);
      release(rank_cells);
      release(rank_cell_dofs);
      release(rank_cell_all_join);
      release(rank_vertex_dofs);
      layout_body_force.reinit(0);
      ranks_dofs.reset();
      add_detail("degree", degree);
      if (Utilities::MPI::n_mpi_processes(communicator) > 1 &&
          why_not_on_ranks().empty())
        setup_ranks();
      else
        setup_serial();

      tissue_lame.clear();
      for (unsigned int t = 0; t < scene->n_tissues(); ++t)
        tissue_lame.push_back(scene->tissue(t).lame());
    }

    void
    ReferenceFEM::setup_serial()
    {
      dof_handler = std::make_unique<DoFHandler<3>>(scene->triangulation);
      dof_handler->distribute_dofs(*fe);
      const unsigned int n = dof_handler->n_dofs();

      // Join DoFs: the DoFs at join vertices and mark_cell_join_dofs()'s.
      // The support points serve ML's rigid-body modes.
      const auto        &unit_points = fe->get_unit_support_points();
      const unsigned int n_cell      = fe->n_dofs_per_cell();
      is_join.assign(n, false);
      at_vertex_dof.assign(scene->dof_handler.n_dofs(),
                           numbers::invalid_dof_index);
      dof_points.resize(n);
      dof_component.resize(n);
      std::vector<types::global_dof_index> dofs(n_cell);
      for (const auto &cell : dof_handler->active_cell_iterators())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int i = 0; i < n_cell; ++i)
            {
              const unsigned int c  = fe->system_to_component_index(i).first;
              const Point<3>    &xi = unit_points[i];
              const std::array<double, 4> weight = vertex_weights(xi);
              Point<3>                    x;
              for (unsigned int a = 0; a < 4; ++a)
                {
                  const auto vertex_dof =
                    scene->vertex_dofs()[cell->vertex_index(a)][c];
                  x += weight[a] * cell->vertex(a);
                  if (weight[a] == 1.)
                    {
                      at_vertex_dof[vertex_dof] = dofs[i];
                      if (scene->join_dofs()[vertex_dof])
                        is_join[dofs[i]] = true;
                    }
                }
              dof_points[dofs[i]]    = x;
              dof_component[dofs[i]] = c;
            }
          mark_cell_join_dofs(
            cell,
            dofs,
            scene->segments,
            [&](const unsigned int a) {
              return bool(
                scene->join_dofs()[scene->vertex_dofs()[cell->vertex_index(a)]
                                                       [0]]);
            },
            [&](const unsigned int a) {
              return scene->vertex_segment()[cell->vertex_index(a)];
            },
            [&](const types::global_dof_index i) { is_join[i] = true; });
        }

      all_join_cell.assign(scene->triangulation.n_active_cells(), false);
      for (const auto &cell : dof_handler->active_cell_iterators())
        {
          cell->get_dof_indices(dofs);
          bool all = true;
          for (const auto i : dofs)
            all &= is_join[i];
          all_join_cell[cell->active_cell_index()] = all;
        }

      DynamicSparsityPattern dsp(n, n);
      DoFTools::make_sparsity_pattern(*dof_handler, dsp);
      sparsity.copy_from(dsp);

      // The body force integrated against this layout's shape functions.
      if (scene->has_body_force())
        {
          const std::vector<DoFHandler<3>::active_cell_iterator> cells(
            dof_handler->active_cell_iterators().begin(),
            dof_handler->active_cell_iterators().end());
          layout_body_force.reinit(n);
          Elasticity::assemble_body_force(scene->mapping,
                                          QGaussSimplex<3>(3),
                                          scene->effects,
                                          cells,
                                          complete_index_set(n),
                                          layout_body_force);
          body_force = &layout_body_force;
        }
    }

    void
    ReferenceFEM::setup_ranks()
    {
      // The model's DoFs are its element's on the layout's part of the mesh,
      // numbered across the ranks by deal.II, and its whole vectors
      // (Newton's) are in that numbering: no rank builds the element on the
      // scene's whole mesh, which the members of a group of ranks may not
      // hold (Scene::has_cells()).
      ranks_layout = &distributed_layout(*scene);
      ranks_dofs = std::make_unique<DoFHandler<3>>(ranks_layout->triangulation);
      ranks_dofs->distribute_dofs(*fe);
      ranks_dof_handler = ranks_dofs.get();
      DoFTools::extract_locally_relevant_dofs(*ranks_dofs, relevant_dofs);
      ranks_serial_dofs.assign(relevant_dofs.begin(), relevant_dofs.end());
      ranks_dofs_per_cell = fe->n_dofs_per_cell();
      ranks_cell_dofs.clear();

      std::vector<unsigned char> join = collect_rank_cells();
      share_join_flags(join);
      rank_cell_all_join.assign(rank_cells.size(), true);
      for (unsigned int k = 0; k < rank_cells.size(); ++k)
        for (unsigned int i = 0; i < ranks_dofs_per_cell; ++i)
          if (!is_join[rank_cell_dofs[ranks_dofs_per_cell * k + i]])
            rank_cell_all_join[k] = false;

      if (scene->has_body_force())
        assemble_body_force_on_ranks();
    }

    std::vector<unsigned char>
    ReferenceFEM::collect_rank_cells()
    {
      const DistributedLayout      &layout = *ranks_layout;
      const types::global_dof_index n      = ranks_dofs->n_dofs();
      const IndexSet               &owned  = ranks_dofs->locally_owned_dofs();
      // The join DoFs by setup_serial()'s rules, decided for the DoFs this
      // rank owns: every cell at one of them is its own or a ghost cell, and
      // a ghost cell's face that bounds only this rank's part (boundary id
      // 0 there) touches none of them. The vertices' join points and their
      // segments are the layout's decisions, the serial ones. ML's points
      // are needed at the owned DoFs only (DistributedTangent's rows).
      const auto                &unit_points = fe->get_unit_support_points();
      const unsigned int         n_cell      = fe->n_dofs_per_cell();
      std::vector<unsigned char> join(n, 0);
      dof_points.assign(n, Point<3>());
      dof_component.assign(n, 0);
      std::vector<types::global_dof_index> dofs(n_cell);
      std::vector<bool> owned_vertex_dof_seen(owned.n_elements(), false);
      for (const auto &cell : ranks_dofs->active_cell_iterators())
        if (!cell->is_artificial())
          {
            const DoFHandler<3>::active_cell_iterator p1_cell(
              &layout.triangulation,
              cell->level(),
              cell->index(),
              &layout.dof_handler);
            cell->get_dof_indices(dofs);
            bool at_own_dof = false;
            for (unsigned int i = 0; i < n_cell; ++i)
              {
                const unsigned int c = fe->system_to_component_index(i).first;
                const std::array<double, 4> weight =
                  vertex_weights(unit_points[i]);
                Point<3> x;
                for (unsigned int a = 0; a < 4; ++a)
                  {
                    x += weight[a] * cell->vertex(a);
                    if (weight[a] == 1.)
                      {
                        const auto vertex_dof = p1_cell->vertex_dof_index(a, c);
                        if (layout.is_join_dof(vertex_dof))
                          join[dofs[i]] = 1;
                        if (owned.is_element(dofs[i]) &&
                            !owned_vertex_dof_seen[owned.index_within_set(
                              dofs[i])])
                          {
                            owned_vertex_dof_seen[owned.index_within_set(
                              dofs[i])] = true;
                            rank_vertex_dofs.emplace_back(
                              layout.serial_dof(vertex_dof), dofs[i]);
                          }
                      }
                  }
                dof_points[dofs[i]]    = x;
                dof_component[dofs[i]] = c;
                at_own_dof |= owned.is_element(dofs[i]);
              }
            mark_cell_join_dofs(
              cell,
              dofs,
              scene->segments,
              [&](const unsigned int a) {
                return layout.is_join_dof(p1_cell->vertex_dof_index(a, 0));
              },
              [&](const unsigned int a) {
                return layout.join_segment_of_dof(
                  p1_cell->vertex_dof_index(a, 0));
              },
              [&](const types::global_dof_index i) { join[i] = 1; });
            if (!at_own_dof)
              continue;
            rank_cells.push_back(cell);
            ranks_cell_dofs.insert(ranks_cell_dofs.end(),
                                   dofs.begin(),
                                   dofs.end());
          }
      rank_cell_dofs = ranks_cell_dofs;
      return join;
    }

    void
    ReferenceFEM::share_join_flags(std::vector<unsigned char> &join)
    {
      const types::global_dof_index n     = ranks_dofs->n_dofs();
      const IndexSet               &owned = ranks_dofs->locally_owned_dofs();
      // Each rank's answers for its own DoFs make the whole flags.
      Point<3>                owned_points_sum;
      types::global_dof_index next = 0;
      for (const auto dof : owned)
        {
          std::fill(join.begin() + next, join.begin() + dof, 0);
          next = dof + 1;
          owned_points_sum += dof_points[dof];
        }
      std::fill(join.begin() + next, join.end(), 0);
      const int ierr = MPI_Allreduce(MPI_IN_PLACE,
                                     join.data(),
                                     join.size(),
                                     MPI_UNSIGNED_CHAR,
                                     MPI_MAX,
                                     communicator);
      AssertThrowMPI(ierr);
      is_join.assign(join.begin(), join.end());
      release(join);
      // Rotations about the centroid of all the DoFs' points, as on one rank.
      dof_points_centroid = Point<3>(
        Utilities::MPI::sum(Tensor<1, 3>(owned_points_sum), communicator) /
        std::max<double>(n, 1));
    }

    void
    ReferenceFEM::assemble_body_force_on_ranks()
    {
      // Each rank its own DoFs' whole loads, from every cell at them, so
      // that the sum over the ranks adds one number to zeros and is the same
      // on every rank.
      layout_body_force.reinit(ranks_dofs->n_dofs());
      Elasticity::assemble_body_force(scene->mapping,
                                      QGaussSimplex<3>(3),
                                      scene->effects,
                                      rank_cells,
                                      ranks_dofs->locally_owned_dofs(),
                                      layout_body_force);
      sum_over_ranks(layout_body_force);
      body_force = &layout_body_force;
    }

    void
    ReferenceFEM::sum_over_ranks(Vector<double> &whole) const
    {
      const int ierr = MPI_Allreduce(MPI_IN_PLACE,
                                     whole.data(),
                                     whole.size(),
                                     MPI_DOUBLE,
                                     MPI_SUM,
                                     communicator);
      AssertThrowMPI(ierr);
    }

    bool
    ReferenceFEM::evaluate_on_ranks(const Vector<double> &u,
                                    Vector<double>       &forces,
                                    const bool            with_tangent) const
    {
      distributed_tangent->begin_assembly(with_tangent);
      // The serial evaluation's rule (evaluate()).
      FEValues<3>               fe_values(scene->mapping,
                            *fe,
                            QGaussSimplex<3>(3),
                            update_gradients | update_JxW_values);
      const unsigned int        n = fe->n_dofs_per_cell();
      std::vector<unsigned int> component(n);
      for (unsigned int i = 0; i < n; ++i)
        component[i] = fe->system_to_component_index(i).first;
      std::vector<double> u_cell(n);
      Vector<double>      f_cell(n);
      FullMatrix<double>  K_cell(n, n);
      // The first refused cell in the scene's order, as on one rank.
      unsigned int refused = numbers::invalid_unsigned_int;
      for (unsigned int k = 0; k < rank_cells.size(); ++k)
        {
          const auto        &cell = rank_cells[k];
          const unsigned int c    = DistributedLayout::serial_cell_index(cell);
          fe_values.reinit(cell);
          for (unsigned int i = 0; i < n; ++i)
            u_cell[i] = u[rank_cell_dofs[n * k + i]];
          const Lame &lame = tissue_lame[ranks_layout->tissue_of_cell(cell)];
          if (Elasticity::cell_response(law,
                                        lame,
                                        fe_values,
                                        component,
                                        u_cell,
                                        f_cell,
                                        with_tangent ? &K_cell : nullptr))
            distributed_tangent->add_cell(k, f_cell, K_cell);
          else if (!rank_cell_all_join[k])
            refused = std::min(refused, c);
        }
      return end_evaluation_on_ranks(forces, refused);
    }

    bool
    ReferenceFEM::evaluate(const Vector<double> &u,
                           Vector<double>       &forces,
                           SparseMatrix<double> *tangent) const
    {
      AssertThrow(!distributed_tangent,
                  ExcMessage("On several MPI ranks the model evaluates "
                             "through evaluate_on_ranks()."));
      // A 3-point-per-direction rule: exact for the quadratic element's
      // linear stiffness and accurate for its nonlinear terms.
      unsigned int refused_cell = 0;
      const bool   valid        = Elasticity::assemble(law,
                                              tissue_lame,
                                              scene->effects.tissue_of_cell,
                                              scene->mapping,
                                              *dof_handler,
                                              QGaussSimplex<3>(3),
                                              u,
                                              forces,
                                              tangent,
                                              &all_join_cell,
                                              &refused_cell);
      if (!valid)
        refusal = describe_cell(refused_cell);
      return valid;
    }

    void
    ReferenceFEM::join_motion(const Vector<double> &prescribed,
                              Vector<double>       &motion) const
    {
      // A join DoF's value is the linear interpolation of its cell's vertex
      // values (the rigid motion is affine), found cell by cell: kept per
      // DoF it took 64 bytes of every DoF on every rank.
      motion.reinit(is_join.size());
      const auto        &unit_points = fe->get_unit_support_points();
      const unsigned int n_cell      = fe->n_dofs_per_cell();
      if (ranks_dofs)
        {
          // Each rank its own DoFs, from its cells at them; summed.
          const IndexSet &owned = ranks_dofs->locally_owned_dofs();
          for (unsigned int k = 0; k < rank_cells.size(); ++k)
            {
              const DoFHandler<3>::active_cell_iterator p1_cell(
                &ranks_layout->triangulation,
                rank_cells[k]->level(),
                rank_cells[k]->index(),
                &ranks_layout->dof_handler);
              for (unsigned int i = 0; i < n_cell; ++i)
                if (const auto dof = rank_cell_dofs[n_cell * k + i];
                    is_join[dof] && owned.is_element(dof))
                  {
                    const unsigned int c =
                      fe->system_to_component_index(i).first;
                    const std::array<double, 4> weight =
                      vertex_weights(unit_points[i]);
                    double value = 0.;
                    for (unsigned int a = 0; a < 4; ++a)
                      value += weight[a] * prescribed[ranks_layout->serial_dof(
                                             p1_cell->vertex_dof_index(a, c))];
                    motion[dof] = value;
                  }
            }
          sum_over_ranks(motion);
          return;
        }
      std::vector<types::global_dof_index> dofs(n_cell);
      for (const auto &cell : dof_handler->active_cell_iterators())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int i = 0; i < n_cell; ++i)
            if (is_join[dofs[i]])
              {
                const unsigned int c  = fe->system_to_component_index(i).first;
                const Point<3>    &xi = unit_points[i];
                const std::array<double, 4> weight = vertex_weights(xi);
                double                      value  = 0.;
                for (unsigned int a = 0; a < 4; ++a)
                  value +=
                    weight[a] *
                    prescribed[scene->vertex_dofs()[cell->vertex_index(a)][c]];
                motion[dofs[i]] = value;
              }
        }
    }

    void
    ReferenceFEM::vertex_values(const Vector<double> &u,
                                Vector<double>       &displacement)
    {
      displacement.reinit(scene->n_dofs());
      has_solution = true;
      if (ranks_dofs)
        {
          // The field at the evaluation points needs this rank's DoFs only.
          relevant_solution.resize(relevant_dofs.n_elements());
          for (unsigned int k = 0; k < relevant_solution.size(); ++k)
            relevant_solution[k] = u[relevant_dofs.nth_index_in_set(k)];
          for (const auto &[vertex_dof, dof] : rank_vertex_dofs)
            displacement[vertex_dof] = u[dof];
          sum_over_ranks(displacement);
          return;
        }
      solution = u;
      for (unsigned int i = 0; i < displacement.size(); ++i)
        if (at_vertex_dof[i] != numbers::invalid_dof_index)
          displacement[i] = u[at_vertex_dof[i]];
    }

    void
    ReferenceFEM::do_solve(const Vector<double> &prescribed,
                           Vector<double>       &displacement)
    {
      has_solution = false;
      NonlinearElasticity::do_solve(prescribed, displacement);
    }

    const Vector<double> *
    ReferenceFEM::guess_in_model_numbering(const Vector<double> *guess,
                                           Vector<double> &translated) const
    {
      // Linear elements: the vertex values in the model's numbering, which
      // is its own DoFHandler's (the scene's may be renumbered) or, on the
      // ranks, the layout's. Quadratic ones have DoFs between the vertices:
      // the guess's size tells Newton it is not theirs.
      if (guess == nullptr || fe->degree != 1 ||
          guess->size() != scene->n_dofs())
        return guess;
      translated.reinit(is_join.size());
      if (ranks_dofs)
        {
          for (const auto &[vertex_dof, dof] : rank_vertex_dofs)
            translated[dof] = (*guess)[vertex_dof];
          sum_over_ranks(translated);
        }
      else
        for (unsigned int i = 0; i < at_vertex_dof.size(); ++i)
          if (at_vertex_dof[i] != numbers::invalid_dof_index)
            translated[at_vertex_dof[i]] = (*guess)[i];
      return &translated;
    }

    std::pair<const DoFHandler<3> *, const Vector<double> *>
    ReferenceFEM::displacement_field() const
    {
      if (has_solution && dof_handler)
        return {dof_handler.get(), &solution};
      return {nullptr, nullptr};
    }

    bool
    ReferenceFEM::displacement_field_at(
      const std::vector<Point<3>>     &points,
      const std::vector<unsigned int> &cells,
      const std::vector<Point<3>>     &reference_points,
      std::vector<Tensor<1, 3>>       &values) const
    {
      if (!ranks_dofs || !has_solution)
        return false;
      // Each point on the rank that owns its cell: the layout's cell has the
      // scene's cell's vertices in the same order, so the point has the same
      // reference coordinates in it (checked: they map to the point) and its
      // local shape functions are the serial cell's.
      unsigned int misplaced = numbers::invalid_unsigned_int;
      std::multimap<unsigned int, unsigned int> points_of_cell;
      for (unsigned int p = 0; p < cells.size(); ++p)
        points_of_cell.emplace(cells[p], p);
      std::vector<double>                  flat(3 * cells.size(), 0.);
      std::vector<types::global_dof_index> dofs(fe->n_dofs_per_cell());
      for (const auto &cell : ranks_dofs->active_cell_iterators())
        if (cell->is_locally_owned())
          {
            const auto [first, last] = points_of_cell.equal_range(
              DistributedLayout::serial_cell_index(cell));
            if (first == last)
              continue;
            cell->get_dof_indices(dofs);
            for (auto point = first; point != last; ++point)
              {
                const Point<3> &xi = reference_points[point->second];
                const std::array<double, 4> weight = vertex_weights(xi);
                Point<3>                    x;
                for (unsigned int a = 0; a < 4; ++a)
                  x += weight[a] * cell->vertex(a);
                // (PointEvaluation clips a point on a face into its cell.)
                if (x.distance(points[point->second]) >
                    1e-6 * (1. + cell->diameter()))
                  misplaced = std::min(misplaced, point->second);
                for (unsigned int i = 0; i < dofs.size(); ++i)
                  flat[3 * point->second +
                       fe->system_to_component_index(i).first] +=
                    relevant_solution[relevant_dofs.index_within_set(dofs[i])] *
                    fe->shape_value(i, xi);
              }
          }
      Utilities::MPI::sum(flat, communicator, flat);
      misplaced = Utilities::MPI::min(misplaced, communicator);
      AssertThrow(misplaced == numbers::invalid_unsigned_int,
                  ExcMessage("Evaluation point " +
                             std::to_string(misplaced + 1) +
                             ": its cell on the MPI ranks is not the "
                             "scene's cell of the same number."));
      values.assign(cells.size(), Tensor<1, 3>());
      for (unsigned int p = 0; p < cells.size(); ++p)
        for (unsigned int d = 0; d < 3; ++d)
          values[p][d] = flat[3 * p + d];
      return true;
    }

    SOFTFACE_REGISTER_MODEL(ReferenceFEM,
                            "reference fem",
                            "The nonlinear FEM equations on quadratic "
                            "tetrahedra (by quadrature, on a layout of its "
                            "own): the accuracy benchmark's reference.")
  } // namespace Models
} // namespace softface
