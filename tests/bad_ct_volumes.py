#!/usr/bin/python3
"""The damaged CT volumes of tests/bad_input/ct_*: a few hundred bytes each, written with numpy
and the standard library (NIfTI-1 is a 348-byte header), each with one defect a scanner, a
converter or a cut-short copy can leave. Run from anywhere; writes into tests/bad_input.

usage: /usr/bin/python3 tests/bad_ct_volumes.py
Needs Debian's python3-numpy and, for the DICOM series, python3-pydicom.
"""
import gzip, os, struct, zlib
import numpy as np

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bad_input")


def nifti_header(shape, datatype=4, bitpix=16, spacing=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0)):
    """A NIfTI-1 header (348 bytes and the 4-byte extension flag) of a single-file volume."""
    h = bytearray(348)
    struct.pack_into("<i", h, 0, 348)                        # sizeof_hdr
    struct.pack_into("<8h", h, 40, 3, *shape, 1, 1, 1, 1)    # dim
    struct.pack_into("<hh", h, 70, datatype, bitpix)
    struct.pack_into("<4f", h, 76, 1.0, *spacing)            # pixdim (qfac, voxel size)
    struct.pack_into("<ff", h, 108, 352.0, 1.0)              # vox_offset, scl_slope
    h[123] = 2                                               # xyzt_units: mm
    struct.pack_into("<hh", h, 252, 1, 0)                    # qform_code, sform_code
    struct.pack_into("<6f", h, 256, 0, 0, 0, *origin)        # quaternion b, c, d; offset
    h[344:348] = b"n+1\0"
    return bytes(h) + b"\0\0\0\0"


def head(shape, dtype=np.int16):
    """A ball of soft tissue (40 HU) in air (-1000 HU), indexed [k, j, i]."""
    k, j, i = np.mgrid[0:shape[2], 0:shape[1], 0:shape[0]]
    c = (np.array(shape) - 1) / 2
    r = np.sqrt((i - c[0]) ** 2 + (j - c[1]) ** 2 + (k - c[2]) ** 2)
    return np.where(r < min(shape) / 3, 40, -1000).astype(dtype)


def write(name, data, compressed=None):
    compressed = name.endswith(".gz") if compressed is None else compressed
    with open(os.path.join(OUT, name), "wb") as f:
        f.write(gzip.compress(data, mtime=0) if compressed else data)


N16, N8 = (16, 16, 16), (8, 8, 8)
ct16, ct8 = head(N16).tobytes(), head(N8).tobytes()

# An intact gzip stream that holds half the voxels its header declares.
write("ct_gzip_short.nii.gz", nifti_header(N16) + ct16[:len(ct16) // 2])
# Uncompressed, 200 bytes of voxels missing: still longer than the voxels alone.
write("ct_short.nii", nifti_header(N8) + ct8[:-200])
# float32 voxels, three of them NaN, +inf and -inf.
v = head(N8, np.float32)
v[3, 3, 3], v[4, 4, 4], v[5, 2, 1] = np.nan, np.inf, -np.inf
write("ct_nan_voxels.nii.gz", nifti_header(N8, 16, 32) + v.tobytes())
# Voxel sizes no scan has.
for name, spacing in [("zero", (1, 0, 1)), ("negative", (1, 1, -1)),
                      ("nan", (float("nan"), 1, 1)), ("huge", (1, 1, 1000))]:
    write("ct_spacing_%s.nii.gz" % name, nifti_header(N8, spacing=spacing) + ct8)
# A dimension of 0 voxels.
write("ct_size_zero.nii.gz", nifti_header((8, 8, 0)) + ct8)
# 2048^3 voxels (16 GiB) declared in a file of a hundred bytes.
write("ct_size_huge.nii.gz", nifti_header((2048, 2048, 2048)) + ct8)
# An origin that is not a number.
write("ct_origin_nan.nii.gz", nifti_header(N8, origin=(0, float("nan"), 0)) + ct8)
# MetaImage with its voxels in the file, the last 100 bytes missing.
write("ct_mha_short.mha",
      b"ObjectType = Image\nNDims = 3\nDimSize = 8 8 8\nElementSpacing = 1 1 1\n"
      b"ElementType = MET_SHORT\nElementDataFile = LOCAL\n" + ct8[:-100], False)
# NRRD, gzip encoding: an intact stream of half the voxels.
write("ct_nrrd_gzip_short.nrrd",
      b"NRRD0004\ntype: short\ndimension: 3\nsizes: 16 16 16\nspacings: 1 1 1\n"
      b"encoding: gzip\nendian: little\n\n" + gzip.compress(ct16[:len(ct16) // 2], mtime=0),
      False)

import pydicom
from pydicom.dataset import FileDataset, FileMetaDataset
from pydicom.uid import ExplicitVRLittleEndian

root = "1.2.826.0.1.3680043.10.1031."           # fixed UIDs: the files are the same each time


def dicom_series(name, positions, uids, patient, bright=None):
    """A series of 8 x 8 axial slices at @p positions (x, y, z in mm), one file each, in
    tests/bad_input/NAME; @p uids: the suffixes of its study, series, images and frame of
    reference UIDs. With @p bright, unsigned stored values with intercept -1024 and, in the
    middle of the first slice, 2 x 2 voxels of the stored value @p bright."""
    folder = os.path.join(OUT, name)
    os.makedirs(folder, exist_ok=True)
    slices = head((8, 8, len(positions)), np.int32)
    if bright is not None:
        slices += 1024
        slices[0, 3:5, 3:5] = bright
    for n, position in enumerate(positions):
        meta = FileMetaDataset()
        meta.MediaStorageSOPClassUID = "1.2.840.10008.5.1.4.1.1.2"          # CT Image Storage
        meta.MediaStorageSOPInstanceUID = root + uids[2] + ".%d" % (n + 1)
        meta.TransferSyntaxUID = ExplicitVRLittleEndian
        filename = os.path.join(folder, "slice%d.dcm" % n)
        ds = FileDataset(filename, {}, file_meta=meta, preamble=b"\0" * 128)
        ds.SOPClassUID = meta.MediaStorageSOPClassUID
        ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
        ds.Modality, ds.PatientName, ds.PatientID = "CT", patient, "softface-test"
        ds.StudyInstanceUID, ds.SeriesInstanceUID = root + uids[0], root + uids[1]
        ds.FrameOfReferenceUID = root + uids[3]
        ds.InstanceNumber, ds.SeriesNumber = n + 1, 1
        ds.ImagePositionPatient = list(position)
        ds.ImageOrientationPatient = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        ds.PixelSpacing, ds.SliceThickness = [2.0, 2.0], 2.0
        ds.Rows, ds.Columns = 8, 8
        ds.SamplesPerPixel, ds.PhotometricInterpretation = 1, "MONOCHROME2"
        ds.BitsAllocated, ds.BitsStored, ds.HighBit = 16, 16, 15
        ds.PixelRepresentation = 1 if bright is None else 0
        ds.RescaleSlope, ds.RescaleIntercept, ds.RescaleType = 1, 0 if bright is None else -1024, "HU"
        ds.PixelData = slices[n].astype(np.int16 if bright is None else np.uint16).tobytes()
        ds.is_little_endian, ds.is_implicit_VR = True, False
        ds.save_as(filename, write_like_original=False)


# Slices at z = 0, 2, 4 and 8 mm: the slice at 6 mm is missing.
dicom_series("ct_dicom_missing_slice", [(0.0, 0.0, z) for z in (0.0, 2.0, 4.0, 8.0)],
             ("1", "2", "3", "4"), "Test^Missing")
# Slices 2 mm apart along z and 1 mm apart along y, with axial rows and columns: the stack of
# a gantry tilted by 26.6 degrees, sheared along the table.
dicom_series("ct_dicom_gantry_tilt", [(0.0, z / 2, z) for z in (0.0, 2.0, 4.0, 6.0)],
             ("11", "12", "13", "14"), "Test^Tilt")
# Unsigned stored values with intercept -1024, four of them 65000: 63976 HU after the rescale,
# past the 16-bit integers softface keeps (converted, they would wrap around to -1560 HU, air).
dicom_series("ct_dicom_rescale_overflow", [(0.0, 0.0, z) for z in (0.0, 2.0, 4.0, 6.0)],
             ("21", "22", "23", "24"), "Test^Overflow", bright=65000)
