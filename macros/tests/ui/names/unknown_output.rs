articulated::chain! {
    chain Bad {
        outputs: [mass_matrix, mas_matrix];
        body a { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }
        joint j: revolute(z) { parent: world, child: a }
    }
}

fn main() {}
