//! Mesh geoms' volume and inertia, as MuJoCo's compiler computes them (`user_mesh.cc`): the
//! mesh's triangles as pyramids from an apex, summed. Its default, `inertia="legacy"`, takes
//! each pyramid's volume unsigned, which over-counts a non-convex mesh (MuJoCo keeps it for
//! compatibility); `exact` signs them (a closed, outward-oriented mesh); `shell` spreads the mass
//! over the surface. `convex` (the hull's inertia) needs a convex hull, not computed yet: refused.
//!
//! Meshes are read from binary STL files (MuJoCo's STL reader takes only those), Wavefront OBJ
//! files (through `tobj`) or the `vertex` and `face` attributes, then scaled (`scale`); vertices
//! are single precision, as MuJoCo stores them.

use std::path::Path;

/// MuJoCo's `mjMINVAL`: a face's area, a mesh's volume below it is none.
const MINVAL: f64 = 1e-15;

/// How a mesh's mass is spread (`<mesh inertia>`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum MeshInertia {
    /// Unsigned pyramid volumes (MuJoCo's default).
    Legacy,
    /// Signed pyramid volumes.
    Exact,
    /// On the surface.
    Shell,
}

/// A mesh's mass properties for a unit density: its volume (its area for a shell), centre of
/// mass and inertia tensor about it, in the mesh's coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct MeshMass {
    pub(super) volume: f64,
    pub(super) com: [f64; 3],
    pub(super) inertia: [[f64; 3]; 3],
}

/// The triangles of a binary STL file (MuJoCo reads 1 to 200,000 faces).
pub(super) fn read_stl(path: &Path) -> Result<Vec<[[f64; 3]; 3]>, String> {
    let bytes =
        std::fs::read(path).map_err(|e| format!("cannot read `{}`: {e}", path.display()))?;
    let count = bytes
        .get(80..84)
        .and_then(|b| <[u8; 4]>::try_from(b).ok())
        .map(u32::from_le_bytes)
        .ok_or_else(|| format!("`{}` is not a binary STL file", path.display()))?
        as usize;
    if !(1..=200_000).contains(&count) || bytes.len() != 84 + 50 * count {
        return Err(format!(
            "`{}` is not a binary STL file of 1 to 200000 triangles (MuJoCo reads no other)",
            path.display()
        ));
    }
    let float = |at: usize| -> f64 {
        let b = [bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]];
        f64::from(f32::from_le_bytes(b))
    };
    Ok((0..count)
        .map(|t| {
            // Each record: the normal (ignored), three vertices, two attribute bytes.
            let at = 84 + 50 * t + 12;
            let v = |k: usize| {
                [
                    float(at + 12 * k),
                    float(at + 12 * k + 4),
                    float(at + 12 * k + 8),
                ]
            };
            [v(0), v(1), v(2)]
        })
        .collect())
}

/// The triangles of a Wavefront OBJ file, every object of it, polygons split into fans
/// (single-precision vertices, as MuJoCo reads them).
pub(super) fn read_obj(path: &Path) -> Result<Vec<[[f64; 3]; 3]>, String> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, _materials) = tobj::load_obj(path, &options)
        .map_err(|e| format!("cannot read `{}` as OBJ: {e}", path.display()))?;
    let mut tris = Vec::new();
    for m in &models {
        let p = &m.mesh.positions;
        let vertex = |i: u32| -> Option<[f64; 3]> {
            let i = 3 * i as usize;
            Some([p.get(i)?, p.get(i + 1)?, p.get(i + 2)?].map(|x| f64::from(*x)))
        };
        for f in m.mesh.indices.chunks_exact(3) {
            let t = [vertex(f[0]), vertex(f[1]), vertex(f[2])];
            match t {
                [Some(a), Some(b), Some(c)] => tris.push([a, b, c]),
                _ => {
                    return Err(format!(
                        "`{}`: a face names a vertex it does not have",
                        path.display()
                    ))
                }
            }
        }
    }
    Ok(tris)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// A triangle's unit normal, centre and area (MuJoCo's `triangle`: no area below `MINVAL`).
fn triangle(t: &[[f64; 3]; 3]) -> ([f64; 3], [f64; 3], f64) {
    let center = [0, 1, 2].map(|k| (t[0][k] + t[1][k] + t[2][k]) / 3.0);
    let (b, c) = (sub(t[1], t[0]), sub(t[2], t[0]));
    let n = [
        b[1] * c[2] - b[2] * c[1],
        b[2] * c[0] - b[0] * c[2],
        b[0] * c[1] - b[1] * c[0],
    ];
    let len = dot(n, n).sqrt();
    if len < MINVAL {
        return (n, center, 0.0);
    }
    (n.map(|x| x / len), center, 0.5 * len)
}

/// The mass properties of the closed mesh `tris` for a unit density, as MuJoCo computes them.
pub(super) fn mass_properties(
    tris: &[[[f64; 3]; 3]],
    mode: MeshInertia,
) -> Result<MeshMass, String> {
    // The area-weighted centroid of the faces: the apex of the first pyramids.
    let (mut facecen, mut area) = ([0.0; 3], 0.0);
    for t in tris {
        let (_, c, a) = triangle(t);
        for k in 0..3 {
            facecen[k] += a * c[k];
        }
        area += a;
    }
    if area < MINVAL {
        return Err("its surface area is too small".into());
    }
    facecen = facecen.map(|x| x / area);
    // The centre of mass, from pyramids on `facecen` (or the faces, for a shell).
    let (mut com, mut total) = ([0.0; 3], 0.0);
    for t in tris {
        let (n, c, a) = triangle(t);
        let w = match mode {
            MeshInertia::Shell => a,
            MeshInertia::Exact => dot(sub(c, facecen), n) * a / 3.0,
            MeshInertia::Legacy => (dot(sub(c, facecen), n) * a / 3.0).abs(),
        };
        total += w;
        for k in 0..3 {
            com[k] += w * (c[k] * 3.0 / 4.0 + facecen[k] / 4.0);
        }
    }
    if total < MINVAL {
        return Err(if total < 0.0 {
            "its volume is negative (triangles oriented inward)".into()
        } else {
            "its volume is too small (`inertia=\"shell\"` spreads its mass on its surface)".into()
        });
    }
    com = com.map(|x| x / total);
    // Products of inertia from pyramids on the centre of mass.
    let pairs = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];
    let (mut p, mut volume) = ([0.0; 6], 0.0);
    for t in tris {
        let [d, e, f] = t.map(|v| sub(v, com));
        let (n, c, a) = triangle(&[d, e, f]);
        let (w, divisor) = match mode {
            MeshInertia::Shell => (a, 12.0),
            MeshInertia::Exact => (dot(c, n) * a / 3.0, 20.0),
            MeshInertia::Legacy => ((dot(c, n) * a / 3.0).abs(), 20.0),
        };
        volume += w;
        for (slot, (i, j)) in p.iter_mut().zip(pairs) {
            *slot += w / divisor
                * (2.0 * (d[i] * d[j] + e[i] * e[j] + f[i] * f[j])
                    + d[i] * e[j]
                    + d[j] * e[i]
                    + d[i] * f[j]
                    + d[j] * f[i]
                    + e[i] * f[j]
                    + e[j] * f[i]);
        }
    }
    let inertia = [
        [p[1] + p[2], -p[3], -p[4]],
        [-p[3], p[0] + p[2], -p[5]],
        [-p[4], -p[5], p[0] + p[1]],
    ];
    Ok(MeshMass {
        volume,
        com,
        inertia,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube's twelve outward triangles.
    fn cube() -> Vec<[[f64; 3]; 3]> {
        let v = |i: usize| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64];
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        quads
            .iter()
            .flat_map(|q| [[v(q[0]), v(q[1]), v(q[2])], [v(q[0]), v(q[2]), v(q[3])]])
            .collect()
    }

    #[test]
    fn a_unit_cube_has_unit_volume_and_a_sixth_for_each_moment() {
        for mode in [MeshInertia::Legacy, MeshInertia::Exact] {
            let m = mass_properties(&cube(), mode).unwrap();
            assert!((m.volume - 1.0).abs() < 1e-14, "{mode:?}: {}", m.volume);
            for k in 0..3 {
                assert!((m.com[k] - 0.5).abs() < 1e-14);
                assert!(
                    (m.inertia[k][k] - 1.0 / 6.0).abs() < 1e-14,
                    "{:?}",
                    m.inertia
                );
            }
            assert!(m.inertia[0][1].abs() < 1e-14);
        }
        // Inward triangles: a negative volume for `exact`.
        let inward: Vec<_> = cube().into_iter().map(|[a, b, c]| [a, c, b]).collect();
        assert!(mass_properties(&inward, MeshInertia::Exact).is_err());
    }
}
