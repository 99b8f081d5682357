articulated::chain! {
    chain Bad {
        body a { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }
        body b { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }
        joint j: revolute(z) { parent: world, child: a }
        joint j: revolute(z) { parent: a, child: b }
    }
}

fn main() {}
