// A contact simulation's scene with mistakes: a sphere on a frame the chain does not have (at
// the frame's name), a zero ground normal, a negative radius, a restitution above 1, and
// spheres without a friction coefficient.
articulated::chain! {
    chain Crate {
        grounds: [floor: [0.0, 0.0, 0.0, 0.0]];
        spheres: [heel: sphere(bxo, [0.0, 0.0, -0.1], 0.0), toe: sphere(bx, [0.1, 0.0, -0.1], -0.01)];
        restitution: 1.5;
        body bx { mass: 1.0, inertia: diag(0.1, 0.1, 0.1) }
        joint base: free(quaternion) { parent: world, child: bx }
    }
}

fn main() {}
