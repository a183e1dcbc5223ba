// Sliding contact (effects; future work in Mollemans et al. 2007, Sec. 3.3):
// tissue on a named bone surface slides along it without friction instead of
// being glued, in every model (constraints in both FEMs, projected local
// updates in the mass tensor and mass spring models).

#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <softface/core/error.h>
#include <softface/effects/interface.h>

#include <map>
#include <set>
#include <sstream>

namespace softface
{
  namespace Effects
  {
    /**
     * Vertices of the contact faces are not join points: each stays on the
     * surface of its bone segment as the segment moves, n . (u - d) = 0
     * with n the surface's normal at rest (the mean of the contact faces'
     * normals at the vertex, from bone to tissue) and d the segment's
     * displacement there; the tangential motion is free. Unilateral: n .
     * (u - d) >= 0, the tissue may lift off but never enters the bone (an
     * active-set iteration in the FEMs, projected updates in the point
     * models). The plane is the surface's tangent plane at rest, moved with
     * the bone's displacement at the vertex: exact for a flat surface moved
     * by a translation, to first order in the rotation angle otherwise.
     * A vertex that also touches a glued boundary stays glued.
     */
    class SlidingContact : public Interface
    {
    public:
      /// Boundary id the contact faces get (the mesh must not use it).
      static constexpr types::boundary_id contact_boundary_id = 253;

      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Segment",
                          "",
                          Patterns::Anything(),
                          "The bone segment whose surface the tissue slides "
                          "on (one of 'Scene/Bone segments'); its planning "
                          "motion moves the surface.");
        prm.declare_entry(
          "Boundary ids",
          "",
          Patterns::List(Patterns::Integer(0, 252)),
          "Boundary ids of the mesh faces in contact with that surface; "
          "empty: the segment's own boundary ids (its glued faces, e.g. a "
          "patient's bone part), of which 'Region' picks the contact.");
        prm.declare_entry("Region",
                          "",
                          Patterns::Anything(),
                          "A box 'x0, x1, y0, y1, z0, z1' in mm: only faces "
                          "whose centre lies in it slide (e.g. the lips over "
                          "the front teeth); empty: every such face.");
        prm.declare_entry("Unilateral",
                          "false",
                          Patterns::Bool(),
                          "false: the tissue stays on the surface "
                          "(bilateral); true: it may lift off but never "
                          "enters the bone (an active-set iteration).");
        declare_active_set_iterations(prm);
      }

      void
      parse_parameters(ParameterHandler &prm) override
      {
        segment_name = prm.get("Segment");
        if (segment_name.empty())
          throw Error("Segment: name the bone segment the tissue slides on.");
        for (const std::string &id :
             Utilities::split_string_list(prm.get("Boundary ids")))
          boundary_ids.insert(Utilities::string_to_int(id));
        region         = parse_region("Region", prm.get("Region"));
        unilateral     = prm.get_bool("Unilateral");
        max_iterations = prm.get_integer("Maximum active-set iterations");
      }

      unsigned int
      contributions() const override
      {
        return SceneEffects::free_vertex_constraints;
      }

      std::string
      prepare_mesh(Scene &scene) const override
      {
        const unsigned int s   = segment_index(scene);
        auto               ids = boundary_ids;
        if (ids.empty())
          ids = scene.segments[s].boundary_ids;
        if (ids.empty())
          throw Error("Effects/sliding contact: segment '" + segment_name +
                      "' has no boundary ids; give the contact faces' "
                      "'Boundary ids'.");
        unsigned int n_faces = 0;
        for (const auto &cell : scene.triangulation.active_cell_iterators())
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary())
              {
                if (face->boundary_id() == contact_boundary_id)
                  throw Error("Effects/sliding contact: the mesh uses "
                              "boundary id 253, which marks contact faces.");
                if (ids.count(face->boundary_id()) &&
                    region.contains(face->center()))
                  {
                    face->set_boundary_id(contact_boundary_id);
                    ++n_faces;
                  }
              }
        if (n_faces == 0)
          throw Error("Effects/sliding contact: no boundary face of mesh " +
                      scene.mesh_description +
                      " has one of the boundary ids inside the region.");
        // The segment may now glue no vertex: it carries the surface.
        scene.segments[s].carries_contact_only = true;
        std::ostringstream line;
        line << "sliding contact: " << n_faces << " faces on segment '"
             << segment_name << "' slide (boundary id 253)";
        return line.str();
      }

    protected:
      std::string
      check_and_add(Scene &scene) const override
      {
        const unsigned int s = segment_index(scene);
        // Area-weighted normals from bone to tissue: the faces' outward
        // normals (away from their cell) reversed.
        std::map<unsigned int, Tensor<1, 3>> normal;
        for (const auto &cell : scene.triangulation.active_cell_iterators())
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary() &&
                face->boundary_id() == contact_boundary_id)
              {
                const Point<3> p0 = face->vertex(0);
                Tensor<1, 3>   n =
                  cross_product_3d(face->vertex(1) - p0, face->vertex(2) - p0);
                const Tensor<1, 3> out = face->center() - cell->center();
                if (n * out > 0.)
                  n = -n;
                for (const unsigned int v : face->vertex_indices())
                  normal[face->vertex_index(v)] += n;
              }
        std::set<unsigned int> constrained;
        for (const auto &c : scene.effects.vertex_constraints)
          constrained.insert(c.vertex), constrained.insert(c.partner);
        unsigned int glued = 0, taken = 0, added = 0;
        for (const auto &[vertex, n] : normal)
          {
            if (scene.vertex_segment()[vertex] != numbers::invalid_unsigned_int)
              {
                ++glued;
                continue;
              }
            if (constrained.count(vertex))
              {
                ++taken;
                continue;
              }
            VertexConstraint c;
            c.vertex     = vertex;
            c.normal     = n / n.norm();
            c.segment    = s;
            c.unilateral = unilateral;
            scene.effects.vertex_constraints.push_back(c);
            ++added;
          }
        if (added == 0)
          throw Error("Effects/sliding contact: every vertex of the contact "
                      "faces is glued to a bone segment; nothing slides.");
        // Several effects with active sets: the largest limit holds.
        scene.effects.max_active_set_iterations =
          std::max(scene.effects.max_active_set_iterations, max_iterations);
        std::ostringstream line;
        line << "sliding contact: " << added << " vertices slide on '"
             << segment_name << "' ("
             << (unilateral ? "unilateral" : "bilateral") << "), " << glued
             << " on the rim stay glued";
        if (taken > 0)
          line << ", " << taken << " already constrained by another effect";
        return line.str();
      }

    private:
      unsigned int
      segment_index(const Scene &scene) const
      {
        try
          {
            return scene.segment_index(segment_name);
          }
        catch (const Error &e)
          {
            throw Error(std::string("Effects/sliding contact/Segment: ") +
                        e.what());
          }
      }

      std::string                  segment_name;
      std::set<types::boundary_id> boundary_ids;
      Region                       region;
      bool                         unilateral     = false;
      unsigned int                 max_iterations = 50;
    };

    SOFTFACE_REGISTER_EFFECT(SlidingContact,
                             "sliding contact",
                             "Tissue on a bone surface slides along it without "
                             "friction (bilateral, or unilateral: may lift "
                             "off), in every model but reference fem.")
  } // namespace Effects
} // namespace softface
