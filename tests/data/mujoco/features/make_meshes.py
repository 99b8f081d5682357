"""Writes the binary STL meshes of `mesh.xml` (`meshes/*.stl`), a few hundred bytes each:
`wedge.stl`, a convex triangular prism, and `ell.stl`, a non-convex L-shaped prism (where
MuJoCo's `legacy` mesh inertia, its default, over-counts and `exact` does not), and the L again
as `ell.obj` with quadrilateral sides. Run once:
`python tests/data/mujoco/features/make_meshes.py`; the files are committed."""
import os
import struct

here = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'meshes')


def prism(outline, height):
    """The closed prism over the counter-clockwise polygon `outline` (x, y) from z = 0 to
    `height`, as outward triangles: the caps fanned from the first vertex, two per side."""
    n = len(outline)
    bottom = [(x, y, 0.0) for x, y in outline]
    top = [(x, y, height) for x, y in outline]
    tris = []
    for i in range(1, n - 1):
        tris.append((bottom[0], bottom[i + 1], bottom[i]))
        tris.append((top[0], top[i], top[i + 1]))
    for i in range(n):
        j = (i + 1) % n
        tris.append((bottom[i], bottom[j], top[j]))
        tris.append((bottom[i], top[j], top[i]))
    return tris


def write(name, tris):
    data = bytearray(b'articulated test mesh'.ljust(80, b' '))
    data += struct.pack('<I', len(tris))
    for t in tris:
        data += struct.pack('<3f', 0.0, 0.0, 0.0)
        for v in t:
            data += struct.pack('<3f', *v)
        data += struct.pack('<H', 0)
    with open(os.path.join(here, name), 'wb') as f:
        f.write(bytes(data))


os.makedirs(here, exist_ok=True)
write('wedge.stl', prism([(0.0, 0.0), (0.3, 0.0), (0.0, 0.2)], 0.1))
# An L whose outline is fanned from a convex corner: every fan triangle lies inside it.
L = [(0.0, 0.0), (0.4, 0.0), (0.4, 0.1), (0.1, 0.1), (0.1, 0.3), (0.0, 0.3)]
write('ell.stl', prism(L, 0.05))


def write_obj(name, outline, height):
    """The same prism as an OBJ file: its caps as fans of triangles, its sides as quads (which
    the readers split into two triangles each)."""
    n = len(outline)
    lines = ['# articulated test mesh']
    lines += [f'v {x} {y} 0' for x, y in outline] + [f'v {x} {y} {height}' for x, y in outline]
    for i in range(1, n - 1):
        lines.append(f'f 1 {i + 2} {i + 1}')
        lines.append(f'f {n + 1} {n + i + 1} {n + i + 2}')
    for i in range(n):
        j = (i + 1) % n
        lines.append(f'f {i + 1} {j + 1} {n + j + 1} {n + i + 1}')
    with open(os.path.join(here, name), 'w') as f:
        f.write('\n'.join(lines) + '\n')


write_obj('ell.obj', L, 0.05)
