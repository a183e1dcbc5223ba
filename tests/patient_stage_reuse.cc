// A patient stage is reused only when made by the same build of softface. The
// stamp of every stage starts with build_stamp(): the patient library's GNU
// build ID, which must equal what readelf reads from the library file (an
// independent reader of the same ELF note), and the versions of ITK, VTK and
// CGAL. The phantom stage run twice is made, then reused; with its stamp's
// build line changed to another build's, as a rebuilt softface with changed
// code would find it, it is made again, and then reused again.

#include <softface/patient/build_stamp.h>
#include <softface/patient/pipeline.h>

#include "tests.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace softface;
using namespace softface::Patient;

namespace
{
  // The "Build ID:" line of 'readelf -n FILE'.
  std::string
  readelf_build_id(const std::string &file)
  {
    std::string id;
    FILE *pipe = popen(("readelf -n '" + file + "' 2>/dev/null").c_str(), "r");
    if (pipe == nullptr)
      return id;
    char line[512];
    while (std::fgets(line, sizeof(line), pipe) != nullptr)
      {
        const std::string text = line;
        const auto        at   = text.find("Build ID: ");
        if (at != std::string::npos)
          id = text.substr(at + 10, text.find_first_of("\r\n", at) - at - 10);
      }
    pclose(pipe);
    return id;
  }

  bool
  reused(const PatientParameters &prm)
  {
    std::ostringstream log;
    build_patient_model(prm, {}, Stage::phantom, log);
    return log.str().find("phantom CT: reused") != std::string::npos;
  }
} // namespace

SOFTFACE_TEST(patient_stage_reuse)
{
  std::string library;
  const auto  id = library_build_id(&library);
  // Without a build ID in the library, a hash of its file stands in.
  const std::string from_readelf = readelf_build_id(library);
  softface_tests::check_equal("build ID equal to readelf's (or, without one, "
                              "a hash of the library file)",
                              from_readelf.empty() ?
                                id.rfind("fnv1a-", 0) == 0 :
                                id == from_readelf,
                              1);
  const auto stamp = build_stamp();
  for (const std::string &part :
       {id, std::string("ITK "), std::string("VTK "), std::string("CGAL ")})
    softface_tests::check_equal("build stamp names '" +
                                  (part == id ? std::string("the build ID") :
                                                part) +
                                  "'",
                                stamp.find(part) != std::string::npos,
                                1);

  PatientParameters prm;
  prm.work_directory     = "patient_stage_reuse_work";
  prm.phantom.voxel_size = 4.;
  std::filesystem::remove_all(prm.work_directory);
  softface_tests::check_equal("first run: reused", reused(prm), 0);
  softface_tests::check_equal("second run: reused", reused(prm), 1);

  // The stamp as another build of softface would have left it.
  const std::string stamp_file = prm.work_directory + "/ct.stamp";
  std::ifstream     in(stamp_file);
  std::stringstream old;
  old << in.rdbuf();
  in.close();
  std::string text = old.str();
  softface_tests::check_equal("the stage's stamp starts with the build stamp",
                              text.rfind(stamp, 0) == 0,
                              1);
  text.replace(0, stamp.size(), "softface patient library 0123456789abcdef\n");
  std::ofstream(stamp_file) << text;
  softface_tests::check_equal("made by another build: reused", reused(prm), 0);
  softface_tests::check_equal("run again: reused", reused(prm), 1);
  std::filesystem::remove_all(prm.work_directory);
}
