// The runtime's constraint solver computes in f64: constraints in an `f32` chain are an error
// at the first constraint, naming the setting.
articulated::chain! {
    chain Leg {
        scalar: f32;
        contacts: [foot: point];
        body foot { mass: 1.0, inertia: diag(0.1, 0.1, 0.1) }
        joint hip: free { parent: world, child: foot }
    }
}

fn main() {}
