#!/usr/bin/python3
"""A CT volume (NIfTI, in Hounsfield units) written as a DICOM series the way a scanner's export
can hold it, for tests/patient_dicom_series.cc:
- int16 stored values 2 (HU + 1024) with RescaleSlope 0.5 and RescaleIntercept -1024: the stored
  values are not Hounsfield units, only the rescale makes them so;
- one file per slice, file names and InstanceNumber counting down where ImagePositionPatient goes
  up along the slice normal (the order of a scan from the top of the head down);
- ImageOrientationPatient and ImagePositionPatient from the volume's voxel-to-world map, oblique
  when the map is;
- a scout (localiser) in the same folder, which the reader must leave out: a lateral image of
  another SeriesInstanceUID, and a frontal one with the scan's SeriesInstanceUID (as some scanners
  write it) but its own series number, both of another size, orientation and pixel spacing.

usage: /usr/bin/python3 dicom_series.py CT.nii.gz FOLDER
Needs Debian's python3-numpy and python3-pydicom.
"""
import os, sys
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import nifti

from pydicom.dataset import FileDataset, FileMetaDataset
from pydicom.uid import ExplicitVRLittleEndian, generate_uid

source, folder = sys.argv[1], sys.argv[2]
_, ct, affine = nifti.read(source)
os.makedirs(folder, exist_ok=True)
for name in os.listdir(folder):
    os.remove(os.path.join(folder, name))

lps = np.diag([-1.0, -1.0, 1.0])                      # NIfTI's RAS to DICOM's LPS
matrix = lps @ affine[:3, :3]                         # columns: the voxel axes i, j, k
origin = lps @ affine[:3, 3]
spacing = np.linalg.norm(matrix, axis=0)
direction = matrix / spacing
nk, nj, ni = ct.shape


def uid(*what):
    """The same UIDs each time for the same volume: the files do not change between runs."""
    return generate_uid(entropy_srcs=["softface dicom_series", os.path.basename(folder), *what])


study, frame_of_reference = uid("study"), uid("frame of reference")


def ds_numbers(values):
    """Decimal strings of at most 16 characters (DICOM's DS)."""
    return [f"{float(x):.10g}" for x in values]


def write(filename, hounsfield, position, row_direction, column_direction, pixel_spacing,
          series, series_number, number, thickness):
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = "1.2.840.10008.5.1.4.1.1.2"          # CT Image Storage
    meta.MediaStorageSOPInstanceUID = uid(series, str(series_number), str(number))
    meta.TransferSyntaxUID = ExplicitVRLittleEndian
    ds = FileDataset(filename, {}, file_meta=meta, preamble=b"\0" * 128)
    ds.SOPClassUID, ds.SOPInstanceUID = meta.MediaStorageSOPClassUID, meta.MediaStorageSOPInstanceUID
    ds.Modality, ds.PatientName, ds.PatientID = "CT", "Phantom^Head", "softface-test"
    ds.StudyInstanceUID, ds.SeriesInstanceUID = study, series
    ds.FrameOfReferenceUID = frame_of_reference
    ds.SeriesNumber, ds.InstanceNumber = series_number, number
    ds.ImagePositionPatient = ds_numbers(position)
    ds.ImageOrientationPatient = ds_numbers([*row_direction, *column_direction])
    ds.PixelSpacing = ds_numbers(pixel_spacing)         # between rows, between columns
    ds.SliceThickness = ds_numbers([thickness])[0]
    ds.Rows, ds.Columns = hounsfield.shape
    ds.SamplesPerPixel, ds.PhotometricInterpretation = 1, "MONOCHROME2"
    ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 16, 16, 15, 1
    ds.RescaleSlope, ds.RescaleIntercept, ds.RescaleType = "0.5", "-1024", "HU"
    stored = (hounsfield.astype(np.int64) + 1024) * 2
    assert stored.min() >= -32768 and stored.max() <= 32767, "HU outside what int16 stores"
    ds.PixelData = stored.astype("<i2").tobytes()
    ds.is_little_endian, ds.is_implicit_VR = True, False
    ds.save_as(filename, write_like_original=False)


# The series: slice k at origin + k * (slice spacing) along the third axis, named and numbered
# from the last slice to the first.
series = uid("series")
for k in range(nk):
    number = nk - k
    write(os.path.join(folder, f"CT{number:04d}.dcm"), ct[k], origin + matrix[:, 2] * k,
          direction[:, 0], direction[:, 1], (spacing[1], spacing[0]), series, 2, number,
          spacing[2])

# The scout: a lateral image (rows going down the head, columns from the face back) and a
# frontal one (rows down, columns from the patient's right to left), every second voxel of the
# volume's middle planes, placed at the volume's world bounding box. The frontal one shares the
# scan's SeriesInstanceUID: only its series number, size and thickness tell it apart.
corners = np.array([origin + matrix @ np.array([a, b, c])
                    for a in (0, ni - 1) for b in (0, nj - 1) for c in (0, nk - 1)])
low, high = corners.min(axis=0), corners.max(axis=0)
middle = (low + high) / 2
scout = uid("scout")
lateral = ct[::-2, :, ni // 2][:, ::2]
write(os.path.join(folder, "SCOUT1.dcm"), np.ascontiguousarray(lateral),
      (middle[0], low[1], high[2]), (0.0, 1.0, 0.0), (0.0, 0.0, -1.0),
      (2 * spacing[2], 2 * spacing[1]), scout, 1, 1, 2 * spacing[0])
frontal = ct[::-2, nj // 2, :][:, ::2]
write(os.path.join(folder, "SCOUT2.dcm"), np.ascontiguousarray(frontal),
      (low[0], middle[1], high[2]), (1.0, 0.0, 0.0), (0.0, 0.0, -1.0),
      (2 * spacing[2], 2 * spacing[0]), series, 1, 2, 2 * spacing[1])
