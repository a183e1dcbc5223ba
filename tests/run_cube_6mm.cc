// A complete run of a scene file (run_cube_6mm.prm, the defaults otherwise):
// summary.csv has the documented columns and one row per model, whose counts
// match the mesh; displacements_linear_fem.csv has one row per vertex with
// the bone's join points at exactly (0, 0, 6) and the fixed ones at 0;
// solution.vtu carries the fields ParaView needs; the input and the expanded
// parameter file are kept beside the results.

#include <deal.II/base/utilities.h>

#include <softface/simulator/simulator.h>

#include "tests.h"

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace softface;

namespace
{
  std::string
  joined(const std::vector<std::string> &fields)
  {
    std::string s;
    for (const auto &f : fields)
      s += (s.empty() ? "" : ",") + f;
    return s;
  }

  std::vector<std::vector<std::string>>
  read_csv(const std::string &filename)
  {
    std::ifstream                         in(filename);
    std::vector<std::vector<std::string>> rows;
    std::string                           line;
    while (std::getline(in, line))
      rows.push_back(Utilities::split_string_list(line));
    return rows;
  }
} // namespace

SOFTFACE_TEST(run_cube_6mm)
{
  const std::string out = "run_cube_6mm_output";
  std::filesystem::remove_all(out);
  std::ostringstream log;
  auto              *old = std::cout.rdbuf(log.rdbuf());
  const int          rc =
    Simulator::run(softface_tests::source_file("run_cube_6mm.prm"));
  std::cout.rdbuf(old);
  softface_tests::check(rc == 0, "run returns 0");

  const auto summary = read_csv(out + "/summary.csv");
  softface_tests::check(
    summary.size() == 2 &&
      joined(summary[0]) ==
        "model,n_tets,n_vertices,n_free_dofs,setup_s,solve_s,iterations,"
        "max_displacement_mm,max_diff_to_linear_fem_mm,"
        "mean_diff_to_linear_fem_mm,relative_residual,phases,details",
    "summary.csv: documented header and one row");
  deallog << "model " << summary[1][0] << ", tets " << summary[1][1]
          << ", vertices " << summary[1][2] << ", free DoFs " << summary[1][3]
          << ", max |u| "
          << softface_tests::rounded(Utilities::string_to_double(summary[1][7]),
                                     6)
          << std::endl;

  const auto         nodal = read_csv(out + "/displacements_linear_fem.csv");
  const unsigned int n_vertices = Utilities::string_to_int(summary[1][2]);
  softface_tests::check(nodal.size() == n_vertices + 1 &&
                          joined(nodal[0]) == "x,y,z,ux,uy,uz",
                        "nodal CSV: header and one row per vertex");
  unsigned int n_bone = 0, n_fixed = 0, n_wrong = 0, n_free = 0;
  for (unsigned int r = 1; r < nodal.size(); ++r)
    {
      const auto v       = Utilities::string_to_double(nodal[r]);
      const bool on_face = std::min({v[0], v[1], v[2]}) == 0. ||
                           std::max({v[0], v[1], v[2]}) == 80.;
      const bool in_bone = std::min({v[0], v[1], v[2]}) >= 35. &&
                           std::max({v[0], v[1], v[2]}) <= 45.;
      if (on_face)
        {
          ++n_fixed;
          n_wrong += (v[3] != 0. || v[4] != 0. || v[5] != 0.);
        }
      else if (in_bone)
        {
          ++n_bone;
          n_wrong += (v[3] != 0. || v[4] != 0. || v[5] != 6.);
        }
      else
        ++n_free;
    }
  deallog << "vertices: " << n_fixed << " on the faces, " << n_bone
          << " in the bone, " << n_free << " free" << std::endl;
  softface_tests::check(n_wrong == 0, "join points move exactly as planned");
  softface_tests::check(int(3 * n_free) ==
                          Utilities::string_to_int(summary[1][3]),
                        "free DoFs = 3 x free vertices");

  std::ifstream      vtu(out + "/solution.vtu");
  std::ostringstream text;
  text << vtu.rdbuf();
  for (const std::string field :
       {"displacement_linear_fem", "join_point", "segment_id", "material_id"})
    softface_tests::check(text.str().find("Name=\"" + field + "\"") !=
                            std::string::npos,
                          "solution.vtu has " + field);
  softface_tests::check(std::filesystem::exists(out + "/input.prm") &&
                          std::filesystem::exists(out + "/parameters.prm"),
                        "input and expanded parameters kept");
}
