#!/usr/bin/python3
"""FEniCSx (dolfinx 0.5.2) peer of softface's `linear fem` / `cg amg` on a make_mesh.py cube.

Linear elasticity, vector P1, E = 3000, nu = 0.46; u = 0 on facets tagged 1 ("fixed"),
u = (0, 0, 6) on every vertex of a cell tagged 2 ("bone"). CG + hypre BoomerAMG, rigid-body
near-nullspace on the matrix, rtol 1e-10. One MPI rank (run as plain `python3`).

usage: fenicsx_elasticity.py MESH.msh OUT.csv
Prints one JSON line: phase timings (s), CG iterations, residual; writes x,y,z,ux,uy,uz for all
vertices to OUT.csv.
"""
import sys, json, time
T0 = time.perf_counter()
import numpy as np
from mpi4py import MPI
from petsc4py import PETSc
import gmsh
import ufl
import dolfinx
from dolfinx import fem, mesh as dmesh, la
from dolfinx.fem.petsc import create_matrix, assemble_matrix, assemble_vector, apply_lifting, set_bc
from dolfinx.io import gmshio

msh_file, out_csv = sys.argv[1], sys.argv[2]
E, NU, UZ = 3000.0, 0.46, 6.0
t = {"import": time.perf_counter() - T0}


def tic():
    return time.perf_counter()


# Mesh read. gmshio.read_from_msh in Debian's dolfinx 0.5.2 is broken (it returns an undefined
# name `msh`: NameError), so do what it was meant to do: open the file in gmsh, model_to_mesh.
s = tic()
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.open(msh_file)
mesh, cell_tags, facet_tags = gmshio.model_to_mesh(gmsh.model, MPI.COMM_WORLD, 0, gdim=3)
gmsh.finalize()
t["mesh read"] = tic() - s

# Function space and forms (FFCx JIT: compiled on the first run, from the cache afterwards).
s = tic()
V = fem.VectorFunctionSpace(mesh, ("Lagrange", 1))
mu, lam = E / (2 * (1 + NU)), E * NU / ((1 + NU) * (1 - 2 * NU))
u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
eps = lambda w: ufl.sym(ufl.grad(w))
sigma = lambda w: 2 * mu * eps(w) + lam * ufl.tr(eps(w)) * ufl.Identity(3)
a = fem.form(ufl.inner(sigma(u), eps(v)) * ufl.dx)
L = fem.form(ufl.inner(fem.Constant(mesh, PETSc.ScalarType((0, 0, 0))), v) * ufl.dx)
t["forms"] = tic() - s

# Dirichlet conditions: facets tagged 1; all vertices of the cells tagged 2.
s = tic()
tdim = mesh.topology.dim
mesh.topology.create_connectivity(tdim - 1, tdim)
fixed_dofs = fem.locate_dofs_topological(V, tdim - 1, facet_tags.find(1))
mesh.topology.create_connectivity(tdim, 0)
bone_vertices = dmesh.compute_incident_entities(mesh, cell_tags.find(2), tdim, 0)
bone_dofs = fem.locate_dofs_topological(V, 0, bone_vertices)
bcs = [fem.dirichletbc(np.zeros(3, dtype=PETSc.ScalarType), fixed_dofs, V),
       fem.dirichletbc(np.array([0, 0, UZ], dtype=PETSc.ScalarType), bone_dofs, V)]
t["boundary conditions"] = tic() - s

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

# Rigid-body near-nullspace (3 translations, 3 rotations), as in the dolfinx elasticity demo.
s = tic()
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
A.setNearNullSpace(PETSc.NullSpace().create(vectors=ns))
t["nullspace"] = tic() - s

# CG + BoomerAMG. PETSc's hypre interface passes the matrix block size (3) and the near-nullspace
# vectors to BoomerAMG. Options: hypre's usual choice for 3D elasticity (HMIS coarsening, ext+i
# interpolation, at most 4 weights per row, strong threshold 0.5). On the 105k cube they took the
# whole process from about 6.3 s (BoomerAMG defaults: 13 iterations but a slow, dense hierarchy)
# to about 4.1 s (18 iterations). PETSC_OPTIONS in the environment overrides them.
s = tic()
opts = PETSc.Options()
for k, v in (("pc_hypre_boomeramg_coarsen_type", "HMIS"), ("pc_hypre_boomeramg_interp_type", "ext+i"),
             ("pc_hypre_boomeramg_P_max", "4"), ("pc_hypre_boomeramg_strong_threshold", "0.5")):
    if not opts.hasName(k):
        opts[k] = v
ksp = PETSc.KSP().create(mesh.comm)
ksp.setOperators(A)
ksp.setType("cg")
ksp.getPC().setType("hypre")
ksp.getPC().setHYPREType("boomeramg")
ksp.setTolerances(rtol=1e-10, atol=0.0, max_it=2000)
ksp.setFromOptions()
ksp.setUp()
t["preconditioner"] = tic() - s

s = tic()
uh = fem.Function(V)
ksp.solve(b, uh.vector)
uh.x.scatter_forward()
t["solve"] = tic() - s
reason, its = ksp.getConvergedReason(), ksp.getIterationNumber()
r = b.duplicate(); A.mult(uh.vector, r); r.axpy(-1.0, b)
relres = r.norm() / b.norm()

s = tic()
U = uh.x.array.reshape(-1, 3)[:n]
np.savetxt(out_csv, np.hstack([X, U]), delimiter=",", header="x,y,z,ux,uy,uz", comments="",
           fmt="%.12g")
t["write"] = tic() - s
t["in-process total"] = tic() - T0
print(json.dumps(dict(phases=t, iterations=int(its), converged_reason=int(reason),
                      relative_residual=float(relres), n_cells=int(mesh.topology.index_map(tdim).size_local),
                      n_vertices=int(n), n_dofs=int(3 * n),
                      n_fixed_dofs=int(3 * len(fixed_dofs)), n_bone_dofs=int(3 * len(bone_dofs)),
                      max_u=float(np.abs(U).max()), dolfinx=dolfinx.__version__,
                      petsc=".".join(map(str, PETSc.Sys.getVersion())))))
