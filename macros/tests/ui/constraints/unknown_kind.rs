// A contact's kind is `six_d` or `point`, a loop's `point(a, b)`: an unknown one is an error at
// its token, with the nearest kind where one is near; code using the constraints after it
// reports nothing more.
articulated::chain! {
    chain Leg {
        contacts: [foot: plane];
        loops: [rod: pont(foot, anchor)];
        body foot { mass: 1.0, inertia: diag(0.1, 0.1, 0.1) }
        joint hip: free { parent: world, child: foot }
        frame anchor { parent: world }
    }
}

fn main() {
    let q = articulated::nalgebra::SVector::<f64, 6>::zeros();
    let (qdd, forces) = Leg::constrained_forward_dynamics(&q, &q, &q).unwrap();
    let _ = (qdd, forces, Leg::CONTACTS, Leg::LOOPS, Leg::CONSTRAINT_ROWS);
}
