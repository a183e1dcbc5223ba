// The skin end to end (run_skin_truth.prm): the post-operative skin is made by
// a truth scene (run_skin_truth_post.prm: the same cube and planning, linear
// FEM), run on the first run, reused on the second and run again on a third
// that finds another build's stamp beside it; linear FEM's
// predicted skin then lies on it (distance at the solver's precision), and
// the mass tensor model's is no farther than its displacement differs from
// linear FEM's on the mesh (a closest point is never farther than the
// corresponding point; inside a tetrahedron the shape functions are convex
// weights). The same holds for the distances between TPS-RPM
// correspondences. The truth moved the same skin points, so each predicted
// point's true partner is known: linear FEM's lies on it, and the mass
// tensor model's exact distances are no smaller than its closest-point
// distances (percentile by percentile, since they are point by point) and
// equal |predicted - true| computed here from the two written skins. The
// per-point distance files agree with skin.csv, and each point's TPS-RPM
// partner lies on the post-operative skin. The skin is a sphere in the
// tissue around the cube's bone.

#include <deal.II/base/utilities.h>

#include <softface/mapping/triangle_search.h>
#include <softface/patient/backend.h>
#include <softface/simulator/simulator.h>

#include "tests.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

using namespace softface;

namespace
{
  std::vector<std::map<std::string, std::string>>
  read_csv(const std::string &filename)
  {
    std::ifstream                                   in(filename);
    std::vector<std::map<std::string, std::string>> rows;
    std::string                                     line;
    std::getline(in, line);
    const auto header = Utilities::split_string_list(line);
    while (std::getline(in, line))
      {
        // Keep empty fields: split on every comma.
        std::vector<std::string> fields(1);
        for (const char c : line)
          if (c == ',')
            fields.emplace_back();
          else
            fields.back() += c;
        std::map<std::string, std::string> row;
        for (unsigned int i = 0; i < header.size() && i < fields.size(); ++i)
          row[header[i]] = fields[i];
        rows.push_back(row);
      }
    return rows;
  }
} // namespace

SOFTFACE_TEST(run_skin_truth)
{
  std::filesystem::remove_all("run_skin_truth_post_output");
  for (const std::string pass : {"first", "second", "another build's"})
    {
      // A skin made by another build of softface is made again.
      if (pass == "another build's")
        std::ofstream("run_skin_truth_post_output/truth_build_id.txt")
          << "another build";
      Simulator          simulator;
      std::ostringstream out, err;
      const int          code =
        simulator.run(softface_tests::source_file("run_skin_truth.prm"),
                      out,
                      err);
      softface_tests::check_equal(pass + " run: exit code", code, 0);
      softface_tests::check_equal(pass + " run: the truth scene ran",
                                  out.str().find("running the truth scene") !=
                                    std::string::npos,
                                  pass != "second");
    }

  double mtm_difference = 0.;
  for (const auto &row : read_csv("run_skin_truth_output/summary.csv"))
    if (row.at("model") == "mass tensor")
      mtm_difference = std::stod(row.at("max_diff_to_reference_mm"));
  softface_tests::check_above("mass tensor: max |u - u_linear| on the mesh mm",
                              mtm_difference,
                              1e-4);

  const auto rows = read_csv("run_skin_truth_output/skin.csv");
  softface_tests::check_equal("skin.csv rows", rows.size(), 2);
  for (const auto &row : rows)
    {
      const std::string name = row.at("model") + ", " + row.at("mapping");
      softface_tests::check_equal(name + ": skin points",
                                  std::stoi(row.at("skin points")),
                                  2562);
      softface_tests::check_equal(name + ": mapped points",
                                  std::stoi(row.at("mapped points")),
                                  2562);
      softface_tests::check_equal(name + ": measured points",
                                  std::stoi(row.at("measured points")),
                                  2562);
      const double largest = std::stod(row.at("max |d| mm"));
      // Exact correspondences.
      const double exact_max = std::stod(row.at("exact max mm"));
      if (row.at("model") == "linear fem")
        softface_tests::check_below(name + ": exact max mm", exact_max, 1e-5);
      else
        {
          for (const std::string q : {"p50", "p90", "max"})
            softface_tests::check_above(
              name + ": exact " + q + " - closest-point " + q + " (mm)",
              std::stod(row.at("exact " + q + " mm")) -
                std::stod(row.at(q == "max" ? "max |d| mm" : q + " mm")),
              -1e-5,
              2);
          softface_tests::check_below(name + ": exact max / max |u - u_linear|",
                                      exact_max / mtm_difference,
                                      1.);
          const auto predicted = Patient::backend().read_surface(
            "run_skin_truth_output/skin_mass_tensor.ply");
          const auto truth = Patient::backend().read_surface(
            "run_skin_truth_output/skin_postoperative.ply");
          double by_hand = 0.;
          for (unsigned int i = 0; i < predicted.points.size(); ++i)
            {
              double squared = 0.;
              for (unsigned int d = 0; d < 3; ++d)
                squared +=
                  std::pow(predicted.points[i][d] - truth.points[i][d], 2);
              by_hand = std::max(by_hand, std::sqrt(squared));
            }
          softface_tests::check_below(
            name + ": |exact max - max |predicted - true| from the files| mm",
            std::abs(exact_max - by_hand),
            1e-5);
        }
      // TPS-RPM correspondences: every measured point matched.
      softface_tests::check_equal(name + ": correspondence points",
                                  std::stoi(row.at("correspondence points")),
                                  2562);
      const double corresponding = std::stod(row.at("correspondence max mm"));
      if (row.at("model") == "linear fem")
        softface_tests::check_below(name + ": correspondence max mm",
                                    corresponding,
                                    1e-5);
      else
        softface_tests::check_below(
          name + ": correspondence max / max |u - u_linear|",
          corresponding / mtm_difference,
          1.);
      // The per-point file (Write distances): each point's correspondence
      // distance is the length of its vector to the partner, the partner
      // lies on the post-operative surface, and the largest of each column
      // is skin.csv's.
      {
        const std::string model =
          row.at("model") == "linear fem" ? "linear_fem" : "mass_tensor";
        const auto points =
          read_csv("run_skin_truth_output/skin_" + model + "_distance.csv");
        const auto predicted = Patient::backend().read_surface(
          "run_skin_truth_output/skin_" + model + ".ply");
        const auto truth = Patient::backend().read_surface(
          "run_skin_truth_output/skin_postoperative.ply");
        SurfaceMapping::Surface post_operative;
        for (const auto &q : truth.points)
          post_operative.points.emplace_back(q[0], q[1], q[2]);
        post_operative.triangles = truth.triangles;
        const SurfaceMapping::TriangleSearch search(post_operative);
        softface_tests::check_equal(name + ": distance file rows",
                                    points.size(),
                                    predicted.points.size());
        double length_error = 0., off_surface = 0., largest_exact = 0.,
               largest_correspondence = 0.;
        for (unsigned int i = 0; i < points.size(); ++i)
          {
            const double distance =
              std::stod(points[i].at("correspondence distance mm"));
            Point<3> partner;
            for (unsigned int d = 0; d < 3; ++d)
              partner[d] =
                predicted.points[i][d] +
                std::stod(points[i].at(std::string("to correspondence ") +
                                       "xyz"[d] + " mm"));
            Point<3> p;
            for (unsigned int d = 0; d < 3; ++d)
              p[d] = predicted.points[i][d];
            length_error =
              std::max(length_error, std::abs(partner.distance(p) - distance));
            off_surface =
              std::max(off_surface, search.closest(partner).distance);
            largest_correspondence = std::max(largest_correspondence, distance);
            largest_exact =
              std::max(largest_exact,
                       std::stod(points[i].at("exact distance mm")));
          }
        // The file holds 6 digits of values below 1 mm; the .ply single
        // precision (40 mm x 2^-24 per coordinate).
        softface_tests::check_below(
          name + ": max | |to correspondence| - correspondence distance | mm",
          length_error,
          1e-6);
        softface_tests::check_below(
          name + ": partner's largest distance to the post-operative skin mm",
          off_surface,
          1e-5);
        softface_tests::check_below(
          name + ": |largest correspondence distance - skin.csv's| mm",
          std::abs(largest_correspondence -
                   std::stod(row.at("correspondence max mm"))),
          1e-6);
        softface_tests::check_below(
          name + ": |largest exact distance - skin.csv's| mm",
          std::abs(largest_exact - std::stod(row.at("exact max mm"))),
          1e-6);
      }
      // The post-operative .ply stores single precision: 40 mm x 2^-24.
      if (row.at("model") == "linear fem")
        softface_tests::check_below(name + ": max |distance| mm",
                                    largest,
                                    1e-5);
      else
        {
          softface_tests::check_below(name +
                                        ": max |distance| / max |u - u_linear|",
                                      largest / mtm_difference,
                                      1.);
          softface_tests::check_above(name + ": max |distance| mm",
                                      largest,
                                      1e-6);
        }
    }
  for (const std::string file : {"skin_preoperative.ply",
                                 "skin_postoperative.vtp",
                                 "skin_linear_fem.vtp",
                                 "skin_mass_tensor.ply"})
    softface_tests::check_equal("run_skin_truth_output/" + file + " written",
                                std::filesystem::exists(
                                  "run_skin_truth_output/" + file),
                                true);
}
