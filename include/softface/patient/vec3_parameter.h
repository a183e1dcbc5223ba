#ifndef softface_patient_vec3_parameter_h
#define softface_patient_vec3_parameter_h

#include <softface/patient/volume.h>

#include <string>

namespace softface
{
  namespace Patient
  {
    /**
     * A parameter's 'x, y, z' (a point or direction of the patient
     * subsections); anything else is an Error naming @p where, the
     * parameter's path.
     */
    Vec3
    parse_vec3(const std::string &text, const std::string &where);
  } // namespace Patient
} // namespace softface

#endif
