// A syntax error stops the parse at the first bad token; the type is still declared, so using
// it below adds no error.
articulated::chain! {
    chain Bad {
        body a { mass 1.0, inertia: diag(1.0, 1.0, 1.0) }
        joint j: revolute(z) { parent: world, child: a }
    }
}

fn main() {
    let _ = Bad::NQ;
}
