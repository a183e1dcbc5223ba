// softface serve's planner and request handler without a network (issue
// 17): a re-plan from the page's sliders (a translation and rotations about
// x, y and z through the segment's centre) must equal the skin displacement
// of a whole simulator run of the same motion written as a planning (axis
// and angle), to the float32 the page receives; every bad request gets an
// error answer; a good one the binary layout the page reads.

#include <deal.II/base/utilities.h>

#include <softface/outputs/skin_output.h>
#include <softface/serve/serve.h>

#include "tests.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

using namespace softface;

namespace
{
  // The scene with its planning replaced by @p planning_text, run whole;
  // returns its linear FEM displacement mapped onto the skin.
  std::vector<Tensor<1, 3>>
  simulated_skin(const std::string &planning_text)
  {
    std::ostringstream text;
    // The scene's relative skin path, made absolute for a copy written
    // here.
    text << std::ifstream(softface_tests::source_file("serve_cube.prm")).rdbuf()
         << "subsection Skin\n  set Skin surface = "
         << softface_tests::source_file("data/cube_sphere_skin.ply")
         << "\n  set Post-operative skin =\nend\nsubsection Output\n  set "
            "Output directory = "
            "serve_planner_output\nend\n"
         << planning_text;
    const std::string file = "serve_planner.prm";
    std::ofstream(file) << text.str();
    Simulator          simulator;
    std::ostringstream out, err;
    simulator.run(file, out, err);
    std::vector<Tensor<1, 3>> skin_u;
    for (const auto &run : simulator.runs())
      if (run.model == "linear fem")
        simulator.skin()->map(simulator.scene(), run.displacement, skin_u);
    return skin_u;
  }

  // @p a on the planner's moving points (zero elsewhere) against @p b on
  // every skin point.
  double
  relative_difference(const std::vector<unsigned int> &moving,
                      const std::vector<float>        &a_moving,
                      const std::vector<Tensor<1, 3>> &b)
  {
    std::vector<double> a(3 * b.size(), 0.);
    for (unsigned int k = 0; k < moving.size(); ++k)
      for (unsigned int c = 0; c < 3; ++c)
        a[3 * moving[k] + c] = a_moving[3 * k + c];
    double difference = 0., largest = 0.;
    for (unsigned int i = 0; i < b.size(); ++i)
      for (unsigned int c = 0; c < 3; ++c)
        {
          difference = std::max(difference, std::abs(a[3 * i + c] - b[i][c]));
          largest    = std::max(largest, std::abs(b[i][c]));
        }
    return difference / largest;
  }
} // namespace

SOFTFACE_TEST(serve_planner)
{
  std::ostringstream              log;
  const Serve::InteractivePlanner planner(
    softface_tests::source_file("serve_cube.prm"), log);
  const auto &centre = planner.moved_segments()[0].centre;
  softface_tests::check_equal("moved segments",
                              planner.moved_segments().size(),
                              1);
  softface_tests::check_equal("skin points",
                              planner.surface().points.size(),
                              2562);
  softface_tests::check_equal("post-operative skin points",
                              planner.post_operative().points.size(),
                              2562);

  // Rotations about one axis at a time are the planning's axis and angle.
  const char *axes[3] = {"1, 0, 0", "0, 1, 0", "0, 0, 1"};
  for (unsigned int a = 0; a < 3; ++a)
    {
      Serve::InteractivePlanner::Motion motion = {{1., -2., 3., 0., 0., 0.}};
      motion[3 + a]                            = 12.;
      std::ostringstream planning;
      planning << "subsection Planning\n  subsection Motion bone\n"
               << "    set Translation = 1, -2, 3\n"
               << "    set Rotation axis = " << axes[a] << "\n"
               << "    set Rotation angle = 12\n"
               << "    set Rotation centre = " << centre[0] << ", " << centre[1]
               << ", " << centre[2] << "\n  end\nend\n";
      const auto expected = simulated_skin(planning.str());
      softface_tests::check_below(
        std::string("rotation about ") + "xyz"[a] +
          ", linear fem: |re-plan - run| / |run|",
        relative_difference(planner.moving_points(),
                            planner.replan("linear fem", {motion}).displacement,
                            expected),
        1e-6);
    }

  // Rotations about x, then y (then z) are their product, R = Ry Rx here,
  // written for the run as one axis and angle.
  {
    const Serve::InteractivePlanner::Motion motion = {
      {0., 0., 0., 20., 20., 0.}};
    // R = Ry(20) Rx(20): its axis and angle by hand.
    const double c       = std::cos(20. * M_PI / 180.),
                 s       = std::sin(20. * M_PI / 180.);
    const double R[3][3] = {{c, s * s, s * c}, {0., c, -s}, {-s, c * s, c * c}};
    const double angle =
      std::acos((R[0][0] + R[1][1] + R[2][2] - 1.) / 2.) * 180. / M_PI;
    const double       axis[3] = {R[2][1] - R[1][2],
                                  R[0][2] - R[2][0],
                                  R[1][0] - R[0][1]};
    std::ostringstream planning;
    planning << std::setprecision(17)
             << "subsection Planning\n  subsection Motion bone\n"
             << "    set Translation = 0, 0, 0\n"
             << "    set Rotation axis = " << axis[0] << ", " << axis[1] << ", "
             << axis[2] << "\n    set Rotation angle = " << angle
             << "\n    set Rotation centre = " << centre[0] << ", " << centre[1]
             << ", " << centre[2] << "\n  end\nend\n";
    softface_tests::check_below(
      "rotation about x then y, linear fem: |re-plan - run| / |run|",
      relative_difference(planner.moving_points(),
                          planner.replan("linear fem", {motion}).displacement,
                          simulated_skin(planning.str())),
      1e-6);
  }

  // The request handler: errors for bad requests, the binary layout for a
  // good one.
  Serve::PlannerHandler handler(planner, "");
  for (const std::string &request :
       {std::string("not json"),
        std::string(R"({"id": 1, "motions": {"nobody": [0, 0, 0, 0, 0, 0]}})"),
        std::string(
          R"({"id": 2, "motions": {"bone": ["nan", 0, 0, 0, 0, 0]}})"),
        std::string(R"({"id": 3, "motions": {"bone": [1, 2, 3]}})"),
        std::string(R"({"id": 4, "motions": {"bone": [0, 0, 25, 0, 0, 0]}})"),
        std::string(R"({"id": 5, "motions": {"bone": [0, 0, 0, 0, 0, 31]}})"),
        std::string(R"({"id": 6, "model": "mass spring"})"),
        std::string(R"({"id": 9, "motions": {"bone": [0, 0, 1, 0, 0, 0, 7]}})"),
        std::string(
          R"({"id": 10, "motions": {"bone": ["0x10", 0, 0, 0, 0, 0]}})"),
        std::string(R"({"id": 11, "x": [[[[[[[[[[1]]]]]]]]]]})"),
        std::string(R"({"id": -5})")})
    {
      const auto answer = handler.message(request);
      deallog << request << " -> " << (answer.binary ? "binary" : answer.data)
              << std::endl;
      if (answer.binary)
        throw std::runtime_error("a bad request was answered with a plan");
    }
  const auto answer = handler.message(
    R"({"id": 7, "model": "mass tensor", "motions": {"bone": [0, 0, 6, 0, 0, 0]}})");
  std::uint32_t id, n;
  std::memcpy(&id, answer.data.data(), 4);
  std::memcpy(&n, answer.data.data() + 16, 4);
  softface_tests::check_equal("answer is binary", answer.binary, true);
  softface_tests::check_equal("answer id", id, 7);
  softface_tests::check_equal("answer points (the moving ones)",
                              n,
                              planner.moving_points().size());
  softface_tests::check_equal("answer bytes", answer.data.size(), 24 + 12 * n);

  // The post-operative skin was made by linear FEM with the bone lifted
  // 6 mm and turned 5 degrees about z (serve_cube_post.prm): the same plan
  // here predicts it, so every distance to it vanishes; at rest they do not.
  {
    const auto result =
      planner.replan("linear fem", {{{0., 0., 6., 0., 0., 5.}}}, true);
    double largest = 0.;
    for (const float d : result.distance)
      largest = std::max(largest, std::abs(double(d)));
    softface_tests::check_equal("distances of the moving points",
                                result.distance.size(),
                                planner.moving_points().size());
    softface_tests::check_below("the post-operative plan: largest |distance| "
                                "(mm)",
                                largest,
                                1e-4);
    double at_rest = 0.;
    for (const float d : planner.rest_distances())
      at_rest = std::max(at_rest, std::abs(double(d)));
    softface_tests::check_above("at rest: largest |distance| (mm)",
                                at_rest,
                                1.);
    const auto with_distances = handler.message(
      R"({"id": 8, "motions": {"bone": [0, 0, 6, 0, 0, 5]}, "distance": true})");
    softface_tests::check_equal("answer bytes with distances",
                                with_distances.data.size(),
                                24 + 16 * n);
  }
  softface_tests::check_equal("GET /scene.json",
                              handler.get("/scene.json").status,
                              200);
  softface_tests::check_equal("GET /nothing",
                              handler.get("/nothing").status,
                              404);
  softface_tests::check_equal("GET /three/addons/../x",
                              handler.get("/three/addons/../x").status,
                              403);
}
