// A complete run of a scene file (run_cube_6mm.prm, the defaults otherwise):
// summary.csv has the documented columns and one row per model, whose counts
// match the mesh; displacements_linear_fem.csv has one row per vertex with
// the bone's join points at exactly (0, 0, 6) and the fixed ones at 0;
// solution.vtu carries the fields ParaView needs; the input, the expanded
// parameter file and the statistics table are kept beside the results.

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
  std::ostringstream log, errors;
  Simulator          simulator;
  const int          rc =
    simulator.run(softface_tests::source_file("run_cube_6mm.prm"), log, errors);
  softface_tests::check_equal("exit code", rc, 0);

  // The columns are part of the interface: benchmarks read them by name.
  const auto summary = read_csv(out + "/summary.csv");
  softface_tests::check_equal("summary.csv rows (header + one model)",
                              summary.size(),
                              2);
  deallog << "summary.csv columns: " << joined(summary[0]) << std::endl;
  const auto column = [&](const std::string &name) {
    for (unsigned int c = 0; c < summary[0].size(); ++c)
      if (summary[0][c] == name)
        return summary[1][c];
    throw std::runtime_error("no column " + name);
  };
  deallog << "model " << column("model") << ", status " << column("status")
          << ", tets " << column("n_tets") << ", vertices "
          << column("n_vertices") << ", free DoFs " << column("n_free_dofs")
          << ", max |u| "
          << softface_tests::rounded(
               Utilities::string_to_double(column("max_displacement_mm")), 6)
          << std::endl;

  const auto         nodal = read_csv(out + "/displacements_linear_fem.csv");
  const unsigned int n_vertices =
    Utilities::string_to_int(column("n_vertices"));
  softface_tests::check_equal("nodal CSV rows (header + one per vertex)",
                              nodal.size(),
                              n_vertices + 1);
  deallog << "nodal CSV columns: " << joined(nodal[0]) << std::endl;
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
  softface_tests::check_equal("join points not moved exactly as planned",
                              n_wrong,
                              0);
  softface_tests::check_equal("free DoFs - 3 x free vertices",
                              Utilities::string_to_int(column("n_free_dofs")) -
                                3 * n_free,
                              0);

  std::ifstream      vtu(out + "/solution.vtu");
  std::ostringstream text;
  text << vtu.rdbuf();
  for (const std::string field :
       {"displacement_linear_fem", "join_point", "segment_id", "material_id"})
    softface_tests::check_equal("solution.vtu fields named " + field,
                                text.str().find("Name=\"" + field + "\"") !=
                                  std::string::npos,
                                1);
  for (const std::string file : {"input.prm", "parameters.prm", "statistics"})
    softface_tests::check_equal(file + " written",
                                std::filesystem::exists(out + "/" + file),
                                1);
}
