// What a patient stage's result depends on besides its inputs (patient
// pipeline): this library's build and the versions of the libraries that
// shape a stage (ITK, VTK, CGAL). See include/softface/patient/build_stamp.h.

#include <softface/patient/build_stamp.h>
#include <softface/patient/image_io.h>

#include <CGAL/version.h>

#include <dlfcn.h>
#include <elf.h>
#include <link.h>
#include <vtkVersion.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      struct Search
      {
        const void *base = nullptr;
        std::string id;
      };

      // The NT_GNU_BUILD_ID note among the program headers of the object
      // loaded at search->base.
      int
      find_build_id(struct dl_phdr_info *info, std::size_t, void *data)
      {
        auto *search = static_cast<Search *>(data);
        if (reinterpret_cast<const void *>(info->dlpi_addr) != search->base)
          return 0;
        for (int i = 0; i < info->dlpi_phnum; ++i)
          {
            const auto &segment = info->dlpi_phdr[i];
            if (segment.p_type != PT_NOTE)
              continue;
            const char *p =
              reinterpret_cast<const char *>(info->dlpi_addr + segment.p_vaddr);
            const char *const end = p + segment.p_memsz;
            while (p + sizeof(ElfW(Nhdr)) <= end)
              {
                const auto *note = reinterpret_cast<const ElfW(Nhdr) *>(p);
                const char *name = p + sizeof(ElfW(Nhdr));
                const char *desc = name + ((note->n_namesz + 3) & ~3u);
                if (note->n_type == NT_GNU_BUILD_ID && note->n_namesz == 4 &&
                    std::memcmp(name, "GNU", 4) == 0)
                  {
                    std::ostringstream hex;
                    for (unsigned int k = 0; k < note->n_descsz; ++k)
                      hex << std::hex << std::setw(2) << std::setfill('0')
                          << static_cast<unsigned int>(
                               static_cast<unsigned char>(desc[k]));
                    search->id = hex.str();
                    return 1;
                  }
                p = desc + ((note->n_descsz + 3) & ~3u);
              }
          }
        return 1;
      }

      // FNV-1a over a file's bytes: the build's fingerprint where the
      // linker wrote no build ID.
      std::string
      file_hash(const std::string &file)
      {
        std::ifstream in(file, std::ios::binary);
        std::uint64_t hash = 1469598103934665603ULL;
        char          buffer[1 << 16];
        while (in.read(buffer, sizeof(buffer)) || in.gcount() > 0)
          {
            for (std::streamsize k = 0; k < in.gcount(); ++k)
              hash = (hash ^ static_cast<unsigned char>(buffer[k])) *
                     1099511628211ULL;
            if (!in)
              break;
          }
        std::ostringstream hex;
        hex << "fnv1a-" << std::hex << hash;
        return hex.str();
      }
    } // namespace

    std::string
    library_build_id(std::string *library_file)
    {
      Dl_info info;
      if (dladdr(reinterpret_cast<const void *>(&library_build_id), &info) == 0)
        return "unknown";
      if (library_file != nullptr)
        *library_file = info.dli_fname;
      Search search;
      search.base = info.dli_fbase;
      dl_iterate_phdr(find_build_id, &search);
      return search.id.empty() ? file_hash(info.dli_fname) : search.id;
    }

    std::string
    build_stamp()
    {
      return "softface patient library " + library_build_id() + ", ITK " +
             itk_version() + ", VTK " + vtkVersion::GetVTKVersion() +
             ", CGAL " + CGAL_VERSION_STR + "\n";
    }
  } // namespace Patient
} // namespace softface
