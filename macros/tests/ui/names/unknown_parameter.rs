articulated::chain! {
    chain Bad {
        param m = 1.0;
        body a { mass: n, inertia: diag(1.0, 1.0, 1.0) }
        joint j: revolute(z) { parent: world, child: a }
    }
}

fn main() {}
