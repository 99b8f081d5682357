// A contact or a loop on a frame the chain does not have is an error at the frame's name, with
// the nearest name where one is near.
articulated::chain! {
    chain Leg {
        contacts: [fot: six_d];
        loops: [rod: point(foot, ancor)];
        body foot { mass: 1.0, inertia: diag(0.1, 0.1, 0.1) }
        joint hip: free { parent: world, child: foot }
        frame anchor { parent: world }
    }
}

fn main() {}
