// Plugins from outside the tree (core): the libraries a scene names in
// 'Additional shared libraries', loaded with dlopen before its parameters
// are declared.

#include <deal.II/base/utilities.h>

#include <softface/core/error.h>
#include <softface/core/shared_libraries.h>

#include <dlfcn.h>
#include <elf.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

namespace softface
{
  namespace SharedLibraries
  {
    namespace
    {
      // dlopen maps a library's segments as its headers describe them; a
      // truncated file then ends the process with SIGBUS when the loader
      // reads past its end. So the headers are checked against the file's
      // size first: a 64-bit ELF whose program and section headers and
      // loaded segments all lie inside the file. Returns what is wrong, or
      // an empty string.
      std::string
      elf_defect(const std::filesystem::path &file)
      {
        const std::uintmax_t size = std::filesystem::file_size(file);
        std::ifstream        in(file, std::ios::binary);
        Elf64_Ehdr           header;
        if (!in.read(reinterpret_cast<char *>(&header), sizeof(header)) ||
            std::memcmp(header.e_ident, ELFMAG, SELFMAG) != 0)
          return "not an ELF shared library";
        if (header.e_ident[EI_CLASS] != ELFCLASS64)
          return "not a 64-bit ELF library";
        const auto inside = [size](const std::uint64_t offset,
                                   const std::uint64_t length) {
          return offset <= size && length <= size - offset;
        };
        if (header.e_phentsize != sizeof(Elf64_Phdr) ||
            !inside(header.e_phoff,
                    std::uint64_t(header.e_phnum) * sizeof(Elf64_Phdr)) ||
            !inside(header.e_shoff,
                    std::uint64_t(header.e_shnum) * header.e_shentsize))
          return "its headers point past the end of the file (truncated?)";
        std::vector<Elf64_Phdr> segments(header.e_phnum);
        in.seekg(header.e_phoff);
        if (!in.read(reinterpret_cast<char *>(segments.data()),
                     segments.size() * sizeof(Elf64_Phdr)))
          return "its program headers cannot be read";
        for (const Elf64_Phdr &segment : segments)
          if (segment.p_type == PT_LOAD &&
              !inside(segment.p_offset, segment.p_filesz))
            return "a segment ends past the end of the file (truncated?)";
        return "";
      }
    } // namespace

    void
    declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry(
        "Additional shared libraries",
        "",
        Patterns::List(Patterns::FileName()),
        "Shared libraries to load before the scene is read, each holding "
        "plugins (models, effects, mesh sources, outputs) built against an "
        "installed softface (doc/extending.md). Relative paths are taken "
        "from the parameter file's folder.");
    }

    void
    load(ParameterHandler &prm, const std::string &input_directory)
    {
      for (const std::string &name :
           Utilities::split_string_list(prm.get("Additional shared libraries")))
        {
          std::filesystem::path file(name);
          // "./" keeps dlopen from searching the library path instead.
          if (file.is_relative())
            file = std::filesystem::path(
                     input_directory.empty() ? "." : input_directory) /
                   file;
          if (!std::filesystem::is_regular_file(file))
            throw Error("Additional shared libraries: '" + file.string() +
                        "' is not a file.");
          if (const std::string defect = elf_defect(file); !defect.empty())
            throw Error("Additional shared libraries: cannot load '" +
                        file.string() + "': " + defect + ".");
          // RTLD_GLOBAL: a library's plugins may use another's symbols.
          // Never closed: its registrations live as long as the process.
          if (dlopen(file.c_str(), RTLD_NOW | RTLD_GLOBAL) == nullptr)
            throw Error("Additional shared libraries: cannot load '" +
                        file.string() + "': " + dlerror());
        }
    }
  } // namespace SharedLibraries
} // namespace softface
