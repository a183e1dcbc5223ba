#!/usr/bin/python3
"""Peer benchmark driver: softface `linear fem` (cg amg) against FEniCSx (dolfinx) and CalculiX
on the same gmsh cube meshes. Called by run.sh (see README.md).

usage: run.py --softface BIN --work DIR --results DIR --command "..." [--quick]

For each mesh and repetition it runs each program once (interleaved: rep 1 of every program, then
rep 2, ...), one thread each, every run its own process under /usr/bin/time (peak RSS). After the
first repetition of a mesh it compares every vertex displacement with softface's and stops with a
non-zero exit if a peer differs by more than TOL_MM. Writes peers.md, peers.csv, peers.png.
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
ENV = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", DEAL_II_NUM_THREADS="1",
           CCX_NPROC_EQUATION_SOLVER="1", CCX_NPROC_STIFFNESS="1", CCX_NPROC_RESULTS="1")

MODELS = """  set Models = linear fem
  subsection linear fem
    set Solver = cg amg
    set Relative tolerance = 1e-10
  end
"""


def timed(cmd, cwd, log):
    """Run cmd under /usr/bin/time; return (wall s, peak RSS MB, CPU s, stdout)."""
    tf = os.path.join(cwd, "time.txt")
    t0 = time.perf_counter()
    r = subprocess.run(["/usr/bin/time", "-f", "%M %U %S", "-o", tf] + cmd, cwd=cwd, env=ENV,
                       capture_output=True, text=True)
    wall = time.perf_counter() - t0
    open(os.path.join(cwd, log), "w").write(r.stdout + r.stderr)
    if r.returncode != 0:
        sys.exit(f"FAILED ({r.returncode}): {' '.join(cmd)} in {cwd}\n{r.stdout[-2000:]}{r.stderr[-2000:]}")
    rss, usr, sys_ = open(tf).read().split()[-3:]
    return wall, int(rss) / 1024, float(usr) + float(sys_), r.stdout


def run_softface(binary, mesh, d):
    os.makedirs(d, exist_ok=True)
    open(os.path.join(d, "scene.prm"), "w").write(cube_scene(os.path.join(d, "out"), mesh=mesh, models=MODELS,
                   output="  set Write nodal displacements = true\n"))
    wall, rss, cpu, out = timed([binary, "scene.prm"], d, "softface.log")
    ph = {"mesh read": float(re.search(r"free DoFs \(([\d.]+) s\)", out).group(1))}
    row = next(csv.DictReader(open(os.path.join(d, "out", "summary.csv"))))
    for kv in row["phases"].split(";"):
        k, v = kv.split("=")
        ph[k] = float(v)
    return dict(phases=ph, wall=wall, rss=rss, cpu=cpu, iterations=int(row["iterations"]),
                residual=float(row["relative_residual"]),
                csv=os.path.join(d, "out", "displacements_linear_fem.csv"))


def run_fenicsx(mesh, d):
    os.makedirs(d, exist_ok=True)
    wall, rss, cpu, out = timed([PY, os.path.join(HERE, "fenicsx_elasticity.py"), mesh, "u.csv"],
                                d, "fenicsx.log")
    j = json.loads(out.strip().splitlines()[-1])
    return dict(phases=j["phases"], wall=wall, rss=rss, cpu=cpu, iterations=j["iterations"],
                residual=j["relative_residual"], csv=os.path.join(d, "u.csv"))


def run_calculix(case_dir, d):
    """ccx on the prepared case.inp (copied to d so the repetitions do not share files)."""
    os.makedirs(d, exist_ok=True)
    for f in ("case.inp", "nodes.npy"):
        subprocess.run(["cp", os.path.join(case_dir, f), d], check=True)
    wall, rss, cpu, out = timed(["ccx", "-i", "case"], d, "ccx.log")
    if "Job finished" not in out or "*ERROR" in out:
        sys.exit(f"CalculiX failed in {d}")
    ccx_total = float(re.search(r"Total CalculiX Time:\s*([\d.eE+-]+)", out).group(1))
    subprocess.run([PY, os.path.join(HERE, "calculix_case.py"), "collect", d, os.path.join(d, "u.csv")],
                   check=True, capture_output=True)
    for ext in ("frd", "dat", "inp"):          # large; the CSV holds what we need
        os.remove(os.path.join(d, "case." + ext))
    return dict(phases={"ccx total (own timer)": ccx_total}, wall=wall, rss=rss, cpu=cpu,
                iterations=None, residual=None, csv=os.path.join(d, "u.csv"))


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
    args = ap.parse_args()
    meshes = MESHES[:1] if args.quick else MESHES
    reps = 1 if args.quick else args.reps
    W = args.work
    os.makedirs(args.results, exist_ok=True)

    # Untimed warm-up on the smallest mesh: fills the FFCx JIT cache (the first dolfinx run compiles
    # the forms, ~1 s) and the page cache for all three programs' binaries and libraries.
    m0 = os.path.join(W, meshes[0][1])
    print("warm-up on", meshes[0][1], flush=True)
    run_softface(args.softface, m0, os.path.join(W, "warmup", "softface"))
    run_fenicsx(m0, os.path.join(W, "warmup", "fenicsx"))

    # softface's fixed cost of a process: start it on a scene file that does not exist (it exits
    # with an error after loading its libraries); median of 3.
    startup, startup_mb, tf = [], [], os.path.join(W, "startup_time.txt")
    for _ in range(3):
        t0 = time.perf_counter()
        subprocess.run(["/usr/bin/time", "-f", "%M", "-o", tf, args.softface, os.path.join(W, "no-such-scene.prm")],
                       env=ENV, capture_output=True)
        startup.append(time.perf_counter() - t0)
        startup_mb.append(int(open(tf).read().split()[-1]) / 1024)

    rows, runs, diffs = [], {}, {}
    info = {"startup": statistics.median(startup), "startup_mb": statistics.median(startup_mb)}
    t_start = time.time()
    for label, fname, _, with_ccx in meshes:
        mesh = os.path.join(W, fname)
        progs = PROGRAMS if with_ccx else PROGRAMS[:2]
        if with_ccx:
            case = os.path.join(W, label, "calculix_case")
            info[label] = json.loads(subprocess.run(
                [PY, os.path.join(HERE, "calculix_case.py"), "prepare", mesh, case],
                check=True, capture_output=True, text=True).stdout)
        for rep in range(1, reps + 1):
            for prog in progs:
                d = os.path.join(W, label, prog, f"rep{rep}")
                load = open("/proc/loadavg").read().split()[0]
                print(f"[{time.time() - t_start:6.0f} s] {label} rep {rep} {prog} (load {load})", flush=True)
                r = (run_softface(args.softface, mesh, d) if prog == "softface" else
                     run_fenicsx(mesh, d) if prog == "FEniCSx" else
                     run_calculix(os.path.join(W, label, "calculix_case"), d))
                r["load"] = float(load)
                runs[(label, prog, rep)] = r
                print(f"    whole process {r['wall']:.2f} s, peak {r['rss']:.0f} MB, CPU {r['cpu']:.2f} s, "
                      f"iterations {r['iterations']}", flush=True)
            if rep == 1:                       # agreement check on the first repetition
                for prog in progs[1:]:
                    dmax = max_diff(runs[(label, "softface", 1)]["csv"], runs[(label, prog, 1)]["csv"])
                    diffs[(label, prog)] = dmax
                    print(f"    max |u_softface - u_{prog}| = {dmax:.2e} mm", flush=True)
                    if not dmax <= TOL_MM:
                        sys.exit(f"DISAGREEMENT on {label}: {prog} differs from softface by {dmax:.3e} mm "
                                 f"> {TOL_MM} mm")
        import gmsh                            # mesh size for the report
        gmsh.initialize(); gmsh.option.setNumber("General.Terminal", 0); gmsh.open(mesh)
        info.setdefault(label, {})
        info[label]["n_tets"] = int(sum(len(t) for t in gmsh.model.mesh.getElements(3)[1]))
        info[label]["n_nodes"] = int(len(np.unique(gmsh.model.mesh.getElements(3)[2][0])))  # used nodes
        gmsh.finalize()
    elapsed = time.time() - t_start

    for (label, prog, rep), r in runs.items():
        base = dict(program=prog, mesh=label, n_tets=info[label]["n_tets"],
                    n_vertices=info[label]["n_nodes"], rep=rep, load1=r["load"],
                    iterations=r["iterations"], peak_mb=round(r["rss"], 1),
                    max_diff_to_softface_mm=diffs.get((label, prog), 0.0 if prog == "softface" else ""))
        for ph, v in list(r["phases"].items()) + [("whole process", r["wall"]), ("cpu user+sys", r["cpu"])]:
            rows.append(dict(base, phase=ph, seconds=round(v, 4)))
    with open(os.path.join(args.results, "peers.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    report(args, meshes, reps, runs, diffs, info, elapsed)
    plot(args, meshes, reps, runs)


def col(r, phases):
    """Sum of the given phases of one run, None if the program does not report any of them."""
    v = [r["phases"][p] for p in phases if p in r["phases"]]
    return sum(v) if v else None


def stats(runs, label, prog, reps, f):
    vals = [f(runs[(label, prog, k)]) for k in range(1, reps + 1)]
    return None if vals[0] is None else (min(vals), statistics.median(vals))


def report(args, meshes, reps, runs, diffs, info, elapsed):
    cpu = next(l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name"))
    fx = json.loads(open(os.path.join(args.work, "warmup", "fenicsx", "fenicsx.log")).read().strip().splitlines()[-1])
    ccxv = subprocess.run(["ccx", "-v"], capture_output=True, text=True).stdout.strip().splitlines()[-1].replace("This is ", "")
    git = subprocess.run(["git", "-C", HERE, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    dirty = subprocess.run(["git", "-C", HERE, "status", "--porcelain", "--untracked-files=no"],
                           capture_output=True, text=True).stdout.strip()
    L = [f"# softface against FEniCSx and CalculiX: linear elasticity on the same meshes\n",
         f"Command: `{args.command.strip()}` ({elapsed / 60:.1f} min). Date: {datetime.datetime.now():%Y-%m-%d %H:%M}. "
         f"Machine: {cpu}, {os.cpu_count()} cores, {platform.system()} {platform.release()}. "
         f"softface: `linear fem`, `cg amg`, built from commit {git}{' with uncommitted changes' if dirty else ''}; "
         f"FEniCSx: dolfinx {fx['dolfinx']} with PETSc {fx['petsc']} (Debian), one MPI rank; CalculiX: {ccxv} (Debian), SPOOLES.\n",
         "**The machine was shared**: another engineer was compiling on its 2 cores during the runs, so absolute "
         "times are noisy (the 1-minute load average before each run is in peers.csv, column `load1`). "
         "Ratios measured in the same interleaved run are more robust than absolute figures.\n",
         "## Problem and method\n",
         "The cube of `make_mesh.py`: box [0,80]^3 mm, inner box [35,45]^3 mm meshed conformingly; P1 tetrahedra, "
         "E = 3000, Poisson's ratio 0.46; u = 0 on every vertex of the six outer faces, u = (0, 0, 6) mm on every "
         "vertex of the inner box's cells. softface and FEniCSx: CG with algebraic multigrid (softface: Trilinos ML "
         "through deal.II; FEniCSx: hypre BoomerAMG with the settings in fenicsx_elasticity.py and the rigid-body "
         "near-nullspace; FEniCSx's times depend on these options, see benchmarks/peers/README.md), relative "
         "tolerance 1e-10. CalculiX: linear static, C3D4, SPOOLES direct solver; "
         f"**CalculiX only on the 35k and 105k meshes** (about 164 s at 491k on this machine). "
         f"{reps} repetition(s), interleaved (repetition 1 of every program, then 2, ...), each run a separate "
         "process with one thread (OMP_NUM_THREADS=1, CCX_NPROC_*=1, OPENBLAS_NUM_THREADS=1); an untimed warm-up "
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
    L.append("## What the numbers show\n")
    L += summary(meshes, reps, runs, diffs, info)
    L.append("Files: peers.csv (one row per program, mesh, repetition and phase, with load average, iterations, "
             "peak memory and the agreement), peers.png (median phases stacked per program and mesh).\n")
    open(os.path.join(args.results, "peers.md"), "w").write("\n".join(L))


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
        out.append("- **The issue's target** (softface `cg amg` whole process at least 2x faster than dolfinx on one "
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


def plot(args, meshes, reps, runs):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axs = plt.subplots(1, len(meshes), figsize=(4.2 * len(meshes), 4.2), squeeze=False)
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
    fig.legend(h, l, fontsize=8, loc="lower center", ncol=len(l))
    fig.suptitle("Linear elasticity on the same mesh, one thread:\nwhole process split into phases "
                 "(median of %d)" % reps, fontsize=10)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    fig.savefig(os.path.join(args.results, "peers.png"), dpi=120)


if __name__ == "__main__":
    main()
