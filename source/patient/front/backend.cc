// Loading the patient pipeline on first use (backend.h).

#include <softface/core/error.h>
#include <softface/patient/backend.h>

#include <dlfcn.h>
#include <unistd.h>

#include <mutex>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      // The folder of the shared library this function is in (the core).
      std::string
      core_folder()
      {
        Dl_info info;
        if (dladdr(reinterpret_cast<void *>(&core_folder), &info) == 0 ||
            info.dli_fname == nullptr)
          return "";
        const std::string file  = info.dli_fname;
        const auto        slash = file.rfind('/');
        return slash == std::string::npos ? "." : file.substr(0, slash);
      }

      const Backend *
      load()
      {
        // Next to the core first (a copied or installed softface), then
        // where this build put it, then the dynamic linker's search path.
        const std::string beside = core_folder() + "/libsoftface_patient.so";
        std::string       tried;
        void             *library = nullptr;
        for (const std::string &file : {beside,
                                        std::string(SOFTFACE_PATIENT_LIBRARY),
                                        std::string("libsoftface_patient.so")})
          {
            if (file.find('/') != std::string::npos &&
                access(file.c_str(), F_OK) != 0)
              {
                tried += (tried.empty() ? " " : "; ") + file + ": no such file";
                continue;
              }
            library = dlopen(file.c_str(), RTLD_NOW);
            if (library != nullptr)
              {
                tried = file;
                break;
              }
            tried += (tried.empty() ? " " : "; ") + file + ": " + dlerror();
          }
        if (library == nullptr)
          throw Error("Cannot load the patient pipeline "
                      "(libsoftface_patient.so); tried:" +
                      tried);
        using Entry = const Backend *(*)();
        const auto entry =
          reinterpret_cast<Entry>(dlsym(library, "softface_patient_backend"));
        const Backend *backend = entry == nullptr ? nullptr : entry();
        if (backend == nullptr || backend->version != backend_version ||
            backend->size_of_backend != sizeof(Backend) ||
            backend->size_of_parameters != sizeof(PatientParameters))
          throw Error("The patient pipeline " + tried +
                      " does not belong to this softface (another build?): "
                      "rebuild it, or put this build's next to "
                      "libsoftface_core.so.");
        return backend;
      }
    } // namespace

    const Backend &
    backend()
    {
      // A mutex, not std::call_once: a failed load throws, and a later
      // call tries again.
      static std::mutex           mutex;
      static const Backend       *loaded = nullptr;
      std::lock_guard<std::mutex> lock(mutex);
      if (loaded == nullptr)
        loaded = load();
      return *loaded;
    }
  } // namespace Patient
} // namespace softface
