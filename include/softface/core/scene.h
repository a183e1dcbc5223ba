#ifndef softface_scene_h
#define softface_scene_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>

#include <softface/core/cell_rules.h>
#include <softface/core/material.h>
#include <softface/core/mesh.h>

#include <array>
#include <map>
#include <memory>
#include <ostream>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace softface
{
  using namespace dealii;

  /**
   * A bone segment (Mollemans et al. 2007, Sec. 3.3): the mesh vertices that
   * touch it are its join points. They are the vertices of cells with one of
   * the material ids and the vertices of boundary faces with one of the
   * boundary ids.
   */
  struct BoneSegment
  {
    std::string                  name;
    std::set<types::material_id> material_ids;
    std::set<types::boundary_id> boundary_ids;
    /// A point in the segment's bone (patient scenes: which bone part of
    /// the osteotomy is this segment); empty for other scenes.
    std::vector<double> seed_point;
    /// True if the segment only carries a sliding contact surface
    /// (effects: sliding contact): it may then have no join point.
    bool carries_contact_only = false;
    /// The mean of its join points when first found (the default rotation
    /// centre): an effect that later frees some of them does not move it.
    std::vector<double> join_centroid = {};

    /// For Scene::share_without_cells() (Boost serialisation).
    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &name &material_ids &boundary_ids &seed_point
        &carries_contact_only &join_centroid;
    }
  };

  /**
   * The bone segments that claim the vertices of @p cell (paper, Sec. 3.3),
   * added to
   * @p claims by the cell's vertex indices: a segment whose material ids
   * hold the cell's claims its four vertices, one whose boundary ids hold a
   * boundary face's claims that face's three, once per cell or face. A
   * vertex claimed by exactly one segment is its join point; by several, it
   * touches two segments' bone (join_segment()).
   */
  void
  add_segment_claims(const std::vector<BoneSegment>               &segments,
                     const Triangulation<3>::active_cell_iterator &cell,
                     std::vector<std::map<unsigned int, unsigned int>> &claims);

  /// The refusal of a vertex with @p claims by two segments, where the
  /// scene does not leave it free; @p vertex names it ("vertex 12 at (...)").
  std::string
  shared_join_point_error(const std::string                          &vertex,
                          const std::vector<BoneSegment>             &segments,
                          const std::map<unsigned int, unsigned int> &claims);

  /// The segment of a vertex with @p claims, or numbers::invalid_unsigned_int
  /// if it is free: claimed by none, or by several (a vertex that touches
  /// two segments' bone, which the caller refuses or leaves free).
  inline unsigned int
  join_segment(const std::map<unsigned int, unsigned int> &claims)
  {
    return claims.size() == 1 ? claims.begin()->first :
                                numbers::invalid_unsigned_int;
  }

  /**
   * A constraint on a free vertex (effects: sliding contact, separated
   * lips): with n the unit normal at rest,
   *   n . (u_vertex - u_partner) = g   (bilateral), or
   *   n . (u_vertex - u_partner) >= g  (unilateral: may lift off, never
   *                                     pass through),
   * where u_partner is zero without a partner, and g = n . d with d the
   * displacement of bone segment 'segment' at the vertex (the prescribed
   * displacement holds it there, see Planning), or 0 without a segment.
   * n points from the surface the vertex must not pass into the vertex's
   * side. A vertex is in at most one constraint.
   */
  struct VertexConstraint
  {
    unsigned int vertex;
    unsigned int partner = numbers::invalid_unsigned_int;
    Tensor<1, 3> normal;
    unsigned int segment    = numbers::invalid_unsigned_int;
    bool         unilateral = false;

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &vertex &partner &normal &segment &unilateral;
    }
  };

  /**
   * What a scene's effects (effects/interface.h) add to it. All empty unless
   * the scene names an effect; a model then reads Scene::material in every
   * cell and feels no load but the bone motion.
   */
  struct SceneEffects
  {
    /// What a model must honour to simulate an effect (bit flags).
    enum Contribution : unsigned int
    {
      none                    = 0,
      cell_materials          = 1, ///< tissues per cell (tissues, tissue_rule)
      body_forces             = 2, ///< body forces (body_force_rules)
      free_vertex_constraints = 4  ///< vertex_constraints
    };

    /// The names of the effects applied, in the order they were applied.
    std::vector<std::string> names;

    /**
     * The effects' rules per cell (core/cell_rules.h), declared by each
     * effect on every MPI rank (Effects::Interface::declare_rules()): the
     * tissues and which one fills a cell (none: Scene::material in every
     * cell), and the body forces, summed.
     */
    std::vector<Material>                         tissues;
    std::shared_ptr<const TissueRule>             tissue_rule;
    std::vector<std::shared_ptr<const BodyForce>> body_force_rules;

    /// The tissue of @p cell by the rule (0 without one).
    unsigned int
    tissue(const Triangulation<3>::active_cell_iterator &cell) const
    {
      return tissue_rule ? tissue_rule->tissue(cell) : 0;
    }
    /// The body forces per unit volume in @p cell (N/mm^3).
    Tensor<1, 3>
    body_force_per_unit_volume(
      const Triangulation<3>::active_cell_iterator &cell) const;
    /// The load (N) the body forces put on each vertex of @p cell: a
    /// quarter of the force on the cell, the consistent P1 load of a force
    /// constant in it. The scene and each rank's part sum it alike.
    Tensor<1, 3>
    body_force_vertex_load(
      const Triangulation<3>::active_cell_iterator &cell) const;

    /// The rules applied to the scene's whole mesh (Scene::apply_rules()):
    /// every cell's tissue (active cell index; empty without a tissue rule)
    /// and the nodal loads in N on the shared layout, added to every
    /// model's equilibrium (empty without a body force).
    std::vector<unsigned char> tissue_of_cell;
    Vector<double>             body_force;

    /// Constraints on free vertices (sliding contact, the lips' contact).
    std::vector<VertexConstraint> vertex_constraints;
    /// Active-set iterations a FEM model may take for unilateral ones (the
    /// largest any effect asks for; 0: none asked, 50).
    unsigned int max_active_set_iterations = 0;
    unsigned int
    active_set_limit() const
    {
      return max_active_set_iterations > 0 ? max_active_set_iterations : 50;
    }

    /// What Scene::share_without_cells() sends in its archive: neither the
    /// rules, which each rank's effects declare, nor the arrays per cell
    /// and per DoF, which it leaves out or sends as arrays.
    template <class Archive>
    void
    serialize_names_and_constraints(Archive &archive)
    {
      archive &names &vertex_constraints &max_active_set_iterations;
    }
  };

  /**
   * What every model works on: the tetrahedral mesh, the one DoF layout
   * (FESystem(FE_SimplexP<3>(1), 3): three DoFs per vertex), the tissue, and
   * which vertex is a join point of which bone segment. Vertices that touch no
   * segment are free; their displacement is what a model computes.
   *
   * Build it from a parameter file (declare_parameters, parse_parameters) or
   * in code (fill triangulation and segments, then call setup()).
   */
  class Scene
  {
  public:
    Scene();

    /**
     * The Scene and Material sections, with every mesh source's entries.
     * One subsection "Segment <name>" is declared for each name in
     * @p segment_names; @p cut_names are what the mesh sources read in a
     * first pass (cut_names(): the patient's osteotomy declares one "Cut
     * <name>" for each).
     */
    static void
    declare_parameters(ParameterHandler               &prm,
                       const std::vector<std::string> &segment_names,
                       const std::vector<std::string> &cut_names = {});

    /// What the mesh sources read in a first pass: the names listed in
    /// "Scene/Patient/Osteotomy/Cuts".
    static std::vector<std::string>
    cut_names(ParameterHandler &prm);

    /// The names listed in "Scene/Bone segments" of a parsed handler.
    static std::vector<std::string>
    segment_names(ParameterHandler &prm);

    /**
     * Read the parameters, let the mesh source 'Mesh source' names make the
     * mesh (include/softface/core/mesh_source.h: a relative mesh file name
     * is taken relative to @p input_directory; a patient's is made by the
     * patient pipeline in @p work_directory unless the scene names one,
     * with its progress on @p log) and call setup(). For a patient scene
     * under MPI this is collective on MPI_COMM_WORLD: rank 0 runs the
     * pipeline and every rank reads the mesh it wrote.
     *
     * A read mesh is read by the ranks of @p mesh_readers (collectively;
     * rank 0 of MPI_COMM_WORLD among them). On a rank where it is
     * MPI_COMM_NULL the scene gets no cells: it parses the parameters only
     * and waits for share_without_cells().
     */
    void
    parse_parameters(ParameterHandler  &prm,
                     const std::string &input_directory,
                     const std::string &work_directory = "patient",
                     std::ostream      *log            = nullptr,
                     const MPI_Comm     mesh_readers   = MPI_COMM_WORLD);

    /**
     * Whether this rank holds the scene's cells (its triangulation and
     * DoFHandler). It does not on a member of a group of MPI ranks
     * (Models/Mesh group size) whose run needs no serial mesh on every rank:
     * such a scene holds what rank 0 sent it
     * (share_without_cells()), the arrays per vertex and per DoF (positions,
     * DoFs, segments, join flags, the body force), the segments and the
     * effects' rules, but no cell, nor the effects' arrays per cell.
     */
    bool
    has_cells() const
    {
      return holds_cells;
    }

    /**
     * Rank 0's scene to the ranks of @p communicator whose scene has no
     * cells (parse_parameters() without a mesh), once rank 0 has set it up
     * and applied the effects. Collective; rank 0 must hold the cells. The
     * effects' rules are not sent: each rank's effects declare them
     * (Effects::Interface::declare_rules()).
     */
    void
    share_without_cells(const MPI_Comm communicator);

    /**
     * Check the cells, distribute the DoFs, find the join points of every
     * segment and check that every free vertex is connected to one.
     */
    void
    setup();

    /**
     * Apply the effects' rules (SceneEffects::tissue_rule and
     * body_force_rules) to every cell of the mesh this rank holds:
     * SceneEffects::tissue_of_cell and the nodal loads body_force. Each
     * effect calls it once it has declared its rules
     * (Effects::Interface::apply()).
     */
    void
    apply_rules();

    /// Index of the segment called @p name; throws a clear error if unknown.
    unsigned int
    segment_index(const std::string &name) const;

    unsigned int
    n_vertices() const;
    /// The mesh's cells (also where this rank holds none, has_cells()).
    unsigned int
    n_cells() const;
    /// The DoFs of the one layout (dof_handler.n_dofs(), also without it).
    types::global_dof_index
    n_dofs() const;
    /// The mesh's vertices (triangulation.get_vertices(), also without it).
    const std::vector<Point<3>> &
    vertices() const;
    unsigned int
    n_free_dofs() const;
    unsigned int
    n_join_vertices(const unsigned int segment) const;

    /// The three DoFs of every used vertex (triangulation vertex numbering).
    const std::vector<std::array<types::global_dof_index, 3>> &
    vertex_dofs() const;
    /// Segment of every vertex, or numbers::invalid_unsigned_int if free.
    const std::vector<unsigned int> &
    vertex_segment() const;
    /// True for the DoFs of join points.
    const std::vector<bool> &
    join_dofs() const;

    /**
     * True if the DoFs of every vertex are 3p, 3p+1, 3p+2 for some point
     * index p (how deal.II numbers FESystem(FE_SimplexP(1), 3) unless
     * renumbered). The point-based models and ML's vertex aggregation rely
     * on it.
     */
    bool
    dofs_are_point_blocks() const;

    Triangulation<3>         triangulation;
    const FESystem<3>        fe;
    const MappingFE<3>       mapping;
    DoFHandler<3>            dof_handler;
    Material                 material;
    std::vector<BoneSegment> segments;
    /// Names the mesh in messages (file name or "generated cube").
    std::string mesh_description;
    /// Names a cell in messages as the mesh file did (empty: "cell i").
    Mesh::CellNamer cell_name;
    /**
     * Whether a vertex that touches two segments' bone is free (patient
     * meshes: every cut leaves such vertices, where the tissue covers the
     * saw kerf and is attached to neither part) instead of an error
     * (hand-made scenes, where it is a mistake in the segment definitions).
     */
    bool resolve_shared_join_points = false;
    /// The vertices that touched two segments and were left free.
    unsigned int n_shared_join_points = 0;

    /// What the scene's effects contribute; empty without effects.
    SceneEffects effects;

    /// The tissues: Scene::material alone unless an effect made them
    /// heterogeneous.
    unsigned int
    n_tissues() const
    {
      return effects.tissues.empty() ? 1 : effects.tissues.size();
    }
    const Material &
    tissue(const unsigned int t) const
    {
      return effects.tissues.empty() ? material : effects.tissues[t];
    }
    /// The tissue of the cell with active cell index @p c (where this rank
    /// holds the cells: has_cells()).
    unsigned int
    tissue_of_cell(const unsigned int c) const
    {
      Assert(holds_cells, ExcMessage("This rank holds no cell of the scene."));
      return effects.tissue_of_cell.empty() ? 0 : effects.tissue_of_cell[c];
    }
    bool
    has_body_force() const
    {
      return !effects.body_force_rules.empty();
    }
    bool
    has_vertex_constraints() const
    {
      return !effects.vertex_constraints.empty();
    }

    /// What the patient pipeline reported (stage, figure), if it ran.
    std::vector<std::pair<std::string, std::string>> patient_figures;

  private:
    void
    find_join_points();
    void
    check_free_region_connectivity() const;

    std::vector<std::array<types::global_dof_index, 3>> vertex_dof_indices;
    std::vector<unsigned int>                           segment_of_vertex;
    std::vector<bool>                                   is_join_dof;
    std::vector<unsigned int>                           n_joins_of_segment;
    bool                                                point_blocks = false;

    bool holds_cells = true;
    /// Where this rank holds no cells: what the mesh would tell.
    std::vector<Point<3>>   vertices_without_cells;
    unsigned int            n_cells_without_cells         = 0;
    unsigned int            n_used_vertices_without_cells = 0;
    types::global_dof_index n_dofs_without_cells          = 0;
  };
} // namespace softface

#endif
