// Where a scene's tetrahedra come from and what they must be (core): the
// cube benchmark of Mollemans et al. 2007 generated with a target size, grading
// and symmetric split, and the check that every cell is a positively oriented,
// non-degenerate tetrahedron. Mesh files are read in io/mesh_reader.cc.

#include <deal.II/grid/reference_cell.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <softface/core/error.h>
#include <softface/core/mesh.h>
#include <softface/core/tetrahedron.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <unistd.h>

namespace softface
{
  namespace Mesh
  {
    std::string
    far_coordinate(const double x)
    {
      // Enough digits that a coordinate just past the limit does not print
      // as the limit.
      std::ostringstream s;
      s << std::setprecision(12) << x << " mm, larger in magnitude than "
        << number_text(largest_coordinate)
        << " mm (1000 km); softface reads coordinates in millimetres";
      return s.str();
    }

    void
    CubeParameters::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Cube");
      prm.declare_entry("Edge length",
                        "80",
                        Patterns::Double(0., largest_coordinate),
                        "Edge length of the cube [0, L]^3 in mm.");
      prm.declare_entry("Inner region size",
                        "10",
                        Patterns::Double(0.),
                        "Edge length in mm of the centred inner cube (material "
                        "id 2) that a planning moves; the rest is tissue "
                        "(material id 1) and the outer faces have boundary "
                        "id 1.");
      prm.declare_entry("Target number of tetrahedra",
                        "30000",
                        Patterns::Integer(6, 50000000),
                        "About how many tetrahedra to generate (the grid "
                        "spacing is chosen so that 6 tetrahedra per grid "
                        "box come close; typical range 10k to 2M).");
      prm.declare_entry("Grading",
                        "1",
                        Patterns::Double(1., 1000.),
                        "Ratio of the grid spacing at the outer faces to the "
                        "spacing at the planes of the inner cube's faces. 1 "
                        "gives the uniform grid of Mollemans et al. 2007; "
                        "larger values grow the "
                        "spacing linearly with the distance from those planes "
                        "(1 + (Grading - 1) d / ((L - s) / 2)), which puts "
                        "the tetrahedra where the inner cube's edges and "
                        "corners make the displacement singular. Used for "
                        "converged references (benchmarks/accuracy).");
      prm.declare_entry("Mirror-symmetric split",
                        "false",
                        Patterns::Bool(),
                        "Split the grid boxes into tetrahedra so that the mesh "
                        "is symmetric under the reflections x -> L - x, y -> "
                        "L - y and z -> L - z (each octant a mirror image of "
                        "the others; the inner cube then has an even number "
                        "of grid boxes across). With false every box is split "
                        "along the same diagonal direction (1, 1, 1), and a "
                        "symmetric planning gets a slightly asymmetric "
                        "answer.");
      prm.declare_entry("Upper tissue material id",
                        "1",
                        Patterns::Integer(1, 255),
                        "Material id of the tissue cells above the mid-plane "
                        "z = L/2 (outside the inner cube): a second tissue "
                        "for Effects/heterogeneous tissue. The default, 1, "
                        "is the tissue below it (one tissue). 2 is the "
                        "inner cube's.");
      prm.leave_subsection();
    }

    void
    CubeParameters::parse_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Cube");
      edge_length         = prm.get_double("Edge length");
      inner_size          = prm.get_double("Inner region size");
      target_n_tetrahedra = prm.get_integer("Target number of tetrahedra");
      grading             = prm.get_double("Grading");
      mirror_symmetric    = prm.get_bool("Mirror-symmetric split");
      upper_material_id   = prm.get_integer("Upper tissue material id");
      prm.leave_subsection();
      // The least any model needs per tetrahedron: the mesh, its DoFs and
      // one stiffness matrix, about 1 KB (1.05 KB measured with gmres
      // jacobi between 197k and 511k tetrahedra, doc/results/linear_fem.md).
      // A target past the machine's memory is refused before any work.
      const double bytes_per_tetrahedron = 1024.;
      const double memory =
        double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
      if (memory > 0 && target_n_tetrahedra * bytes_per_tetrahedron > memory)
        {
          std::ostringstream m;
          m << std::setprecision(3) << "Scene/Cube/Target number of tetrahedra"
            << " = " << target_n_tetrahedra << " would need at least "
            << target_n_tetrahedra * bytes_per_tetrahedron / 1073741824.
            << " GB (about 1 KB per tetrahedron), more than this machine's "
            << memory / 1073741824. << " GB of memory.";
          throw Error(m.str());
        }
      if (upper_material_id == cube_inner_id)
        throw Error("Scene/Cube/Upper tissue material id: 2 is the inner "
                    "cube's material id; choose another.");
      if (!(edge_length > 0.) || !(inner_size > 0.) ||
          !(inner_size < edge_length))
        throw Error("Scene/Cube: the inner region size (" +
                    number_text(inner_size) +
                    " mm) must be positive and smaller than the edge length (" +
                    number_text(edge_length) + " mm).");
    }

    namespace
    {
      // The grid lines of the cube along each axis (the same for all three),
      // with six tetrahedra per box as close to the target count as the
      // grid allows.
      std::vector<double>
      cube_grid_lines(const CubeParameters &parameters)
      {
        const double L = parameters.edge_length, s = parameters.inner_size;
        const double a = (L - s) / 2., b = a + s;

        // Grid lines that include the inner cube's faces. Uniform grids space
        // them about h in each of the three intervals. Graded grids (spacing
        // h (1 + c d) at distance d from the nearest inner-face plane) place
        // the lines of a stretch of length D leaving such a plane where the
        // integral of 1 / spacing is a multiple of its total: geometric-like
        // steps d_i = ((1 + c D)^(i/n) - 1) / c. Inside the inner cube the two
        // halves grade towards its two faces.
        const double c = (parameters.grading - 1.) / a;
        // (Only for c > 0; the uniform grid keeps the paper's spacing below.)
        const auto graded_steps = [c](const double D, const double h) {
          const double       total = std::log1p(c * D);
          const unsigned int n =
            std::max<long>(1, std::lround(total / (c * h)));
          std::vector<double> steps;
          for (unsigned int i = 1; i <= n; ++i)
            steps.push_back(i == n ? D : std::expm1(total * i / n) / c);
          return steps;
        };
        const auto grid_lines = [&](const double h) {
          std::vector<double> lines{0.};
          if (c == 0.)
            {
              for (const auto &[from, to] : {std::make_pair(0., a),
                                             std::make_pair(a, b),
                                             std::make_pair(b, L)})
                {
                  // The mirror-symmetric split needs the mid planes as grid
                  // planes: an even count across the inner cube.
                  const unsigned int n =
                    (parameters.mirror_symmetric && from == a) ?
                      2 *
                        std::max<long>(1, std::lround((to - from) / (2. * h))) :
                      std::max<long>(1, std::lround((to - from) / h));
                  for (unsigned int i = 1; i <= n; ++i)
                    lines.push_back(i == n ? to : from + (to - from) * i / n);
                }
              return lines;
            }
          // From the outer face in to a: the steps leave a, so reverse them.
          const auto outer = graded_steps(a, h);
          for (auto d = outer.rbegin() + 1; d != outer.rend(); ++d)
            lines.push_back(a - *d);
          lines.push_back(a);
          const auto half = graded_steps(s / 2., h);
          for (unsigned int i = 0; i + 1 < half.size(); ++i)
            lines.push_back(a + half[i]);
          lines.push_back(a + s / 2.);
          for (auto d = half.rbegin() + 1; d != half.rend(); ++d)
            lines.push_back(b - *d);
          lines.push_back(b);
          for (unsigned int i = 0; i < outer.size(); ++i)
            lines.push_back(i + 1 == outer.size() ? L : b + outer[i]);
          return lines;
        };
        // Start from the uniform spacing, scaled for the graded grid by the
        // ratio of line counts at that spacing; then search the spacing that
        // brings six tetrahedra per box closest to the target count.
        const double h_uniform =
          std::cbrt(6. * L * L * L / parameters.target_n_tetrahedra);
        const double h0 =
          (c == 0.) ?
            h_uniform :
            h_uniform * (grid_lines(h_uniform).size() - 1.) * h_uniform / L;
        std::vector<double> lines = grid_lines(h0);
        for (double f = 0.8; f < 1.25; f += 0.005)
          {
            const auto candidate = grid_lines(h0 * f);
            const auto n_tets    = [](const std::vector<double> &l) {
              return 6. * std::pow(l.size() - 1., 3);
            };
            if (std::abs(n_tets(candidate) - parameters.target_n_tetrahedra) <
                std::abs(n_tets(lines) - parameters.target_n_tetrahedra))
              lines = candidate;
          }
        return lines;
      }

      // The cube's tetrahedra on the grid @p lines: six per box.
      std::vector<CellData<3>>
      kuhn_split(const CubeParameters        &parameters,
                 const std::vector<double>   &lines,
                 const std::vector<Point<3>> &vertices)
      {
        const double L = parameters.edge_length, s = parameters.inner_size;
        const double a = (L - s) / 2., b = a + s;
        const unsigned int n_lines = lines.size(), n_boxes = n_lines - 1;
        const auto         index =
          [n_lines](unsigned int i, unsigned int j, unsigned int k) {
            return i + n_lines * (j + n_lines * k);
          };

        // Kuhn split: the six tetrahedra of a box share its main diagonal and
        // follow the six paths along the box edges from its lowest to its
        // highest corner. Every face diagonal then runs from the face's lowest
        // to its highest corner in both neighbouring boxes: conforming. The
        // mirror-symmetric split reflects this in each octant (paths start at
        // the box corner nearest the centre): boxes on either side of a mid
        // plane share faces in that plane, whose diagonals depend only on the
        // other two directions, so the mesh stays conforming.
        static const unsigned int paths[6][3] = {
          {0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
        std::vector<CellData<3>> cells;
        cells.reserve(6 * n_boxes * n_boxes * n_boxes);
        for (unsigned int k = 0; k < n_boxes; ++k)
          for (unsigned int j = 0; j < n_boxes; ++j)
            for (unsigned int i = 0; i < n_boxes; ++i)
              {
                const Point<3> centre((lines[i] + lines[i + 1]) / 2.,
                                      (lines[j] + lines[j + 1]) / 2.,
                                      (lines[k] + lines[k + 1]) / 2.);
                const bool     inner =
                  (centre[0] > a && centre[0] < b && centre[1] > a &&
                   centre[1] < b && centre[2] > a && centre[2] < b);
                bool flip[3] = {false, false, false};
                if (parameters.mirror_symmetric)
                  for (unsigned int d = 0; d < 3; ++d)
                    flip[d] = centre[d] > L / 2.;
                for (const auto &path : paths)
                  {
                    unsigned int corner[3] = {i + flip[0],
                                              j + flip[1],
                                              k + flip[2]};
                    CellData<3>  cell(4);
                    cell.vertices[0] = index(corner[0], corner[1], corner[2]);
                    for (unsigned int step = 0; step < 3; ++step)
                      {
                        if (flip[path[step]])
                          --corner[path[step]];
                        else
                          ++corner[path[step]];
                        cell.vertices[step + 1] =
                          index(corner[0], corner[1], corner[2]);
                      }
                    const std::array<Point<3>, 4> x = {
                      {vertices[cell.vertices[0]],
                       vertices[cell.vertices[1]],
                       vertices[cell.vertices[2]],
                       vertices[cell.vertices[3]]}};
                    if (Tetrahedron::signed_volume(x) < 0)
                      std::swap(cell.vertices[1], cell.vertices[2]);
                    cell.material_id = inner ? cube_inner_id :
                                       centre[2] > L / 2. ?
                                               parameters.upper_material_id :
                                               cube_tissue_id;
                    cells.push_back(cell);
                  }
              }
        return cells;
      }
    } // namespace

    void
    generate_cube(const CubeParameters &parameters,
                  Triangulation<3>     &triangulation)
    {
      const std::vector<double> lines   = cube_grid_lines(parameters);
      const unsigned int        n_lines = lines.size();
      std::vector<Point<3>>     vertices;
      vertices.reserve(n_lines * n_lines * n_lines);
      for (unsigned int k = 0; k < n_lines; ++k)
        for (unsigned int j = 0; j < n_lines; ++j)
          for (unsigned int i = 0; i < n_lines; ++i)
            vertices.emplace_back(lines[i], lines[j], lines[k]);
      const std::vector<CellData<3>> cells =
        kuhn_split(parameters, lines, vertices);

      // The grid's lexicographic order is local already (and measured
      // faster than a Hilbert order of the same cells).
      triangulation.clear();
      triangulation.create_triangulation(vertices, cells, SubCellData());
      for (const auto &cell : triangulation.active_cell_iterators())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            face->set_boundary_id(cube_outer_face);
    }

    std::string
    cell_description(const CellNamer &cell_name, const unsigned int cell)
    {
      return cell_name ? cell_name(cell) : "cell " + std::to_string(cell);
    }

    void
    check_cells(const Triangulation<3> &triangulation,
                const std::string      &source,
                const CellNamer        &cell_name)
    {
      for (const auto &cell : triangulation.active_cell_iterators())
        {
          const auto describe = [&]() {
            std::ostringstream s;
            s << "Mesh " << source << ": "
              << cell_description(cell_name, cell->active_cell_index())
              << " (vertices";
            for (const unsigned int v : cell->vertex_indices())
              s << (v ? ", " : " ") << '(' << cell->vertex(v) << ')';
            s << ")";
            return s.str();
          };
          if (cell->reference_cell() != ReferenceCells::Tetrahedron)
            throw Error(describe() +
                        " is not a tetrahedron; softface needs a mesh of "
                        "tetrahedra only.");

          std::array<Point<3>, 4> x;
          double                  longest_edge = 0.;
          for (unsigned int v = 0; v < 4; ++v)
            {
              x[v] = cell->vertex(v);
              for (unsigned int w = 0; w < v; ++w)
                longest_edge = std::max(longest_edge, x[v].distance(x[w]));
            }
          const double volume = Tetrahedron::signed_volume(x);
          // A volume this small against the cube of the longest edge is a
          // flat tetrahedron whose stiffness would be singular.
          if (std::abs(volume) <= 1e-10 * std::pow(longest_edge, 3))
            {
              std::ostringstream s;
              s << describe() << " is degenerate (volume " << volume
                << " mm^3).";
              throw Error(s.str());
            }
          if (volume < 0)
            {
              std::ostringstream s;
              s << describe() << " is inverted (signed volume " << volume
                << " mm^3); tetrahedra must be positively oriented.";
              throw Error(s.str());
            }
        }
    }
  } // namespace Mesh
} // namespace softface
