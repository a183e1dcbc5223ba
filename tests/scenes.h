#ifndef softface_tests_scenes_h
#define softface_tests_scenes_h

// Scenes that several tests share, built in code.

#include <deal.II/grid/grid_tools.h>

#include <softface/core/mesh.h>
#include <softface/core/planning.h>
#include <softface/core/scene.h>

#include <cmath>

namespace softface_tests
{
  using namespace softface;

  /// The cube of Mollemans et al. 2007: outer faces held (segment 0, "fixed"),
  /// inner cube (segment 1, "bone") free to be moved by a planning. The upper
  /// half (z > 40) has material id @p upper_material_id (for two tissues), the
  /// rest of the tissue 1.
  inline void
  make_cube_scene(
    Scene                   &scene,
    const unsigned int       target_n_tetrahedra,
    const types::material_id upper_material_id = Mesh::cube_tissue_id)
  {
    Mesh::CubeParameters cube;
    cube.target_n_tetrahedra = target_n_tetrahedra;
    cube.upper_material_id   = upper_material_id;
    Mesh::generate_cube(cube, scene.triangulation);
    scene.mesh_description = "generated cube";
    scene.segments         = {{"fixed", {}, {Mesh::cube_outer_face}, {}},
                              {"bone", {Mesh::cube_inner_id}, {}, {}}};
    scene.setup();
  }

  /**
   * The paper's cube with its interior vertices moved by a smooth field that
   * vanishes on the outer faces, so that no tetrahedron is a right-angled
   * Kuhn tetrahedron and element shapes vary. With @p with_bone the inner
   * cube is segment 1 ("bone") besides the held faces (segment 0), without
   * it the faces are the only segment ("boundary").
   */
  inline void
  make_distorted_cube_scene(Scene             &scene,
                            const unsigned int target_n_tetrahedra,
                            const bool         with_bone)
  {
    Mesh::CubeParameters cube;
    cube.target_n_tetrahedra = target_n_tetrahedra;
    Mesh::generate_cube(cube, scene.triangulation);
    GridTools::transform(
      [](const Point<3> &x) {
        const double s = std::sin(M_PI * x[0] / 80) *
                         std::sin(M_PI * x[1] / 80) *
                         std::sin(M_PI * x[2] / 80);
        return x + Point<3>(2.5 * s, -1.5 * s * std::cos(x[2]), 2. * s);
      },
      scene.triangulation);
    scene.mesh_description = "distorted cube";
    if (with_bone)
      scene.segments = {{"fixed", {}, {Mesh::cube_outer_face}, {}},
                        {"bone", {Mesh::cube_inner_id}, {}, {}}};
    else
      scene.segments = {{"boundary", {}, {Mesh::cube_outer_face}, {}}};
    scene.setup();
  }

  /// The paper's cube held on its face z = 0 only (segment 0, "fixed"; the
  /// other outer faces free), the inner cube segment 1 ("bone"). With the
  /// cells in slabs of z, a rank of a partition may own no join point.
  inline void
  make_cube_held_at_bottom(Scene &scene, const unsigned int target_n_tetrahedra)
  {
    Mesh::CubeParameters parameters;
    parameters.target_n_tetrahedra = target_n_tetrahedra;
    Mesh::generate_cube(parameters, scene.triangulation);
    for (const auto &cell : scene.triangulation.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() && face->center()[2] > 1e-6)
          face->set_boundary_id(Mesh::cube_outer_face + 1);
    scene.mesh_description = "cube held at z = 0";
    scene.segments         = {{"fixed", {}, {Mesh::cube_outer_face}, {}},
                              {"bone", {Mesh::cube_inner_id}, {}, {}}};
    scene.setup();
  }

  /// Segments that share vertices, as a patient's cuts leave them: the
  /// cube's upper half is a third segment, and its vertices on the held
  /// faces and at the inner bone touch two segments' bone and are left free.
  /// A fourth segment takes boundary id 0, which no face of the cube has but
  /// the faces at the edge of a rank's part do on that rank (a contact-only
  /// segment may have no join point).
  inline void
  make_cube_with_shared_join_points(Scene             &scene,
                                    const unsigned int target_n_tetrahedra)
  {
    Mesh::CubeParameters parameters;
    parameters.target_n_tetrahedra = target_n_tetrahedra;
    parameters.upper_material_id   = 7;
    Mesh::generate_cube(parameters, scene.triangulation);
    scene.mesh_description = "generated cube";
    scene.segments         = {{"fixed", {}, {Mesh::cube_outer_face}, {}},
                              {"bone", {Mesh::cube_inner_id}, {}, {}},
                              {"upper half", {7}, {}, {}},
                              {"boundary id 0", {}, {0}, {}, true}};
    scene.resolve_shared_join_points = true;
    scene.setup();
  }

  /// The paper's planning: the inner cube moves by @p translation, rotated by
  /// @p angle degrees about z through the cube's centre.
  inline Vector<double>
  move_bone(const Scene    &scene,
            const Point<3> &translation,
            const double    angle = 0.)
  {
    Planning planning;
    planning.set_motion(
      1,
      RigidMotion(translation, Point<3>(0, 0, 1), angle, Point<3>(40, 40, 40)));
    return planning.prescribed_displacement(scene);
  }

  /// max_i |a_i - b_i| / max_i |b_i|
  inline double
  relative_difference(const Vector<double> &a, const Vector<double> &b)
  {
    Vector<double> d = a;
    d -= b;
    return d.linfty_norm() / b.linfty_norm();
  }
} // namespace softface_tests

#endif
