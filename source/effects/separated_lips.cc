// Separated lips (effects): the mouth slit as a cut in the mesh, its two
// sides kept from passing through each other (self-contact), in every model.

#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <softface/core/error.h>
#include <softface/core/vec3_parameter.h>
#include <softface/effects/interface.h>

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <set>
#include <sstream>

namespace softface
{
  namespace Effects
  {
    /**
     * The slit is the set of interior faces between a cell whose centre
     * lies below the slit plane and one above it, with the face centre in
     * 'Region'; on a mesh without a grid plane there it follows the cell
     * faces closest to the plane. The mesh is cut along it: a vertex of the
     * slit whose cells fall into two groups across it (every slit vertex
     * but those on the slit's inner edge, where the lips join) is duplicated
     * and the cells above get the copy. The slit's faces become boundary
     * faces (id 252) on both sides; each vertex and its copy stay apart
     * along the slit's normal n at rest: n . (u_above - u_below) >= 0, a
     * unilateral constraint (node to node: the lips may slide along each
     * other and open freely).
     */
    class SeparatedLips : public Interface
    {
    public:
      /// Boundary id of both sides of the slit (the mesh must not use it).
      static constexpr types::boundary_id slit_boundary_id = 252;

      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Slit point",
                          "",
                          Patterns::Anything(),
                          "A point 'x, y, z' (mm) of the plane the mouth "
                          "slit follows.");
        prm.declare_entry("Slit normal",
                          "0, 0, 1",
                          Patterns::Anything(),
                          "The plane's normal 'x, y, z', pointing to the "
                          "upper lip.");
        prm.declare_entry("Region",
                          "",
                          Patterns::Anything(),
                          "A box 'x0, x1, y0, y1, z0, z1' (mm) that holds the "
                          "slit: from the mouth opening on the skin to where "
                          "the lips join inside.");
        declare_active_set_iterations(prm);
      }

      void
      parse_parameters(ParameterHandler &prm) override
      {
        const std::string point_text = prm.get("Slit point");
        if (point_text.empty())
          throw Error("Slit point: give a point of the slit plane.");
        const auto p = parse_vec3(point_text, "Slit point");
        const auto n = parse_vec3(prm.get("Slit normal"), "Slit normal");
        for (unsigned int d = 0; d < 3; ++d)
          point[d] = p[d], normal[d] = n[d];
        if (!(normal.norm() > 0.))
          throw Error("Slit normal: the normal must not be zero.");
        normal /= normal.norm();
        region         = parse_region("Region", prm.get("Region"));
        max_iterations = prm.get_integer("Maximum active-set iterations");
      }

      unsigned int
      contributions() const override
      {
        return SceneEffects::free_vertex_constraints;
      }

      std::string
      prepare_mesh(Scene &scene) const override;

    protected:
      std::string
      check_and_add(Scene &scene) const override;

    private:
      Point<3>     point;
      Tensor<1, 3> normal;
      Region       region;
      unsigned int max_iterations = 50;
      // Filled by prepare_mesh(): each slit vertex below and its copy above.
      mutable std::vector<std::pair<unsigned int, unsigned int>> copies;
      mutable std::vector<Tensor<1, 3>>                          copy_normal;
    };

    namespace
    {
      using Face   = std::array<unsigned int, 3>;
      using Copies = std::vector<std::pair<unsigned int, unsigned int>>;

      Face
      sorted_face(const unsigned int a,
                  const unsigned int b,
                  const unsigned int c)
      {
        Face f = {{a, b, c}};
        std::sort(f.begin(), f.end());
        return f;
      }

      unsigned int
      find_root(std::vector<unsigned int> &parent, unsigned int i)
      {
        while (parent[i] != i)
          i = parent[i] = parent[parent[i]];
        return i;
      }

      // The mesh as arrays, to be cut: cell vertices, materials, sides;
      // boundary ids by face.
      struct MeshArrays
      {
        std::vector<Point<3>>                    vertices;
        std::vector<std::array<unsigned int, 4>> cells;
        std::vector<types::material_id>          materials;
        std::vector<bool>                        cell_above;
        std::map<Face, types::boundary_id>       boundary_of;
        // Per cell: the neighbour across each face (or -1) and whether that
        // face's centre lies in the region.
        std::vector<std::array<int, 4>>  neighbour;
        std::vector<std::array<bool, 4>> in_region;

        // Face f of cell c is on the slit: in the region, between the sides.
        bool
        slit_face(const unsigned int c, const unsigned int f) const
        {
          return neighbour[c][f] >= 0 && in_region[c][f] &&
                 cell_above[c] != cell_above[neighbour[c][f]];
        }
      };

      MeshArrays
      read_mesh(const Triangulation<3>  &tria,
                const Point<3>          &point,
                const Tensor<1, 3>      &normal,
                const Region            &region,
                const types::boundary_id slit_boundary_id)
      {
        MeshArrays mesh;
        mesh.vertices = tria.get_vertices();
        for (const auto &cell : tria.active_cell_iterators())
          {
            std::array<unsigned int, 4> v;
            for (unsigned int a = 0; a < 4; ++a)
              v[a] = cell->vertex_index(a);
            mesh.cells.push_back(v);
            mesh.materials.push_back(cell->material_id());
            mesh.cell_above.push_back((cell->center() - point) * normal >= 0.);
            std::array<int, 4>  across;
            std::array<bool, 4> inside;
            for (const unsigned int f : cell->face_indices())
              {
                const auto face = cell->face(f);
                inside[f]       = region.contains(face->center());
                across[f]       = face->at_boundary() ?
                                    -1 :
                                    cell->neighbor(f)->active_cell_index();
                if (face->at_boundary())
                  {
                    if (face->boundary_id() == slit_boundary_id)
                      throw Error("Effects/separated lips: the mesh uses "
                                  "boundary id 252, which marks the slit.");
                    mesh.boundary_of[sorted_face(face->vertex_index(0),
                                                 face->vertex_index(1),
                                                 face->vertex_index(2))] =
                      face->boundary_id();
                  }
              }
            mesh.neighbour.push_back(across);
            mesh.in_region.push_back(inside);
          }
        return mesh;
      }

      // On an unstructured mesh the cells nearest the plane zigzag, and a
      // group of cells on one side may touch the rest of the mesh only
      // across the slit and by edges or vertices: cut, it would hinge (a
      // mechanism) or float. Every group of cells joined by faces that are
      // not on the slit must be the whole mesh; a smaller one joins the
      // side around it, until none is left.
      void
      join_cut_off_groups(MeshArrays &mesh, const std::string &description)
      {
        const unsigned int n_cells = mesh.cells.size();
        for (unsigned int round = 0;; ++round)
          {
            std::vector<unsigned int> parent(n_cells);
            std::iota(parent.begin(), parent.end(), 0u);
            for (unsigned int c = 0; c < n_cells; ++c)
              for (unsigned int f = 0; f < 4; ++f)
                if (mesh.neighbour[c][f] >= 0 && !mesh.slit_face(c, f))
                  parent[find_root(parent, c)] =
                    find_root(parent, mesh.neighbour[c][f]);
            std::map<unsigned int, unsigned int> size_of_group;
            for (unsigned int c = 0; c < n_cells; ++c)
              ++size_of_group[find_root(parent, c)];
            if (size_of_group.size() == 1)
              return;
            if (round == 100)
              throw Error("Effects/separated lips: the slit in mesh " +
                          description +
                          " keeps cutting off pieces of tissue; choose a "
                          "plane and region that cut the lips cleanly.");
            unsigned int largest = 0, largest_size = 0;
            for (const auto &[root, size] : size_of_group)
              if (size > largest_size)
                largest = root, largest_size = size;
            for (unsigned int c = 0; c < n_cells; ++c)
              if (find_root(parent, c) != largest)
                mesh.cell_above[c] = !mesh.cell_above[c];
          }
      }

      std::set<Face>
      find_slit(const MeshArrays &mesh, const std::string &description)
      {
        std::set<Face> slit;
        for (unsigned int c = 0; c < mesh.cells.size(); ++c)
          for (unsigned int f = 0; f < 4; ++f)
            if (mesh.cell_above[c] && mesh.slit_face(c, f))
              {
                // The face: the three vertices the two cells share.
                std::vector<unsigned int> w;
                const auto &other = mesh.cells[mesh.neighbour[c][f]];
                for (const unsigned int a : mesh.cells[c])
                  if (std::find(other.begin(), other.end(), a) != other.end())
                    w.push_back(a);
                slit.insert(sorted_face(w[0], w[1], w[2]));
              }
        if (slit.empty())
          throw Error("Effects/separated lips: no face of mesh " + description +
                      " separates cells on the two sides of the slit plane "
                      "inside the region.");
        return slit;
      }

      // The cells around each slit vertex, grouped by the faces through the
      // vertex that are not slit faces; the groups that hold cells above the
      // plane and next to a slit face get a copy of the vertex, unless one
      // group holds both sides. Returns each vertex below and its copy.
      Copies
      duplicate_slit_vertices(MeshArrays           &mesh,
                              const std::set<Face> &slit,
                              const std::string    &description)
      {
        std::map<unsigned int, std::vector<unsigned int>> star;
        for (const Face &f : slit)
          for (const unsigned int v : f)
            star[v];
        for (unsigned int c = 0; c < mesh.cells.size(); ++c)
          for (const unsigned int v : mesh.cells[c])
            {
              const auto s = star.find(v);
              if (s != star.end())
                s->second.push_back(c);
            }
        const auto &cells = mesh.cells;
        Copies      copies;
        for (const auto &[v, around] : star)
          {
            std::vector<unsigned int> parent(around.size());
            std::iota(parent.begin(), parent.end(), 0u);
            for (unsigned int i = 0; i < around.size(); ++i)
              for (unsigned int j = i + 1; j < around.size(); ++j)
                {
                  // Shared vertices of the two cells (v among them).
                  std::vector<unsigned int> shared;
                  for (const unsigned int a : cells[around[i]])
                    if (std::find(cells[around[j]].begin(),
                                  cells[around[j]].end(),
                                  a) != cells[around[j]].end())
                      shared.push_back(a);
                  if (shared.size() == 3 &&
                      !slit.count(sorted_face(shared[0], shared[1], shared[2])))
                    parent[find_root(parent, i)] = find_root(parent, j);
                }
            std::set<unsigned int> roots_above, roots_below;
            for (unsigned int i = 0; i < around.size(); ++i)
              (mesh.cell_above[around[i]] ? roots_above : roots_below)
                .insert(find_root(parent, i));
            bool joined = false;
            for (const unsigned int r : roots_above)
              joined |= roots_below.count(r) > 0;
            if (joined)
              continue; // the slit's inner edge: the lips join here
            const unsigned int copy = mesh.vertices.size();
            mesh.vertices.push_back(mesh.vertices[v]);
            for (const unsigned int c : around)
              if (mesh.cell_above[c])
                std::replace(mesh.cells[c].begin(),
                             mesh.cells[c].end(),
                             v,
                             copy);
            copies.emplace_back(v, copy);
          }
        if (copies.empty())
          throw Error("Effects/separated lips: the slit in mesh " +
                      description +
                      " does not separate any vertex (it has no opening).");
        return copies;
      }

      // The slit's normal at each pair: the mean of its faces' normals,
      // oriented to the upper side.
      std::vector<Tensor<1, 3>>
      normals_at_copies(const std::vector<Point<3>> &vertices,
                        const std::set<Face>        &slit,
                        const Copies                &copies,
                        const Tensor<1, 3>          &normal)
      {
        std::map<unsigned int, Tensor<1, 3>> mean_normal;
        for (const Face &f : slit)
          {
            Tensor<1, 3> n = cross_product_3d(vertices[f[1]] - vertices[f[0]],
                                              vertices[f[2]] - vertices[f[0]]);
            if (n * normal < 0.)
              n = -n;
            for (const unsigned int v : f)
              mean_normal[v] += n;
          }
        std::vector<Tensor<1, 3>> copy_normal;
        for (const auto &[below, above_copy] : copies)
          copy_normal.push_back(mean_normal[below] / mean_normal[below].norm());
        return copy_normal;
      }

      // The cut mesh: the same cells (vertex order, materials) with the
      // copies; boundary ids carried over through each face's original
      // vertices, the slit's both sides @p slit_boundary_id.
      void
      make_cut_mesh(const MeshArrays        &mesh,
                    const std::set<Face>    &slit,
                    const Copies            &copies,
                    const types::boundary_id slit_boundary_id,
                    Scene                   &scene)
      {
        std::vector<unsigned int> original(mesh.vertices.size());
        std::iota(original.begin(), original.end(), 0u);
        for (const auto &[below, above_copy] : copies)
          original[above_copy] = below;
        std::vector<CellData<3>> cell_data(mesh.cells.size());
        for (unsigned int c = 0; c < mesh.cells.size(); ++c)
          {
            cell_data[c].vertices.assign(mesh.cells[c].begin(),
                                         mesh.cells[c].end());
            cell_data[c].material_id = mesh.materials[c];
          }
        Triangulation<3> &tria = scene.triangulation;
        scene.dof_handler.clear();
        tria.clear();
        tria.create_triangulation(mesh.vertices, cell_data, SubCellData());
        for (const auto &cell : tria.active_cell_iterators())
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary())
              {
                const Face key = sorted_face(original[face->vertex_index(0)],
                                             original[face->vertex_index(1)],
                                             original[face->vertex_index(2)]);
                const auto b   = mesh.boundary_of.find(key);
                face->set_boundary_id(slit.count(key) ? slit_boundary_id :
                                      b != mesh.boundary_of.end() ? b->second :
                                                                    0);
              }
      }
    } // namespace

    std::string
    SeparatedLips::prepare_mesh(Scene &scene) const
    {
      copies.clear();
      copy_normal.clear();
      const std::string &description = scene.mesh_description;
      MeshArrays         mesh =
        read_mesh(scene.triangulation, point, normal, region, slit_boundary_id);
      join_cut_off_groups(mesh, description);
      const std::set<Face> slit = find_slit(mesh, description);
      copies      = duplicate_slit_vertices(mesh, slit, description);
      copy_normal = normals_at_copies(mesh.vertices, slit, copies, normal);
      make_cut_mesh(mesh, slit, copies, slit_boundary_id, scene);
      std::ostringstream line;
      line << "separated lips: the mesh is cut along " << slit.size()
           << " faces, " << copies.size() << " vertices duplicated";
      return line.str();
    }

    std::string
    SeparatedLips::check_and_add(Scene &scene) const
    {
      if (copies.empty())
        throw Error("Effects/separated lips: the mesh was not cut (internal "
                    "error: prepare_mesh() did not run).");
      std::set<unsigned int> constrained;
      for (const auto &c : scene.effects.vertex_constraints)
        constrained.insert(c.vertex), constrained.insert(c.partner);
      unsigned int at_bone = 0, added = 0, taken = 0;
      for (unsigned int i = 0; i < copies.size(); ++i)
        {
          const auto [below, above_copy] = copies[i];
          const unsigned int free        = numbers::invalid_unsigned_int;
          if (scene.vertex_segment()[below] != free ||
              scene.vertex_segment()[above_copy] != free)
            {
              ++at_bone;
              continue;
            }
          if (constrained.count(below) || constrained.count(above_copy))
            {
              ++taken;
              continue;
            }
          VertexConstraint c;
          c.vertex     = above_copy;
          c.partner    = below;
          c.normal     = copy_normal[i];
          c.unilateral = true;
          scene.effects.vertex_constraints.push_back(c);
          ++added;
        }
      scene.effects.max_active_set_iterations =
        std::max(scene.effects.max_active_set_iterations, max_iterations);
      std::ostringstream line;
      line << "separated lips: " << added
           << " vertex pairs may not pass through each other";
      if (at_bone > 0)
        line << ", " << at_bone << " at a bone left to it";
      if (taken > 0)
        line << ", " << taken << " already constrained by another effect";
      return line.str();
    }

    SOFTFACE_REGISTER_EFFECT(
      SeparatedLips,
      "separated lips",
      "The mouth slit cut into the mesh; its two sides "
      "may open and slide but never pass through each "
      "other (self-contact), in every model but reference fem.")
  } // namespace Effects
} // namespace softface
