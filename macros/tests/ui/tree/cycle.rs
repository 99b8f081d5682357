articulated::chain! {
    chain Bad {
        body a { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }
        body b { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }
        body c { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }
        joint j: revolute(z) { parent: world, child: a }
        joint k: revolute(z) { parent: c, child: b }
        joint l: revolute(z) { parent: b, child: c }
    }
}

fn main() {}
