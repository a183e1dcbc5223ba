// Loading the patient pipeline on first use (backend.h).

#include <softface/core/error.h>
#include <softface/patient/backend.h>

#include <dlfcn.h>

#include <mutex>

namespace softface
{
  namespace Patient
  {
    const Backend &
    backend()
    {
      static const Backend *loaded = nullptr;
      static std::once_flag once;
      std::call_once(once, [] {
        // The library's name first: LD_LIBRARY_PATH and the core's own
        // search path (a copied build, an install) come before the path
        // the build put it at.
        void       *library = dlopen("libsoftface_patient.so", RTLD_NOW);
        std::string reason  = library == nullptr ? dlerror() : "";
        if (library == nullptr)
          {
            library = dlopen(SOFTFACE_PATIENT_LIBRARY, RTLD_NOW);
            if (library == nullptr)
              reason += "; " + std::string(dlerror());
          }
        if (library == nullptr)
          throw Error("Cannot load the patient pipeline "
                      "(libsoftface_patient.so, built at " +
                      std::string(SOFTFACE_PATIENT_LIBRARY) + "): " + reason);
        using Entry = const Backend *(*)();
        const auto entry =
          reinterpret_cast<Entry>(dlsym(library, "softface_patient_backend"));
        if (entry == nullptr)
          throw Error("The patient pipeline " +
                      std::string(SOFTFACE_PATIENT_LIBRARY) +
                      " has no entry point softface_patient_backend: a "
                      "library from another build?");
        loaded = entry();
      });
      return *loaded;
    }
  } // namespace Patient
} // namespace softface
