#ifndef softface_core_cell_rules_h
#define softface_core_cell_rules_h

#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

namespace softface
{
  using namespace dealii;

  /**
   * Rules by which an effect contributes to any cell (SceneEffects): each
   * part of softface that needs the contribution asks the rule about its
   * own cells, whether the scene's whole mesh (Scene), one MPI rank's part
   * of it (DistributedLayout) or the quadrature points of a model's own
   * element (the quadratic reference). The effect declares its rules once
   * (Effects::Interface::declare_rules()) on every rank and nobody derives
   * them again.
   */

  /// A body force (N/mm^3), constant in each cell.
  class BodyForce
  {
  public:
    virtual ~BodyForce() = default;

    /// The force per unit volume in @p cell (N/mm^3).
    virtual Tensor<1, 3>
    per_unit_volume(
      const Triangulation<3>::active_cell_iterator &cell) const = 0;

    /// The force on the whole of @p cell (N). The default is the cell's
    /// volume times per_unit_volume().
    virtual Tensor<1, 3>
    on_cell(const Triangulation<3>::active_cell_iterator &cell) const;
  };

  /// The tissue that fills each cell: an index into SceneEffects::tissues.
  class TissueRule
  {
  public:
    virtual ~TissueRule() = default;

    virtual unsigned int
    tissue(const Triangulation<3>::active_cell_iterator &cell) const = 0;
  };
} // namespace softface

#endif
