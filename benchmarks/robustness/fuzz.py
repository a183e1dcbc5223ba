#!/usr/bin/python3
"""Seeded mutation fuzzer for softface's inputs: parameter files, meshes, CT volumes.

    /usr/bin/python3 benchmarks/robustness/fuzz.py [--softface PATH] [--cases N] [--seed S]
        [--timeout SECONDS] [--jobs J] [--out DIR] [--keep DIR] [--strict] [--binary-note TEXT]
        [--ranks R] [--mpiexec PATH]   (Open MPI's mpiexec)
        [--seeds NAME,NAME,...]

Each case takes one seed (a valid scene: the templates below, with a gmsh 4.1 or
gmsh 2.2, legacy VTK or .vtu mesh, or the parameter file itself), applies one to three
mutations (truncation, byte flips, a line moved, deleted or repeated, a number swapped for an
extreme one) and runs softface on it with a time limit. On one rank a CT volume is a seed too:
the phantom's CT at 4 mm (written by `softface phantom` at the start), run through `softface
segment`, with its own mutations (voxel data cut short inside an intact gzip stream, the .gz
file cut, NaN and infinite voxels, voxel size, size, data offset, data type or origin in the
NIfTI header replaced by an absurd value, header bytes overwritten, stored uncompressed).
--seeds NAME,NAME,... runs only the seeds named (e.g. "nifti ct"). Outcomes:

    ok         exit 0 and no nan/inf in summary.csv or the displacement outputs
    refused    exit 1 with softface's one-line message ("softface: error: ...")
    unclear    non-zero exit without that line (an uncaught exception, std::bad_alloc alone, ...)
    nan        exit 0 but nan/inf in the outputs (a silent wrong answer)
    crash      killed by a signal (SIGSEGV, SIGABRT, ...)
    hang       still running at the time limit

With --ranks R (more than 1) each case runs as `mpiexec -n R softface scene.prm` (an
error on any rank must end every rank with one message): *refused* then also asks that the
`softface: error` line come exactly once; two or more are *unclear*, and a rank killed by a
signal (Open MPI's "exited on signal") is a *crash*. At the time limit mpiexec is asked to end
and then every process left in the case's session (its ranks too) is killed.

Writes DIR/robustness.{md,csv,png} (DIR defaults to doc/results of this repository) with the
counts by seed and outcome, and keeps every input that did not end ok or refused in --keep
(default /tmp/softface_fuzz_kept) to reproduce it. Standard library only (matplotlib for the
plot if present). Exit code 0 unless --strict and a crash, hang, nan or unclear case occurred.
"""
import array
import csv
import gzip
import math
import os
import random
import re
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
SEEDS = os.path.join(ROOT, "tests", "data", "mesh_seeds")

SCENE_GMSH = """subsection Scene
  set Mesh source   = file
  set Mesh file     = {mesh}
  set Bone segments = fixed, bone
  subsection Segment fixed
    set Boundary ids = 1
    set Material ids =
  end
  subsection Segment bone
    set Boundary ids =
    set Material ids = 2
  end
end
subsection Planning
  subsection Motion bone
    set Translation = 0, 0, 4
  end
end
"""
# deal.II's legacy VTK reader gives every boundary face id 0: the box's outer faces.
SCENE_VTK = SCENE_GMSH.replace("set Boundary ids = 1", "set Boundary ids = 0")
# A vtu seed of the test suite (tests/data/vtu): the unit cube in six tetrahedra, boundary id 3
# on its two triangles of z = 0, which are moved (all its 8 vertices are on the boundary).
SCENE_VTU = """subsection Scene
  set Mesh source   = file
  set Mesh file     = {mesh}
  set Bone segments = base
  subsection Segment base
    set Boundary ids = 3
    set Material ids =
  end
end
subsection Planning
  set Moved segments = base
  subsection Motion base
    set Translation = 0, 0, 0.1
  end
end
"""
# The parameter-file seed: the generated cube with every model, mutated itself.
SCENE_PRM = """subsection Scene
  set Mesh source = cube
  subsection Cube
    set Target number of tetrahedra = 2000
  end
end
subsection Material
  set Young's modulus = 3000
  set Poisson's ratio = 0.46
end
subsection Planning
  set Moved segments = bone
  subsection Motion bone
    set Translation     = 0, 0, 6
    set Rotation axis   = 0, 0, 1
    set Rotation angle  = 10
    set Rotation centre = 40, 40, 40
  end
end
subsection Models
  set Models = linear fem, nonlinear fem, mass tensor, mass spring
  subsection nonlinear fem
    set Minimum load increment = 0.01
  end
  subsection mass tensor
    set Relaxation factor = 1
    set Maximum sweeps = 5000
  end
end
"""
OUTPUT = """subsection Output
  set Output directory          = {out}
  set Write VTU                 = false
  set Write nodal displacements = true
end
"""

SEED_FILES = {
    "gmsh 4.1": ("box41.msh", SCENE_GMSH),
    "gmsh 2.2": ("box22.msh", SCENE_GMSH),
    "legacy vtk": ("box.vtk", SCENE_VTK),
    "vtu ascii": (os.path.join(ROOT, "tests", "data", "vtu", "cube6_ascii.vtu"), SCENE_VTU),
    "vtu zlib": (os.path.join(ROOT, "tests", "data", "vtu", "cube6_appended_zlib.vtu"), SCENE_VTU),
    "parameter file": (None, SCENE_PRM),
}
NUMBERS = ["0", "-1", "1e308", "-1e308", "4294967296", "2147483648", "-2147483649", "nan",
           "inf", "1e-300", "0.5", "99999999999", "3", "7", ""]
NUMBER = re.compile(rb"-?\d+(?:\.\d*)?(?:[eE][+-]?\d+)?")

# The CT seed: a patient scene reading a volume, run through `softface segment` (the CT and
# segmentation stages: what reads the volume, and what a silently wrong volume would mislead).
SCENE_CT = """subsection Scene
  set Mesh source   = patient
  set Bone segments = cranium
  subsection Segment cranium
    set Seed point = 0, -40, 30
  end
  subsection Patient
    set CT volume = {mesh}
  end
end
"""
# The phantom whose CT is the seed: 4 mm voxels, so that a case runs in a few seconds.
SCENE_PHANTOM = """subsection Scene
  set Mesh source   = patient
  set Bone segments = cranium
  subsection Segment cranium
    set Seed point = 0, -40, 30
  end
  subsection Patient
    subsection Phantom
      set Voxel size = 4
    end
  end
end
subsection Output
  set Output directory = out
end
"""
CT_SEED = "nifti ct"
VOLUME_KINDS = ("cut voxels", "cut voxels", "cut file", "nan voxels", "nan voxels", "voxel size",
                "voxel size", "size", "size", "data offset", "data type", "origin",
                "header bytes", "uncompressed")
ABSURD_FLOATS = [0.0, -1.0, math.nan, math.inf, -math.inf, 1e6, 1e-30, 150.0, 3.4e38]


def make_ct_seed(softface, timeout):
    """The phantom's CT as an uncompressed NIfTI-1 file (bytes), written by softface itself."""
    work = tempfile.mkdtemp(prefix="softface_fuzz_ct_")
    try:
        with open(os.path.join(work, "phantom.prm"), "w") as f:
            f.write(SCENE_PHANTOM)
        subprocess.run([softface, "phantom", "phantom.prm"], cwd=work, check=True,
                       stdout=subprocess.DEVNULL, timeout=timeout * 5)
        with gzip.open(os.path.join(work, "out", "patient", "ct.nii.gz")) as f:
            return f.read()
    finally:
        shutil.rmtree(work, ignore_errors=True)


def mutate_volume(nii, rng):
    """One or two mutations of an uncompressed little-endian NIfTI-1 file (header 348 bytes,
    voxels from vox_offset); returns (file name, bytes as written, description)."""
    data = bytearray(nii)
    done, compressed, cut_file = [], True, False
    offset = int(struct.unpack_from("<f", data, 108)[0])
    for _ in range(rng.choice((1, 1, 2))):
        kind = rng.choice(VOLUME_KINDS)
        if kind == "cut voxels":        # an intact gzip stream of fewer voxels
            data = data[:rng.randrange(offset, len(data))]
        elif kind == "cut file":        # the .gz itself cut short
            cut_file = True
        elif kind == "nan voxels":
            datatype = struct.unpack_from("<h", data, 70)[0]
            if datatype == 4:           # int16 to float32, the header saying so
                voxels = array.array("h", bytes(data[offset:offset + (len(data) - offset) // 2 * 2]))
                voxels = array.array("f", (float(v) for v in voxels))
                struct.pack_into("<hh", data, 70, 16, 32)
                data = data[:offset] + bytearray(voxels.tobytes())
            if struct.unpack_from("<h", data, 70)[0] == 16:
                n = (len(data) - offset) // 4
                for _ in range(rng.randint(1, 20)):
                    if n > 0:
                        struct.pack_into("<f", data, offset + 4 * rng.randrange(n),
                                         rng.choice((math.nan, math.inf, -math.inf)))
        elif kind == "voxel size":
            struct.pack_into("<f", data, 76 + 4 * rng.randint(1, 3), rng.choice(ABSURD_FLOATS))
        elif kind == "size":
            axis = rng.randint(1, 3)
            n = struct.unpack_from("<h", data, 40 + 2 * axis)[0]
            struct.pack_into("<h", data, 40 + 2 * axis,
                             rng.choice((0, -1, 1, 2, n - 1, n + 1, 2 * n, 2048, 32767)))
        elif kind == "data offset":
            struct.pack_into("<f", data, 108, rng.choice((0.0, 100.0, 348.0, 356.0, 1e9,
                                                          math.nan, -1.0)))
        elif kind == "data type":
            struct.pack_into("<h", data, 70, rng.choice((0, 1, 2, 8, 16, 64, 128, 256, 512,
                                                         768, 1024, 2048, 32767)))
        elif kind == "origin":
            struct.pack_into("<f", data, rng.choice((256, 260, 264, 268, 272, 276, 280, 296)),
                             rng.choice(ABSURD_FLOATS))
        elif kind == "header bytes":
            for _ in range(rng.randint(1, 4)):
                data[rng.randrange(348)] = rng.randrange(256)
        elif kind == "uncompressed":
            compressed = False
        done.append(kind)
    out = gzip.compress(bytes(data), mtime=0) if compressed else bytes(data)
    if cut_file:
        out = out[:rng.randrange(1, len(out))]
    return ("ct.nii.gz" if compressed else "ct.nii"), out, "+".join(done)


def mutate(data, rng):
    """One to three mutations of bytes; returns (data, description)."""
    done = []
    for _ in range(rng.choice((1, 1, 2, 3))):
        kind = rng.choice(("truncate", "flip", "move line", "delete line", "repeat line",
                           "number", "number", "number"))
        lines = data.split(b"\n")
        if kind == "truncate" and len(data) > 1:
            data = data[:rng.randrange(1, len(data))]
        elif kind == "flip" and data:
            b = bytearray(data)
            for _ in range(rng.randint(1, 8)):
                i = rng.randrange(len(b))
                b[i] = rng.randrange(256)
            data = bytes(b)
        elif kind in ("move line", "delete line", "repeat line") and len(lines) > 2:
            i = rng.randrange(len(lines))
            line = lines[i]
            if kind != "repeat line":
                del lines[i]
            lines.insert(rng.randrange(len(lines) + 1), line) if kind != "delete line" else None
            data = b"\n".join(lines)
        elif kind == "number":
            found = list(NUMBER.finditer(data))
            if found:
                m = rng.choice(found)
                data = data[:m.start()] + rng.choice(NUMBERS).encode() + data[m.end():]
        else:
            continue
        done.append(kind)
    return data, "+".join(done) or "none"


def run_case(case, softface, timeout, keep, launcher):
    """Run one mutated input in its own folder; returns the row."""
    work = tempfile.mkdtemp(prefix="softface_fuzz_")
    try:
        seed_name, mesh_file, scene = case["seed"], case["mesh"], case["scene"]
        out = os.path.join(work, "out")
        mesh_file = case.get("file", mesh_file)
        prm_text = scene.format(mesh=os.path.basename(mesh_file) if mesh_file else "") + \
            OUTPUT.format(out=out)
        if mesh_file:
            with open(os.path.join(work, os.path.basename(mesh_file)), "wb") as f:
                f.write(case["data"])
            with open(os.path.join(work, "scene.prm"), "w") as f:
                f.write(prm_text)
        else:
            # the parameter file is the mutated input; the output section stays intact
            with open(os.path.join(work, "scene.prm"), "wb") as f:
                f.write(case["data"] + b"\n" + OUTPUT.format(out=out).encode())
        t0 = time.time()
        # A session of its own, so that at the time limit every process it started can be found.
        proc = subprocess.Popen(launcher + [softface] + case.get("command", []) + ["scene.prm"],
                                cwd=work,
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                start_new_session=True)
        try:
            output, _ = proc.communicate(timeout=timeout)
            rc = proc.returncode
        except subprocess.TimeoutExpired:
            end_session(proc)
            output, _ = proc.communicate()
            rc = None
        text = output.decode("utf-8", "replace")
        seconds = time.time() - t0
        # Counted in the text, not per line: ranks' lines can share one in the merged output.
        errors = re.findall(r"softface: error[^\n]*", text)
        several = len(launcher) > 0
        if rc is None:
            outcome = "hang"
        elif rc < 0 or (several and "exited on signal" in text):
            outcome = "crash"
        elif rc == 0:
            outcome = "nan" if outputs_not_finite(out) else "ok"
        elif len(errors) == 1 or (errors and not several):
            outcome = "refused"
        else:
            outcome = "unclear"
        last = (errors[-1] if errors else (text.strip().splitlines() or [""])[-1])[:300]
        row = {"case": case["index"], "seed": seed_name, "mutation": case["mutation"],
               "outcome": outcome, "exit": "timeout" if rc is None else rc,
               "seconds": round(seconds, 2), "message": last}
        if outcome not in ("ok", "refused") and keep:
            dest = os.path.join(keep, "case%05d_%s" % (case["index"], outcome))
            shutil.rmtree(dest, ignore_errors=True)
            shutil.copytree(work, dest, ignore=shutil.ignore_patterns("out"))
            with open(os.path.join(dest, "softface.log"), "w") as f:
                f.write(text)
        return row
    finally:
        shutil.rmtree(work, ignore_errors=True)


def end_session(proc):
    """Stop a case at its time limit: mpiexec is asked first (it ends its ranks), then every
    process left in the case's session is killed. Open MPI puts each rank in a process group of
    its own, so killing mpiexec's group alone leaves them running."""
    try:
        proc.terminate()
        proc.wait(timeout=5)
    except (subprocess.TimeoutExpired, ProcessLookupError):
        pass
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open("/proc/%s/stat" % entry) as f:
                fields = f.read().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[3]) == proc.pid:  # the session id (field 6 of /proc/PID/stat)
            try:
                os.kill(int(entry), signal.SIGKILL)
            except ProcessLookupError:
                pass
    try:
        proc.kill()
    except ProcessLookupError:
        pass


def outputs_not_finite(out):
    if not os.path.isdir(out):
        return False
    for name in os.listdir(out):
        if name == "summary.csv" or name.startswith("displacements_"):
            with open(os.path.join(out, name), errors="replace") as f:
                text = f.read().lower()
            if re.search(r"(?<![a-z])(nan|inf)(?![a-z])", text):
                return True
    return False


def main(argv):
    opts = {"--softface": os.path.join(ROOT, "build", "softface"), "--cases": "300",
            "--seed": "1", "--timeout": "30", "--jobs": "2",
            "--out": os.path.join(ROOT, "doc", "results"), "--keep": "/tmp/softface_fuzz_kept",
            "--strict": None, "--binary-note": None, "--ranks": "1", "--mpiexec": "mpiexec",
            "--seeds": None}
    it = iter(argv[1:])
    for a in it:
        if a == "--strict":
            opts[a] = True
        elif a in opts:
            opts[a] = next(it)
        else:
            sys.exit(__doc__)
    softface = os.path.abspath(opts["--softface"])
    if not os.access(softface, os.X_OK):
        sys.exit("fuzz.py: %s is not an executable (build softface first)" % softface)
    ranks = int(opts["--ranks"])
    launcher = []
    if ranks > 1:
        launcher = [opts["--mpiexec"], "-n", str(ranks)]
        if ranks > (os.cpu_count() or 1):
            launcher.append("--oversubscribe")
        if os.geteuid() == 0:  # Open MPI refuses root unless told
            os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
            os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    rng = random.Random(int(opts["--seed"]))
    wanted = None if opts["--seeds"] is None else opts["--seeds"].split(",")
    all_seeds = list(SEED_FILES) + ([CT_SEED] if ranks == 1 else [])
    if wanted and any(w not in all_seeds for w in wanted):
        sys.exit("fuzz.py: --seeds: the seeds are %s" % ", ".join(all_seeds))
    seeds = {}
    for name, (mesh, scene) in SEED_FILES.items():
        if wanted and name not in wanted:
            continue
        path = mesh if mesh is None or os.path.isabs(mesh) else os.path.join(SEEDS, mesh)
        data = open(path, "rb").read() if path else scene.encode()
        seeds[name] = (path, scene, data)
    # The stages that read a CT run on one rank only (softface refuses more).
    if ranks == 1 and (not wanted or CT_SEED in wanted):
        seeds[CT_SEED] = ("ct.nii.gz", SCENE_CT, make_ct_seed(softface, float(opts["--timeout"])))

    def case_of(i, name, data, how):
        case = {"index": i, "seed": name, "mesh": seeds[name][0], "scene": seeds[name][1],
                "data": data, "mutation": how}
        if name == CT_SEED:
            if how.startswith("none"):
                case["data"] = gzip.compress(data, mtime=0)
            else:
                case["file"], case["data"], case["mutation"] = mutate_volume(data, rng)
            case["command"] = ["segment"]
        return case

    # The seeds unchanged first: each must run (else the fuzzer tests nothing).
    cases = [case_of(i, name, seeds[name][2], "none (the seed)") for i, name in enumerate(seeds)]
    names = list(seeds)
    for i in range(len(cases), int(opts["--cases"])):
        name = names[i % len(names)]
        if name == CT_SEED:
            cases.append(case_of(i, name, seeds[name][2], "volume"))
        else:
            data, how = mutate(seeds[name][2], rng)
            cases.append(case_of(i, name, data, how))
    keep = opts["--keep"]
    if keep:
        os.makedirs(keep, exist_ok=True)
    t0 = time.time()
    rows = []
    with ThreadPoolExecutor(max_workers=int(opts["--jobs"])) as pool:
        futures = [pool.submit(run_case, c, softface, float(opts["--timeout"]), keep, launcher)
                   for c in cases]
        for k, fut in enumerate(futures):
            row = fut.result()
            rows.append(row)
            if row["outcome"] not in ("ok", "refused") or (k + 1) % 50 == 0:
                print("[%d/%d, %.0f s] case %d (%s, %s): %s %s" % (
                    k + 1, len(cases), time.time() - t0, row["case"], row["seed"],
                    row["mutation"], row["outcome"], row["message"][:120]), flush=True)
    bad_seeds = [r for r in rows[:len(seeds)] if r["outcome"] != "ok"]
    write_results(opts, rows, time.time() - t0, softface)
    if bad_seeds:
        print("fuzz.py: a seed does not run cleanly: %s" % bad_seeds, file=sys.stderr)
        return 1
    bad = [r for r in rows if r["outcome"] in ("crash", "hang", "nan", "unclear")]
    return 1 if opts["--strict"] and bad else 0


def write_results(opts, rows, seconds, softface):
    out = opts["--out"]
    os.makedirs(out, exist_ok=True)
    keys = ["case", "seed", "mutation", "outcome", "exit", "seconds", "message"]
    with open(os.path.join(out, "robustness.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    outcomes = ["ok", "refused", "unclear", "nan", "crash", "hang"]
    seeds = list(dict.fromkeys(r["seed"] for r in rows))
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    md = ["# Robustness: softface on mutated inputs", "",
          "What damaged input files and parameters do to softface: whether every one ends "
          "in a result or in one clear error message, never in a crash, a hang, an unclear "
          "exit or nan/inf in the outputs.", "",
          "Reproduce: `/usr/bin/python3 benchmarks/robustness/fuzz.py --cases %s --seed %s "
          "--timeout %s --jobs %s%s` (%d cases in %.0f s)." % (
              opts["--cases"], opts["--seed"], opts["--timeout"], opts["--jobs"],
              "" if opts["--ranks"] == "1" else " --ranks " + opts["--ranks"],
              len(rows), seconds), "",
          "Measured at commit %s%s on %d cores." % (
              commit, " (%s)" % opts["--binary-note"] if opts["--binary-note"] else "",
              os.cpu_count()), "",
          "Outcomes: **ok** exit 0 with finite outputs; **refused** exit 1 with one "
          "`softface: error:` line; **unclear** non-zero exit without it; **nan** exit 0 with "
          "nan/inf in the outputs; **crash** a signal; **hang** over the time limit. The first "
          "case of each seed is the seed unchanged. Data: `robustness.csv`.", "",
          "| seed | cases | " + " | ".join(outcomes) + " |",
          "|---|---|" + "---|" * len(outcomes)]
    for s in seeds + ["all"]:
        sel = [r for r in rows if s == "all" or r["seed"] == s]
        md.append("| %s | %d | %s |" % (s, len(sel), " | ".join(
            str(sum(r["outcome"] == o for r in sel)) for o in outcomes)))
    bad = [r for r in rows if r["outcome"] not in ("ok", "refused")]
    md += ["", "![outcome by seed input](robustness.png)", "",
           "## What the numbers show", "",
           "- Of %d damaged inputs, %s." % (
               len(rows), "none crashes, hangs, ends without softface's one-line message, or "
               "writes nan/inf with exit code 0" if not bad else
               "%d end otherwise than ok or refused (listed below)" % len(bad)),
           "- A 120-case sample of the same cases runs in the test suite (`fuzz_sample`, 72 s); under "
           "`./test.sh --sanitize` (ASan + UBSan) it and the 62 bad inputs pass (430 s).",
           ""]
    # A comparison written by hand (the same cases on another build) stays.
    path = os.path.join(out, "robustness.md")
    kept_heading = "## The same cases with deal.II's readers"
    if os.path.exists(path):
        old = open(path).read()
        if kept_heading in old:
            kept = old[old.index(kept_heading):]
            end = kept.find("\n## Every case that did not end ok or refused")
            md += [kept[:end if end >= 0 else len(kept)].rstrip("\n"), ""]
    md += ["## Every case that did not end ok or refused", "",
           "| case | seed | mutation | outcome | exit | message (last line) |",
           "|---|---|---|---|---|---|"]
    for r in rows:
        if r["outcome"] not in ("ok", "refused"):
            md.append("| %d | %s | %s | %s | %s | %s |" % (
                r["case"], r["seed"], r["mutation"], r["outcome"], r["exit"],
                r["message"].replace("|", "/")[:200]))
    with open(os.path.join(out, "robustness.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(9, 4))
    left = [0] * len(seeds)
    colours = {"ok": "#4c9a2a", "refused": "#9ecae1", "unclear": "#fdae6b", "nan": "#e6550d",
               "crash": "#a50f15", "hang": "#54278f"}
    for o in outcomes:
        vals = [sum(r["outcome"] == o for r in rows if r["seed"] == s) for s in seeds]
        ax.barh(seeds, vals, left=left, color=colours[o], label=o)
        left = [a + b for a, b in zip(left, vals)]
    ax.set_xlabel("cases")
    ax.set_title("softface on mutated inputs: outcome by seed")
    ax.legend(loc="lower right", fontsize=8)
    ax.invert_yaxis()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "robustness.png"), dpi=110)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
