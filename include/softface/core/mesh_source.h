#ifndef softface_core_mesh_source_h
#define softface_core_mesh_source_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/grid/tria.h>

#include <softface/core/mesh.h>

#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace softface
{
  using namespace dealii;

  struct BoneSegment;

  /**
   * Where a scene's tetrahedral mesh comes from: a plugin family like
   * ASPECT's geometry models. 'Scene/Mesh source' names one; each registers
   * itself with SOFTFACE_REGISTER_MESH_SOURCE, declares its own entries of
   * the Scene section and makes the mesh. The sources shipped with softface
   * live in source/mesh_sources/ (cube, file, patient); a new one is one
   * file there.
   */
  namespace MeshSources
  {
    /// What the scene learns from its mesh source besides the cells.
    struct MadeMesh
    {
      /// Names the mesh in messages (a file name, "generated cube").
      std::string description;
      /// Names a cell in messages as the source did (empty: "cell i").
      Mesh::CellNamer cell_name;
      /**
       * Whether a vertex touching two segments' bone is left free (the
       * patient pipeline's cuts leave such vertices) instead of an error
       * (hand-made scenes, where it is a mistake).
       */
      bool resolve_shared_join_points = false;
      /// What the source reported (stage, figure): the patient pipeline's.
      std::vector<std::pair<std::string, std::string>> figures;
    };

    class Interface
    {
    public:
      virtual ~Interface() = default;

      /**
       * The names of subsections the source's declaration depends on,
       * read from a first pass over the file (the patient's cuts). A
       * source that needs none inherits this one.
       */
      static std::vector<std::string>
      names_from_first_pass(ParameterHandler &)
      {
        return {};
      }

      /**
       * Reads the source's entries; @p prm is inside the Scene section.
       * Relative file names are relative to @p input_directory; a source
       * that keeps files between runs keeps them in @p work_directory.
       */
      virtual void
      parse_parameters(ParameterHandler  &prm,
                       const std::string &input_directory,
                       const std::string &work_directory) = 0;

      /**
       * Makes the mesh. Every rank of MPI_COMM_WORLD calls it; the ranks of
       * @p mesh_readers fill @p triangulation (MPI_COMM_NULL on a rank that
       * holds no cells). A source may add to what makes a vertex a join
       * point of each of @p segments (the patient's bone faces). Progress
       * goes to @p log if it is not null.
       */
      virtual MadeMesh
      make_mesh(std::vector<BoneSegment> &segments,
                Triangulation<3>         &triangulation,
                MPI_Comm                  mesh_readers,
                std::ostream             *log) = 0;
    };

    struct Registration
    {
      /// Completes "'<name>' ..." in the description of 'Mesh source'.
      std::string description;
      /**
       * Declares the source's entries in the Scene section; the names are
       * those names_from_first_pass found (empty in the first pass).
       */
      std::function<void(ParameterHandler &, const std::vector<std::string> &)>
        declare_parameters;
      /**
       * The names of subsections the source's declaration depends on (the
       * patient's cuts), read from a first pass over the file; may be
       * empty.
       */
      std::function<std::vector<std::string>(ParameterHandler &)>
                                                  names_from_first_pass;
      std::function<std::unique_ptr<Interface>()> factory;
    };

    /**
     * Declares 'Mesh source' and every source's entries; @p prm is inside
     * the Scene section.
     */
    void
    declare_parameters(ParameterHandler               &prm,
                       const std::vector<std::string> &first_pass_names);

    /// Every source's names_from_first_pass; @p prm is inside Scene.
    std::vector<std::string>
    names_from_first_pass(ParameterHandler &prm);

    /// The source 'Mesh source' names; @p prm is inside the Scene section.
    std::unique_ptr<Interface>
    create(ParameterHandler &prm);

    /// One line per source: name and description (for --help).
    std::string
    describe_registered();

    namespace internal
    {
      /// Throws if @p name is registered already.
      bool
      register_mesh_source(const std::string &name, Registration registration);
    } // namespace internal
  }   // namespace MeshSources
} // namespace softface

/**
 * Register a mesh source under the name 'Scene/Mesh source' uses. The class
 * needs a default constructor and a static declare_parameters(prm, names)
 * that declares its entries in the Scene section; it may hide
 * Interface::names_from_first_pass with its own.
 */
#define SOFTFACE_REGISTER_MESH_SOURCE(classname, name, description)  \
  namespace                                                          \
  {                                                                  \
    const bool softface_registered_mesh_source_##classname =         \
      softface::MeshSources::internal::register_mesh_source(         \
        name,                                                        \
        {description,                                                \
         &classname::declare_parameters,                             \
         &classname::names_from_first_pass,                          \
         []() -> std::unique_ptr<softface::MeshSources::Interface> { \
           return std::make_unique<classname>();                     \
         }});                                                        \
  }

#endif
