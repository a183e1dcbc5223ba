#!/bin/bash
# The pictures of doc/patient.md's sections "Preview" and "Closed mouths":
# 'softface preview' on the default phantom scene (prm/patient.prm) and on the
# closed mouth's (prm/patient_closed_mouth.prm, its coronal and sagittal
# slices as closed_mouth_*.png), copied into doc/images/preview/. A picture
# over 250 KB is stored with a palette of 256 colours (the CT's noise makes
# full-colour PNGs large). Run from anywhere, after a build:
#   doc/make_preview_pictures.sh [SOFTFACE]   (default: build/softface)
set -e
cd "$(dirname "$0")/.."
softface=${1:-build/softface}
listing=$(mktemp)
trap 'rm -f "$listing"' EXIT
mkdir -p doc/images/preview

# preview SCENE PREFIX PICTURE...: the scene's pictures, as PREFIXPICTURE.png.
preview() {
  local scene=$1 prefix=$2
  shift 2
  # Exit code 1 (parts not made) still leaves pictures worth showing.
  "$softface" preview "$scene" | tee "$listing" || true
  local folder
  folder=$(sed -n 's|^Files in \(.*\)/:.*|\1|p' "$listing")
  [ -n "$folder" ] || { echo "no pictures written"; exit 1; }
  for picture in "$@"; do
    /usr/bin/python3 - "$folder/$picture.png" "doc/images/preview/$prefix$picture.png" <<'PYTHON'
import os, shutil, sys
from PIL import Image
source, target = sys.argv[1], sys.argv[2]
shutil.copyfile(source, target)
if os.path.getsize(target) > 250_000:
    Image.open(source).convert("RGB").quantize(256).save(target, optimize=True)
print(target, os.path.getsize(target) // 1000, "KB")
PYTHON
  done
}

preview prm/patient.prm "" axial coronal sagittal bone_parts_front bone_parts_left
preview prm/patient_closed_mouth.prm closed_mouth_ coronal sagittal
