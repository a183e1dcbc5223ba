// The scene's layout on several MPI ranks: the serial mesh
// partitioned, the parts of a group of ranks described by its root from the
// mesh's cells (no copy of the mesh) and sent to the members as plain arrays,
// a fully distributed triangulation and DoFHandler per rank, the join points
// of each rank's vertices and the effects of its cells decided on the rank,
// and the map from its DoFs to the scene's, through which serial vectors
// reach the ranks and answers come back. See core/distributed_layout.h.

#include <deal.II/base/utilities.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria_description.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>

#include <softface/core/distributed_layout.h>
#include <softface/core/error.h>
#include <softface/core/sub_communicator.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <type_traits>

namespace softface
{
  DistributedTriangulation::DistributedTriangulation(
    const MPI_Comm communicator,
    const bool     allow_table)
      : parallel::fullydistributed::Triangulation<3>(communicator)
      , allow_table(allow_table)
  {}

  void
  DistributedTriangulation::create_triangulation(
    const TriangulationDescription::Description<3, 3> &description)
  {
    // The lookup first: deal.II's create_triangulation() sorts through
    // coarse_cell_id_to_coarse_cell_index().
    index_of_id.clear();
    sorted_ids.clear();
    const auto &ids = description.coarse_cell_index_to_coarse_cell_id;
    if (ids.empty())
      // deal.II builds a rank without cells one artificial cell, whose id
      // is the invalid one.
      sorted_ids.emplace_back(numbers::invalid_coarse_cell_id, 0);
    else
      {
        const auto [smallest, largest] =
          std::minmax_element(ids.begin(), ids.end());
        const std::uint64_t range = std::uint64_t(*largest) - *smallest + 1;
        if (allow_table && *largest != numbers::invalid_coarse_cell_id &&
            range <= 4 * std::uint64_t(ids.size()) + 1024)
          {
            first_id = *smallest;
            index_of_id.assign(range, numbers::invalid_unsigned_int);
            for (unsigned int i = 0; i < ids.size(); ++i)
              index_of_id[ids[i] - first_id] = i;
          }
        else
          {
            sorted_ids.reserve(ids.size());
            for (unsigned int i = 0; i < ids.size(); ++i)
              sorted_ids.emplace_back(ids[i], i);
            std::sort(sorted_ids.begin(), sorted_ids.end());
          }
      }
    parallel::fullydistributed::Triangulation<3>::create_triangulation(
      description);
  }

  unsigned int
  DistributedTriangulation::coarse_cell_id_to_coarse_cell_index(
    const types::coarse_cell_id coarse_cell_id) const
  {
    if (!index_of_id.empty())
      {
        const types::coarse_cell_id k = coarse_cell_id - first_id;
        AssertThrow(coarse_cell_id >= first_id && k < index_of_id.size() &&
                      index_of_id[k] != numbers::invalid_unsigned_int,
                    ExcMessage("Coarse cell " + std::to_string(coarse_cell_id) +
                               " is not on this rank."));
        return index_of_id[k];
      }
    const auto found = std::lower_bound(sorted_ids.begin(),
                                        sorted_ids.end(),
                                        std::make_pair(coarse_cell_id, 0u));
    AssertThrow(found != sorted_ids.end() && found->first == coarse_cell_id,
                ExcMessage("Coarse cell " + std::to_string(coarse_cell_id) +
                           " is not on this rank."));
    return found->second;
  }

  bool
  DistributedTriangulation::has_index_table() const
  {
    return !index_of_id.empty();
  }

  DistributedLayout::Partitioner
  DistributedLayout::parse_partitioner(const std::string &name)
  {
    if (name == "cell order")
      return Partitioner::cell_order;
    if (name == "metis")
      return Partitioner::metis;
    throw Error("Unknown partitioner '" + name +
                "'; use 'cell order' or 'metis'.");
  }

  void
  DistributedLayout::declare_partitioner(ParameterHandler &prm)
  {
    prm.declare_entry("Partitioner",
                      "cell order",
                      Patterns::Selection("cell order|metis"),
                      "On several MPI ranks (mpirun), how the cells are "
                      "shared among them: 'cell order' (contiguous pieces "
                      "of the cells' order, a space-filling curve for a "
                      "read mesh) or 'metis' (METIS on the cells' face "
                      "graph: fewer faces between the ranks).");
    prm.declare_entry("Mesh group size",
                      "1",
                      Patterns::Integer(1),
                      "On several MPI ranks, how many consecutive ranks "
                      "share one root that describes their parts of the "
                      "mesh (in one walk over it) and sends them (deal.II's "
                      "partitioning in groups). 1: every rank describes its "
                      "own part. Where every model of the run reads only its "
                      "part on the ranks (linear FEM with 'cg amg', "
                      "nonlinear FEM where it runs on the ranks) or its "
                      "points (mass tensor, mass spring) and no "
                      "effect adds vertex constraints, a group's members "
                      "then hold none of the scene's cells, only its arrays "
                      "per vertex and DoF: one group per node (G = ranks "
                      "per node, ranks placed on nodes in blocks) holds the "
                      "serial mesh once per node. Otherwise every rank holds "
                      "the whole scene, and a group only costs its root "
                      "time.");
  }

  SharedDistributedLayout::SharedDistributedLayout(
    const MPI_Comm                       communicator,
    const DistributedLayout::Partitioner partitioner,
    const unsigned int                   group_size)
      : communicator(communicator)
      , partitioner(partitioner)
      , group_size(group_size)
  {}

  const DistributedLayout &
  SharedDistributedLayout::get(const Scene &scene)
  {
    // One layout per run: the models keep references to it.
    AssertThrow(!layout || &layout->scene == &scene,
                ExcMessage("A shared layout serves one scene."));
    if (!layout)
      layout = std::make_unique<DistributedLayout>(scene,
                                                   communicator,
                                                   partitioner,
                                                   group_size);
    return *layout;
  }

  std::vector<types::subdomain_id>
  cell_owners(const Triangulation<3>              &mesh,
              const unsigned int                   n_parts,
              const DistributedLayout::Partitioner partitioner)
  {
    const std::uint64_t              n_cells = mesh.n_active_cells();
    std::vector<types::subdomain_id> owner(n_cells, 0);
    if (n_parts == 1)
      return owner;
    if (partitioner == DistributedLayout::Partitioner::metis)
      {
        // The graph GridTools::partition_triangulation() gives METIS,
        // without the copy of the mesh whose subdomain ids it would set.
        SparsityPattern faces;
        {
          DynamicSparsityPattern dynamic;
          GridTools::get_face_connectivity_of_cells(mesh, dynamic);
          faces.copy_from(dynamic);
        }
        std::vector<unsigned int> parts(n_cells);
        SparsityTools::partition(faces,
                                 n_parts,
                                 parts,
                                 SparsityTools::Partitioner::metis);
        owner.assign(parts.begin(), parts.end());
        return owner;
      }
    for (std::uint64_t c = 0; c < n_cells; ++c)
      owner[c] = static_cast<types::subdomain_id>(c * n_parts / n_cells);
    return owner;
  }

  std::vector<TriangulationDescription::Description<3, 3>>
  describe_parts(const Triangulation<3>                 &mesh,
                 const std::vector<types::subdomain_id> &owner,
                 const types::subdomain_id               first_rank,
                 const unsigned int                      n_parts,
                 const MPI_Comm                          communicator,
                 std::vector<std::vector<unsigned int>> *serial_vertices)
  {
    AssertThrow(mesh.n_levels() == 1 && owner.size() == mesh.n_active_cells(),
                ExcMessage("describe_parts() takes an unrefined mesh and one "
                           "owner per cell."));
    // Every part has one level of cells (the mesh is unrefined).
    std::vector<TriangulationDescription::Description<3, 3>> parts(n_parts);
    for (auto &part : parts)
      {
        part.comm      = communicator;
        part.smoothing = mesh.get_mesh_smoothing();
        part.settings  = TriangulationDescription::Settings::default_setting;
        part.cell_infos.resize(1);
      }
    if (serial_vertices != nullptr)
      serial_vertices->assign(n_parts, {});
    // The parts in chunks of 64, one bit each: one walk over the mesh for
    // up to 64 parts (a group's root describes all its members').
    for (unsigned int chunk = 0; chunk < n_parts; chunk += 64)
      {
        const unsigned int n_chunk = std::min(64u, n_parts - chunk);
        const auto         bit     = [&](const types::subdomain_id r) {
          const std::uint64_t p = std::uint64_t(r) - first_rank - chunk;
          return p < n_chunk ? std::uint64_t(1) << p : std::uint64_t(0);
        };
        // The parts with a cell at each vertex, then the parts each vertex
        // is relevant to: a part holds its cells and the cells that share a
        // vertex with one of them (its ghosts), as deal.II takes them.
        // softface's meshes have no periodic faces, so no vertices coincide.
        std::vector<std::uint64_t> at_own_cell(mesh.n_vertices(), 0);
        for (const auto &cell : mesh.active_cell_iterators())
          if (const std::uint64_t b = bit(owner[cell->active_cell_index()]))
            for (const unsigned int v : cell->vertex_indices())
              at_own_cell[cell->vertex_index(v)] |= b;

        std::vector<std::uint64_t> relevant_to(mesh.n_vertices(), 0);
        for (const auto &cell : mesh.active_cell_iterators())
          {
            std::uint64_t in_parts = 0;
            for (const unsigned int v : cell->vertex_indices())
              in_parts |= at_own_cell[cell->vertex_index(v)];
            if (in_parts == 0)
              continue;

            CellData<3> coarse(cell->n_vertices());
            coarse.material_id = cell->material_id();
            coarse.manifold_id = cell->manifold_id();
            for (const unsigned int v : cell->vertex_indices())
              {
                coarse.vertices[v] = cell->vertex_index(v);
                relevant_to[cell->vertex_index(v)] |= in_parts;
              }
            TriangulationDescription::CellData<3> info;
            info.id = cell->id().to_binary<3>();
            for (const unsigned int f : cell->face_indices())
              if (const types::boundary_id b = cell->face(f)->boundary_id();
                  b != numbers::internal_face_boundary_id)
                info.boundary_ids.emplace_back(f, b);
            info.manifold_id = cell->manifold_id();
            // A hexahedron's arrays: a tetrahedron fills the first 6 and 4.
            info.manifold_line_ids.fill(numbers::flat_manifold_id);
            info.manifold_quad_ids.fill(numbers::flat_manifold_id);
            for (const unsigned int l : cell->line_indices())
              info.manifold_line_ids[l] = cell->line(l)->manifold_id();
            for (const unsigned int f : cell->face_indices())
              info.manifold_quad_ids[f] = cell->quad(f)->manifold_id();
            info.subdomain_id       = owner[cell->active_cell_index()];
            info.level_subdomain_id = cell->level_subdomain_id();

            for (unsigned int p = 0; p < n_chunk; ++p)
              if (in_parts & (std::uint64_t(1) << p))
                {
                  auto &part = parts[chunk + p];
                  part.coarse_cells.push_back(coarse);
                  part.coarse_cell_index_to_coarse_cell_id.push_back(
                    cell->id().get_coarse_cell_id());
                  part.cell_infos[0].push_back(info);
                }
          }

        // Each part's vertices in the mesh's order, numbered from 0 (one
        // table of the mesh's vertices serves the parts in turn, reset
        // after each).
        std::vector<std::vector<unsigned int>> vertices(n_chunk);
        for (unsigned int v = 0; v < mesh.n_vertices(); ++v)
          for (std::uint64_t m = relevant_to[v]; m != 0; m &= m - 1)
            {
              const unsigned int p = __builtin_ctzll(m);
              vertices[p].push_back(v);
              parts[chunk + p].coarse_cell_vertices.push_back(
                mesh.get_vertices()[v]);
            }
        std::vector<unsigned int> local_index(mesh.n_vertices(),
                                              numbers::invalid_unsigned_int);
        for (unsigned int p = 0; p < n_chunk; ++p)
          {
            for (unsigned int k = 0; k < vertices[p].size(); ++k)
              local_index[vertices[p][k]] = k;
            for (auto &cell : parts[chunk + p].coarse_cells)
              for (auto &v : cell.vertices)
                {
                  v = local_index[v];
                  Assert(v != numbers::invalid_unsigned_int,
                         ExcInternalError());
                }
            for (const unsigned int v : vertices[p])
              local_index[v] = numbers::invalid_unsigned_int;
            if (serial_vertices != nullptr)
              (*serial_vertices)[chunk + p] = std::move(vertices[p]);
          }
      }

    return parts;
  }

  TriangulationDescription::Description<3, 3>
  describe_part(const Triangulation<3>                 &mesh,
                const std::vector<types::subdomain_id> &owner,
                const types::subdomain_id               rank,
                const MPI_Comm                          communicator,
                std::vector<unsigned int>              *serial_vertex)
  {
    std::vector<std::vector<unsigned int>> vertices;
    auto                                   parts = describe_parts(mesh,
                                owner,
                                rank,
                                1,
                                communicator,
                                serial_vertex != nullptr ? &vertices : nullptr);
    if (serial_vertex != nullptr)
      *serial_vertex = std::move(vertices[0]);
    return std::move(parts[0]);
  }

  namespace
  {
    /// Tags of the messages a group's root sends its members.
    constexpr int part_tag = 2011;

    /// What pack_part() writes for each cell (but its boundary faces) and
    /// for each vertex.
    constexpr std::size_t bytes_per_cell =
      4 * sizeof(unsigned int) + sizeof(types::material_id) +
      sizeof(types::manifold_id) + sizeof(types::coarse_cell_id) +
      sizeof(CellId::binary_type) + 2 * sizeof(types::subdomain_id) +
      sizeof(types::manifold_id) +
      (GeometryInfo<3>::lines_per_cell + GeometryInfo<3>::quads_per_cell) *
        sizeof(types::manifold_id) +
      sizeof(std::uint32_t);
    constexpr std::size_t bytes_per_vertex =
      3 * sizeof(double) + sizeof(unsigned int);

    /// Appends @p n objects of a plain type to @p buffer.
    template <typename T>
    void
    put(std::vector<char> &buffer, const T *data, const std::size_t n)
    {
      static_assert(std::is_trivially_copyable_v<T>);
      const char *bytes = reinterpret_cast<const char *>(data);
      buffer.insert(buffer.end(), bytes, bytes + n * sizeof(T));
    }

    /// Reads @p n objects of a plain type from @p buffer at @p position.
    template <typename T>
    void
    get(const std::vector<char> &buffer,
        std::size_t             &position,
        T                       *data,
        const std::size_t        n)
    {
      static_assert(std::is_trivially_copyable_v<T>);
      AssertThrow(position + n * sizeof(T) <= buffer.size(),
                  ExcMessage("A part's message ended early."));
      std::memcpy(data, buffer.data() + position, n * sizeof(T));
      position += n * sizeof(T);
    }

  } // namespace

  std::vector<char>
  pack_part(const TriangulationDescription::Description<3, 3> &part,
            const std::vector<unsigned int>                   &serial_vertex)
  {
    AssertThrow(part.cell_infos.size() == 1 &&
                  part.cell_infos[0].size() == part.coarse_cells.size() &&
                  serial_vertex.size() == part.coarse_cell_vertices.size(),
                ExcInternalError());
    const std::uint64_t n_cells  = part.coarse_cells.size();
    const std::uint64_t header[] = {n_cells,
                                    part.coarse_cell_vertices.size(),
                                    std::uint64_t(part.smoothing),
                                    std::uint64_t(part.settings)};
    std::vector<char>   buffer;
    buffer.reserve(n_cells * 200 + serial_vertex.size() * 28 + 64);
    put(buffer, header, 4);
    for (const auto &cell : part.coarse_cells)
      {
        AssertThrow(cell.vertices.size() == 4,
                    ExcMessage("Only tetrahedra are distributed."));
        put(buffer, cell.vertices.data(), 4);
        put(buffer, &cell.material_id, 1);
        put(buffer, &cell.manifold_id, 1);
        put(buffer, &cell.boundary_id, 1);
      }
    put(buffer, part.coarse_cell_index_to_coarse_cell_id.data(), n_cells);
    for (const auto &info : part.cell_infos[0])
      {
        put(buffer, info.id.data(), info.id.size());
        put(buffer, &info.subdomain_id, 1);
        put(buffer, &info.level_subdomain_id, 1);
        put(buffer, &info.manifold_id, 1);
        put(buffer,
            info.manifold_line_ids.data(),
            info.manifold_line_ids.size());
        put(buffer,
            info.manifold_quad_ids.data(),
            info.manifold_quad_ids.size());
        const std::uint32_t n_faces = info.boundary_ids.size();
        put(buffer, &n_faces, 1);
        for (const auto &[face, id] : info.boundary_ids)
          {
            put(buffer, &face, 1);
            put(buffer, &id, 1);
          }
      }
    for (const auto &x : part.coarse_cell_vertices)
      for (unsigned int d = 0; d < 3; ++d)
        put(buffer, &x[d], 1);
    put(buffer, serial_vertex.data(), serial_vertex.size());
    return buffer;
  }

  TriangulationDescription::Description<3, 3>
  unpack_part(const std::vector<char>   &buffer,
              const MPI_Comm             communicator,
              std::vector<unsigned int> &serial_vertex)
  {
    TriangulationDescription::Description<3, 3> part;
    std::size_t                                 position = 0;
    std::uint64_t                               header[4];
    get(buffer, position, header, 4);
    const std::uint64_t n_cells = header[0], n_vertices = header[1];
    part.comm      = communicator;
    part.smoothing = static_cast<Triangulation<3>::MeshSmoothing>(header[2]);
    part.settings  = static_cast<TriangulationDescription::Settings>(header[3]);
    part.coarse_cells.resize(n_cells, CellData<3>(4));
    for (auto &cell : part.coarse_cells)
      {
        get(buffer, position, cell.vertices.data(), 4);
        get(buffer, position, &cell.material_id, 1);
        get(buffer, position, &cell.manifold_id, 1);
        get(buffer, position, &cell.boundary_id, 1);
      }
    part.coarse_cell_index_to_coarse_cell_id.resize(n_cells);
    get(buffer,
        position,
        part.coarse_cell_index_to_coarse_cell_id.data(),
        n_cells);
    part.cell_infos.resize(1);
    part.cell_infos[0].resize(n_cells);
    for (auto &info : part.cell_infos[0])
      {
        get(buffer, position, info.id.data(), info.id.size());
        get(buffer, position, &info.subdomain_id, 1);
        get(buffer, position, &info.level_subdomain_id, 1);
        get(buffer, position, &info.manifold_id, 1);
        get(buffer,
            position,
            info.manifold_line_ids.data(),
            info.manifold_line_ids.size());
        get(buffer,
            position,
            info.manifold_quad_ids.data(),
            info.manifold_quad_ids.size());
        std::uint32_t n_faces = 0;
        get(buffer, position, &n_faces, 1);
        AssertThrow(n_faces <= 4, ExcMessage("A part's message is wrong."));
        info.boundary_ids.resize(n_faces);
        for (auto &[face, id] : info.boundary_ids)
          {
            get(buffer, position, &face, 1);
            get(buffer, position, &id, 1);
          }
      }
    part.coarse_cell_vertices.resize(n_vertices);
    for (auto &x : part.coarse_cell_vertices)
      for (unsigned int d = 0; d < 3; ++d)
        get(buffer, position, &x[d], 1);
    serial_vertex.resize(n_vertices);
    get(buffer, position, serial_vertex.data(), n_vertices);
    AssertThrow(position == buffer.size(),
                ExcMessage("A part's message is longer than its parts."));
    return part;
  }

  /// @p buffer to rank @p to, in pieces MPI's int counts can hold.
  void
  send_bytes(const std::vector<char> &buffer,
             const unsigned int       to,
             const int                tag,
             const MPI_Comm           communicator)
  {
    const std::uint64_t size = buffer.size();
    int error = MPI_Send(&size, 1, MPI_UINT64_T, to, tag, communicator);
    AssertThrowMPI(error);
    const std::uint64_t piece = std::numeric_limits<int>::max();
    for (std::uint64_t first = 0; first < size; first += piece)
      {
        error = MPI_Send(buffer.data() + first,
                         static_cast<int>(std::min(piece, size - first)),
                         MPI_CHAR,
                         to,
                         tag,
                         communicator);
        AssertThrowMPI(error);
      }
  }

  std::vector<char>
  receive_bytes(const unsigned int from,
                const int          tag,
                const MPI_Comm     communicator)
  {
    std::uint64_t size  = 0;
    int           error = MPI_Recv(
      &size, 1, MPI_UINT64_T, from, tag, communicator, MPI_STATUS_IGNORE);
    AssertThrowMPI(error);
    std::vector<char>   buffer(size);
    const std::uint64_t piece = std::numeric_limits<int>::max();
    for (std::uint64_t first = 0; first < size; first += piece)
      {
        error = MPI_Recv(buffer.data() + first,
                         static_cast<int>(std::min(piece, size - first)),
                         MPI_CHAR,
                         from,
                         tag,
                         communicator,
                         MPI_STATUS_IGNORE);
        AssertThrowMPI(error);
      }
    return buffer;
  }


  DistributedLayout::DistributedLayout(const Scene       &scene,
                                       const MPI_Comm     communicator,
                                       const Partitioner  partitioner,
                                       const unsigned int group_size)
      : scene(scene)
      , communicator(communicator)
      , triangulation(communicator)
      , n_serial_dofs(scene.join_dofs().size())
  {
    AssertThrow(group_size >= 1,
                ExcMessage("The mesh group size must be at least 1."));
    const unsigned int rank    = Utilities::MPI::this_mpi_process(communicator);
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(communicator);
    const unsigned int root    = rank - rank % group_size;

    // The parts, described by each group's root from the scene's mesh
    // (deal.II's partitioning in groups): rank 0 partitions the cells, the
    // roots learn the owners and describe their members' parts, which the
    // members receive with the scene's index of each of their vertices. A
    // member reads nothing of the scene's mesh here but its number of levels
    // (none, where a member holds no mesh). An error on a root while it
    // describes or sends is deal.II's (not softface's Error, which a model's
    // run takes for the model's failure on every rank): the program aborts
    // every rank, so no member waits for its part forever.
    TriangulationDescription::Description<3, 3> part;
    std::vector<unsigned int>                   serial_vertex;
    {
      // A coarse cell id is the serial cell's active index only on an
      // unrefined mesh (softface's meshes are).
      AssertThrow(scene.triangulation.n_levels() <= 1,
                  ExcMessage("A refined mesh cannot be distributed over "
                             "several MPI ranks."));
      const SubCommunicator roots(communicator, rank == root);
      if (rank == root)
        {
          std::vector<types::subdomain_id> owner;
          if (rank == 0)
            owner = cell_owners(scene.triangulation, n_ranks, partitioner);
          owner = Utilities::MPI::broadcast(roots.communicator, owner);

          // The group's parts, a batch at a time in one walk over the mesh
          // (more would hold more of them at once), the root's own first;
          // each member's sent as plain arrays and freed.
          const unsigned int batch   = 8;
          const unsigned int n_group = std::min(group_size, n_ranks - root);
          for (unsigned int first = 0; first < n_group; first += batch)
            {
              std::vector<std::vector<unsigned int>> vertices;
              auto parts = describe_parts(scene.triangulation,
                                          owner,
                                          root + first,
                                          std::min(batch, n_group - first),
                                          communicator,
                                          &vertices);
              for (unsigned int p = 0; p < parts.size(); ++p)
                if (first + p == 0)
                  {
                    part          = std::move(parts[0]);
                    serial_vertex = std::move(vertices[0]);
                  }
                else
                  {
                    send_bytes(pack_part(parts[p], vertices[p]),
                               root + first + p,
                               part_tag,
                               communicator);
                    parts[p]    = TriangulationDescription::Description<3, 3>();
                    vertices[p] = std::vector<unsigned int>();
                  }
            }
        }
      else
        part = unpack_part(receive_bytes(root, part_tag, communicator),
                           communicator,
                           serial_vertex);
    }
    // deal.II gives a rank without cells one artificial cell of its own
    // (8 vertices), which maps to no vertex of the scene.
    const bool without_cells = part.coarse_cells.empty();
    triangulation.create_triangulation(part);
    part = TriangulationDescription::Description<3, 3>();

    dof_handler.reinit(triangulation);
    dof_handler.distribute_dofs(scene.fe);
    locally_owned_dofs = dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_handler, locally_relevant_dofs);

    // The part numbers its vertices as its description does, and the root
    // sent the scene's index of each: the DoFs of a vertex and component
    // correspond to the scene's (Scene::vertex_dofs()).
    AssertThrow(without_cells ||
                  triangulation.n_vertices() == serial_vertex.size(),
                ExcInternalError());
    serial_dof_of_relevant.assign(locally_relevant_dofs.n_elements(),
                                  numbers::invalid_dof_index);
    const auto &vertex_dofs = scene.vertex_dofs();
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        for (const unsigned int v : cell->vertex_indices())
          for (unsigned int c = 0; c < 3; ++c)
            serial_dof_of_relevant[locally_relevant_dofs.index_within_set(
              cell->vertex_dof_index(v, c))] =
              vertex_dofs[serial_vertex[cell->vertex_index(v)]][c];

    decide_join_points(scene.segments, scene.resolve_shared_join_points);
    decide_body_force();
  }

  void
  DistributedLayout::decide_body_force()
  {
    // Every rank must answer alike (the vector below is collective): a
    // member's scene has the body force rank 0 sent (Scene::has_cells()).
    AssertThrow(
      Utilities::MPI::min(int(scene.has_body_force()), communicator) ==
        Utilities::MPI::max(int(scene.has_body_force()), communicator),
      ExcMessage("The ranks disagree on the body force."));
    if (!scene.has_body_force())
      return;
    // Each cell's vertex load, as the scene sums it (Scene::apply_rules()),
    // over the cells at an owned vertex: its own and ghost cells, in the
    // scene's order (the part keeps it).
    Vector<double> local(locally_owned_dofs.n_elements());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          const Tensor<1, 3> load = scene.effects.body_force_vertex_load(cell);
          for (unsigned int a = 0; a < 4; ++a)
            for (unsigned int i = 0; i < 3; ++i)
              if (const auto dof = cell->vertex_dof_index(a, i);
                  locally_owned_dofs.is_element(dof))
                local[locally_owned_dofs.index_within_set(dof)] += load[i];
        }
    owned_body_force.reinit(locally_owned_dofs, communicator);
    unsigned int k = 0;
    for (const auto dof : locally_owned_dofs)
      owned_body_force[dof] = local[k++];
    owned_body_force.compress(VectorOperation::insert);
  }

  types::global_dof_index
  DistributedLayout::serial_dof(const types::global_dof_index dof) const
  {
    AssertThrow(locally_relevant_dofs.is_element(dof),
                ExcMessage("DoF " + std::to_string(dof) +
                           " is not locally relevant on this rank."));
    return serial_dof_of_relevant[locally_relevant_dofs.index_within_set(dof)];
  }

  Triangulation<3>::active_cell_iterator
  DistributedLayout::serial_cell(
    const DoFHandler<3>::active_cell_iterator &cell) const
  {
    return Triangulation<3>::active_cell_iterator(
      &scene.triangulation, 0, cell->id().get_coarse_cell_id());
  }

  void
  DistributedLayout::cells_at_owned_dofs(
    std::vector<DoFHandler<3>::active_cell_iterator> &cells,
    std::vector<types::global_dof_index>             &cell_dofs) const
  {
    cells.clear();
    cell_dofs.clear();
    std::array<types::global_dof_index, 12> dofs;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          bool at_owned_dof = false;
          for (unsigned int a = 0; a < 4; ++a)
            for (unsigned int i = 0; i < 3; ++i)
              {
                dofs[3 * a + i] = cell->vertex_dof_index(a, i);
                at_owned_dof |= locally_owned_dofs.is_element(dofs[3 * a + i]);
              }
          if (!at_owned_dof)
            continue;
          cells.push_back(cell);
          cell_dofs.insert(cell_dofs.end(), dofs.begin(), dofs.end());
        }
  }

  void
  DistributedLayout::decide_join_points(
    const std::vector<BoneSegment> &segments,
    const bool                      resolve_shared_join_points)
  {
    const unsigned int free = numbers::invalid_unsigned_int;
    std::vector<std::map<unsigned int, unsigned int>> claims(
      triangulation.n_vertices());
    for (const auto &cell : triangulation.active_cell_iterators())
      if (!cell->is_artificial())
        add_segment_claims(segments, cell, claims);

    // The owner's answer, sent to the ranks that hold the vertex as a ghost
    // through a ghosted vector (segment + 1, -1 for free: exact in doubles;
    // 0 is a DoF no owner decided).
    TrilinosWrappers::MPI::Vector owned(locally_owned_dofs, communicator);
    std::vector<bool>             decided(triangulation.n_vertices(), false);
    owned_shared_join_points = 0;
    // A vertex that touches two segments where the scene does not allow
    // it: the first this rank met, refused on every rank below.
    std::string refused;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned int v : cell->vertex_indices())
          {
            const auto first = cell->vertex_dof_index(v, 0);
            if (!locally_owned_dofs.is_element(first) ||
                decided[cell->vertex_index(v)])
              continue;
            decided[cell->vertex_index(v)] = true;
            const auto &c                  = claims[cell->vertex_index(v)];
            if (c.size() > 1)
              {
                ++owned_shared_join_points;
                if (!resolve_shared_join_points && refused.empty())
                  {
                    std::ostringstream where;
                    where << "the vertex at (" << cell->vertex(v) << ')';
                    refused = shared_join_point_error(where.str(), segments, c);
                  }
              }
            const unsigned int segment = join_segment(c);
            for (unsigned int i = 0; i < 3; ++i)
              owned[cell->vertex_dof_index(v, i)] =
                segment == free ? -1. : segment + 1.;
          }
    owned.compress(VectorOperation::insert);
    // Every rank refuses, with the message of the first rank that met one
    // (the scene refuses the same before a layout is made).
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(communicator);
    const unsigned int first_refusing =
      Utilities::MPI::min(refused.empty() ?
                            n_ranks :
                            Utilities::MPI::this_mpi_process(communicator),
                          communicator);
    if (first_refusing < n_ranks)
      throw Error(
        Utilities::MPI::broadcast(communicator, refused, first_refusing));

    TrilinosWrappers::MPI::Vector relevant(locally_owned_dofs,
                                           locally_relevant_dofs,
                                           communicator);
    relevant = owned;

    join_segment_of_relevant.assign(locally_relevant_dofs.n_elements(), free);
    unsigned int k = 0;
    for (const auto dof : locally_relevant_dofs)
      {
        const double value = relevant[dof];
        AssertThrow(value != 0., ExcMessage("A DoF whose owner decided none."));
        join_segment_of_relevant[k++] =
          value < 0. ? free : static_cast<unsigned int>(value) - 1;
      }
  }

  unsigned int
  DistributedLayout::join_segment_of_dof(
    const types::global_dof_index dof) const
  {
    AssertThrow(locally_relevant_dofs.is_element(dof),
                ExcMessage("DoF " + std::to_string(dof) +
                           " is not locally relevant on this rank."));
    return join_segment_of_relevant[locally_relevant_dofs.index_within_set(
      dof)];
  }

  bool
  DistributedLayout::is_join_dof(const types::global_dof_index dof) const
  {
    return join_segment_of_dof(dof) != numbers::invalid_unsigned_int;
  }

  unsigned int
  DistributedLayout::n_owned_shared_join_points() const
  {
    return owned_shared_join_points;
  }

  void
  DistributedLayout::scatter(const Vector<double>          &serial,
                             TrilinosWrappers::MPI::Vector &distributed) const
  {
    for (const auto dof : locally_owned_dofs)
      distributed[dof] = serial[serial_dof(dof)];
    distributed.compress(VectorOperation::insert);
  }

  Vector<double>
  DistributedLayout::gather(
    const TrilinosWrappers::MPI::Vector &distributed) const
  {
    // Each rank writes its owned entries into a zero serial vector; the sum
    // over the ranks is the whole vector, since every DoF has one owner.
    Vector<double> serial(n_serial_dofs);
    for (const auto dof : locally_owned_dofs)
      serial[serial_dof(dof)] = distributed[dof];
    Utilities::MPI::sum(serial, communicator, serial);
    return serial;
  }
} // namespace softface
