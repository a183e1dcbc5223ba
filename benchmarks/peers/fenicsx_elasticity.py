#!/usr/bin/python3
"""FEniCSx (dolfinx 0.5.2) peer of softface's `linear fem` / `cg amg` (and, with --law svk, of
`nonlinear fem` with St. Venant-Kirchhoff, with --law neo-hooke of its compressible Neo-Hooke) on
a make_mesh.py cube.

Vector P1, E = 3000, nu = 0.46; u = 0 on facets tagged 1 ("fixed"), u = (0, 0, 6) on every vertex
of a cell tagged 2 ("bone"). Linear: CG + hypre BoomerAMG, rigid-body near-nullspace on the
matrix, rtol 1e-10. SVK: dolfinx's Newton solver from u = 0, its first iteration the linear
(tangent) predictor as in softface, stopping when the residual is below 1e-10 of the force that
predictor balances (softface's criterion), each Newton step solved by the same CG + BoomerAMG to
rtol 1e-6 (softface's `Linear tolerance`). Neo-Hooke: the same stored energy as softface's,
W = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2, its residual and tangent derived by UFL; the
bone's displacement ramped in --steps equal steps (ln J needs J > 0 on the way), each step's Newton
to the same residual bound with MUMPS (direct) linear solves. Runs on one MPI rank as plain `python3`, or on N with `mpirun -np
N`; the timings are rank 0's, the peak memory the sum over the ranks.

With --tissues ID:E:NU,... each physical volume ID (a tissue) takes its own Young's modulus and
Poisson's ratio (softface's Effects/heterogeneous tissue); volume 2 stays the bone.

usage: fenicsx_elasticity.py MESH.msh OUT.csv [--law linear|svk|neo-hooke] [--steps N]
                             [--tissues ID:E:NU,...] [--solver cg|direct]
(--solver: the linear law's solver, CG + BoomerAMG by default or MUMPS.)
Prints one JSON line: phase timings (s), CG iterations (in all), Newton iterations, residual;
writes x,y,z,ux,uy,uz for all vertices to OUT.csv.
"""
import json, resource, sys, time
T0 = time.perf_counter()
import numpy as np
from mpi4py import MPI
from petsc4py import PETSc
import gmsh
import ufl
import dolfinx
from dolfinx import fem, mesh as dmesh, la
from dolfinx.fem.petsc import create_matrix, assemble_matrix, assemble_vector, apply_lifting, set_bc
from dolfinx.fem.petsc import NonlinearProblem
from dolfinx.io import gmshio
from dolfinx.nls.petsc import NewtonSolver

msh_file, out_csv = sys.argv[1], sys.argv[2]
options = dict(zip(sys.argv[3::2], sys.argv[4::2]))
law, load_steps = options.get("--law", "linear"), int(options.get("--steps", 10))
assert law in ("linear", "svk", "neo-hooke"), f"unknown --law {law}"
E, NU, UZ = 3000.0, 0.46, 6.0
comm = MPI.COMM_WORLD
t = {"import": time.perf_counter() - T0}


def tic():
    return time.perf_counter()


# Mesh read. gmshio.read_from_msh in Debian's dolfinx 0.5.2 is broken (it returns an undefined
# name `msh`: NameError), so do what it was meant to do: open the file in gmsh, model_to_mesh.
# With N ranks the file is read on rank 0 and the mesh distributed from there.
s = tic()
if comm.rank == 0:
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.open(msh_file)
mesh, cell_tags, facet_tags = gmshio.model_to_mesh(gmsh.model, comm, 0, gdim=3)
if comm.rank == 0:
    gmsh.finalize()
t["mesh read"] = tic() - s

# Function space and forms (FFCx JIT: compiled on the first run, from the cache afterwards).
s = tic()
V = fem.VectorFunctionSpace(mesh, ("Lagrange", 1))
mu, lam = E / (2 * (1 + NU)), E * NU / ((1 + NU) * (1 - 2 * NU))
if "--tissues" in options:
    # Lame's coefficients per cell (DG0), from each cell's physical volume.
    Q = fem.FunctionSpace(mesh, ("DG", 0))
    mu_cells, lam_cells = fem.Function(Q), fem.Function(Q)
    mu_cells.x.array[:], lam_cells.x.array[:] = mu, lam
    for tissue in options["--tissues"].split(","):
        tag, E_t, nu_t = (float(w) for w in tissue.split(":"))
        cells = cell_tags.find(int(tag))
        mu_cells.x.array[cells] = E_t / (2 * (1 + nu_t))
        lam_cells.x.array[cells] = E_t * nu_t / ((1 + nu_t) * (1 - 2 * nu_t))
    mu, lam = mu_cells, lam_cells
u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
eps = lambda w: ufl.sym(ufl.grad(w))
sigma = lambda w: 2 * mu * eps(w) + lam * ufl.tr(eps(w)) * ufl.Identity(3)
if law == "linear":
    a = fem.form(ufl.inner(sigma(u), eps(v)) * ufl.dx)
    L = fem.form(ufl.inner(fem.Constant(mesh, PETSc.ScalarType((0, 0, 0))), v) * ufl.dx)
elif law == "svk":
    uh = fem.Function(V)
    F = ufl.Identity(3) + ufl.grad(uh)
    Egl = 0.5 * (F.T * F - ufl.Identity(3))
    S = lam * ufl.tr(Egl) * ufl.Identity(3) + 2 * mu * Egl
    residual = ufl.inner(F * S, ufl.grad(v)) * ufl.dx
    tangent = ufl.derivative(residual, uh, u)
else:
    uh = fem.Function(V)
    F = ufl.variable(ufl.Identity(3) + ufl.grad(uh))
    J = ufl.det(F)
    W = mu / 2 * (ufl.tr(F.T * F) - 3) - mu * ufl.ln(J) + lam / 2 * ufl.ln(J) ** 2
    residual = ufl.inner(ufl.diff(W, F), ufl.grad(v)) * ufl.dx
    tangent = ufl.derivative(residual, uh, u)
t["forms"] = tic() - s

# Dirichlet conditions: facets tagged 1; all vertices of the cells tagged 2.
s = tic()
tdim = mesh.topology.dim
mesh.topology.create_connectivity(tdim - 1, tdim)
fixed_dofs = fem.locate_dofs_topological(V, tdim - 1, facet_tags.find(1))
mesh.topology.create_connectivity(tdim, 0)
bone_vertices = dmesh.compute_incident_entities(mesh, cell_tags.find(2), tdim, 0)
bone_dofs = fem.locate_dofs_topological(V, 0, bone_vertices)
bone_motion = fem.Constant(mesh, PETSc.ScalarType((0, 0, UZ)))
bcs = [fem.dirichletbc(np.zeros(3, dtype=PETSc.ScalarType), fixed_dofs, V),
       fem.dirichletbc(bone_motion, bone_dofs, V)]
t["boundary conditions"] = tic() - s

def near_nullspace(V):
    """The rigid-body modes (3 translations, 3 rotations), as in the dolfinx elasticity demo."""
    x = V.tabulate_dof_coordinates()          # one row per block (vertex) of 3 dofs
    ns = [la.create_petsc_vector(V.dofmap.index_map, V.dofmap.index_map_bs) for _ in range(6)]
    arrs = [w.array.reshape(-1, 3) for w in ns]   # views into the owned part
    n = V.dofmap.index_map.size_local
    for i in range(3):
        arrs[i][:, i] = 1.0
    X = x[:n]
    arrs[3][:, 0], arrs[3][:, 1] = -X[:, 1], X[:, 0]
    arrs[4][:, 0], arrs[4][:, 2] = X[:, 2], -X[:, 0]
    arrs[5][:, 2], arrs[5][:, 1] = X[:, 1], -X[:, 2]
    la.orthonormalize(ns)
    return PETSc.NullSpace().create(vectors=ns)


# CG + BoomerAMG. PETSc's hypre interface passes the matrix block size (3) and the near-nullspace
# vectors to BoomerAMG. Options: hypre's usual choice for 3D elasticity (HMIS coarsening, ext+i
# interpolation, at most 4 weights per row, strong threshold 0.5). On the 105k cube they took the
# whole process from about 6.3 s (BoomerAMG defaults: 13 iterations but a slow, dense hierarchy)
# to about 4.1 s (18 iterations). PETSC_OPTIONS in the environment overrides them. CG tests the
# unpreconditioned residual, as softface's CG does (PETSc's default is the preconditioned one).
def cg_amg(ksp, rtol):
    """Through the options database, under the KSP's prefix: dolfinx's Newton solver sets its own
    (preonly + LU) there, which a plain setType would lose to setFromOptions."""
    prefix = ksp.getOptionsPrefix() or ""
    opts = PETSc.Options()
    for k, val in (("ksp_type", "cg"), ("ksp_norm_type", "unpreconditioned"), ("pc_type", "hypre"),
                   ("pc_hypre_type", "boomeramg"),
                   ("pc_hypre_boomeramg_coarsen_type", "HMIS"),
                   ("pc_hypre_boomeramg_interp_type", "ext+i"),
                   ("pc_hypre_boomeramg_P_max", "4"), ("pc_hypre_boomeramg_strong_threshold", "0.5")):
        if k.startswith("pc_hypre_boomeramg") and opts.hasName(prefix + k):
            continue                          # PETSC_OPTIONS in the environment, prefixed
        if k.startswith("pc_hypre_boomeramg") and opts.hasName(k):
            val = opts.getString(k)           # unprefixed: carried to this KSP's prefix
        opts[prefix + k] = val
    ksp.setFromOptions()
    ksp.setTolerances(rtol=rtol, atol=0.0, max_it=2000)


newton_its = None
if law == "linear":
    # Sparsity (matrix creation), then assembly of matrix and right-hand side (with lifting).
    s = tic()
    A = create_matrix(a)
    t["sparsity"] = tic() - s
    s = tic()
    assemble_matrix(A, a, bcs=bcs)
    A.assemble()
    b = assemble_vector(L)
    apply_lifting(b, [a], bcs=[bcs])
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    set_bc(b, bcs)
    t["assemble"] = tic() - s

    s = tic()
    A.setNearNullSpace(near_nullspace(V))
    t["nullspace"] = tic() - s

    s = tic()
    ksp = PETSc.KSP().create(mesh.comm)
    ksp.setOperators(A)
    if options.get("--solver", "cg") == "direct":
        ksp.setType("preonly")
        ksp.getPC().setType("lu")
        ksp.getPC().setFactorSolverType("mumps")
    else:
        cg_amg(ksp, 1e-10)
    ksp.setUp()
    t["preconditioner"] = tic() - s

    s = tic()
    uh = fem.Function(V)
    ksp.solve(b, uh.vector)
    uh.x.scatter_forward()
    t["solve"] = tic() - s
    reason, its = ksp.getConvergedReason(), ksp.getIterationNumber()
    r = b.duplicate()
    A.mult(uh.vector, r)
    r.axpy(-1.0, b)
    relres = r.norm() / b.norm()
else:
    # dolfinx's Newton from u = 0 with the conditions imposed by the first correction: that first
    # iteration solves the tangent at u = 0 (linear elasticity) for the lift, which is softface's
    # tangent predictor. The stop is softface's: the residual below 1e-10 of the force that
    # predictor balances (the free rows of K times the lift; the conditions' rows are zero once
    # imposed).
    # The reference force is a phase of its own: softface has K at hand, FEniCSx assembles it here.
    s = tic()
    lift = fem.Function(V)
    set_bc(lift.vector, bcs)
    lift.x.scatter_forward()
    K0 = assemble_matrix(fem.form(ufl.inner(sigma(u), eps(v)) * ufl.dx))
    K0.assemble()
    unbalanced = lift.vector.duplicate()
    K0.mult(lift.vector, unbalanced)
    set_bc(unbalanced, bcs, scale=0.0)
    reference_force = unbalanced.norm()
    K0.destroy()
    unbalanced.destroy()
    t["reference force"] = tic() - s
    s = tic()
    problem = NonlinearProblem(residual, uh, bcs, J=tangent)
    solver = NewtonSolver(comm, problem)
    solver.convergence_criterion = "residual"
    solver.rtol, solver.atol, solver.max_it = 0.0, 1e-10 * reference_force, 50
    solver.error_on_nonconvergence = False    # report it in the JSON line instead of a traceback
    if law == "svk":
        solver.A.setNearNullSpace(near_nullspace(V))
        cg_amg(solver.krylov_solver, 1e-6)
    else:
        opts, prefix = PETSc.Options(), solver.krylov_solver.getOptionsPrefix() or ""
        opts[prefix + "ksp_type"], opts[prefix + "pc_type"] = "preonly", "lu"
        opts[prefix + "pc_factor_mat_solver_type"] = "mumps"
        solver.krylov_solver.setFromOptions()
    linear_its = [0]
    solver.krylov_solver.setMonitor(lambda ksp, it, rnorm: linear_its.__setitem__(0, linear_its[0] + (it > 0)))
    t["setup"] = tic() - s
    s = tic()
    if law == "svk":
        newton_its, converged = solver.solve(uh)
    else:
        newton_its = 0
        for step in range(1, load_steps + 1):
            bone_motion.value = (0, 0, UZ * step / load_steps)
            its_step, converged = solver.solve(uh)
            newton_its += its_step
            if not converged:
                break
    uh.x.scatter_forward()
    t["solve"] = tic() - s
    reason, its, relres = int(converged), linear_its[0], float("nan")

# Every vertex's displacement, gathered on rank 0 (each rank owns some).
s = tic()
n = V.dofmap.index_map.size_local
X = V.tabulate_dof_coordinates()[:n]
U = uh.x.array.reshape(-1, 3)[:n]
parts = comm.gather(np.hstack([X, U]), root=0)
if comm.rank == 0:
    np.savetxt(out_csv, np.vstack(parts), delimiter=",", header="x,y,z,ux,uy,uz", comments="",
               fmt="%.12g")
t["write"] = tic() - s
t["in-process total"] = tic() - T0
n_vertices = comm.allreduce(n)
n_cells = comm.allreduce(mesh.topology.index_map(tdim).size_local)
# Peak memory of all ranks together (/usr/bin/time around mpirun sees only the largest one).
peak_mb = comm.allreduce(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss) / 1024
if comm.rank == 0:
    print(json.dumps(dict(phases=t, law=law, ranks=comm.size, iterations=int(its),
                          newton_iterations=newton_its, converged_reason=int(reason),
                          relative_residual=float(relres), peak_mb_all_ranks=peak_mb,
                          n_cells=int(n_cells),
                          n_vertices=int(n_vertices), n_dofs=int(3 * n_vertices),
                          max_u=float(np.abs(np.vstack(parts)[:, 3:]).max()),
                          dolfinx=dolfinx.__version__,
                          petsc=".".join(map(str, PETSc.Sys.getVersion())))))
