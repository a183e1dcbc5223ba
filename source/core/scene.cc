// The scene every model works on (core): the mesh (generated or read), the one
// DoF layout, the tissue, and which vertices are join points of which bone
// segment (Mollemans et al. 2007, Sec. 3.3), with the checks that make the
// problem well posed.

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>
#include <deal.II/dofs/dof_accessor.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <softface/core/error.h>
#include <softface/core/mesh_source.h>
#include <softface/core/scene.h>
#include <softface/core/sub_communicator.h>
#include <softface/core/vec3_parameter.h>

#include <boost/archive/binary_iarchive.hpp>
#include <boost/archive/binary_oarchive.hpp>
#include <boost/serialization/map.hpp>
#include <boost/serialization/set.hpp>
#include <boost/serialization/string.hpp>
#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>

#include <cstdint>
#include <cstring>
#include <iterator>
#include <map>
#include <numeric>
#include <sstream>

namespace softface
{
  namespace
  {
    // A list of ids from the parameter file: "1, 3" -> {1, 3}.
    template <typename Id>
    std::set<Id>
    parse_ids(const std::string &text)
    {
      std::set<Id> ids;
      for (const std::string &entry : Utilities::split_string_list(text))
        ids.insert(static_cast<Id>(Utilities::string_to_int(entry)));
      return ids;
    }

    // Union-find with path halving, for the connectivity check.
    unsigned int
    find_root(std::vector<unsigned int> &parent, unsigned int i)
    {
      while (parent[i] != i)
        i = parent[i] = parent[parent[i]];
      return i;
    }
  } // namespace

  Tensor<1, 3>
  SceneEffects::body_force_per_unit_volume(
    const Triangulation<3>::active_cell_iterator &cell) const
  {
    Tensor<1, 3> force;
    for (const auto &rule : body_force_rules)
      force += rule->per_unit_volume(cell);
    return force;
  }

  Tensor<1, 3>
  SceneEffects::body_force_vertex_load(
    const Triangulation<3>::active_cell_iterator &cell) const
  {
    Tensor<1, 3> force;
    for (const auto &rule : body_force_rules)
      force += rule->on_cell(cell);
    return 0.25 * force;
  }

  Scene::Scene()
      : fe(FE_SimplexP<3>(1), 3)
      , mapping(FE_SimplexP<3>(1))
      , dof_handler(triangulation)
  {}

  void
  Scene::declare_parameters(ParameterHandler               &prm,
                            const std::vector<std::string> &segment_names,
                            const std::vector<std::string> &cut_names)
  {
    prm.enter_subsection("Scene");
    prm.declare_entry("Bone segments",
                      "fixed, bone",
                      Patterns::List(Patterns::Anything()),
                      "Names of the bone segments. Each has a subsection "
                      "'Segment <name>' saying which vertices touch it; those "
                      "are its join points (Mollemans et al. 2007, Sec. 3.3). "
                      "The defaults describe "
                      "the generated cube.");
    for (const std::string &name : segment_names)
      {
        prm.enter_subsection("Segment " + name);
        prm.declare_entry("Material ids",
                          name == "bone" ? "2" : "",
                          Patterns::List(Patterns::Integer(0, 255)),
                          "The vertices of cells with these material ids are "
                          "join points of this segment.");
        prm.declare_entry("Boundary ids",
                          name == "fixed" ? "1" : "",
                          Patterns::List(Patterns::Integer(0, 255)),
                          "The vertices of boundary faces with these boundary "
                          "ids are join points of this segment.");
        prm.declare_entry("Seed point",
                          "",
                          Patterns::Anything(),
                          "Patient scenes: a point 'x, y, z' (mm) in this "
                          "segment's bone; the bone part of the osteotomy "
                          "that holds it is the segment, and the soft tissue "
                          "touching that part are its join points.");
        prm.leave_subsection();
      }
    MeshSources::declare_parameters(prm, cut_names);
    prm.leave_subsection();
    Material::declare_parameters(prm);
  }

  std::vector<std::string>
  Scene::cut_names(ParameterHandler &prm)
  {
    prm.enter_subsection("Scene");
    const auto names = MeshSources::names_from_first_pass(prm);
    prm.leave_subsection();
    return names;
  }

  std::vector<std::string>
  Scene::segment_names(ParameterHandler &prm)
  {
    prm.enter_subsection("Scene");
    const auto names = Utilities::split_string_list(prm.get("Bone segments"));
    prm.leave_subsection();
    return names;
  }

  void
  Scene::parse_parameters(ParameterHandler  &prm,
                          const std::string &input_directory,
                          const std::string &work_directory,
                          std::ostream      *log,
                          const MPI_Comm     mesh_readers)
  {
    material.parse_parameters(prm);
    // A rank outside the readers holds no cells: share_without_cells().
    holds_cells = mesh_readers != MPI_COMM_NULL;

    prm.enter_subsection("Scene");
    segments.clear();
    for (const std::string &name :
         Utilities::split_string_list(prm.get("Bone segments")))
      {
        BoneSegment segment;
        segment.name = name;
        prm.enter_subsection("Segment " + name);
        segment.material_ids =
          parse_ids<types::material_id>(prm.get("Material ids"));
        segment.boundary_ids =
          parse_ids<types::boundary_id>(prm.get("Boundary ids"));
        const std::string seed = prm.get("Seed point");
        if (!seed.empty())
          {
            const auto point =
              parse_vec3(seed, "Scene/Segment " + name + "/Seed point");
            segment.seed_point = {point[0], point[1], point[2]};
          }
        prm.leave_subsection();
        segments.push_back(segment);
      }
    const auto source = MeshSources::create(prm);
    source->parse_parameters(prm, input_directory, work_directory);
    prm.leave_subsection();

    auto made = source->make_mesh(segments, triangulation, mesh_readers, log);
    mesh_description           = made.description;
    cell_name                  = std::move(made.cell_name);
    resolve_shared_join_points = made.resolve_shared_join_points;
    patient_figures            = std::move(made.figures);
    if (holds_cells)
      setup();
  }

  void
  Scene::share_without_cells(const MPI_Comm communicator)
  {
    const bool sends = Utilities::MPI::this_mpi_process(communicator) == 0;
    AssertThrow(!sends || holds_cells,
                ExcMessage("Rank 0 shares a scene it holds."));
    // A fingerprint of the mesh, which every rank with the cells compares
    // with rank 0's: a root of another group that read another file (an
    // older one of the same name on its node) would build its members'
    // parts of another mesh. A 64-bit FNV-1a hash of the vertices' bits in
    // order and of each cell's vertices, material id and boundary faces.
    const auto fingerprint = [this]() {
      std::uint64_t hash = 14695981039346656037ull;
      const auto    add  = [&hash](const std::uint64_t value) {
        for (unsigned int byte = 0; byte < 8; ++byte)
          hash = (hash ^ ((value >> (8 * byte)) & 0xff)) * 1099511628211ull;
      };
      for (const auto &vertex : triangulation.get_vertices())
        for (unsigned int d = 0; d < 3; ++d)
          {
            std::uint64_t bits;
            std::memcpy(&bits, &vertex[d], sizeof(bits));
            add(bits);
          }
      for (const auto &cell : triangulation.active_cell_iterators())
        {
          for (const unsigned int v : cell->vertex_indices())
            add(cell->vertex_index(v));
          add(cell->material_id());
          for (const auto &face : cell->face_iterators())
            add(face->at_boundary() ? face->boundary_id() : 0xffff);
        }
      return hash;
    };
    // What is not an array per vertex or DoF goes as one archive, with the
    // arrays' lengths; the arrays follow as they are, to the ranks without
    // cells only.
    std::uint64_t n_vertices_in_all = 0, n_dofs_in_all = 0,
                  n_body_force_in_all = 0, n_cells_in_all = 0, n_used = 0;
    std::uint64_t mesh_fingerprint = 0;
    std::string   small;
    if (sends)
      {
        n_vertices_in_all   = triangulation.n_vertices();
        n_dofs_in_all       = dof_handler.n_dofs();
        n_body_force_in_all = effects.body_force.size();
        n_cells_in_all      = triangulation.n_active_cells();
        n_used              = triangulation.n_used_vertices();
        mesh_fingerprint    = fingerprint();
        std::ostringstream              stream;
        boost::archive::binary_oarchive archive(stream);
        archive << n_vertices_in_all << n_dofs_in_all << n_body_force_in_all
                << n_cells_in_all << n_used << mesh_fingerprint << segments
                << resolve_shared_join_points << n_shared_join_points
                << mesh_description << n_joins_of_segment << point_blocks;
        effects.serialize_names_and_constraints(archive);
        small = stream.str();
      }
    small        = Utilities::MPI::broadcast(communicator, small, 0);
    bool differs = false;
    if (!sends)
      {
        std::istringstream              stream(small);
        boost::archive::binary_iarchive archive(stream);
        archive >> n_vertices_in_all >> n_dofs_in_all >> n_body_force_in_all >>
          n_cells_in_all >> n_used >> mesh_fingerprint;
        if (holds_cells)
          differs = fingerprint() != mesh_fingerprint;
        else
          {
            archive >> segments >> resolve_shared_join_points >>
              n_shared_join_points >> mesh_description >> n_joins_of_segment >>
              point_blocks;
            effects.serialize_names_and_constraints(archive);
            n_cells_without_cells         = n_cells_in_all;
            n_used_vertices_without_cells = n_used;
            n_dofs_without_cells          = n_dofs_in_all;
          }
      }
    if (Utilities::MPI::max(int(differs), communicator) != 0)
      throw Error("Scene: the roots of the groups of MPI ranks read "
                  "different meshes from " +
                  mesh_description +
                  ": the mesh must be the same file on every node.");

    const SubCommunicator receivers(communicator, sends || !holds_cells);
    if (receivers.communicator == MPI_COMM_NULL)
      return;
    std::vector<unsigned char> join;
    if (sends)
      join.assign(is_join_dof.begin(), is_join_dof.end());
    else
      {
        vertices_without_cells.resize(n_vertices_in_all);
        vertex_dof_indices.resize(n_vertices_in_all);
        segment_of_vertex.resize(n_vertices_in_all);
        join.resize(n_dofs_in_all);
        effects.body_force.reinit(n_body_force_in_all);
      }
    static_assert(sizeof(Point<3>) == 3 * sizeof(double) &&
                    sizeof(vertex_dof_indices[0]) ==
                      3 * sizeof(types::global_dof_index),
                  "points and DoF triples are sent as plain arrays");
    const MPI_Comm to = receivers.communicator;
    // The root only reads its buffer: rank 0 sends its mesh's own vertices.
    Point<3> *positions =
      sends ? const_cast<Point<3> *>(triangulation.get_vertices().data()) :
              vertices_without_cells.data();
    Utilities::MPI::broadcast(reinterpret_cast<double *>(positions),
                              3 * n_vertices_in_all,
                              0,
                              to);
    Utilities::MPI::broadcast(reinterpret_cast<types::global_dof_index *>(
                                vertex_dof_indices.data()),
                              3 * vertex_dof_indices.size(),
                              0,
                              to);
    Utilities::MPI::broadcast(segment_of_vertex.data(),
                              segment_of_vertex.size(),
                              0,
                              to);
    Utilities::MPI::broadcast(join.data(), join.size(), 0, to);
    Utilities::MPI::broadcast(effects.body_force.begin(),
                              effects.body_force.size(),
                              0,
                              to);
    if (!sends)
      is_join_dof.assign(join.begin(), join.end());
  }

  void
  Scene::setup()
  {
    Mesh::check_cells(triangulation, mesh_description, cell_name);
    if (segments.empty())
      throw Error("Scene: no bone segment is defined; without join points "
                  "every displacement is undetermined.");

    dof_handler.distribute_dofs(fe);
    vertex_dof_indices.assign(triangulation.n_vertices(),
                              {{numbers::invalid_dof_index,
                                numbers::invalid_dof_index,
                                numbers::invalid_dof_index}});
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        for (unsigned int c = 0; c < 3; ++c)
          vertex_dof_indices[cell->vertex_index(v)][c] =
            cell->vertex_dof_index(v, c);

    point_blocks = true;
    for (const auto &dofs : vertex_dof_indices)
      if (dofs[0] != numbers::invalid_dof_index)
        point_blocks &= (dofs[0] % 3 == 0 && dofs[1] == dofs[0] + 1 &&
                         dofs[2] == dofs[0] + 2);

    find_join_points();
    check_free_region_connectivity();
  }

  void
  Scene::apply_rules()
  {
    Assert(holds_cells, ExcMessage("This rank holds no cell of the scene."));
    effects.tissue_of_cell.clear();
    if (effects.tissue_rule)
      {
        effects.tissue_of_cell.reserve(triangulation.n_active_cells());
        for (const auto &cell : triangulation.active_cell_iterators())
          effects.tissue_of_cell.push_back(effects.tissue(cell));
      }
    effects.body_force.reinit(0);
    if (has_body_force())
      {
        effects.body_force.reinit(dof_handler.n_dofs());
        for (const auto &cell : triangulation.active_cell_iterators())
          {
            const Tensor<1, 3> load = effects.body_force_vertex_load(cell);
            for (unsigned int a = 0; a < 4; ++a)
              for (unsigned int i = 0; i < 3; ++i)
                effects
                  .body_force[vertex_dof_indices[cell->vertex_index(a)][i]] +=
                  load[i];
          }
      }
  }

  void
  add_segment_claims(const std::vector<BoneSegment>               &segments,
                     const Triangulation<3>::active_cell_iterator &cell,
                     std::vector<std::map<unsigned int, unsigned int>> &claims)
  {
    for (unsigned int s = 0; s < segments.size(); ++s)
      {
        if (segments[s].material_ids.count(cell->material_id()))
          for (const unsigned int v : cell->vertex_indices())
            ++claims[cell->vertex_index(v)][s];
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() &&
              segments[s].boundary_ids.count(face->boundary_id()))
            for (const unsigned int v : face->vertex_indices())
              ++claims[face->vertex_index(v)][s];
      }
  }

  std::string
  shared_join_point_error(const std::string                          &vertex,
                          const std::vector<BoneSegment>             &segments,
                          const std::map<unsigned int, unsigned int> &claims)
  {
    return "Scene: " + vertex + " touches both bone segment '" +
           segments[claims.begin()->first].name + "' and '" +
           segments[std::next(claims.begin())->first].name +
           "'; a join point belongs to one segment.";
  }

  void
  Scene::find_join_points()
  {
    const unsigned int free = numbers::invalid_unsigned_int;
    segment_of_vertex.assign(triangulation.n_vertices(), free);
    n_joins_of_segment.assign(segments.size(), 0);
    n_shared_join_points = 0;

    // How many of a vertex's bone cells and faces belong to each segment.
    std::vector<std::map<unsigned int, unsigned int>> claims(
      triangulation.n_vertices());
    for (const auto &cell : triangulation.active_cell_iterators())
      add_segment_claims(segments, cell, claims);

    for (unsigned int vertex = 0; vertex < claims.size(); ++vertex)
      {
        const auto &c = claims[vertex];
        if (c.empty())
          continue;
        if (c.size() > 1 && !resolve_shared_join_points)
          {
            std::ostringstream where;
            where << "vertex " << vertex << " at ("
                  << triangulation.get_vertices()[vertex] << ')';
            throw Error(shared_join_point_error(where.str(), segments, c));
          }
        // Where a cut leaves a vertex touching two bone parts (patient
        // meshes), the tissue covers the saw kerf and is attached to
        // neither part: the vertex is free.
        if (c.size() > 1)
          {
            ++n_shared_join_points;
            continue;
          }
        segment_of_vertex[vertex] = join_segment(c);
        ++n_joins_of_segment[segment_of_vertex[vertex]];
      }
    for (unsigned int s = 0; s < segments.size(); ++s)
      if (n_joins_of_segment[s] == 0 && !segments[s].carries_contact_only)
        {
          std::ostringstream m;
          m << "Scene: bone segment '" << segments[s].name
            << "' selects no vertex of mesh " << mesh_description
            << " (material ids {";
          for (const auto id : segments[s].material_ids)
            m << ' ' << static_cast<unsigned int>(id);
          m << " }, boundary ids {";
          for (const auto id : segments[s].boundary_ids)
            m << ' ' << static_cast<unsigned int>(id);
          m << " }).";
          throw Error(m.str());
        }

    for (unsigned int s = 0; s < segments.size(); ++s)
      if (segments[s].join_centroid.empty() && n_joins_of_segment[s] > 0)
        {
          Point<3> centre;
          for (unsigned int v = 0; v < triangulation.n_vertices(); ++v)
            if (segment_of_vertex[v] == s)
              centre += triangulation.get_vertices()[v];
          centre /= n_joins_of_segment[s];
          segments[s].join_centroid = {centre[0], centre[1], centre[2]};
        }

    is_join_dof.assign(dof_handler.n_dofs(), false);
    for (unsigned int v = 0; v < triangulation.n_vertices(); ++v)
      if (segment_of_vertex[v] != free &&
          vertex_dof_indices[v][0] != numbers::invalid_dof_index)
        for (const auto dof : vertex_dof_indices[v])
          is_join_dof[dof] = true;
  }

  void
  Scene::check_free_region_connectivity() const
  {
    // Every connected piece of the mesh must contain a join point: a piece
    // without one could move freely and make the system singular.
    std::vector<unsigned int> parent(triangulation.n_vertices());
    std::iota(parent.begin(), parent.end(), 0u);
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        const unsigned int root0 = find_root(parent, cell->vertex_index(0));
        for (unsigned int v = 1; v < 4; ++v)
          parent[find_root(parent, cell->vertex_index(v))] = root0;
      }

    std::vector<bool> component_has_join(parent.size(), false);
    for (unsigned int v = 0; v < parent.size(); ++v)
      if (segment_of_vertex[v] != numbers::invalid_unsigned_int)
        component_has_join[find_root(parent, v)] = true;

    unsigned int n_stranded = 0, example = 0;
    for (unsigned int v = 0; v < parent.size(); ++v)
      if (vertex_dof_indices[v][0] != numbers::invalid_dof_index &&
          !component_has_join[find_root(parent, v)])
        {
          if (n_stranded++ == 0)
            example = v;
        }
    if (n_stranded > 0)
      {
        std::ostringstream m;
        m << "Scene: " << n_stranded << " free vertices (e.g. vertex "
          << example << " at (" << triangulation.get_vertices()[example]
          << ")) of mesh " << mesh_description
          << " form a region connected to no join point, so their "
             "displacement is undetermined. Let a bone segment hold that "
             "region or remove it from the mesh.";
        throw Error(m.str());
      }
  }

  unsigned int
  Scene::segment_index(const std::string &name) const
  {
    for (unsigned int s = 0; s < segments.size(); ++s)
      if (segments[s].name == name)
        return s;
    std::string known;
    for (const auto &s : segments)
      known += (known.empty() ? "'" : ", '") + s.name + "'";
    throw Error("Unknown bone segment '" + name +
                "'; the scene's segments are " + known + ".");
  }

  unsigned int
  Scene::n_vertices() const
  {
    return holds_cells ? triangulation.n_used_vertices() :
                         n_used_vertices_without_cells;
  }

  unsigned int
  Scene::n_cells() const
  {
    return holds_cells ? triangulation.n_active_cells() : n_cells_without_cells;
  }

  types::global_dof_index
  Scene::n_dofs() const
  {
    return holds_cells ? dof_handler.n_dofs() : n_dofs_without_cells;
  }

  const std::vector<Point<3>> &
  Scene::vertices() const
  {
    return holds_cells ? triangulation.get_vertices() : vertices_without_cells;
  }

  unsigned int
  Scene::n_free_dofs() const
  {
    return std::count(is_join_dof.begin(), is_join_dof.end(), false);
  }

  unsigned int
  Scene::n_join_vertices(const unsigned int segment) const
  {
    return n_joins_of_segment.at(segment);
  }

  const std::vector<std::array<types::global_dof_index, 3>> &
  Scene::vertex_dofs() const
  {
    return vertex_dof_indices;
  }

  const std::vector<unsigned int> &
  Scene::vertex_segment() const
  {
    return segment_of_vertex;
  }

  const std::vector<bool> &
  Scene::join_dofs() const
  {
    return is_join_dof;
  }

  bool
  Scene::dofs_are_point_blocks() const
  {
    return point_blocks;
  }
} // namespace softface
