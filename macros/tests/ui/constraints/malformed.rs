// Items of `contacts` and `loops` that are not `frame: kind` and `name: point(a, b)`, a contact
// named twice, a loop of a frame on itself: each an error at its token, all at once.
articulated::chain! {
    chain Leg {
        contacts: [foot, foot: point, foot: six_d];
        loops: [rod: point(foot), tie: point(foot, foot)];
        body foot { mass: 1.0, inertia: diag(0.1, 0.1, 0.1) }
        joint hip: free { parent: world, child: foot }
    }
}

fn main() {}
