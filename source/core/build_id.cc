// The build ID of a loaded library, read from its ELF notes.

#include <softface/core/build_id.h>

#include <dlfcn.h>
#include <elf.h>
#include <link.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace softface
{
  namespace
  {
    struct Search
    {
      ElfW(Addr) address = 0; ///< of a function in the library sought
      std::string id;
    };

    // The NT_GNU_BUILD_ID note of the loaded object one of whose loaded
    // segments holds search->address.
    int
    find_build_id(struct dl_phdr_info *info, std::size_t, void *data)
    {
      auto *search = static_cast<Search *>(data);
      bool  holds  = false;
      for (int i = 0; i < info->dlpi_phnum; ++i)
        {
          const auto &segment = info->dlpi_phdr[i];
          const auto  start   = info->dlpi_addr + segment.p_vaddr;
          holds |= segment.p_type == PT_LOAD && search->address >= start &&
                   search->address < start + segment.p_memsz;
        }
      if (!holds)
        return 0;
      for (int i = 0; i < info->dlpi_phnum; ++i)
        {
          const auto &segment = info->dlpi_phdr[i];
          if (segment.p_type != PT_NOTE)
            continue;
          // Note fields are padded to the segment's alignment (4 or 8).
          const std::size_t align = segment.p_align == 8 ? 8 : 4;
          const auto        pad   = [align](const std::size_t n) {
            return (n + align - 1) & ~(align - 1);
          };
          const char *p =
            reinterpret_cast<const char *>(info->dlpi_addr + segment.p_vaddr);
          const char *const end = p + segment.p_memsz;
          while (p + sizeof(ElfW(Nhdr)) <= end)
            {
              const auto *note = reinterpret_cast<const ElfW(Nhdr) *>(p);
              const char *name = p + sizeof(ElfW(Nhdr));
              const char *desc = name + pad(note->n_namesz);
              if (desc + note->n_descsz > end)
                break;
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
              p = desc + pad(note->n_descsz);
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
      while (in)
        {
          in.read(buffer, sizeof(buffer));
          for (std::streamsize k = 0; k < in.gcount(); ++k)
            hash =
              (hash ^ static_cast<unsigned char>(buffer[k])) * 1099511628211ULL;
        }
      std::ostringstream hex;
      hex << "fnv1a-" << std::hex << hash;
      return hex.str();
    }
  } // namespace


  std::string
  library_build_id_of(const void *self, std::string *library_file)
  {
    Dl_info info;
    if (dladdr(self, &info) == 0 || info.dli_fname == nullptr ||
        info.dli_fname[0] == '\0')
      return "";
    if (library_file != nullptr)
      *library_file = info.dli_fname;
    Search search;
    search.address = reinterpret_cast<ElfW(Addr)>(self);
    dl_iterate_phdr(find_build_id, &search);
    return search.id.empty() ? file_hash(info.dli_fname) : search.id;
  }
} // namespace softface
