#!/usr/bin/python3
"""CT volumes read from files, as a user's scanner writes them: not the phantom's own grid.

1. The phantom's CT at 2 mm (`softface phantom`, `softface segment`) is the reference. Written
   again as NIfTI turned half a turn about the body axis (the voxel array flipped in x and y, the
   voxel-to-world map saying so), it segments into the same labels, voxel for voxel.
2. The phantom at 1 mm, turned the same way and each two rows averaged into one (1 x 2 x 1 mm
   voxels, as a scanner's thicker rows), runs end to end (segmentation, cuts, mesh, linear FEM). Its labels, looked up at the
   same points in space, agree with the 1 mm phantom's (a wrong orientation or spacing would put
   them elsewhere), and its tissue volumes are the 1 mm phantom's to 10 %.
3. That volume as a DICOM series (one file per slice, stored values (HU + 1024) * 2 with rescale
   slope 0.5 and intercept -1024, files named in the reverse order of their positions, an oblique
   scout image of another series in the same folder): `softface segment` gives the same labels
   as from the NIfTI file, voxel for voxel.
Prints each figure; exit code 1 if a check fails.

usage: patient_ct_files.py SOFTFACE SCENE.prm WORK_DIR
SCENE.prm: a phantom patient scene (tests/run_patient.prm); its Output and Models are replaced.
Needs Debian's python3-numpy and python3-pydicom.
"""
import csv, os, re, shutil, subprocess, sys
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import nifti

softface, template, work = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
failures = []


def check(what, value, low, high):
    print(f"{what}: {value:.4g} (in [{low:.4g}, {high:.4g}])")
    if not low <= value <= high:
        failures.append(f"{what} = {value} is outside [{low}, {high}]")


def scene(name, ct_volume=None, models=False, voxel_size=None):
    """A copy of the template with its own output folder (and CT volume, phantom voxel size);
    with models, linear FEM alone on about 4000 tetrahedra."""
    text = open(template).read()
    if voxel_size:
        text = re.sub(r"set Voxel size = [0-9.]+", f"set Voxel size = {voxel_size}", text)
    text = re.sub(r"\nsubsection Models\n.*?\nend\n", "\n", text, flags=re.S)
    text = re.sub(r"\nsubsection Output\n.*?\nend\n", "\n", text, flags=re.S)
    if ct_volume:
        text = text.replace("  subsection Patient\n",
                            f"  subsection Patient\n    set CT volume = {ct_volume}\n", 1)
    text += f"\nsubsection Output\n  set Output directory = {name}_output\nend\n"
    if models:
        text += "subsection Models\n  set Models = linear fem\n" \
                "  subsection linear fem\n    set Solver = direct\n  end\nend\n"
    with open(os.path.join(work, name + ".prm"), "w") as f:
        f.write(text.replace("set Target number of tetrahedra = 8000",
                             "set Target number of tetrahedra = 4000"))
    return name + ".prm"


def softface_run(*arguments):
    result = subprocess.run([softface, *arguments], cwd=work, capture_output=True, text=True)
    if result.returncode != 0:
        print(result.stdout[-3000:] + result.stderr[-3000:])
        raise SystemExit(f"softface {' '.join(arguments)}: exit code {result.returncode}")
    return result.stdout


def labels_at(volume, affine, points):
    """The label of each point (RAS, mm) in a label volume (nearest voxel; -1 outside)."""
    ijk = np.rint(np.linalg.solve(affine, np.vstack([points.T, np.ones(len(points))]))[:3].T)
    ijk = ijk.astype(int)
    inside = np.all((ijk >= 0) & (ijk < np.array(volume.shape[::-1])), axis=1)
    found = np.full(len(points), -1)
    found[inside] = volume[ijk[inside, 2], ijk[inside, 1], ijk[inside, 0]]
    return found


def turned_half(ct, affine):
    """The volume turned half a turn about z: voxel array flipped in i and j, the map saying so."""
    turned_affine = affine.copy()
    turned_affine[:3, 3] = affine[:3, :3] @ np.array([ct.shape[2] - 1, ct.shape[1] - 1, 0]) + \
        affine[:3, 3]
    turned_affine[:3, 0] *= -1
    turned_affine[:3, 1] *= -1
    return ct[:, ::-1, ::-1], turned_affine


def volume_cm3(labels, affine, label):
    return np.count_nonzero(labels == label) * abs(np.linalg.det(affine[:3, :3])) / 1000


# 1. The reference: the phantom's CT and labels at 2 mm; half a turn gives the same labels,
# voxel for voxel.
softface_run("segment", scene("phantom"))
header, ct, affine = nifti.read(os.path.join(work, "phantom_output/patient/ct.nii.gz"))
_, labels, labels_affine = nifti.read(os.path.join(work, "phantom_output/patient/labels.nii.gz"))
nifti.write(os.path.join(work, "ct_turned.nii.gz"), header, *turned_half(ct, affine))
softface_run("segment", scene("turned", "ct_turned.nii.gz"))
_, labels_turned, labels_turned_affine = nifti.read(
    os.path.join(work, "turned_output/patient/labels.nii.gz"))
expected, expected_affine = turned_half(labels, labels_affine)
check("turned: largest |voxel-to-world difference| to the reference's turned (mm)",
      float(np.abs(labels_turned_affine - expected_affine).max()), 0, 1e-3)
check("turned: voxels labelled differently from the reference's turned",
      float(np.count_nonzero(labels_turned != expected)), 0, 0)

# 2. At 1 mm, turned and two rows averaged into one (1 x 2 x 1 mm), end to end.
softface_run("segment", scene("fine", voxel_size=1))
header, ct, affine = nifti.read(os.path.join(work, "fine_output/patient/ct.nii.gz"))
_, labels, labels_affine = nifti.read(os.path.join(work, "fine_output/patient/labels.nii.gz"))
coarse, coarse_affine = turned_half(ct, affine)
# A row of 2 mm holds two of 1 mm: their mean (the partial-volume effect of a thicker row),
# centred between them.
rows = coarse.shape[1] // 2 * 2
coarse = np.rint((coarse[:, 0:rows:2, :].astype(np.float64) + coarse[:, 1:rows:2, :]) / 2)
coarse = coarse.astype(ct.dtype)
coarse_affine[:3, 3] += 0.5 * coarse_affine[:3, 1]
coarse_affine[:3, 1] *= 2
nifti.write(os.path.join(work, "ct_anisotropic.nii.gz"), header, coarse, coarse_affine)
softface_run(scene("anisotropic", "ct_anisotropic.nii.gz", models=True))
_, labels_coarse, labels_coarse_affine = nifti.read(
    os.path.join(work, "anisotropic_output/patient/labels.nii.gz"))
nk, nj, ni = labels_coarse.shape
k, j, i = np.meshgrid(np.arange(nk), np.arange(nj), np.arange(ni), indexing="ij")
centres = (labels_coarse_affine @ np.vstack([i.ravel(), j.ravel(), k.ravel(),
                                             np.ones(i.size)]))[:3].T
reference_there = labels_at(labels, labels_affine, centres)
body = (reference_there > 0) | (labels_coarse.ravel() > 0)
check("anisotropic: labels equal to the 1 mm reference's at the same points (fraction of the "
      "body)", np.mean(labels_coarse.ravel()[body] == reference_there[body]), 0.95, 1.0)
for label, name in ((1, "skin"), (2, "fat"), (3, "muscle"), (4, "bone"), (5, "internal")):
    ratio = volume_cm3(labels_coarse, labels_coarse_affine, label) / \
        volume_cm3(labels, labels_affine, label)
    check(f"anisotropic: {name} volume / the 1 mm reference's", ratio, 0.97, 1.03)
with open(os.path.join(work, "anisotropic_output/summary.csv")) as f:
    run = next(csv.DictReader(f))
print(f"anisotropic: linear fem {run['status']}, {run['n_tets']} tetrahedra, "
      f"max |u| {float(run['max_displacement_mm']):.3f} mm")
check("anisotropic: linear fem ran (1: ok)", float(run["status"] == "ok"), 1, 1)
turned, turned_affine = coarse, coarse_affine

# 3. The same volume as a DICOM series with a scout beside it.
import pydicom
from pydicom.dataset import FileDataset, FileMetaDataset
from pydicom.uid import ExplicitVRLittleEndian, generate_uid

folder = os.path.join(work, "dicom")
os.makedirs(folder)
study, series, frame_of_reference = generate_uid(), generate_uid(), generate_uid()
lps = np.diag([-1.0, -1.0, 1.0])                      # NIfTI's RAS to DICOM's LPS
direction = lps @ turned_affine[:3, :3]
origin = lps @ turned_affine[:3, 3]
spacing = np.linalg.norm(direction, axis=0)


def dicom_slice(filename, pixels, position, row_direction, column_direction, pixel_spacing,
                series_uid, number):
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = "1.2.840.10008.5.1.4.1.1.2"          # CT Image Storage
    meta.MediaStorageSOPInstanceUID = generate_uid()
    meta.TransferSyntaxUID = ExplicitVRLittleEndian
    ds = FileDataset(filename, {}, file_meta=meta, preamble=b"\0" * 128)
    ds.SOPClassUID, ds.SOPInstanceUID = meta.MediaStorageSOPClassUID, meta.MediaStorageSOPInstanceUID
    ds.Modality, ds.PatientName, ds.PatientID = "CT", "Phantom^Turned", "softface-test"
    ds.StudyInstanceUID, ds.SeriesInstanceUID = study, series_uid
    ds.FrameOfReferenceUID = frame_of_reference
    ds.InstanceNumber, ds.SeriesNumber = number, 2 if series_uid == series else 1
    ds.ImagePositionPatient = [float(x) for x in position]
    ds.ImageOrientationPatient = [float(x) for x in (*row_direction, *column_direction)]
    ds.PixelSpacing = [float(pixel_spacing[1]), float(pixel_spacing[0])]
    ds.SliceThickness = float(spacing[2])
    ds.Rows, ds.Columns = pixels.shape
    ds.SamplesPerPixel, ds.PhotometricInterpretation = 1, "MONOCHROME2"
    ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 16, 16, 15, 0
    ds.RescaleSlope, ds.RescaleIntercept, ds.RescaleType = 0.5, -1024, "HU"
    ds.PixelData = ((pixels.astype(np.int32) + 1024) * 2).astype(np.uint16).tobytes()
    ds.is_little_endian, ds.is_implicit_VR = True, False
    ds.save_as(filename, write_like_original=False)


n_slices = turned.shape[0]
for k in range(n_slices):
    position = origin + direction[:, 2] * k
    dicom_slice(os.path.join(folder, f"image_{n_slices - 1 - k:04d}.dcm"), turned[k], position,
                direction[:, 0] / spacing[0], direction[:, 1] / spacing[1], spacing[:2], series,
                k + 1)
scout = turned[:, :, turned.shape[2] // 2][::-1].copy()                 # a sagittal view
dicom_slice(os.path.join(folder, "scout.dcm"), scout, origin, (0.0, 0.6, 0.8), (0.0, 0.8, -0.6),
            (4.0, 2.0), generate_uid(), 1)
softface_run("segment", scene("dicom", "dicom"))
_, labels_dicom, labels_dicom_affine = nifti.read(
    os.path.join(work, "dicom_output/patient/labels.nii.gz"))
check("DICOM: largest |voxel-to-world difference| to the NIfTI's (mm)",
      float(np.abs(labels_dicom_affine - labels_coarse_affine).max()), 0, 1e-3)
same_shape = labels_dicom.shape == labels_coarse.shape
check("DICOM: same grid as the NIfTI's (1: yes)", float(same_shape), 1, 1)
if same_shape:
    check("DICOM: voxels labelled differently from the NIfTI's",
          float(np.count_nonzero(labels_dicom != labels_coarse)), 0, 0)

if failures:
    print("patient_ct_files: failed:\n  " + "\n  ".join(failures))
    sys.exit(1)
