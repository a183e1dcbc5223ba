#ifndef softface_mesh_h
#define softface_mesh_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/grid/tria.h>

#include <array>
#include <functional>
#include <string>

namespace softface
{
  using namespace dealii;

  /**
   * Where the tetrahedral meshes come from: the generated cube of the
   * benchmark of Mollemans et al. 2007 (Sec. 2.3.6, Fig. 2) or a file. Every
   * mesh passes Mesh::check_cells() before anything is computed on it.
   */
  namespace Mesh
  {
    /// The largest magnitude a point's coordinate may have, in millimetres
    /// (1000 km): beyond any anatomy in millimetres, and a tetrahedron's
    /// volume (three differences multiplied) overflows past about 1e102.
    constexpr double largest_coordinate = 1e9;

    /// "1e+305 mm, larger in magnitude than ..." for a message that refuses
    /// the coordinate @p x (farther than largest_coordinate).
    std::string
    far_coordinate(const double x);

    /// Material and boundary ids the generated cube carries.
    constexpr types::material_id cube_tissue_id  = 1;
    constexpr types::material_id cube_inner_id   = 2;
    constexpr types::boundary_id cube_outer_face = 1;

    /**
     * The cube [0, L]^3 with a centred inner cube of edge s (the region that
     * the paper moves 6 mm upwards). The mesh is a tensor grid whose lines
     * include the inner cube's faces, each hexahedron split into six
     * tetrahedra along its main diagonal (Kuhn), so the tetrahedra conform to
     * the inner region and to each other. Cells inside the inner cube get
     * material id 2, the others 1; all outer faces get boundary id 1.
     * With grading > 1 the grid lines crowd towards the planes of the inner
     * cube's faces (see the parameter "Grading"); with mirror_symmetric
     * the split of each octant mirrors the others.
     */
    struct CubeParameters
    {
      static void
      declare_parameters(ParameterHandler &prm);
      void
      parse_parameters(ParameterHandler &prm);

      double       edge_length         = 80.;
      double       inner_size          = 10.;
      unsigned int target_n_tetrahedra = 30000;
      double       grading             = 1.;
      bool         mirror_symmetric    = false;
      /// Material id of the tissue above z = L/2 (1: one tissue).
      types::material_id upper_material_id = cube_tissue_id;
    };

    void
    generate_cube(const CubeParameters &parameters,
                  Triangulation<3>     &triangulation);

    /**
     * Throw a clear error unless every cell is a positively oriented,
     * non-degenerate tetrahedron. @p source names the mesh in the message,
     * @p cell_name the cell.
     */
    /**
     * How a message names cell i of a triangulation. softface renumbers the
     * cells of every mesh for locality (order_for_locality()), so a read
     * mesh's cell is named by its number and line in the file; empty means
     * "cell i".
     */
    using CellNamer = std::function<std::string(unsigned int)>;

    /// Cell @p cell as @p cell_name names it, or "cell i" if it is empty.
    std::string
    cell_description(const CellNamer &cell_name, unsigned int cell);

    void
    check_cells(const Triangulation<3> &triangulation,
                const std::string      &source,
                const CellNamer        &cell_name = {});

  } // namespace Mesh
} // namespace softface

#endif
