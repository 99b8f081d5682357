articulated::chain! {
    chain Bad {
        body a { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }
        joint j: spherical(xxy) { parent: world, child: a }
    }
}

fn main() {}
