#!/usr/bin/python3
"""The patient commands one by one, as a user runs them on a phantom scene:

  softface phantom   the CT (its grid: field of view / voxel size)
  softface segment   the labels (every tissue present) and the skin and skull surfaces
  softface mesh      the bone parts and the tetrahedral mesh; run again, every stage is reused
  softface postop    the post-operative skull, each bone part moved by the scene's Planning
  softface plan      the Planning recovered from that skull by ICP: the scene's own motions
  softface preview   the pictures of the CT with its labels, bone parts, cuts and seed points
                     (the earlier stages reused); on a scene without a patient, an error
  softface register  a post-operative CT (the phantom's, its voxel-to-world map shifted by a
                     known translation) registered to the pre-operative one: the shift, undone

Prints each figure; exit code 1 if a check fails.

usage: patient_commands.py SOFTFACE SCENE.prm WORK_DIR
SCENE.prm: a phantom patient scene (tests/run_patient.prm) that advances the maxilla by
(0, -3, 0) mm and the mandible by (0, -5, 0) mm; its Output section is replaced.
Needs Debian's python3-numpy.
"""
import csv, os, re, shutil, subprocess, sys
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import nifti

softface, template, work = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
failures = []
stages = os.path.join(work, "commands_output", "patient")


def check(what, value, low, high):
    print(f"{what}: {value:.4g} (in [{low:.4g}, {high:.4g}])")
    if not low <= value <= high:
        failures.append(f"{what} = {value} is outside [{low}, {high}]")


def run(command):
    result = subprocess.run([softface, command, "commands.prm"], cwd=work, capture_output=True,
                            text=True)
    print(f"softface {command}: exit code {result.returncode}")
    if result.returncode != 0:
        print(result.stdout[-3000:] + result.stderr[-3000:])
        raise SystemExit(f"softface {command} failed")
    return result.stdout


text = open(template).read()
text = re.sub(r"\nsubsection Output\n.*?\nend\n", "\n", text, flags=re.S)
text = text.replace("  subsection Patient\n", "  subsection Patient\n"
                    "    set Post-operative skull = commands_output/patient/postop_skull.ply\n"
                    "    subsection Registration\n"
                    "      set Post-operative CT = postop_ct.nii.gz\n"
                    "    end\n", 1)
text += "\nsubsection Output\n  set Output directory = commands_output\nend\n"
with open(os.path.join(work, "commands.prm"), "w") as f:
    f.write(text)
voxel = float(re.search(r"set Voxel size = ([0-9.]+)", text).group(1))

run("phantom")
header, ct, affine = nifti.read(os.path.join(stages, "ct.nii.gz"))
for axis, (n, extent) in enumerate(zip(ct.shape[::-1], (180, 240, 256))):
    check(f"phantom: voxels along axis {axis} - field of view / voxel size", n - extent / voxel,
          0, 0)

run("segment")
_, labels, _ = nifti.read(os.path.join(stages, "labels.nii.gz"))
for label, name in enumerate(("outside", "skin", "fat", "muscle", "bone", "internal")):
    check(f"segment: {name} voxels (thousands)", np.count_nonzero(labels == label) / 1000,
          1, 1e9)
for surface in ("skin.ply", "skull.ply"):
    check(f"segment: {surface} written (1: yes)", float(os.path.isfile(
        os.path.join(stages, surface))), 1, 1)

output = run("mesh")
tetrahedra = int(re.search(r"tetrahedra: *([0-9]+)", output).group(1))
check("mesh: tetrahedra", tetrahedra, 4000, 16000)
check("mesh: mesh.vtu written (1: yes)", float(os.path.isfile(os.path.join(stages, "mesh.vtu"))),
      1, 1)
output = run("mesh")
check("mesh again: stages reused (phantom, segmentation, mesh)",
      len(re.findall(r": reused ", output)), 3, 3)

output = run("preview")
check("preview: stages reused (phantom, segmentation)", len(re.findall(r": reused ", output)), 2,
      2)
for picture in ("axial", "coronal", "sagittal", "bone_parts_front", "bone_parts_left"):
    check(f"preview: {picture}.png written (1: yes)", float(os.path.isfile(
        os.path.join(stages, "preview", picture + ".png"))), 1, 1)
with open(os.path.join(work, "no_patient.prm"), "w") as f:
    f.write(text.replace("set Mesh source   = patient", "set Mesh source   = file"))
result = subprocess.run([softface, "preview", "no_patient.prm"], cwd=work, capture_output=True,
                        text=True)
print("softface preview on a scene without a patient: exit code", result.returncode, "|",
      result.stderr.strip())
check("preview without a patient: exit code", result.returncode, 1, 1)
check("preview without a patient: the message says so (1: yes)",
      float("'softface preview' runs the patient stages" in result.stderr), 1, 1)

run("postop")
run("plan")
planning = open(os.path.join(stages, "planning.prm")).read()
for segment, planned in (("maxilla", (0, -3, 0)), ("mandible", (0, -5, 0))):
    motion = re.search(r"subsection Motion " + segment + r"\n(.*?)\n  end", planning, re.S).group(1)
    angle = float(re.search(r"Rotation angle *= *(\S+)", motion).group(1))
    translation = [float(x) for x in
                   re.search(r"Translation *= *(.*)", motion).group(1).split(",")]
    check(f"plan: {segment}, |translation - planned| (mm)",
          float(np.linalg.norm(np.array(translation) - planned)), 0, 0.01)
    check(f"plan: {segment}, rotation angle (degrees)", abs(angle), 0, 0.01)

# The post-operative CT: the phantom's voxels, its map moved by shift (LPS, mm). In NIfTI's RAS
# frame the x and y components change sign.
shift = np.array([3.0, -2.0, 1.0])
moved = affine.copy()
moved[:3, 3] += shift * np.array([-1, -1, 1])
nifti.write(os.path.join(work, "postop_ct.nii.gz"), header, ct, moved)
run("register")
with open(os.path.join(work, "commands_output", "registration.csv")) as f:
    rows = {row[0]: row[1:] for row in csv.reader(f) if row and not row[0].startswith("#")}
translation = np.array([float(x) for x in rows["translation"]])
print("register: translation " + ", ".join(f"{x:.3f}" for x in translation) + " mm")
check("register: |translation + shift| (mm)", float(np.linalg.norm(translation + shift)), 0, 0.05)
check("register: rotation angle (degrees)", abs(float(rows["angle_degrees"][0])), 0, 0.2)

if failures:
    print("patient_commands: failed:\n  " + "\n  ".join(failures))
    sys.exit(1)
