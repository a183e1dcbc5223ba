"""What both scaling benchmarks (run.py, reference.py) do with softface: run a scene on one rank
or through mpiexec, read the figures it prints, and name the commit they were made at."""
import os, re, subprocess, sys, time

# Open MPI refuses root (CI runs as root) unless told.
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
NUMBER = r"[-+]?[\d.]+(?:e[-+]?\d+)?"


def cube_scene(n, models, out, nodal):
    """A parameter file: the generated cube of about N tetrahedra (the paper's benchmark, 6 mm
    lift), MODELS on one thread per rank, outputs in OUT (nodal displacements if NODAL)."""
    return f"""subsection Scene
  set Mesh source = cube
  subsection Cube
    set Target number of tetrahedra = {n}
  end
end
subsection Models
  set Models  = {", ".join(models)}
  set Threads = 1
end
subsection Output
  set Output directory          = {out}
  set Write VTU                 = false
  set Write nodal displacements = {"true" if nodal else "false"}
end
"""


def run(softface, mpiexec, prm, ranks, who):
    """softface on PRM, serially (RANKS 1) or through mpiexec: its stdout and the command's wall
    time; a failed run ends the benchmark, named WHO."""
    cmd = [softface, prm] if ranks == 1 else [mpiexec, "-n", str(ranks), softface, prm]
    start = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, env=ENV)
    wall = time.perf_counter() - start
    if p.returncode != 0:
        sys.exit(f"{who}: {' '.join(cmd)} failed:\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    return p.stdout, wall


def phases(out, model):
    """MODEL's phase report ('<model> phases (s): name value ...') as {name: seconds}; empty
    without one."""
    line = re.search(rf"^{model} phases \(s\):(.*)$", out, re.M)
    if not line:
        return {}
    return {name.strip(): float(value)
            for name, value in re.findall(r"([a-zA-Z][a-zA-Z ()]*?) ([\d.]+)(?=\s|$)", line.group(1))}


def table_row(out, model):
    """MODEL's row of the side-by-side table: setup s, solve s, iterations."""
    cells = re.search(rf"^ *{model} +\d+ +\d+ +\d+ +([\d.]+) +([\d.]+) +(\d+)", out, re.M)
    return float(cells.group(1)), float(cells.group(2)), int(cells.group(3))


def process_figures(out):
    """The whole process's wall time (s) and peak memory (MB, the largest rank's)."""
    return (float(re.search(r"Wall time ([\d.]+) s", out).group(1)),
            float(re.search(r"peak memory (\d+) MB", out).group(1)))


def commit():
    """The repository's short HEAD, or empty outside one."""
    try:
        return subprocess.run(["git", "-C", os.path.dirname(os.path.abspath(__file__)), "rev-parse",
                               "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    except OSError:
        return ""
