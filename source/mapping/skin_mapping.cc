// Volume/surface mapping (Mollemans et al. 2007, Sec. 3.4, eqs. 13-14): step A
// builds, for every point of the dense skin surface, weights of
// tetrahedral-mesh vertices (the shape functions of the tetrahedron at the
// point, or inverse distances to the skin points that mesh vertices were
// matched to); step B sums them.

#include <deal.II/base/timer.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <softface/core/error.h>
#include <softface/core/tetrahedron.h>
#include <softface/mapping/skin_mapping.h>

#include <deal.II/base/timer.h>

#include <algorithm>
#include <limits>
#include <map>
#include <sstream>

namespace softface
{
  namespace SurfaceMapping
  {
    VolumeMesh
    VolumeMesh::from_triangulation(
      const Triangulation<3>             &triangulation,
      const std::set<types::boundary_id> &skin_boundary_ids)
    {
      VolumeMesh mesh;
      mesh.vertices    = triangulation.get_vertices();
      mesh.skin.points = mesh.vertices;
      for (const auto &cell : triangulation.active_cell_iterators())
        {
          std::array<unsigned int, 4> c;
          for (unsigned int v = 0; v < 4; ++v)
            c[v] = cell->vertex_index(v);
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary() &&
                (skin_boundary_ids.empty() ||
                 skin_boundary_ids.count(cell->face(f)->boundary_id()) > 0))
              {
                const auto face = cell->face(f);
                mesh.skin.triangles.push_back({{face->vertex_index(0),
                                                face->vertex_index(1),
                                                face->vertex_index(2)}});
                mesh.cell_of_skin_triangle.push_back(mesh.cells.size());
              }
          mesh.cells.push_back(c);
        }
      return mesh;
    }

    Method
    method_from_name(const std::string &name)
    {
      if (name == "shape functions")
        return Method::shape_functions;
      if (name == "inverse distance")
        return Method::inverse_distance;
      throw Error("Unknown mapping method '" + name +
                  "' (shape functions, inverse distance).");
    }

    std::string
    name_of(const Method method)
    {
      return method == Method::shape_functions ? "shape functions" :
                                                 "inverse distance";
    }

    void
    SkinMapping::map(const std::vector<Tensor<1, 3>> &vertex_displacement,
                     std::vector<Tensor<1, 3>>       &skin_displacement) const
    {
      skin_displacement.resize(n_points());
      for (unsigned int i = 0; i < n_points(); ++i)
        {
          Tensor<1, 3> u;
          for (unsigned int k = row_start[i]; k < row_start[i + 1]; ++k)
            u += weights[k] * vertex_displacement[vertices[k]];
          skin_displacement[i] = u;
        }
    }

    namespace
    {
      Tetrahedron::Vertices
      cell_vertices(const VolumeMesh &mesh, const unsigned int c)
      {
        return {{mesh.vertices[mesh.cells[c][0]],
                 mesh.vertices[mesh.cells[c][1]],
                 mesh.vertices[mesh.cells[c][2]],
                 mesh.vertices[mesh.cells[c][3]]}};
      }

      /// The four barycentric coordinates of @p p in cell @p c.
      std::array<double, 4>
      barycentric(const VolumeMesh  &mesh,
                  const unsigned int c,
                  const Point<3>    &p)
      {
        const Point<3> xi =
          Tetrahedron::reference_coordinates(cell_vertices(mesh, c), p);
        return {{1. - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]}};
      }

      void
      check_reach(const SkinMapping &mapping, const Parameters &parameters)
      {
        if (mapping.n_points() > 0 && mapping.n_outside == mapping.n_points())
          {
            std::ostringstream m;
            m << "The skin surface lies outside the mesh's reach: none of its "
              << mapping.n_points() << " points is within " << parameters.reach
              << " mm of the mesh's skin (is it in the mesh's frame, of the "
              << "same patient?).";
            throw Error(m.str());
          }
      }
    } // namespace

    SkinMapping
    shape_function_mapping(const VolumeMesh &mesh,
                           const Surface    &skin_surface,
                           const Parameters &parameters)
    {
      SkinMapping mapping;
      Timer       timer;
      const auto  lap = [&](const std::string &part) {
        mapping.step_a_parts.emplace_back(part, timer.wall_time());
        timer.restart();
      };
      using Box = std::pair<BoundingBox<3>, unsigned int>;
      std::vector<Box> boxes;
      boxes.reserve(mesh.cells.size());
      for (unsigned int c = 0; c < mesh.cells.size(); ++c)
        {
          const auto     x = cell_vertices(mesh, c);
          BoundingBox<3> box(std::vector<Point<3>>(x.begin(), x.end()));
          box.extend(1e-10 *
                     std::sqrt(box.get_boundary_points().first.distance_square(
                       box.get_boundary_points().second)));
          boxes.emplace_back(box, c);
        }
      const auto           cell_tree = pack_rtree(boxes);
      const TriangleSearch skin_search(mesh.skin);
      lap("trees");

      // First the containing tetrahedra; the points outside the mesh are
      // projected afterwards (timed apart).
      std::vector<Box>                   candidates;
      std::vector<unsigned int>          cell_of(skin_surface.points.size(),
                                        numbers::invalid_unsigned_int);
      std::vector<std::array<double, 4>> lambda_of(skin_surface.points.size());
      for (unsigned int i = 0; i < skin_surface.points.size(); ++i)
        {
          const Point<3> &p = skin_surface.points[i];
          // The containing tetrahedron: the candidate with the largest
          // smallest barycentric coordinate, if that is not negative.
          candidates.clear();
          cell_tree.query(boost::geometry::index::intersects(p),
                          std::back_inserter(candidates));
          double                best = -std::numeric_limits<double>::max();
          unsigned int          cell = numbers::invalid_unsigned_int;
          std::array<double, 4> lambda;
          for (const Box &candidate : candidates)
            {
              const auto   l        = barycentric(mesh, candidate.second, p);
              const double smallest = *std::min_element(l.begin(), l.end());
              if (smallest > best)
                {
                  best   = smallest;
                  cell   = candidate.second;
                  lambda = l;
                }
            }
          if (cell != numbers::invalid_unsigned_int && best >= -1e-10)
            {
              cell_of[i]   = cell;
              lambda_of[i] = lambda;
              ++mapping.n_inside;
            }
        }
      lap("containing tetrahedra");

      for (unsigned int i = 0; i < skin_surface.points.size(); ++i)
        {
          const Point<3> &p = skin_surface.points[i];
          if (cell_of[i] == numbers::invalid_unsigned_int &&
              !mesh.skin.triangles.empty())
            {
              // Outside: the tetrahedron of the skin face it projects onto.
              const auto hit = skin_search.closest(p);
              if (hit.distance <= parameters.reach)
                {
                  cell_of[i]   = mesh.cell_of_skin_triangle[hit.triangle];
                  lambda_of[i] = barycentric(mesh, cell_of[i], p);
                }
            }
          if (cell_of[i] == numbers::invalid_unsigned_int)
            {
              ++mapping.n_outside;
              mapping.in_reach.push_back(false);
              mapping.row_start.push_back(mapping.vertices.size());
              continue;
            }
          mapping.in_reach.push_back(true);
          for (unsigned int v = 0; v < 4; ++v)
            {
              mapping.vertices.push_back(mesh.cells[cell_of[i]][v]);
              mapping.weights.push_back(lambda_of[i][v]);
            }
          mapping.row_start.push_back(mapping.vertices.size());
        }
      lap("outside points");
      check_reach(mapping, parameters);
      return mapping;
    }

    SkinMapping
    inverse_distance_mapping(const VolumeMesh &mesh,
                             const Surface    &skin_surface,
                             const Parameters &parameters)
    {
      const unsigned int n_skin = skin_surface.points.size();
      SkinMapping        mapping;
      if (n_skin == 0)
        return mapping;
      Timer      timer;
      const auto lap = [&](const std::string &part) {
        mapping.step_a_parts.emplace_back(part, timer.wall_time());
        timer.restart();
      };

      // Match every vertex of the mesh's skin with its closest skin point.
      using Leaf = std::pair<Point<3>, unsigned int>;
      std::vector<Leaf> leaves;
      leaves.reserve(n_skin);
      for (unsigned int i = 0; i < n_skin; ++i)
        leaves.emplace_back(skin_surface.points[i], i);
      const auto skin_tree = pack_rtree(leaves);
      lap("skin tree");

      std::vector<bool> on_mesh_skin(mesh.vertices.size(), false);
      for (const auto &tri : mesh.skin.triangles)
        for (const unsigned int v : tri)
          on_mesh_skin[v] = true;
      // known[i]: the mesh vertices matched to skin point i.
      std::vector<std::vector<unsigned int>> known(n_skin);
      std::vector<Leaf>                      nearest;
      for (unsigned int v = 0; v < mesh.vertices.size(); ++v)
        if (on_mesh_skin[v])
          {
            nearest.clear();
            skin_tree.query(boost::geometry::index::nearest(mesh.vertices[v],
                                                            1),
                            std::back_inserter(nearest));
            if (mesh.vertices[v].distance(nearest[0].first) <= parameters.reach)
              known[nearest[0].second].push_back(v);
          }
      lap("matching");

      // The skin's edges, for the connectivity rings.
      std::vector<std::vector<unsigned int>> neighbours(n_skin);
      for (const auto &tri : skin_surface.triangles)
        for (unsigned int e = 0; e < 3; ++e)
          {
            neighbours[tri[e]].push_back(tri[(e + 1) % 3]);
            neighbours[tri[(e + 1) % 3]].push_back(tri[e]);
          }

      lap("edges");

      // Which points are within reach of the mesh: the matched ones, and
      // those close enough to the mesh's skin.
      const TriangleSearch mesh_skin_search(mesh.skin);
      for (unsigned int i = 0; i < n_skin; ++i)
        mapping.in_reach.push_back(
          !known[i].empty() ||
          (!mesh.skin.triangles.empty() &&
           mesh_skin_search.closest(skin_surface.points[i]).distance <=
             parameters.reach));
      lap("reach");

      std::vector<unsigned int> ring_of(n_skin, numbers::invalid_unsigned_int);
      std::vector<unsigned int> visited, front, next;
      for (unsigned int i = 0; i < n_skin; ++i)
        {
          const Point<3> &p    = skin_surface.points[i];
          const auto add_known = [&](const unsigned int j, const double w) {
            for (const unsigned int v : known[j])
              {
                mapping.vertices.push_back(v);
                mapping.weights.push_back(w / known[j].size());
              }
          };
          const bool in_reach = mapping.in_reach[i];
          if (!known[i].empty())
            add_known(i, 1.);
          else if (!in_reach)
            ++mapping.n_outside;
          else
            {
              // Points fewer than 'rings' edges away (breadth first), then
              // those of them within the radius that are known.
              visited.assign(1, i);
              ring_of[i] = 0;
              front.assign(1, i);
              for (unsigned int ring = 1; ring < parameters.rings; ++ring)
                {
                  next.clear();
                  for (const unsigned int a : front)
                    for (const unsigned int b : neighbours[a])
                      if (ring_of[b] == numbers::invalid_unsigned_int)
                        {
                          ring_of[b] = ring;
                          visited.push_back(b);
                          next.push_back(b);
                        }
                  front.swap(next);
                }
              // A known point on top of this one (a duplicated point) would
              // take all the weight: 1/distance is bounded.
              const auto inverse_distance = [&](const unsigned int j) {
                return 1. / std::max(p.distance(skin_surface.points[j]), 1e-12);
              };
              double sum = 0.;
              for (const unsigned int j : visited)
                if (!known[j].empty() &&
                    p.distance(skin_surface.points[j]) <= parameters.radius)
                  sum += inverse_distance(j);
              for (const unsigned int j : visited)
                {
                  if (!known[j].empty() &&
                      p.distance(skin_surface.points[j]) <= parameters.radius)
                    add_known(j, inverse_distance(j) / sum);
                  ring_of[j] = numbers::invalid_unsigned_int;
                }
              if (sum == 0.)
                ++mapping.n_without_neighbours;
            }
          mapping.row_start.push_back(mapping.vertices.size());
        }
      lap("rings");
      check_reach(mapping, parameters);
      return mapping;
    }

    SkinMapping
    initialise(const VolumeMesh &mesh,
               const Surface    &skin_surface,
               const Parameters &parameters)
    {
      return parameters.method == Method::shape_functions ?
               shape_function_mapping(mesh, skin_surface, parameters) :
               inverse_distance_mapping(mesh, skin_surface, parameters);
    }
  } // namespace SurfaceMapping
} // namespace softface
