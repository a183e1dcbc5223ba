"""The softface scene both peer scripts run: the paper's cube benchmark (outer faces held, the inner
box lifted 6 mm, E = 3000, nu = 0.46) on a gmsh mesh or on softface's generated cube."""


def cube_scene(out, mesh=None, tets=None, models="  set Models = linear fem\n",
               output=""):
    """Parameter text: MESH (a make_mesh.py file) or, without it, the generated cube with about
    TETS tetrahedra; MODELS is the body of the Models section, OUTPUT extra Output lines."""
    source = (f"  set Mesh source = file\n  set Mesh file = {mesh}\n" if mesh else
              f"  set Mesh source = cube\n  subsection Cube\n"
              f"    set Target number of tetrahedra = {tets}\n  end\n")
    return f"""subsection Scene
{source}  set Bone segments = fixed, bone
  subsection Segment fixed
    set Boundary ids = 1
  end
  subsection Segment bone
    set Material ids = 2
  end
end
subsection Material
  set Young's modulus = 3000
  set Poisson's ratio = 0.46
end
subsection Planning
  set Moved segments = bone
  subsection Motion bone
    set Translation = 0, 0, 6
  end
end
subsection Models
{models}end
subsection Output
  set Output directory = {out}
  set Write VTU = false
{output}end
"""
