// Rules by which an effect contributes to any cell (core): the default
// force on a whole cell from the force per unit volume.

#include <softface/core/cell_rules.h>
#include <softface/core/tetrahedron.h>

namespace softface
{
  Tensor<1, 3>
  BodyForce::on_cell(const Triangulation<3>::active_cell_iterator &cell) const
  {
    return Tetrahedron::signed_volume(Tetrahedron::vertices(cell)) *
           per_unit_volume(cell);
  }
} // namespace softface
