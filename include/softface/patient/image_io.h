#ifndef softface_patient_image_io_h
#define softface_patient_image_io_h

#include <softface/patient/volume.h>

#include <string>

namespace softface
{
  namespace Patient
  {
    /**
     * Volumes in and out through ITK: any format ITK reads (NIfTI .nii and
     * .nii.gz, NRRD, MetaImage .mha/.mhd) or, given a folder, the DICOM
     * series in it (the largest one). The physical frame (origin, spacing,
     * direction) is ITK's, the file's own. Errors name the file.
     */
    CTVolume
    read_ct(const std::string &filename);

    LabelVolume
    read_labels(const std::string &filename);

    /// Written in the format of the file name's extension (.nii.gz, ...).
    void
    write_volume(const CTVolume &volume, const std::string &filename);
    void
    write_volume(const LabelVolume &volume, const std::string &filename);

    /// The version of ITK this process runs with, e.g. "5.2.1".
    std::string
    itk_version();
  } // namespace Patient
} // namespace softface

#endif
