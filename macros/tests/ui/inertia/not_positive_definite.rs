articulated::chain! {
    chain Bad {
        // Eigenvalues -1, 1, 3.
        body a { mass: 1.0, inertia: [[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]] }
        joint j: revolute(z) { parent: world, child: a }
    }
}

fn main() {}
