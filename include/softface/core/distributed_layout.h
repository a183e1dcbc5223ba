#ifndef softface_core_distributed_layout_h
#define softface_core_distributed_layout_h

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/distributed/fully_distributed_tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/grid/tria_description.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>

#include <softface/core/scene.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * deal.II's fully distributed triangulation, with a table from a coarse
   * cell's id to its index on this rank in place of the binary search
   * deal.II 9.4 does. Building a rank's part sorts its cells twice (in
   * dealii::Triangulation and in parallel::fullydistributed::Triangulation's
   * create_triangulation()), and each comparison looks up both cells' ids:
   * tens of millions of binary searches at a million cells per rank. The
   * table spans the rank's ids from the smallest to the largest; where that
   * range is more than a few times the rank's cells (a partition whose cells
   * are scattered over the mesh's order) a binary search over the sorted ids
   * answers, as deal.II's does (which a derived class cannot call).
   */
  class DistributedTriangulation
      : public parallel::fullydistributed::Triangulation<3>
  {
  public:
    /// With @p allow_table false the binary search always answers (for
    /// the test against the table).
    explicit DistributedTriangulation(const MPI_Comm communicator,
                                      const bool     allow_table = true);

    using parallel::fullydistributed::Triangulation<3>::create_triangulation;

    void
    create_triangulation(
      const TriangulationDescription::Description<3, 3> &description) override;

    unsigned int
    coarse_cell_id_to_coarse_cell_index(
      const types::coarse_cell_id coarse_cell_id) const override;

    /// Does the table answer (false: the binary search does)?
    bool
    has_index_table() const;

  private:
    const bool allow_table;
    /// The smallest coarse cell id of this rank.
    types::coarse_cell_id first_id = 0;
    /// Index of id first_id + k, or numbers::invalid_unsigned_int where k is
    /// no id of this rank; empty where the ids are too scattered.
    std::vector<unsigned int> index_of_id;
    /// Pairs (id, index) sorted by id, where index_of_id is empty.
    std::vector<std::pair<types::coarse_cell_id, unsigned int>> sorted_ids;
  };

  /**
   * The scene's P1 layout on the ranks of an MPI communicator.
   * Every rank holds the scene's segments, join points and effects, and its
   * mesh too unless it is a member of a group whose run needs no serial
   * mesh (Scene::has_cells()); the cells are partitioned among
   * the ranks (cell_owners()), and each rank builds a
   * parallel::fullydistributed::Triangulation of its cells and their ghosts
   * (simplex meshes need the fully distributed kind), described from the
   * scene's mesh without a copy of it (describe_parts(), by the root of each
   * group of ranks), and a DoFHandler
   * with the scene's element on it.
   *
   * Each rank decides which of the vertices it owns are join points, and of
   * which segment, from its own and ghost cells (is_join_dof(), the serial
   * answer); a ghost vertex takes its owner's answer. It decides the
   * effects' tissues of its cells and nodal body force at its vertices alike
   * (tissue_of_cell(), body_force()). Each locally relevant
   * DoF knows the scene's DoF of the same vertex and component
   * (serial_dof()): a serial vector gives the owned entries of a distributed
   * one (scatter())
   * and a distributed answer comes back as the serial vector the reports and
   * outputs use (gather()).
   *
   * The parts are described by the root of each group of ranks and sent to
   * its members, which read nothing of the scene's mesh to build theirs; a
   * member's scene may hold no cells at all (Scene::has_cells(): the run's
   * models read only their part), only the arrays per vertex and DoF and
   * the rules rank 0 sent it.
   */
  class DistributedLayout
  {
  public:
    /// How the cells are shared among the ranks.
    enum class Partitioner
    {
      /// Contiguous ranges of the scene's cell order: a read mesh's cells
      /// are in Hilbert order (core/cell_order.h), so the ranges are pieces
      /// of a space-filling curve; the generated cube's are slabs.
      cell_order,
      /// METIS on the cells' face graph (deal.II's GridTools), fewer faces
      /// between the ranks.
      metis
    };

    /// "cell order" or "metis".
    static Partitioner
    parse_partitioner(const std::string &name);

    /// The "Partitioner" and "Mesh group size" entries, in the handler's
    /// current subsection.
    static void
    declare_partitioner(ParameterHandler &prm);

    /**
     * Partition the scene's cells among the ranks of @p communicator and
     * build this rank's part. The ranks form groups of @p group_size
     * consecutive ranks (the last may be smaller): the first rank of each, its
     * root, describes its members' parts from the scene's mesh and sends them
     * (deal.II's partitioning in groups), so a member reads nothing of the
     * scene's mesh or serial DoFHandler here: only Scene::vertex_dofs(),
     * join_dofs(), the segments, the element and the effects' rules.
     * Collective: every rank of the communicator calls it with the same
     * scene (a member's may lack the mesh).
     */
    DistributedLayout(const Scene       &scene,
                      const MPI_Comm     communicator,
                      const Partitioner  partitioner = Partitioner::cell_order,
                      const unsigned int group_size  = 1);

    /// The scene's DoF of the same vertex and component as @p dof, which
    /// must be locally relevant.
    types::global_dof_index
    serial_dof(const types::global_dof_index dof) const;

    /// The scene's cell that the locally relevant @p cell of this rank is
    /// (the same vertices in the same order); it needs the scene's mesh.
    Triangulation<3>::active_cell_iterator
    serial_cell(const DoFHandler<3>::active_cell_iterator &cell) const;

    /// The active index of serial_cell(), read without the scene's mesh:
    /// the cell's coarse cell id (the parts number cells as the scene's
    /// unrefined mesh does). It indexes the scene's per-cell data, such as
    /// tissues.
    static unsigned int
    serial_cell_index(const DoFHandler<3>::active_cell_iterator &cell)
    {
      return cell->id().get_coarse_cell_id();
    }

    /// The cells at a DoF this rank owns, its own and ghost cells, and
    /// their DoFs (12 each, vertex by vertex, components within): the cells
    /// a rank assembles its own rows from (OwnedRowsMatrix).
    void
    cells_at_owned_dofs(std::vector<DoFHandler<3>::active_cell_iterator> &cells,
                        std::vector<types::global_dof_index> &cell_dofs) const;

    /// The bone segment whose join point the vertex of the locally relevant
    /// @p dof is, or numbers::invalid_unsigned_int if it is free: decided
    /// on the rank that owns it (decide_join_points()).
    unsigned int
    join_segment_of_dof(const types::global_dof_index dof) const;

    /// Is the locally relevant @p dof a join point's DoF?
    bool
    is_join_dof(const types::global_dof_index dof) const;

    /// The vertices this rank owns that touch two segments' bone (left free,
    /// as the scene's Scene::resolve_shared_join_points allows).
    unsigned int
    n_owned_shared_join_points() const;

    /// The tissue of the locally relevant @p cell by the effects' rule
    /// (SceneEffects::tissue()): the serial cell's tissue.
    unsigned int
    tissue_of_cell(const DoFHandler<3>::active_cell_iterator &cell) const
    {
      return scene.effects.tissue(cell);
    }

    /// The scene's nodal body force (gravity's consistent P1 loads) at the
    /// DoFs this rank owns, from its own and ghost cells by the effects'
    /// rules (SceneEffects::body_force_vertex_load()): the serial loads,
    /// cell by cell in the serial order. Empty where the scene has no body
    /// force.
    const TrilinosWrappers::MPI::Vector &
    body_force() const
    {
      return owned_body_force;
    }

    /// The owned entries of @p distributed from the serial vector @p serial.
    void
    scatter(const Vector<double>          &serial,
            TrilinosWrappers::MPI::Vector &distributed) const;

    /// The serial vector of @p distributed, on every rank. Collective.
    Vector<double>
    gather(const TrilinosWrappers::MPI::Vector &distributed) const;

    const Scene             &scene;
    const MPI_Comm           communicator;
    DistributedTriangulation triangulation;
    DoFHandler<3>            dof_handler;
    IndexSet                 locally_owned_dofs;
    IndexSet                 locally_relevant_dofs;

  private:
    /**
     * Each locally owned vertex's segment, from the cells and boundary faces
     * around it by the scene's rule (add_segment_claims()): a rank holds them
     * all, its own cells and their ghosts, so its answer is the serial one.
     * A ghost vertex may lack some of its cells here, and a face of a ghost
     * cell whose neighbour the rank does not hold is a boundary face of the
     * rank's mesh only (with boundary id 0); neither touches an owned vertex,
     * so a ghost vertex takes the answer of the rank that owns it. A vertex
     * that touches two segments while the scene does not allow it is refused
     * on every rank. Collective.
     */
    void
    decide_join_points(const std::vector<BoneSegment> &segments,
                       const bool resolve_shared_join_points);

    /// body_force() on this rank's cells.
    void
    decide_body_force();

    /// serial_dof() of each locally relevant DoF, by its place in
    /// locally_relevant_dofs.
    std::vector<types::global_dof_index> serial_dof_of_relevant;
    /// join_segment_of_dof() of each locally relevant DoF, by its place.
    std::vector<unsigned int>     join_segment_of_relevant;
    unsigned int                  owned_shared_join_points = 0;
    TrilinosWrappers::MPI::Vector owned_body_force;
    /// The scene's DoFs (the length of gather()'s vector).
    const types::global_dof_index n_serial_dofs;
  };

  /**
   * Each cell's part (by active cell index) among @p n_parts for the
   * @p partitioner of DistributedLayout; METIS gets the face graph
   * GridTools::partition_triangulation() gives it. DistributedLayout calls
   * it on one rank and sends its answer to the others that need it: METIS
   * need not answer alike on every rank.
   */
  std::vector<types::subdomain_id>
  cell_owners(const Triangulation<3>              &mesh,
              const unsigned int                   n_parts,
              const DistributedLayout::Partitioner partitioner);

  /**
   * describe_part() of the @p n_parts ranks from @p first_rank on, in one
   * walk over the mesh for up to 64 of them: a group's root describes its
   * members' parts so. The mesh's indices of each part's vertices go to
   * @p serial_vertices if given.
   */
  std::vector<TriangulationDescription::Description<3, 3>>
  describe_parts(
    const Triangulation<3>                 &mesh,
    const std::vector<types::subdomain_id> &owner,
    const types::subdomain_id               first_rank,
    const unsigned int                      n_parts,
    const MPI_Comm                          communicator,
    std::vector<std::vector<unsigned int>> *serial_vertices = nullptr);

  /**
   * The part of the unrefined @p mesh that rank @p rank holds, owned by
   * @p owner (one rank per cell): its cells and those sharing a vertex with
   * them, as deal.II's create_description_from_triangulation() describes
   * them from a copy of the mesh whose subdomain ids are @p owner. It reads
   * the mesh without copying it: a copy holds as much memory as the mesh
   * (330 MB at 2M tetrahedra), on every rank. Any rank may describe any
   * rank's part, as a group's root does for its group. The mesh's index of
   * each of the part's vertices, in the part's order, goes to
   * @p serial_vertex if given.
   */
  TriangulationDescription::Description<3, 3>
  describe_part(const Triangulation<3>                 &mesh,
                const std::vector<types::subdomain_id> &owner,
                const types::subdomain_id               rank,
                const MPI_Comm                          communicator,
                std::vector<unsigned int> *serial_vertex = nullptr);

  /**
   * A part of tetrahedra (describe_parts()) and the mesh's index of each of
   * its vertices (@p serial_vertex) as one message of plain arrays, which a
   * group's root sends a member: Boost's serialisation of a description
   * (deal.II's Utilities::pack()) took 0.59 s to pack and 0.44 s to unpack
   * at a million cells, three times the describing.
   */
  std::vector<char>
  pack_part(const TriangulationDescription::Description<3, 3> &part,
            const std::vector<unsigned int>                   &serial_vertex);

  /// pack_part() read back; the description's communicator is
  /// @p communicator. A message that does not hold a part is refused.
  TriangulationDescription::Description<3, 3>
  unpack_part(const std::vector<char>   &buffer,
              const MPI_Comm             communicator,
              std::vector<unsigned int> &serial_vertex);

  /**
   * The scene's DistributedLayout for every model of a run: built when the
   * first model asks for it, then shared, so that a run partitions its scene
   * once however many of its models are distributed.
   */
  class SharedDistributedLayout
  {
  public:
    SharedDistributedLayout(const MPI_Comm                       communicator,
                            const DistributedLayout::Partitioner partitioner,
                            const unsigned int group_size = 1);

    /// The layout of @p scene, built by the first call (collective then);
    /// later calls must name the same scene.
    const DistributedLayout &
    get(const Scene &scene);

    /// Has a model built it (the same answer on every rank)?
    bool
    built() const
    {
      return layout != nullptr;
    }

    const MPI_Comm                       communicator;
    const DistributedLayout::Partitioner partitioner;
    const unsigned int                   group_size;

  private:
    std::unique_ptr<DistributedLayout> layout;
  };
} // namespace softface

#endif
