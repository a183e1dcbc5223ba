// The input files a scene names, made absolute for the expanded parameter
// file (simulator): see input_files.h.

#include <deal.II/base/utilities.h>

#include <softface/simulator/input_files.h>

#include <filesystem>
#include <vector>

namespace softface
{
  void
  make_input_files_absolute(dealii::ParameterHandler &prm,
                            const std::string        &input_directory)
  {
    namespace fs        = std::filesystem;
    const fs::path base = fs::absolute(
      input_directory.empty() ? fs::path(".") : fs::path(input_directory));
    const auto absolute = [&](const std::string &file) {
      if (file.empty() || file == "auto" || file == "none" ||
          fs::path(file).is_absolute())
        return file;
      return (base / file).lexically_normal().string();
    };

    // Entry, the subsections it lies in, and whether it holds a list.
    struct FileEntry
    {
      std::vector<std::string> sections;
      std::string              name;
      bool                     list;
    };
    const std::vector<FileEntry> entries = {
      {{}, "Additional shared libraries", true},
      {{"Scene"}, "Mesh file", false},
      {{"Scene", "Patient"}, "CT volume", false},
      {{"Scene", "Patient"}, "Label volume", false},
      {{"Scene", "Patient"}, "Post-operative skull", false},
      {{"Scene", "Patient", "Registration"}, "Post-operative CT", false},
      {{"Scene", "Patient", "Registration"}, "Post-operative surfaces", true},
      {{"Output"}, "Evaluation points", false},
      {{"Skin"}, "Skin surface", false},
      {{"Skin"}, "Post-operative skin", false}};
    for (const FileEntry &entry : entries)
      {
        for (const std::string &section : entry.sections)
          prm.enter_subsection(section);
        std::string value;
        if (entry.list)
          for (const std::string &file :
               dealii::Utilities::split_string_list(prm.get(entry.name)))
            value += (value.empty() ? "" : ", ") + absolute(file);
        else
          value = absolute(prm.get(entry.name));
        prm.set(entry.name, value);
        for (unsigned int i = 0; i < entry.sections.size(); ++i)
          prm.leave_subsection();
      }
  }
} // namespace softface
