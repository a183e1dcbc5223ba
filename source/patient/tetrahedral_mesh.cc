// The tetrahedral soft-tissue mesh of a patient (patient; Mollemans et al.
// 2007, Sec. 3.1, made it with Amira): CGAL Mesh_3 from the labelled image
// inside the region of interest, sliver perturbation and exudation, boundary
// faces classified as skin, cut of the region or contact with a bone segment,
// quality figures, and VTU/gmsh files that Scene reads back. This is softface's
// only translation unit with CGAL Mesh_3 (about a minute and 3 GB to compile).

#include <softface/core/error.h>
#include <softface/patient/osteotomy.h>
#include <softface/patient/tetrahedral_mesh.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Image_3.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/exude_mesh_3.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/perturb_mesh_3.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
      using Domain = CGAL::Labeled_mesh_domain_3<Kernel>;
      using Tr     = CGAL::
        Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
      using C3t3     = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
      using Criteria = CGAL::Mesh_criteria_3<Tr>;

      Vec3
      minus(const Vec3 &a, const Vec3 &b)
      {
        return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}};
      }
      double
      dot(const Vec3 &a, const Vec3 &b)
      {
        return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
      }
      Vec3
      cross(const Vec3 &a, const Vec3 &b)
      {
        return {{a[1] * b[2] - a[2] * b[1],
                 a[2] * b[0] - a[0] * b[2],
                 a[0] * b[1] - a[1] * b[0]}};
      }
      double
      norm(const Vec3 &a)
      {
        return std::sqrt(dot(a, a));
      }

      // CGAL's sliver perturbation and exudation, each run until every
      // dihedral angle reaches the sliver bound or no move improves the
      // worst one. CGAL's own bound on them is wall-clock time: a mesh cut
      // short by the clock depends on how busy the machine is, so the
      // safety limit ends the run with an error instead of returning it.
      // The outcome of each ("bound reached" or "no further improvement")
      // is reported with the mesh.
      void
      optimise_slivers(C3t3                            &c3t3,
                       const Domain                    &domain,
                       const TetrahedralMeshParameters &prm,
                       std::array<std::string, 2>      &outcome)
      {
        const auto check =
          [&](const std::string                        &step,
              const CGAL::Mesh_optimization_return_code code) -> std::string {
          if (code == CGAL::BOUND_REACHED)
            return "bound reached";
          if (code == CGAL::CANT_IMPROVE_ANYMORE)
            return "no further improvement";
          if (code == CGAL::TIME_LIMIT_REACHED)
            {
              std::ostringstream s;
              s << "Mesh: CGAL's " << step << " ran past "
                << "Scene/Patient/Mesh/Optimisation safety limit = "
                << prm.optimisation_safety_seconds
                << " s (wall-clock time) before it ended by itself. A mesh "
                   "cut short by the clock would depend on how busy the "
                   "machine is, so none is made: raise the limit (0: none) "
                   "or lower Sliver bound.";
              throw Error(s.str());
            }
          return "CGAL code " + std::to_string(static_cast<int>(code));
        };
        namespace p = CGAL::parameters;
        outcome[0] =
          check("sliver perturbation",
                CGAL::perturb_mesh_3(c3t3,
                                     domain,
                                     p::time_limit =
                                       prm.optimisation_safety_seconds,
                                     p::sliver_bound = prm.sliver_bound));
        outcome[1] =
          check("sliver exudation",
                CGAL::exude_mesh_3(c3t3,
                                   p::time_limit =
                                     prm.optimisation_safety_seconds,
                                   p::sliver_bound = prm.sliver_bound));
      }

      // The soft tissue to mesh: which labels are tissue, how many voxels
      // of it lie in the region of interest, and their bounding box (with
      // a margin, so that the image function sees the outside on every
      // side).
      struct TissueBox
      {
        std::vector<bool>          tissue; ///< per label
        std::size_t                n_tissue = 0;
        std::array<std::size_t, 3> lo, size;
      };

      TissueBox
      tissue_box(const LabelVolume               &labels,
                 const std::vector<std::uint8_t> &tissue_labels,
                 const RegionOfInterest          &roi)
      {
        // The voxels to mesh, and their bounding box (with a margin, so that
        // the image function sees the outside on every side).
        TissueBox                  box;
        auto                      &lo = box.lo;
        std::array<std::size_t, 3> hi{{0, 0, 0}};
        lo = {{labels.size[0], labels.size[1], labels.size[2]}};
        box.tissue.assign(256, false);
        auto &tissue = box.tissue;
        for (const auto l : tissue_labels)
          tissue[l] = true;
        std::size_t &n_tissue = box.n_tissue;
        for (std::size_t k = 0; k < labels.size[2]; ++k)
          for (std::size_t j = 0; j < labels.size[1]; ++j)
            for (std::size_t i = 0; i < labels.size[0]; ++i)
              if (tissue[labels(i, j, k)] &&
                  roi.contains(labels.point(i, j, k)))
                {
                  ++n_tissue;
                  const std::size_t ijk[3] = {i, j, k};
                  for (unsigned int d = 0; d < 3; ++d)
                    lo[d] = std::min(lo[d], ijk[d]),
                    hi[d] = std::max(hi[d], ijk[d]);
                }
        if (n_tissue < 8)
          throw Error(
            "Mesh: the region of interest holds no soft tissue (" +
            std::to_string(n_tissue) +
            " voxels); check Scene/Patient/Region of interest against "
            "the volume.");
        auto &size = box.size;
        for (unsigned int d = 0; d < 3; ++d)
          {
            lo[d]   = lo[d] >= 2 ? lo[d] - 2 : 0;
            hi[d]   = std::min(hi[d] + 2, labels.size[d] - 1);
            size[d] = hi[d] - lo[d] + 1;
          }
        return box;
      }

      CGAL::Image_3
      labelled_image(const LabelVolume               &labels,
                     const TissueBox                 &box,
                     const RegionOfInterest          &roi,
                     const TetrahedralMeshParameters &prm)
      {
        const auto &lo = box.lo, &size = box.size;
        const auto &tissue = box.tissue;
        // CGAL's image: the tissue labels, 0 elsewhere, in index space scaled
        // by the spacing (origin and direction are applied afterwards).
        _image *raw  = _createImage(size[0],
                                   size[1],
                                   size[2],
                                   1,
                                   labels.spacing[0],
                                   labels.spacing[1],
                                   labels.spacing[2],
                                   1,
                                   WK_FIXED,
                                   SGN_UNSIGNED);
        auto   *data = static_cast<unsigned char *>(raw->data);
        for (std::size_t k = 0; k < size[2]; ++k)
          for (std::size_t j = 0; j < size[1]; ++j)
            for (std::size_t i = 0; i < size[0]; ++i)
              {
                const std::uint8_t l = labels(lo[0] + i, lo[1] + j, lo[2] + k);
                const bool         in =
                  tissue[l] &&
                  roi.contains(labels.point(lo[0] + i, lo[1] + j, lo[2] + k));
                // One domain unless the interfaces between tissues are to be
                // meshed conformingly.
                data[i + size[0] * (j + size[1] * k)] =
                  in ? (prm.conforming_interfaces ? l : 1) : 0;
              }
        return CGAL::Image_3(raw);
      }

      // Mesh_3 on the image, with the cell size that gives about the
      // target count; the outcome of the sliver optimisers to @p outcome.
      C3t3
      mesh_image(const CGAL::Image_3             &image,
                 const LabelVolume               &labels,
                 const std::size_t                n_tissue,
                 const TetrahedralMeshParameters &prm,
                 std::array<std::string, 2>      &outcome)
      {
        // The cell size that gives about the target count: these criteria
        // average about 0.05 R^3 per tetrahedron (measured on phantoms); the
        // surface's own refinement shifts that, so a count more than 25% off
        // the target is corrected once by the cube root of the ratio.
        const double tissue_volume = n_tissue * labels.voxel_volume();
        double       cell_size =
          prm.cell_size > 0. ?
                  prm.cell_size :
                  std::cbrt(tissue_volume /
                      (0.05 * std::max(1u, prm.target_n_tetrahedra)));

        namespace p = CGAL::parameters;
        C3t3 c3t3;
        for (unsigned int attempt = 0; attempt < 2; ++attempt)
          {
            CGAL::Random random(prm.seed);
            const Domain domain = Domain::create_labeled_image_mesh_domain(
              image, p::relative_error_bound = 1e-6, p::p_rng = &random);
            const Criteria criteria(p::facet_angle    = prm.facet_angle,
                                    p::facet_size     = cell_size,
                                    p::facet_distance = prm.facet_distance,
                                    p::cell_radius_edge_ratio =
                                      prm.radius_edge_ratio,
                                    p::cell_size = cell_size);
            c3t3 = CGAL::make_mesh_3<C3t3>(domain,
                                           criteria,
                                           p::no_perturb(),
                                           p::no_exude());
            optimise_slivers(c3t3, domain, prm, outcome);
            const double ratio = double(c3t3.number_of_cells_in_complex()) /
                                 std::max(1u, prm.target_n_tetrahedra);
            if (prm.cell_size > 0. || (ratio > 0.75 && ratio < 1.25) ||
                ratio == 0.)
              break;
            cell_size *= std::cbrt(ratio);
          }
        if (c3t3.number_of_cells_in_complex() == 0)
          throw Error(
            "Mesh: CGAL made no tetrahedron from the soft tissue (" +
            std::to_string(n_tissue) +
            " voxels); the region may be thinner than the cell size " +
            std::to_string(cell_size) + " mm.");
        return c3t3;
      }
    } // namespace

    bool
    RegionOfInterest::contains(const Vec3 &x) const
    {
      for (unsigned int d = 0; d < 3; ++d)
        if (x[d] < box_min[d] || x[d] > box_max[d])
          return false;
      for (const auto &[point, normal] : planes)
        if (dot(minus(x, point), normal) > 0.)
          return false;
      return true;
    }

    TetrahedralMesh::Quality
    TetrahedralMesh::quality() const
    {
      Quality q;
      q.min_dihedral_angle = 180.;
      q.worst_radius_ratio = 1.;
      q.smallest_volume    = 1e300;
      double sum_ratio     = 0.;
      for (const auto &c : cells)
        {
          const Vec3  *x[4] = {&points[c[0]],
                               &points[c[1]],
                               &points[c[2]],
                               &points[c[3]]};
          const double V = dot(cross(minus(*x[1], *x[0]), minus(*x[2], *x[0])),
                               minus(*x[3], *x[0])) /
                           6.;
          q.volume += V;
          q.smallest_volume = std::min(q.smallest_volume, V);
          // Dihedral angle at each edge (a, b): the angle between the
          // other two vertices seen along the edge.
          static const unsigned int edges[6][4] = {{0, 1, 2, 3},
                                                   {0, 2, 1, 3},
                                                   {0, 3, 1, 2},
                                                   {1, 2, 0, 3},
                                                   {1, 3, 0, 2},
                                                   {2, 3, 0, 1}};
          double                    face_area   = 0.;
          for (const auto &e : edges)
            {
              Vec3         t = minus(*x[e[1]], *x[e[0]]);
              const double l = norm(t);
              for (auto &v : t)
                v /= l;
              Vec3 u = minus(*x[e[2]], *x[e[0]]), w = minus(*x[e[3]], *x[e[0]]);
              const double pu = dot(u, t), pw = dot(w, t);
              for (unsigned int d = 0; d < 3; ++d)
                u[d] -= pu * t[d], w[d] -= pw * t[d];
              const double angle =
                std::acos(
                  std::clamp(dot(u, w) / (norm(u) * norm(w)), -1., 1.)) *
                180. / M_PI;
              q.min_dihedral_angle = std::min(q.min_dihedral_angle, angle);
              q.max_dihedral_angle = std::max(q.max_dihedral_angle, angle);
            }
          static const unsigned int faces[4][3] = {{1, 2, 3},
                                                   {0, 2, 3},
                                                   {0, 1, 3},
                                                   {0, 1, 2}};
          for (const auto &f : faces)
            face_area += 0.5 * norm(cross(minus(*x[f[1]], *x[f[0]]),
                                          minus(*x[f[2]], *x[f[0]])));
          // Circumradius from the products of opposite edge lengths.
          const double a =
            norm(minus(*x[0], *x[1])) * norm(minus(*x[2], *x[3]));
          const double b =
            norm(minus(*x[0], *x[2])) * norm(minus(*x[1], *x[3]));
          const double cc =
            norm(minus(*x[0], *x[3])) * norm(minus(*x[1], *x[2]));
          const double p =
            (a + b + cc) * (a + b - cc) * (a - b + cc) * (-a + b + cc);
          const double R     = std::sqrt(std::max(p, 0.)) / (24. * std::abs(V));
          const double r     = 3. * std::abs(V) / face_area;
          const double ratio = 3. * r / R;
          q.worst_radius_ratio = std::min(q.worst_radius_ratio, ratio);
          sum_ratio += ratio;
        }
      q.mean_radius_ratio = cells.empty() ? 0. : sum_ratio / cells.size();
      return q;
    }

    void
    TetrahedralMesh::write_vtu(const std::string &filename) const
    {
      std::ofstream out(filename);
      if (!out)
        throw Error("Cannot write '" + filename + "'.");
      const std::size_t n_cells = cells.size() + boundary_faces.size();
      out << "<?xml version=\"1.0\"?>\n"
          << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
             "byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n"
          << "<Piece NumberOfPoints=\"" << points.size()
          << "\" NumberOfCells=\"" << n_cells << "\">\n"
          << "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" "
             "format=\"ascii\">\n"
          << std::setprecision(12);
      for (const auto &p : points)
        out << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
      out << "</DataArray>\n</Points>\n<Cells>\n"
          << "<DataArray type=\"Int64\" Name=\"connectivity\" "
             "format=\"ascii\">\n";
      for (const auto &c : cells)
        out << c[0] << ' ' << c[1] << ' ' << c[2] << ' ' << c[3] << '\n';
      for (const auto &f : boundary_faces)
        out << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
      out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" "
             "format=\"ascii\">\n";
      std::size_t offset = 0;
      for (std::size_t c = 0; c < cells.size(); ++c)
        out << (offset += 4) << '\n';
      for (std::size_t f = 0; f < boundary_faces.size(); ++f)
        out << (offset += 3) << '\n';
      out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" "
             "format=\"ascii\">\n";
      for (std::size_t c = 0; c < cells.size(); ++c)
        out << "10\n";
      for (std::size_t f = 0; f < boundary_faces.size(); ++f)
        out << "5\n";
      out
        << "</DataArray>\n</Cells>\n<CellData Scalars=\"MaterialID\">\n"
        << "<DataArray type=\"Int32\" Name=\"MaterialID\" format=\"ascii\">\n";
      for (const auto m : material_ids)
        out << int(m) << '\n';
      for (const auto b : boundary_ids)
        out << b << '\n';
      out << "</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n"
             "</VTKFile>\n";
      if (!out)
        throw Error("Cannot write '" + filename + "'.");
    }

    void
    TetrahedralMesh::write_msh(const std::string &filename) const
    {
      std::ofstream out(filename);
      if (!out)
        throw Error("Cannot write '" + filename + "'.");
      out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n"
          << points.size() << '\n'
          << std::setprecision(12);
      for (std::size_t i = 0; i < points.size(); ++i)
        out << i + 1 << ' ' << points[i][0] << ' ' << points[i][1] << ' '
            << points[i][2] << '\n';
      out << "$EndNodes\n$Elements\n"
          << boundary_faces.size() + cells.size() << '\n';
      std::size_t id = 0;
      for (std::size_t f = 0; f < boundary_faces.size(); ++f)
        out << ++id << " 2 2 " << boundary_ids[f] << ' ' << boundary_ids[f]
            << ' ' << boundary_faces[f][0] + 1 << ' '
            << boundary_faces[f][1] + 1 << ' ' << boundary_faces[f][2] + 1
            << '\n';
      for (std::size_t c = 0; c < cells.size(); ++c)
        out << ++id << " 4 2 " << int(material_ids[c]) << ' '
            << int(material_ids[c]) << ' ' << cells[c][0] + 1 << ' '
            << cells[c][1] + 1 << ' ' << cells[c][2] + 1 << ' '
            << cells[c][3] + 1 << '\n';
      out << "$EndElements\n";
      if (!out)
        throw Error("Cannot write '" + filename + "'.");
    }

    TetrahedralMesh
    make_tetrahedral_mesh(const LabelVolume               &labels,
                          const std::vector<std::uint8_t> &tissue_labels,
                          const std::uint8_t               bone_label,
                          const LabelVolume               &parts,
                          const RegionOfInterest          &roi,
                          const TetrahedralMeshParameters &prm)
    {
      const TissueBox            box = tissue_box(labels, tissue_labels, roi);
      const auto                &lo  = box.lo;
      const auto                &tissue = box.tissue;
      std::array<std::string, 2> outcome;
      const C3t3 c3t3 = mesh_image(labelled_image(labels, box, roi, prm),
                                   labels,
                                   box.n_tissue,
                                   prm,
                                   outcome);

      // From CGAL's index space to the patient frame.
      const auto to_patient = [&](const Tr::Bare_point &x) {
        return labels.point(lo[0] + x.x() / labels.spacing[0],
                            lo[1] + x.y() / labels.spacing[1],
                            lo[2] + x.z() / labels.spacing[2]);
      };
      const auto &D        = labels.direction;
      const bool  mirrored = D[0] * (D[4] * D[8] - D[5] * D[7]) -
                              D[1] * (D[3] * D[8] - D[5] * D[6]) +
                              D[2] * (D[3] * D[7] - D[4] * D[6]) <
                            0.;

      TetrahedralMesh mesh;
      mesh.perturbation_outcome = outcome[0];
      mesh.exudation_outcome    = outcome[1];
      std::map<Tr::Vertex_handle, unsigned int> index;
      const Tr                                 &tr = c3t3.triangulation();
      const auto point_of = tr.geom_traits().construct_point_3_object();
      const auto vertex   = [&](const Tr::Vertex_handle &v) {
        const auto it = index.find(v);
        if (it != index.end())
          return it->second;
        const unsigned int i = mesh.points.size();
        mesh.points.push_back(to_patient(point_of(v->point())));
        index.emplace(v, i);
        return i;
      };
      for (auto c = c3t3.cells_in_complex_begin();
           c != c3t3.cells_in_complex_end();
           ++c)
        {
          std::array<unsigned int, 4> cell;
          for (unsigned int a = 0; a < 4; ++a)
            cell[a] = vertex(c->vertex(a));
          if (mirrored)
            std::swap(cell[1], cell[2]);
          mesh.cells.push_back(cell);
          std::uint8_t material = c3t3.subdomain_index(c);
          if (!prm.conforming_interfaces)
            {
              // The tissue at the cell's centroid (the nearest tissue voxel
              // along the way if the centroid's voxel is not tissue).
              Vec3 centre{{0., 0., 0.}};
              for (const unsigned int v : cell)
                for (unsigned int d = 0; d < 3; ++d)
                  centre[d] += 0.25 * mesh.points[v][d];
              material = tissue_labels.back();
              std::array<std::size_t, 3> ijk;
              if (labels.nearest_voxel(centre, ijk) &&
                  tissue[labels(ijk[0], ijk[1], ijk[2])])
                material = labels(ijk[0], ijk[1], ijk[2]);
            }
          mesh.material_ids.push_back(material);
        }

      // Boundary faces of the meshed tissue, and what lies beyond each.
      const double h =
        std::min({labels.spacing[0], labels.spacing[1], labels.spacing[2]});
      const auto classify = [&](const Vec3 &centre, const Vec3 &outward) {
        for (const double step : {0.5, 1., 1.5, 2.})
          {
            Vec3 x;
            for (unsigned int d = 0; d < 3; ++d)
              x[d] = centre[d] + step * h * outward[d];
            std::array<std::size_t, 3> v;
            if (!roi.contains(x) || !labels.nearest_voxel(x, v))
              return cut_boundary_id;
            const std::uint8_t l = labels(v[0], v[1], v[2]);
            if (l == bone_label)
              {
                const std::uint8_t part =
                  parts.values.empty() ? 0 : parts(v[0], v[1], v[2]);
                if (is_detached(part))
                  return detached_boundary_id;
                if (part_number(part) > 0)
                  return first_bone_boundary_id + part - 1;
              }
            else if (!tissue[l])
              return l == 0 ? skin_boundary_id : other_boundary_id;
          }
        // Still in tissue two voxels out: a face where the mesh cuts a
        // corner of the segmented surface; free, like the skin.
        return other_boundary_id;
      };
      for (auto f = c3t3.facets_in_complex_begin();
           f != c3t3.facets_in_complex_end();
           ++f)
        {
          auto cell = f->first;
          int  i    = f->second;
          if (!c3t3.is_in_complex(cell))
            {
              const auto other = cell->neighbor(i);
              i                = other->index(cell);
              cell             = other;
            }
          if (!c3t3.is_in_complex(cell) ||
              c3t3.is_in_complex(cell->neighbor(i)))
            continue; // an interface between two tissues
          std::array<unsigned int, 3> face;
          for (unsigned int a = 0; a < 3; ++a)
            face[a] = vertex(cell->vertex((i + 1 + a) % 4));
          const Vec3  opposite = to_patient(point_of(cell->vertex(i)->point()));
          const Vec3 &x0 = mesh.points[face[0]], &x1 = mesh.points[face[1]],
                     &x2 = mesh.points[face[2]];
          Vec3 centre, normal = cross(minus(x1, x0), minus(x2, x0));
          for (unsigned int d = 0; d < 3; ++d)
            centre[d] = (x0[d] + x1[d] + x2[d]) / 3.;
          if (dot(normal, minus(opposite, centre)) > 0.)
            {
              std::swap(face[1], face[2]);
              for (auto &n : normal)
                n = -n;
            }
          const double length = norm(normal);
          for (auto &n : normal)
            n /= length;
          mesh.boundary_faces.push_back(face);
          mesh.boundary_ids.push_back(classify(centre, normal));
        }
      return mesh;
    }
  } // namespace Patient
} // namespace softface
