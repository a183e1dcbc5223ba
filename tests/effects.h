#ifndef softface_tests_effects_h
#define softface_tests_effects_h

// What the effect tests share: an effect created from its parameters as a
// scene file would give them, and the cube relabelled as a bar or column
// with named end faces.

#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <softface/core/mesh.h>
#include <softface/core/scene.h>
#include <softface/effects/interface.h>

#include <string>
#include <utility>
#include <vector>

#include "scenes.h"

namespace softface_tests
{
  using namespace softface;

  /// The vector (x, y, z).
  inline Tensor<1, 3>
  vec(const double x, const double y, const double z)
  {
    Tensor<1, 3> v;
    v[0] = x, v[1] = y, v[2] = z;
    return v;
  }

  /// Create the effect @p name with @p values set in its subsection and
  /// apply it to @p scene (set up), as the simulator does: an effect that
  /// changes the mesh does so first, and the scene is set up again.
  inline void
  apply_effect(Scene                                                  &scene,
               const std::string                                      &name,
               const std::vector<std::pair<std::string, std::string>> &values)
  {
    ParameterHandler prm;
    Effects::declare_parameters(prm);
    prm.enter_subsection("Effects");
    prm.enter_subsection(name);
    for (const auto &[entry, value] : values)
      prm.set(entry, value);
    prm.leave_subsection();
    prm.leave_subsection();
    const auto effect = Effects::create(name, prm);
    if (!effect->prepare_mesh(scene).empty())
      scene.setup();
    effect->apply(scene);
    scene.effects.names.push_back(name);
  }

  /**
   * The cube [0, L]^3 (L = 80 mm, mirror-symmetric split, so that the mid
   * planes are grid planes) as one block of tissue: material id 1 where
   * x < L/2, @p right_material_id beyond; the face x = 0 gets boundary id
   * 10, x = L 11, z = L 12, every other face 0. No segment is set.
   */
  inline void
  make_block(Scene                   &scene,
             const unsigned int       target_n_tetrahedra,
             const types::material_id right_material_id)
  {
    Mesh::CubeParameters cube;
    cube.target_n_tetrahedra = target_n_tetrahedra;
    cube.mirror_symmetric    = true;
    Mesh::generate_cube(cube, scene.triangulation);
    const double L = cube.edge_length;
    for (const auto &cell : scene.triangulation.active_cell_iterators())
      {
        cell->set_material_id(cell->center()[0] < L / 2. ? 1 :
                                                           right_material_id);
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              const Point<3> c = face->center();
              face->set_boundary_id(std::abs(c[0]) < 1e-9     ? 10 :
                                    std::abs(c[0] - L) < 1e-9 ? 11 :
                                    std::abs(c[2] - L) < 1e-9 ? 12 :
                                                                0);
            }
      }
    scene.mesh_description = "block";
  }

  /**
   * The cube of Mollemans et al. 2007, of about 3000 tetrahedra in two tissues
   * (the upper half four times stiffer), and, if asked, under gravity: the MPI
   * tests' scene for per-cell materials and a body force.
   */
  inline void
  make_two_tissue_cube(Scene &scene, const bool with_gravity = true)
  {
    make_cube_scene(scene, 3000, 3);
    apply_effect(scene,
                 "heterogeneous tissue",
                 {{"Young's moduli", "1: 3000, 3: 12000"},
                  {"Poisson's ratios", "1: 0.46, 3: 0.4"}});
    if (with_gravity)
      apply_effect(scene,
                   "gravity",
                   {{"Gravity", "0, 0, -9.81"}, {"Density", "1000"}});
  }
} // namespace softface_tests

#endif
