// Bad input to the patient pipeline ends with one message naming the file
// or the parameter, and a non-zero exit code, never a crash or a result made
// of half-written files: a CT that does not exist, is not an image, is cut
// short, or is not 3D; a phantom too large to hold; a malformed plane; a
// threshold that selects nothing or is neither a number nor 'auto'; a region
// of interest outside the volume or touching no bone; a seed point in no
// bone; two segments that no cut separates; a bone part with no join point.
// Each scene is the small phantom (2 mm voxels) with one thing wrong; they
// share one work directory, so the stages that did not change are reused.

#include <softface/patient/image_io.h>

#include "run_scene.h"

#include <filesystem>
#include <fstream>

namespace
{
  const std::string base = R"(
subsection Scene
  set Mesh source   = patient
  set Bone segments = cranium, mandible
  subsection Segment cranium
    set Seed point = 0, -40, 30
  end
  subsection Segment mandible
    set Seed point = -15, -58, -42
  end
  subsection Patient
    set Work directory = patient_bad_input_work
    subsection Phantom
      set Voxel size = 2
    end
    subsection Mesh
      set Target number of tetrahedra = 3000
    end
  end
end
subsection Planning
  set Moved segments = mandible
  subsection Motion mandible
    set Translation = 0, -5, 0
  end
end
subsection Output
  set Output directory = output/patient_bad_input
end
)";

  // The scene with @p change added at the end of subsection Scene/Patient.
  void
  run_case(const std::string &name, const std::string &change)
  {
    std::string text = base;
    const auto  at   = text.find("    subsection Phantom");
    text.insert(at, change);
    const std::string file = "patient_bad_input_" + name + ".prm";
    std::ofstream(file) << text;
    softface::Simulator simulator;
    std::ostringstream  out, err;
    try
      {
        const int exit_code = simulator.run(file, out, err);
        dealii::deallog << name << ": exit code " << exit_code << std::endl;
        softface_tests::log_lines(err.str());
      }
    catch (const std::exception &e)
      {
        // What softface prints before it exits with code 1.
        dealii::deallog << name << ": " << e.what() << std::endl;
      }
  }
} // namespace

SOFTFACE_TEST(patient_bad_input)
{
  std::filesystem::remove_all("patient_bad_input_work");
  std::ofstream("patient_bad_input_garbage.nii.gz") << "not an image\n";
  // A 2D MetaImage of 4 x 3 pixels.
  {
    std::ofstream mha("patient_bad_input_slice.mha", std::ios::binary);
    mha << "ObjectType = Image\nNDims = 2\nDimSize = 4 3\n"
           "ElementType = MET_SHORT\nElementDataFile = LOCAL\n";
    const std::int16_t pixels[12] = {};
    mha.write(reinterpret_cast<const char *>(pixels), sizeof(pixels));
  }

  // A compressed volume cut in half.
  {
    softface::Patient::CTVolume v;
    v.size = {{40, 40, 40}};
    v.values.assign(v.n_voxels(), 0);
    for (std::size_t i = 0; i < v.values.size(); ++i)
      v.values[i] = static_cast<std::int16_t>((i * 7919) % 2000 - 1000);
    softface::Patient::write_volume(v, "patient_bad_input_cut.nii.gz");
    std::filesystem::resize_file(
      "patient_bad_input_cut.nii.gz",
      std::filesystem::file_size("patient_bad_input_cut.nii.gz") / 2);
  }

  run_case("missing CT", "    set CT volume = no_such_ct.nii.gz\n");
  run_case("truncated CT",
           "    set CT volume = patient_bad_input_cut.nii.gz\n");
  run_case("enormous phantom",
           "    subsection Phantom\n      set Field of view = 5000, 5000, "
           "5000\n    end\n");
  run_case("malformed plane",
           "    subsection Region of interest\n      set Planes = 0, 0, x, 0, "
           "0, 1\n    end\n");
  run_case("not an image",
           "    set CT volume = patient_bad_input_garbage.nii.gz\n");
  run_case("not 3D", "    set CT volume = patient_bad_input_slice.mha\n");
  run_case("bone threshold",
           "    subsection Segmentation\n      set Bone threshold = "
           "5000\n    end\n");
  run_case("threshold neither a number nor auto",
           "    subsection Segmentation\n      set Fat threshold = "
           "-30 HU\n    end\n");
  run_case("region outside the volume",
           "    subsection Region of interest\n      set Box = 500, 500, "
           "500; 600, 600, 600\n    end\n");
  run_case(
    "region touching no bone",
    "    subsection Region of interest\n      set Box = -60, -56.5, 8.5; "
    "-44, -55.5, 9.5\n    end\n");
  run_case("part without join points",
           "    subsection Region of interest\n      set Box = -85, -130, "
           "25; 85, 25, 35\n    end\n");
  run_case("seed point in no bone",
           "    subsection Osteotomy\n      set Cuts = \n    end\n"
           "  end\n  subsection Segment mandible\n    set Seed point = 0, "
           "-150, 0\n  end\n  subsection Patient\n");
  run_case("no cut separates",
           "    subsection Osteotomy\n      set Cuts = \n    end\n"
           "  end\n  subsection Segment mandible\n    set Seed point = 0, "
           "-20, 40\n  end\n  subsection Patient\n");

  // Nothing half-written: no partial files left, no mesh stamped.
  unsigned int partial = 0;
  for (const auto &entry :
       std::filesystem::directory_iterator("patient_bad_input_work"))
    partial += entry.path().filename().string().rfind(".partial.", 0) == 0;
  softface_tests::check_equal("partial files left", partial, 0);
  softface_tests::check_equal("mesh stamped",
                              std::filesystem::exists(
                                "patient_bad_input_work/mesh.stamp"),
                              0);
}
