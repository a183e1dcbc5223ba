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

# A DICOM series of 8 x 8 slices at z = 0, 2, 4 and 8 mm: the slice at 6 mm is missing.
import pydicom
from pydicom.dataset import FileDataset, FileMetaDataset
from pydicom.uid import ExplicitVRLittleEndian

folder = os.path.join(OUT, "ct_dicom_missing_slice")
os.makedirs(folder, exist_ok=True)
root = "1.2.826.0.1.3680043.10.1031."           # fixed UIDs: the files are the same each time
slices = head((8, 8, 4))
for n, z in enumerate((0.0, 2.0, 4.0, 8.0)):
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = "1.2.840.10008.5.1.4.1.1.2"          # CT Image Storage
    meta.MediaStorageSOPInstanceUID = root + "3.%d" % (n + 1)
    meta.TransferSyntaxUID = ExplicitVRLittleEndian
    name = os.path.join(folder, "slice%d.dcm" % n)
    ds = FileDataset(name, {}, file_meta=meta, preamble=b"\0" * 128)
    ds.SOPClassUID, ds.SOPInstanceUID = meta.MediaStorageSOPClassUID, meta.MediaStorageSOPInstanceUID
    ds.Modality, ds.PatientName, ds.PatientID = "CT", "Test^Missing", "softface-test"
    ds.StudyInstanceUID, ds.SeriesInstanceUID = root + "1", root + "2"
    ds.FrameOfReferenceUID = root + "4"
    ds.InstanceNumber, ds.SeriesNumber = n + 1, 1
    ds.ImagePositionPatient = [0.0, 0.0, z]
    ds.ImageOrientationPatient = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
    ds.PixelSpacing, ds.SliceThickness = [2.0, 2.0], 2.0
    ds.Rows, ds.Columns = 8, 8
    ds.SamplesPerPixel, ds.PhotometricInterpretation = 1, "MONOCHROME2"
    ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 16, 16, 15, 1
    ds.RescaleSlope, ds.RescaleIntercept, ds.RescaleType = 1, 0, "HU"
    ds.PixelData = slices[n].astype(np.int16).tobytes()
    ds.is_little_endian, ds.is_implicit_VR = True, False
    ds.save_as(name, write_like_original=False)
