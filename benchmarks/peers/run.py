#!/usr/bin/python3
"""Peer benchmark driver: softface `linear fem` (cg amg) and `nonlinear fem` (St. Venant-Kirchhoff)
against FEniCSx (dolfinx) and CalculiX on the same gmsh cube meshes. Called by run.sh (see
README.md).

usage: run.py --softface BIN --work DIR --results DIR --command "..." [--quick] [--passes ...]

A pass is a law (linear, svk) on one thread or on all cores (softface's threads, FEniCSx's MPI
ranks, CalculiX's threads). For each pass, mesh and repetition it runs each program once
(interleaved: rep 1 of every program, then rep 2, ...), every run its own process under
/usr/bin/time (peak RSS). After the first repetition of a mesh it compares every vertex
displacement with softface's and stops with a non-zero exit if a peer differs by more than TOL_MM.
Writes peers.md, peers.csv, peers.png.
"""
import argparse, csv, datetime, json, os, platform, re, statistics, subprocess, sys, time
import numpy as np
from scipy.spatial import cKDTree
from scene import cube_scene

HERE = os.path.dirname(os.path.abspath(__file__))
PY = "/usr/bin/python3"                    # Debian's python3 with dolfinx, gmsh, scipy, matplotlib
TOL_MM = 1e-4
# (label, mesh file, make_mesh.py H, run CalculiX?)  CalculiX took ~164 s at 491k: skipped there.
MESHES = [("35k", "cube_h4.3.msh", 4.3, True), ("105k", "cube_h2.88.msh", 2.88, True),
          ("491k", "cube_h1.68.msh", 1.68, False)]
PROGRAMS = ["softface", "FEniCSx", "CalculiX"]
# Table columns: (title, phases summed into it). softface's "eliminate join DoFs" (its Dirichlet
# step) goes with assembly because dolfinx applies its conditions during assembly.
COLUMNS = [("mesh read", ["mesh read"]),
           ("sparsity + assembly", ["sparsity", "assemble", "eliminate join DoFs"]),
           ("preconditioner", ["preconditioner"]), ("solve", ["solve"])]
CORES = os.cpu_count()
# Passes: (law, cores); 1 is one thread, CORES every core of the machine.
PASSES = {"linear": ("linear", 1), "linear-all": ("linear", CORES), "svk": ("svk", 1),
          "svk-all": ("svk", CORES)}


def environment(cores):
    """One thread per process, or CORES threads (softface, CalculiX); FEniCSx runs one MPI rank
    per core instead, each with one thread."""
    n = str(cores)
    return dict(os.environ, OMP_NUM_THREADS=n, OPENBLAS_NUM_THREADS="1", DEAL_II_NUM_THREADS=n,
                CCX_NPROC_EQUATION_SOLVER=n, CCX_NPROC_STIFFNESS=n, CCX_NPROC_RESULTS=n)


ENV = environment(1)

MODELS = {"linear": """  set Models = linear fem
  subsection linear fem
    set Solver = cg amg
    set Relative tolerance = 1e-10
  end
""", "svk": """  set Models = nonlinear fem
  subsection nonlinear fem
    set Material law = st venant-kirchhoff
    set Solver = cg amg
    set Residual tolerance = 1e-10
  end
"""}
MODEL_NAME = {"linear": "linear_fem", "svk": "nonlinear_fem"}


class RunFailed(Exception):
    """A program did not reach the answer (St. Venant-Kirchhoff may have no equilibrium on the
    way): the mesh is left out of that law's passes and the report says why."""


def timed(cmd, cwd, log, env=ENV, check=True):
    """Run cmd under /usr/bin/time; return (wall s, peak RSS MB, CPU s, stdout). With check, a
    non-zero exit ends the driver; without, the caller judges the outputs."""
    tf = os.path.join(cwd, "time.txt")
    t0 = time.perf_counter()
    r = subprocess.run(["/usr/bin/time", "-f", "%M %U %S", "-o", tf] + cmd, cwd=cwd, env=env,
                       capture_output=True, text=True)
    wall = time.perf_counter() - t0
    open(os.path.join(cwd, log), "w").write(r.stdout + r.stderr)
    if r.returncode != 0 and check:
        sys.exit(f"FAILED ({r.returncode}): {' '.join(cmd)} in {cwd}\n{r.stdout[-2000:]}{r.stderr[-2000:]}")
    rss, usr, sys_ = open(tf).read().split()[-3:]
    return wall, int(rss) / 1024, float(usr) + float(sys_), r.stdout


def run_softface(binary, mesh, d, law="linear", cores=1):
    os.makedirs(d, exist_ok=True)
    open(os.path.join(d, "scene.prm"), "w").write(cube_scene(os.path.join(d, "out"), mesh=mesh, models=MODELS[law],
                   output="  set Write nodal displacements = true\n"))
    # softface exits 1 when its model fails and says why in summary.csv; anything else ends the
    # driver.
    wall, rss, cpu, out = timed([binary, "scene.prm"], d, "softface.log", environment(cores),
                                check=False)
    summary_csv = os.path.join(d, "out", "summary.csv")
    row = next(csv.DictReader(open(summary_csv)), None) if os.path.exists(summary_csv) else None
    if row is None:
        sys.exit(f"softface wrote no summary in {d} (log: {os.path.join(d, 'softface.log')})")
    if row["status"] != "ok":
        raise RunFailed(f"softface: {row['error']}")
    ph = {"mesh read": float(re.search(r"free DoFs \(([\d.]+) s\)", out).group(1))}
    for kv in row["phases"].split(";"):
        k, v = kv.split("=")
        ph[k] = float(v)
    ph["model"] = float(row["setup_s"]) + float(row["solve_s"])
    # The nonlinear model's iterations column counts Newton iterations; its details hold the
    # linear ones (the linear model's column counts CG iterations).
    details = dict(kv.split("=", 1) for kv in row["details"].split(";") if "=" in kv)
    its, newton = int(row["iterations"]), None
    if law == "svk":
        its, newton = int(details["linear iterations"]), its
    return dict(phases=ph, wall=wall, rss=rss, cpu=cpu, iterations=its, newton=newton,
                residual=float(row["relative_residual"]),
                csv=os.path.join(d, "out", f"displacements_{MODEL_NAME[law]}.csv"))


def run_fenicsx(mesh, d, law="linear", cores=1):
    os.makedirs(d, exist_ok=True)
    cmd = [PY, os.path.join(HERE, "fenicsx_elasticity.py"), mesh, "u.csv", "--law", law]
    if cores > 1:
        cmd = ["mpirun", "-np", str(cores)] + (["--allow-run-as-root"] if os.geteuid() == 0 else []) + cmd
    wall, rss, cpu, out = timed(cmd, d, "fenicsx.log", environment(1), check=(law != "svk"))
    log = open(os.path.join(d, "fenicsx.log")).read()
    if "did not converge" in log.lower() and not out.strip().startswith("{"):
        raise RunFailed("FEniCSx: dolfinx's Newton solver did not converge")
    j = json.loads(out.strip().splitlines()[-1])
    ph = dict(j["phases"])
    # The model: everything between reading the mesh and writing the answer, except the force
    # that only the benchmark's common stop criterion needs (softface has it at hand).
    ph["model"] = sum(v for k, v in j["phases"].items()
                      if k not in ("import", "mesh read", "write", "in-process total",
                                   "reference force"))
    if law == "svk" and not j["converged_reason"]:
        raise RunFailed("FEniCSx: dolfinx's Newton solver did not converge")
    if cores > 1:
        rss = j["peak_mb_all_ranks"]          # /usr/bin/time sees only the largest rank
    return dict(phases=ph, wall=wall, rss=rss, cpu=cpu, iterations=j["iterations"],
                newton=j["newton_iterations"], residual=j["relative_residual"],
                csv=os.path.join(d, "u.csv"))


def run_calculix(case_dir, d, cores=1):
    """ccx on the prepared case.inp (copied to d so the repetitions do not share files)."""
    os.makedirs(d, exist_ok=True)
    for f in ("case.inp", "nodes.npy"):
        subprocess.run(["cp", os.path.join(case_dir, f), d], check=True)
    wall, rss, cpu, out = timed(["ccx", "-i", "case"], d, "ccx.log", environment(cores), check=False)
    if "Job finished" not in out or "*ERROR" in out:
        raise RunFailed(f"CalculiX: no answer (see {os.path.join(d, 'ccx.log')})")
    ccx_total = float(re.search(r"Total CalculiX Time:\s*([\d.eE+-]+)", out).group(1))
    subprocess.run([PY, os.path.join(HERE, "calculix_case.py"), "collect", d, os.path.join(d, "u.csv")],
                   check=True, capture_output=True)
    for ext in ("frd", "dat", "inp"):          # large; the CSV holds what is needed
        os.remove(os.path.join(d, "case." + ext))
    return dict(phases={"ccx total (own timer)": ccx_total}, wall=wall, rss=rss, cpu=cpu,
                iterations=None, newton=None, residual=None, csv=os.path.join(d, "u.csv"))


def max_diff(ref_csv, peer_csv):
    """max |u_ref - u_peer| over vertices matched by coordinates (KD-tree, must match exactly)."""
    a = np.loadtxt(ref_csv, delimiter=",", skiprows=1)
    b = np.loadtxt(peer_csv, delimiter=",", skiprows=1)
    dist, i = cKDTree(b[:, :3]).query(a[:, :3])
    assert len(a) == len(b) and dist.max() < 1e-6, (len(a), len(b), dist.max())
    return float(np.abs(a[:, 3:] - b[i, 3:]).max())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--softface", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--results", required=True)
    ap.add_argument("--command", default="benchmarks/peers/run.sh")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--passes", default=",".join(PASSES),
                    help="comma-separated, of " + ", ".join(PASSES) + " (default: all)")
    args = ap.parse_args()
    passes = args.passes.split(",")
    unknown = [p for p in passes if p not in PASSES]
    if unknown or "linear" not in passes:
        sys.exit(f"--passes: unknown {unknown} or no 'linear' (known: {', '.join(PASSES)})")
    meshes = MESHES[:1] if args.quick else MESHES
    reps = 1 if args.quick else args.reps
    W = args.work
    os.makedirs(args.results, exist_ok=True)

    # Untimed warm-up on the smallest mesh: fills the FFCx JIT cache (the first dolfinx run compiles
    # the forms, ~1 s) and the page cache for all three programs' binaries and libraries.
    m0 = os.path.join(W, meshes[0][1])
    print("warm-up on", meshes[0][1], flush=True)
    for law in sorted({PASSES[p][0] for p in passes}):
        for warm in (lambda: run_softface(args.softface, m0, os.path.join(W, "warmup", "softface"), law),
                     lambda: run_fenicsx(m0, os.path.join(W, "warmup", "fenicsx"), law)):
            try:
                warm()
            except RunFailed:                  # it only fills caches; the passes will say
                pass

    # softface's fixed cost of a process: start it on a scene file that does not exist (it exits
    # with an error after loading its libraries); median of 3.
    startup, startup_mb, tf = [], [], os.path.join(W, "startup_time.txt")
    for _ in range(3):
        t0 = time.perf_counter()
        subprocess.run(["/usr/bin/time", "-f", "%M", "-o", tf, args.softface, os.path.join(W, "no-such-scene.prm")],
                       env=ENV, capture_output=True)
        startup.append(time.perf_counter() - t0)
        startup_mb.append(int(open(tf).read().split()[-1]) / 1024)

    rows, runs, diffs, prepared = [], {}, {}, set()
    failed = {}                                # (law, mesh label): why it is not compared
    info = {"startup": statistics.median(startup), "startup_mb": statistics.median(startup_mb)}
    t_start = time.time()
    for name in passes:
        law, cores = PASSES[name]
        for label, fname, _, with_ccx in meshes:
            if (law, label) in failed:             # a program failed on it in this law's other pass
                continue
            mesh = os.path.join(W, fname)
            progs = PROGRAMS if with_ccx else PROGRAMS[:2]
            case = os.path.join(W, label, f"calculix_case_{law}")
            if with_ccx and case not in prepared:   # once per law and mesh in this run
                subprocess.run([PY, os.path.join(HERE, "calculix_case.py"), "prepare", mesh, case]
                               + (["--nlgeom"] if law == "svk" else []),
                               check=True, capture_output=True, text=True)
                prepared.add(case)
            for rep in range(1, reps + 1):
                for prog in progs:
                    d = os.path.join(W, label, name, prog, f"rep{rep}")
                    load = open("/proc/loadavg").read().split()[0]
                    print(f"[{time.time() - t_start:6.0f} s] {name} {label} rep {rep} {prog} (load {load})",
                          flush=True)
                    try:
                        r = (run_softface(args.softface, mesh, d, law, cores) if prog == "softface" else
                             run_fenicsx(mesh, d, law, cores) if prog == "FEniCSx" else
                             run_calculix(case, d, cores))
                    except RunFailed as error:
                        if law != "svk":               # linear elasticity must always agree
                            sys.exit(f"{label} ({name}): {error}")
                        # The other programs still run once, so the report says whether they
                        # reach the answer.
                        failed.setdefault((law, label), []).append(f"{error} ({name}, repetition {rep})")
                        print(f"    {error}", flush=True)
                        continue
                    r["load"] = float(load)
                    runs[(name, label, prog, rep)] = r
                    print(f"    whole process {r['wall']:.2f} s, peak {r['rss']:.0f} MB, CPU {r['cpu']:.2f} s, "
                          f"iterations {r['iterations']}" +
                          (f", Newton {r['newton']}" if r.get("newton") else ""), flush=True)
                if (law, label) in failed:
                    reached = [f"{p} ({runs[(name, label, p, rep)]['wall']:.1f} s)" for p in progs
                               if (name, label, p, rep) in runs]
                    failed[(law, label)].append("reached the answer: " + (", ".join(reached) or "none"))
                    print(f"    not compared on {label}: {'; '.join(failed[(law, label)])}", flush=True)
                    break
                if rep == 1:                       # agreement check on the first repetition
                    for prog in progs[1:]:
                        dmax = max_diff(runs[(name, label, "softface", 1)]["csv"],
                                        runs[(name, label, prog, 1)]["csv"])
                        diffs[(name, label, prog)] = dmax
                        print(f"    max |u_softface - u_{prog}| = {dmax:.2e} mm", flush=True)
                        if not dmax <= TOL_MM:
                            sys.exit(f"DISAGREEMENT on {label} ({name}): {prog} differs from softface by "
                                     f"{dmax:.3e} mm > {TOL_MM} mm")
            if label not in info:
                import gmsh                        # mesh size for the report
                gmsh.initialize(); gmsh.option.setNumber("General.Terminal", 0); gmsh.open(mesh)
                info[label] = {}
                info[label]["n_tets"] = int(sum(len(t) for t in gmsh.model.mesh.getElements(3)[1]))
                info[label]["n_nodes"] = int(len(np.unique(gmsh.model.mesh.getElements(3)[2][0])))  # used nodes
                gmsh.finalize()
    elapsed = time.time() - t_start
    # A mesh on which a program failed is compared in neither pass of that law.
    for key in [k for k in runs if (PASSES[k[0]][0], k[1]) in failed]:
        del runs[key]
    for key in [k for k in diffs if (PASSES[k[0]][0], k[1]) in failed]:
        del diffs[key]

    for (name, label, prog, rep), r in runs.items():
        law, cores = PASSES[name]
        base = dict(program=prog, law=law, cores=cores, mesh=label, n_tets=info[label]["n_tets"],
                    n_vertices=info[label]["n_nodes"], rep=rep, load1=r["load"],
                    iterations=r["iterations"], newton_iterations=r.get("newton") or "",
                    peak_mb=round(r["rss"], 1),
                    max_diff_to_softface_mm=diffs.get((name, label, prog), 0.0 if prog == "softface" else ""))
        for ph, v in list(r["phases"].items()) + [("whole process", r["wall"]), ("cpu user+sys", r["cpu"])]:
            rows.append(dict(base, phase=ph, seconds=round(v, 4)))
    with open(os.path.join(args.results, "peers.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    one = {(l, p, k): r for (n, l, p, k), r in runs.items() if n == "linear"}
    one_diffs = {(l, p): d for (n, l, p), d in diffs.items() if n == "linear"}
    report(args, meshes, reps, one, one_diffs, info, elapsed, passes, runs, diffs, failed)
    plot(args, meshes, reps, one, passes, runs, failed)


def col(r, phases):
    """Sum of the given phases of one run, None if the program does not report any of them."""
    v = [r["phases"][p] for p in phases if p in r["phases"]]
    return sum(v) if v else None


def stats(runs, label, prog, reps, f):
    vals = [f(runs[(label, prog, k)]) for k in range(1, reps + 1)]
    return None if vals[0] is None else (min(vals), statistics.median(vals))


def report(args, meshes, reps, runs, diffs, info, elapsed, passes, all_runs, all_diffs, failed):
    cpu = next(l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name"))
    # The log holds stdout and then stderr (FFCx's JIT messages on a first run): the JSON line.
    fx = json.loads(next(line for line in reversed(open(os.path.join(
        args.work, "warmup", "fenicsx", "fenicsx.log")).read().splitlines()) if line.startswith("{")))
    ccxv = subprocess.run(["ccx", "-v"], capture_output=True, text=True).stdout.strip().splitlines()[-1].replace("This is ", "")
    git = subprocess.run(["git", "-C", HERE, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    # The results this run writes do not count as changes to what it ran.
    dirty = subprocess.run(["git", "-C", HERE, "status", "--porcelain", "--untracked-files=no", "--",
                            "../..", ":!../../doc/results"],
                           capture_output=True, text=True).stdout.strip()
    loads = [r["load"] for r in all_runs.values()]
    shared = max(loads) > 1.5
    L = ["# softface against FEniCSx and CalculiX: linear elasticity and St. Venant-Kirchhoff on the same meshes\n",
         "How softface's whole process and each phase compare with FEniCSx and CalculiX on the same gmsh meshes, "
         "for linear elasticity and St. Venant-Kirchhoff, on one thread and on every core (target: softface "
         "`cg amg` at least 2x faster than FEniCSx on one rank at 100k and 500k tetrahedra).\n",
         f"Reproduce: `{args.command.strip()}` ({elapsed / 60:.1f} min).\n",
         f"Measured at commit {git}{' with uncommitted changes' if dirty else ''} on {cpu}, {os.cpu_count()} cores, "
         f"{platform.system()} {platform.release()}; "
         f"FEniCSx: dolfinx {fx['dolfinx']} with PETSc {fx['petsc']} (Debian); CalculiX: {ccxv} (Debian), SPOOLES.\n",
         (f"**The machine was shared**: the 1-minute load average before the runs reached {max(loads):.1f} "
          f"on {CORES} cores, so absolute times are noisy. " if shared else
          f"The 1-minute load average before the runs: {min(loads):.2f} to {max(loads):.2f} on {CORES} cores "
          "(the machine was otherwise idle). ") +
         "The load before each run is in peers.csv, column `load1`. Ratios measured in the same interleaved run "
         "are more robust than absolute figures.\n",
         "Contents: linear elasticity on one thread (per phase), then on all cores, then St. Venant-Kirchhoff "
         "(nonlinear) on one thread and on all cores.\n",
         "## Problem and method (linear elasticity on one thread)\n",
         "The cube of `make_mesh.py`: box [0,80]^3 mm, inner box [35,45]^3 mm meshed conformingly; P1 tetrahedra, "
         "E = 3000, Poisson's ratio 0.46; u = 0 on every vertex of the six outer faces, u = (0, 0, 6) mm on every "
         "vertex of the inner box's cells. softface and FEniCSx: CG with algebraic multigrid (softface: Trilinos ML "
         "through deal.II; FEniCSx: hypre BoomerAMG with the settings in fenicsx_elasticity.py and the rigid-body "
         "near-nullspace; FEniCSx's times depend on these options, see benchmarks/peers/README.md), relative "
         "tolerance 1e-10. CalculiX: linear static, C3D4, SPOOLES direct solver; "
         "each CG tests the unpreconditioned residual; "
         f"**CalculiX only on the 35k and 105k meshes** (about 164 s at 491k on this machine). "
         f"{reps} repetition(s), interleaved (repetition 1 of every program, then 2, ...), each run a separate "
         "process with one thread (OMP_NUM_THREADS=1, CCX_NPROC_*=1, OPENBLAS_NUM_THREADS=1, FEniCSx one MPI "
         "rank; the other passes are described in their sections); an untimed warm-up "
         "run of softface and FEniCSx on the 35k mesh first (fills FFCx's JIT cache). Whole process = wall time of "
         "the process measured by the driver; peak memory = maximum RSS from `/usr/bin/time -f %M`; phases are "
         "each program's own timers.\n",
         "Column mapping: softface's *mesh read* is the time on its `mesh` line, *sparsity + assembly* = sparsity + "
         "assemble + eliminate join DoFs (its Dirichlet step); FEniCSx's *mesh read* = gmsh open + "
         "`gmshio.model_to_mesh`, *sparsity + assembly* = `create_matrix` + matrix and right-hand-side assembly "
         "with the Dirichlet conditions (lifting, set_bc), *preconditioner* = `ksp.setUp()`. *rest* = whole process "
         "minus those four (process start, Python imports for FEniCSx, output writing, ...). CalculiX reports no "
         "phases; only its whole process (and its own total timer in peers.csv).\n",
         "Cells are **min / median** over the repetitions; ratio rows are peer median / softface median.\n"]
    for label, fname, _, with_ccx in meshes:
        progs = PROGRAMS if with_ccx else PROGRAMS[:2]
        n = info[label]
        L.append(f"## {label}: {n['n_tets']} tetrahedra, {n['n_nodes']} vertices (`{fname}`)\n")
        heads = [c[0] for c in COLUMNS] + ["rest", "whole process"]
        L.append("| program | " + " | ".join(h + " s" for h in heads) +
                 " | CG iterations | peak MB | max \\|u - u_softface\\| mm |")
        L.append("|---" * (len(heads) + 4) + "|")
        fns = [lambda r, ps=ps: col(r, ps) for _, ps in COLUMNS]
        fns.append(lambda r: None if col(r, ["solve"]) is None else
                   r["wall"] - sum(col(r, ps) or 0 for _, ps in COLUMNS))
        fns.append(lambda r: r["wall"])
        fns.append(lambda r: r["rss"])
        med = {}
        for prog in progs:
            cells = []
            for i, f in enumerate(fns):
                s = stats(runs, label, prog, reps, f)
                med[(prog, i)] = s[1] if s else None
                cells.append("—" if s is None else (f"{s[0]:.0f} / {s[1]:.0f}" if i == len(fns) - 1
                                                    else f"{s[0]:.2f} / {s[1]:.2f}"))
            its = sorted({runs[(label, prog, k)]["iterations"] for k in range(1, reps + 1)} - {None})
            dm = diffs.get((label, prog))
            cells = cells[:-1] + [", ".join(map(str, its)) or "— (direct)", cells[-1],
                                  "(reference)" if prog == "softface" else f"{dm:.1e}"]
            L.append(f"| {prog} | " + " | ".join(cells) + " |")
        for prog in progs[1:]:
            rat = [("—" if med[(prog, i)] is None or not med[("softface", i)] else
                    f"{med[(prog, i)] / med[('softface', i)]:.2f}x") for i in range(len(fns))]
            L.append(f"| *{prog} / softface* | " + " | ".join(rat[:-1]) + " | | " + rat[-1] + " | |")
        L.append("")
    L.append("![phases per program and mesh; whole process of every pass](peers.png)\n")
    L.append("## What the numbers show (linear, one thread)\n")
    L += summary(meshes, reps, runs, diffs, info)
    L += more_passes(meshes, reps, passes, all_runs, all_diffs, failed)
    # What the St. Venant-Kirchhoff passes show, written by hand, stays (re-read it against
    # the new figures).
    heading = "## What the numbers show (St. Venant-Kirchhoff)"
    old_path = os.path.join(args.results, "peers.md")
    if os.path.exists(old_path):
        old = open(old_path).read()
        if heading in old:
            kept = old[old.index(heading):]
            kept = kept[:kept.index("\nFiles: ")] if "\nFiles: " in kept else kept
            L.append(kept.rstrip("\n") + "\n")
    L.append("Files: peers.csv (one row per pass, program, mesh, repetition and phase, with load average, "
             "iterations, peak memory and the agreement), peers.png (top: median phases stacked per program and "
             "mesh, linear on one thread; bottom: whole process of every pass).\n")
    open(os.path.join(args.results, "peers.md"), "w").write("\n".join(L))


def median_of(runs, key, reps, f):
    return statistics.median(f(runs[key + (k,)]) for k in range(1, reps + 1))


def more_passes(meshes, reps, passes, runs, diffs, failed):
    """The sections of the passes beyond linear on one thread; a mesh on which a program failed
    is named with the reason instead of compared."""
    L = []
    not_compared = lambda law, label: (
        f"| {label} | **not compared**: {'; '.join(failed[(law, label)])} |" if (law, label) in failed
        else None)
    wall = lambda r: r["wall"]
    def all_cores(law, title):
        if f"{law}-all" not in passes:
            return []
        L = []
        one = law if law in passes else None
        L += [f"## {title} on all {CORES} cores\n",
              f"softface on {CORES} threads (`DEAL_II_NUM_THREADS={CORES}`: threaded assembly and vector "
              f"operations; ML and AztecOO stay on one), FEniCSx on {CORES} MPI ranks (`mpirun -np {CORES}`, "
              f"the mesh partitioned by dolfinx), CalculiX with {CORES} threads (`OMP_NUM_THREADS`, "
              "`CCX_NPROC_*`). Whole process, min / median of the repetitions; *speed-up* = one thread / all "
              "cores (median).\n",
              "| mesh | program | one thread s | all cores s | speed-up | all cores: peer / softface | "
              "max \\|u - u_softface\\| mm |", "|---|---|---:|---:|---:|---:|---:|"]
        for label, _, _, with_ccx in meshes:
            if not_compared(law, label):
                L.append(not_compared(law, label) + " | | | | |")
                continue
            progs = PROGRAMS if with_ccx else PROGRAMS[:2]
            sf = median_of(runs, (f"{law}-all", label, "softface"), reps, wall)
            for prog in progs:
                vals = [runs[(f"{law}-all", label, prog, k)]["wall"] for k in range(1, reps + 1)]
                m = statistics.median(vals)
                m1 = median_of(runs, (one, label, prog), reps, wall) if one else None
                dm = diffs.get((f"{law}-all", label, prog))
                L.append(f"| {label} | {prog} | {f'{m1:.2f}' if m1 else '—'} | {min(vals):.2f} / {m:.2f} | "
                         f"{f'{m1 / m:.2f}' if m1 else '—'} | "
                         f"{'—' if prog == 'softface' else f'{m / sf:.2f}x'} | "
                         f"{'(reference)' if prog == 'softface' else f'{dm:.1e}'} |")
        L.append("")
        return L

    L += all_cores("linear", "Linear elasticity")
    if "svk" in passes:
        L += ["## St. Venant-Kirchhoff on one thread\n",
              "The same cube and lift with CalculiX's material (*ELASTIC with NLGEOM) in all three: softface's "
              "`nonlinear fem` (`Material law = st venant-kirchhoff`, `cg amg`, Newton with line search from one "
              "load step, residual tolerance 1e-10 of the unbalanced force its tangent predictor balances, CG to 1e-6); FEniCSx: "
              "dolfinx's Newton solver (full steps) from u = 0, whose first iteration is the same linear predictor, "
              "with the same stop, each step CG + BoomerAMG to 1e-6; CalculiX: NLGEOM with its automatic incrementation from a tenth of the load, residual "
              "and correction tolerances 1e-9, SPOOLES. *model* = the program's own time between reading the "
              "mesh and writing the answer (softface: setup + solve; FEniCSx: forms, conditions, Newton); "
              "*rest* = whole process minus mesh read and model. Min / median of the repetitions.\n",
              "| mesh | program | mesh read s | model s | rest s | whole process s | Newton iterations | "
              "linear iterations | peak MB | max \\|u - u_softface\\| mm |",
              "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
        fns = [lambda r: r["phases"].get("mesh read"), lambda r: r["phases"].get("model"),
               lambda r: (None if "model" not in r["phases"] else
                          r["wall"] - r["phases"]["model"] - r["phases"]["mesh read"]),
               lambda r: r["wall"]]
        for label, _, _, with_ccx in meshes:
            if not_compared("svk", label):
                L.append(not_compared("svk", label) + " | | | | | | | |")
                continue
            progs = PROGRAMS if with_ccx else PROGRAMS[:2]
            for prog in progs:
                rs = [runs[("svk", label, prog, k)] for k in range(1, reps + 1)]
                cells = []
                for f in fns:
                    v = [f(r) for r in rs]
                    cells.append("—" if v[0] is None else f"{min(v):.2f} / {statistics.median(v):.2f}")
                newton = sorted({r["newton"] for r in rs} - {None})
                its = sorted({r["iterations"] for r in rs} - {None})
                dm = diffs.get(("svk", label, prog))
                cells += [", ".join(map(str, newton)) or "—", ", ".join(map(str, its)) or "— (direct)",
                          f"{statistics.median(r['rss'] for r in rs):.0f}",
                          "(reference)" if prog == "softface" else f"{dm:.1e}"]
                L.append(f"| {label} | {prog} | " + " | ".join(cells) + " |")
            sf = median_of(runs, ("svk", label, "softface"), reps, wall)
            L.append(f"| {label} | *whole process, peer / softface* | | | | " +
                     ", ".join(f"{p} {median_of(runs, ('svk', label, p), reps, wall) / sf:.2f}x"
                               for p in progs[1:]) + " | | | | |")
        checks = [(label, median_of(runs, ("svk", label, "softface"), reps,
                                    lambda r: r["phases"].get("stability checks", 0.0)),
                   median_of(runs, ("svk", label, "softface"), reps, lambda r: r["phases"]["model"]))
                  for label, *_ in meshes if ("svk", label) not in failed]
        L += ["", "softface tests every St. Venant-Kirchhoff equilibrium for stability (a Cholesky "
              "factorisation of the tangent per load step, since CG may pass an indefinite tangent unnoticed); "
              "the peers do not. Its share of softface's model time (median): " +
              "; ".join(f"{l}: {c:.2f} s of {m:.2f} s" for l, c, m in checks) + "."]
        L.append("")
    L += all_cores("svk", "St. Venant-Kirchhoff")
    return L


def summary(meshes, reps, runs, diffs, info):
    """The report's findings, worded from the measured medians only."""
    med = lambda label, prog, f: statistics.median(f(runs[(label, prog, k)]) for k in range(1, reps + 1))
    wall = lambda r: r["wall"]
    out = []
    for label, _, _, with_ccx in meshes:
        sf, fx = med(label, "softface", wall), med(label, "FEniCSx", wall)
        t = (f"- **{label}**: whole process (median) softface {sf:.2f} s, FEniCSx {fx:.2f} s "
             f"(FEniCSx / softface = {fx / sf:.2f}x)")
        if with_ccx:
            cx = med(label, "CalculiX", wall)
            t += f", CalculiX {cx:.2f} s ({cx / sf:.2f}x)"
        ph = []
        for name, ps in COLUMNS:
            a, b = med(label, "softface", lambda r: col(r, ps)), med(label, "FEniCSx", lambda r: col(r, ps))
            ph.append(f"{name} {b / a:.2f}x")
        rest = lambda r: r["wall"] - sum(col(r, ps) or 0 for _, ps in COLUMNS)
        ph.append(f"rest {med(label, 'FEniCSx', rest) / med(label, 'softface', rest):.2f}x")
        its = lambda p: med(label, p, lambda r: r["iterations"])
        t += (f". FEniCSx / softface per phase: {', '.join(ph)}; CG iterations softface {its('softface'):.0f}, "
              f"FEniCSx {its('FEniCSx'):.0f}.")
        out.append(t)
    tgt = [(l, med(l, "FEniCSx", wall) / med(l, "softface", wall)) for l, *_ in meshes if l in ("105k", "491k")]
    if tgt:
        out.append("- **The target** (softface `cg amg` whole process at least 2x faster than dolfinx on one "
                   "rank at 100k and 500k): " + "; ".join(
                       f"{l}: {r:.2f}x, {'met' if r >= 2 else 'not met'}" for l, r in tgt) + ".")
    ag = "; ".join(f"{p} {d:.1e} mm ({l})" for (l, p), d in diffs.items())
    out.append(f"- **Agreement** (max over all vertices of the largest displacement-component difference to "
               f"softface, first repetition): {ag}. FEniCSx agrees to the solver tolerance; CalculiX's figure is "
               f"the rounding of its .dat output (7 significant digits).")
    imp = statistics.median(r["phases"]["import"] for (l, p, k), r in runs.items() if p == "FEniCSx")
    out.append(f"- **The rest** (whole process minus the four phases): a softface process that only starts and "
               f"exits on a missing scene file takes {info['startup']:.2f} s (median of 3, measured in this run); "
               f"FEniCSx's rest includes importing dolfinx, PETSc and gmsh into Python ({imp:.2f} s, median "
               f"over all its runs).")
    mem = "; ".join(f"{l}: softface {med(l, 'softface', lambda r: r['rss']):.0f} MB, FEniCSx "
                    f"{med(l, 'FEniCSx', lambda r: r['rss']):.0f} MB" for l, *_ in meshes)
    out.append(f"- **Peak memory** (maximum RSS, median): {mem}. The softface process that only starts and exits "
               f"(above) peaks at {info['startup_mb']:.0f} MB.")
    loads = [r["load"] for r in runs.values()]
    out.append(f"- 1-minute load average before the runs: {min(loads):.2f} to {max(loads):.2f} (2 cores).\n")
    return out


def plot(args, meshes, reps, runs, passes, all_runs, failed):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axs = plt.subplots(2, len(meshes), figsize=(4.2 * len(meshes), 8.4), squeeze=False)
    names = [c[0] for c in COLUMNS] + ["rest"]
    colors = ["#8da0cb", "#66c2a5", "#fc8d62", "#e78ac3", "#cccccc"]
    for ax, (label, _, _, with_ccx) in zip(axs[0], meshes):
        progs = PROGRAMS if with_ccx else PROGRAMS[:2]
        for x, prog in enumerate(progs):
            med = lambda f: statistics.median(f(runs[(label, prog, k)]) for k in range(1, reps + 1))
            whole = med(lambda r: r["wall"])
            if col(runs[(label, prog, 1)], ["solve"]) is None:      # CalculiX: no phases
                ax.bar(x, whole, color="#999999", hatch="//", label="whole process (no phases)" if x == 2 else None)
            else:
                parts = [med(lambda r, ps=ps: col(r, ps) or 0) for _, ps in COLUMNS]
                parts.append(max(whole - sum(parts), 0))
                bottom = 0
                for p, nm, c in zip(parts, names, colors):
                    ax.bar(x, p, bottom=bottom, color=c, label=nm if x == 0 else None)
                    bottom += p
            ax.text(x, whole, f"{whole:.1f} s", ha="center", va="bottom", fontsize=8)
        ax.set_xticks(range(len(progs)))
        ax.set_xticklabels(progs)
        ax.set_title(f"{label} tetrahedra")
        ax.set_ylabel("median wall time (s), one thread")
    h, l = [], []
    for ax in axs[0]:
        for hh, ll in zip(*ax.get_legend_handles_labels()):
            if ll not in l:
                h.append(hh); l.append(ll)
    # Between the rows, below the top row's program names.
    fig.legend(h, l, fontsize=8, loc="center", bbox_to_anchor=(0.5, 0.475), ncol=len(l))
    # Bottom row: the whole process of every pass, programs side by side.
    width = 0.8 / len(passes)
    for ax, (label, _, _, with_ccx) in zip(axs[1], meshes):
        progs = PROGRAMS if with_ccx else PROGRAMS[:2]
        for i, name in enumerate(passes):
            if (PASSES[name][0], label) in failed:     # not compared: no bars
                continue
            x = [j + (i - (len(passes) - 1) / 2) * width for j in range(len(progs))]
            y = [statistics.median(all_runs[(name, label, p, k)]["wall"] for k in range(1, reps + 1))
                 for p in progs]
            ax.bar(x, y, width, label=name.replace("-all", f", {CORES} cores").replace("svk", "SVK") +
                   ("" if name.endswith("-all") else ", 1 thread"))
        ax.set_xticks(range(len(progs)))
        ax.set_xticklabels(progs)
        ax.set_title(f"{label}: every pass")
        ax.set_ylabel("median whole process (s)")
        ax.legend(fontsize=7)
    fig.suptitle("Top: linear elasticity, one thread, whole process split into phases; bottom: whole "
                 "process of every pass (medians of %d)" % reps, fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.97), h_pad=6)
    fig.savefig(os.path.join(args.results, "peers.png"), dpi=120)


if __name__ == "__main__":
    main()
